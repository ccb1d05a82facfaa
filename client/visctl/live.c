/* The connection and the error reports visctl's live subcommands share. */
#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

int live_is_option(const char *a)
{
	return a[0] == '-' && a[1] != '\0' && !(a[1] >= '0' && a[1] <= '9');
}

int live_help(const char *name)
{
	const struct visctl_command *cmd = visctl_command_find(name);
	const char *args = cmd ? cmd->usage : "";
	printf("usage: visctl %s%s%s\n", name, args[0] ? " " : "", args);
	if (cmd && cmd->help)
		fputs(cmd->help, stdout);
	return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
}

int live_expect_args(struct live *l, int *argc, char **argv, int n, const char *names, bool *json,
		     int *ret)
{
	int k = 1;
	for (int i = 1; i < *argc; i++) {
		if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
			*ret = live_help(argv[0]);
			return -1;
		}
		if (json && strcmp(argv[i], "--json") == 0) {
			*json = true;
			continue;
		}
		if (live_is_option(argv[i])) {
			*ret = live_usage(l, argv[0], "unknown option '%s'", argv[i]);
			return -1;
		}
		argv[k++] = argv[i];
	}
	*argc = k;
	if (k - 1 != n) {
		*ret = n ? live_usage(l, argv[0], "expected %s, got %d arguments", names, k - 1)
			 : live_usage(l, argv[0], "unexpected argument '%s'", argv[1]);
		return -1;
	}
	return 0;
}

int live_window_arg(struct live *l, const char *name, const char *s, uint32_t *id, int *ret)
{
	if (live_parse_u32(s, id) < 0) {
		*ret = live_usage(l, name, "ID '%s' is not a number from 0 to 4294967295", s);
		return -1;
	}
	return 0;
}

int live_coord_arg(struct live *l, const char *name, const char *what, const char *s,
		     int32_t *v, int *ret)
{
	if (live_parse_i32(s, v) < 0) {
		*ret = live_usage(l, name, "%s '%s' is not a number from -2147483648 to 2147483647",
				  what, s);
		return -1;
	}
	return 0;
}

int live_size_arg(struct live *l, const char *name, const char *what, const char *s,
		    uint32_t *v, int *ret)
{
	if (live_parse_u32(s, v) < 0 || *v < 1 || *v > INT32_MAX) {
		*ret = live_usage(l, name, "%s '%s' is not a number from 1 to 2147483647", what, s);
		return -1;
	}
	return 0;
}

struct vis_client *live_connect(struct live *l)
{
	if (l->client)
		return l->client;
	char path[108];
	if (!l->socket && vis_client_default_socket(path, sizeof(path)) < 0) {
		live_error(l, "no socket: set VISD_SOCKET or XDG_RUNTIME_DIR, or give -s SOCKET");
		return NULL;
	}
	struct vis_client *c = vis_client_connect(l->socket ? l->socket : path, l->role);
	if (!c) {
		live_error(l, "%s", strerror(ENOMEM));
		return NULL;
	}
	if (vis_client_error(c)) {
		/* Name the socket, unless the library's message does already. */
		const char *msg = vis_client_error_message(c), *at = l->socket ? l->socket : path;
		if (strstr(msg, at))
			live_error(l, "%s", msg);
		else
			live_error(l, "%s: %s", at, msg);
		vis_client_destroy(c);
		return NULL;
	}
	l->client = c;
	return c;
}

bool live_sees_nothing(struct live *l)
{
	struct vis_window_info *w;
	size_t n;
	if (!l->client || vis_client_role(l->client) != VIS_ROLE_CLIENT ||
	    vis_client_get_tree(l->client, &w, &n) < 0)
		return false;
	free(w);
	return n == 0;
}

void live_warn_sees_nothing(struct live *l, const char *name)
{
	fprintf(stderr,
		"%s: %s: warning: this connection owns no windows, and a client sees only its own "
		"(use --role observer to see every window)\n",
		l->where, name);
}

int live_error(struct live *l, const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "%s: ", l->where);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	return VISCTL_EXIT_FAILURE;
}

int live_usage(struct live *l, const char *name, const char *fmt, ...)
{
	va_list ap;
	fprintf(stderr, "%s: %s: ", l->where, name);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	const struct visctl_command *cmd = visctl_command_find(name);
	if (cmd)
		fprintf(stderr, "usage: visctl %s%s%s\n", name, cmd->usage[0] ? " " : "",
			cmd->usage);
	return VISCTL_EXIT_USAGE;
}

int live_failed(struct live *l, const char *what)
{
	struct vis_error e;
	if (!l->client)
		return VISCTL_EXIT_FAILURE;
	if (vis_client_error(l->client))
		return live_error(l, "%s: %s", what, vis_client_error_message(l->client));
	if (vis_client_last_error(l->client, &e) && e.code == VIS_ERROR_WINDOW &&
	    vis_client_role(l->client) == VIS_ROLE_CLIENT)
		/* The window is likely another connection's: isolation hides it, so say so. */
		return live_error(l,
				  "%s: %s: %s (it may be another connection's: %s a plain client, "
				  "which sees only its own windows; --role observer reads every "
				  "window, --role manager changes them)",
				  what, vis_error_code_name(e.code), e.message,
				  l->in_script ? "this script's connection is"
					       : "each visctl is a new connection,");
	if (vis_client_last_error(l->client, &e))
		return live_error(l, "%s: %s: %s", what, vis_error_code_name(e.code), e.message);
	return live_error(l, "%s: failed", what);
}

const char *live_describe(int argc, char **argv, char *buf, size_t len)
{
	size_t at = 0;
	buf[0] = '\0';
	for (int i = 0; i < argc && at < len; i++) {
		int n = snprintf(buf + at, len - at, "%s%s", i ? " " : "", argv[i]);
		if (n < 0)
			break;
		at += (size_t)n;
	}
	return buf;
}

int live_parse_u32(const char *s, uint32_t *out)
{
	uint64_t v = 0;
	if (!*s)
		return -1;
	for (; *s; s++) {
		if (*s < '0' || *s > '9')
			return -1;
		v = v * 10 + (uint64_t)(*s - '0');
		if (v > UINT32_MAX)
			return -1;
	}
	*out = (uint32_t)v;
	return 0;
}

int live_parse_u64(const char *s, uint64_t *out)
{
	bool hex = s[0] == '0' && (s[1] == 'x' || s[1] == 'X');
	uint64_t v = 0, base = hex ? 16 : 10;
	if (hex)
		s += 2;
	if (!*s)
		return -1;
	for (; *s; s++) {
		int d = *s >= '0' && *s <= '9'			? *s - '0'
			: hex && *s >= 'a' && *s <= 'f' ? *s - 'a' + 10
			: hex && *s >= 'A' && *s <= 'F' ? *s - 'A' + 10
							: -1;
		if (d < 0 || v > (UINT64_MAX - (uint64_t)d) / base)
			return -1;
		v = v * base + (uint64_t)d;
	}
	*out = v;
	return 0;
}

int live_xid_arg(struct live *l, const char *name, const char *s, uint64_t *xid, int *ret)
{
	if (live_parse_u64(s, xid) < 0 || *xid == 0 || *xid > UINT32_MAX) {
		*ret = live_usage(l, name,
				  "XID '%s' is not an X window ID from 0x1 to 0xffffffff (hex 0x... or "
				  "decimal)",
				  s);
		return -1;
	}
	return 0;
}

int live_external_arg(struct live *l, const char *name, const char *s, uint32_t *ns,
		      uint64_t *tag, int *ret)
{
	const char *colon = strchr(s, ':');
	char nsbuf[16];
	size_t len = colon ? (size_t)(colon - s) : 0;
	if (colon && len < sizeof(nsbuf)) {
		memcpy(nsbuf, s, len);
		nsbuf[len] = '\0';
	}
	if (!colon || len >= sizeof(nsbuf) || live_parse_u32(nsbuf, ns) < 0 || *ns == 0 ||
	    live_parse_u64(colon + 1, tag) < 0) {
		*ret = live_usage(l, name,
				  "external ID '%s' is not NS:TAG (NS from 1 to 4294967295, TAG a "
				  "64-bit number, hex 0x... or decimal)",
				  s);
		return -1;
	}
	return 0;
}

const char *live_external_name(uint32_t ns, uint64_t tag, char *buf, size_t len)
{
	if (ns == VIS_EXTERNAL_NONE)
		snprintf(buf, len, "-");
	else if (ns == VIS_EXTERNAL_X11)
		snprintf(buf, len, "x11:0x%" PRIx64, tag);
	else
		snprintf(buf, len, "%u:0x%" PRIx64, ns, tag);
	return buf;
}

void live_x11_role(struct live *l)
{
	if (!l->role_given && !l->client)
		l->role = VIS_ROLE_OBSERVER;
}

int live_parse_i32(const char *s, int32_t *out)
{
	uint32_t v;
	int neg = *s == '-';
	if (live_parse_u32(s + neg, &v) < 0 || v > (uint32_t)INT32_MAX + (uint32_t)neg)
		return -1;
	*out = neg ? (int32_t)(0 - (int64_t)v) : (int32_t)v;
	return 0;
}

int live_drain(struct vis_client *c)
{
	int f;
	while ((f = vis_client_flush(c)) == 1) {
		struct pollfd pfd = { .fd = vis_client_fd(c), .events = POLLIN | POLLOUT };
		if (poll(&pfd, 1, -1) < 0 && errno != EINTR)
			return -1;
		if ((pfd.revents & (POLLIN | POLLHUP | POLLERR)) && vis_client_dispatch(c) < 0)
			return -1;
	}
	return f;
}
