/*
 * The live queries: states, tree, region, repaint, look, lookup. Each prints its records one a line, as text
 * or, with --json, as one JSON object a line (every string is one of ours, nothing to escape,
 * but X's window names of states --x11 --names).
 */
#include <inttypes.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"
#include "x11-names.h"

/* Reports a failed query, naming it by its command line. */
static int query_failed(struct live *l, int argc, char **argv)
{
	char what[256];
	return live_failed(l, live_describe(argc, argv, what, sizeof(what)));
}

/*
 * A query's start: its arguments (n of them, named names, and --json), then the connection.
 * Returns 0, or -1 with *ret the status to exit with.
 */
static int begin(struct live *l, int *argc, char **argv, int n, const char *names, bool *json,
		 int *ret)
{
	if (live_expect_args(l, argc, argv, n, names, json, ret) < 0)
		return -1;
	if (!live_connect(l)) {
		*ret = VISCTL_EXIT_FAILURE;
		return -1;
	}
	return 0;
}

/* JSON's literal for a flag. */
static const char *json_bool(bool b)
{
	return b ? "true" : "false";
}

/* Orders states by window ID, for qsort. */
static int by_window(const void *a, const void *b)
{
	const struct vis_window_state *x = a, *y = b;
	return (x->window > y->window) - (x->window < y->window);
}

/* Orders tree records by external tag, for qsort. */
static int by_external(const void *a, const void *b)
{
	const struct vis_window_info *x = a, *y = b;
	return (x->external > y->external) - (x->external < y->external);
}

/*
 * Prints an X string as text, quoted: '"', '\\' and control bytes escaped ('\\"', '\\\\',
 * '\\xNN'), other bytes as they are (a name is UTF-8 or Latin-1: X does not say which for WM_NAME).
 */
static void print_quoted(const char *s)
{
	putchar('"');
	for (const unsigned char *p = (const unsigned char *)s; *p; p++)
		if (*p == '"' || *p == '\\')
			printf("\\%c", *p);
		else if (*p < 0x20 || *p == 0x7f)
			printf("\\x%02x", *p);
		else
			putchar(*p);
	putchar('"');
}

/* Prints an X string as a JSON string (control bytes as \\u00NN), or null for none. */
static void print_json_string(const char *s)
{
	if (!s) {
		fputs("null", stdout);
		return;
	}
	putchar('"');
	for (const unsigned char *p = (const unsigned char *)s; *p; p++)
		if (*p == '"' || *p == '\\')
			printf("\\%c", *p);
		else if (*p < 0x20 || *p == 0x7f)
			printf("\\u%04x", *p);
		else
			putchar(*p);
	putchar('"');
}

/* A window's name and class after its state, as xwininfo -tree prints them. */
static void print_x11_name(const struct x11_name *x, bool json)
{
	if (json) {
		fputs(",\"name\":", stdout);
		print_json_string(x->name);
		fputs(",\"class\":", stdout);
		if (x->instance) {
			putchar('[');
			print_json_string(x->instance);
			putchar(',');
			print_json_string(x->class_name ? x->class_name : "");
			putchar(']');
		} else {
			fputs("null", stdout);
		}
		return;
	}
	putchar(' ');
	if (x->name)
		print_quoted(x->name);
	else
		fputs("(has no name)", stdout);
	fputs(" (", stdout);
	if (x->instance) {
		print_quoted(x->instance);
		putchar(' ');
		print_quoted(x->class_name ? x->class_name : "");
	}
	putchar(')');
}

/*
 * states --x11: the X windows (external namespace X11) among the viewable windows with a state,
 * by XID, read from the tree, whose records carry the external IDs that states records lack.
 * With names, each window's name and class too, asked of the X server ($DISPLAY): visd knows
 * the windows by XID alone.
 */
static int states_x11(struct live *l, int argc, char **argv, bool json, bool names)
{
	struct vis_window_info *w;
	size_t n, k = 0;
	if (vis_client_get_tree(l->client, &w, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++)
		if (w[i].ext_namespace == VIS_EXTERNAL_X11 && (w[i].flags & VIS_WINDOW_VIEWABLE) &&
		    w[i].state != VIS_VISIBILITY_NONE)
			w[k++] = w[i];
	if (k)
		qsort(w, k, sizeof(*w), by_external);
	struct x11_name *xn = NULL;
	if (names) {
		uint32_t *xids = calloc(k + 1, sizeof(*xids));
		xn = calloc(k + 1, sizeof(*xn));
		char why[160];
		if (!xids || !xn) {
			free(xids);
			free(xn);
			free(w);
			return live_error(l, "%s: out of memory", argv[0]);
		}
		for (size_t i = 0; i < k; i++)
			xids[i] = (uint32_t)w[i].external;
		int r = x11_names_read(NULL, xids, k, xn, why, sizeof(why));
		free(xids);
		if (r < 0) {
			x11_names_finish(xn, k);
			free(xn);
			free(w);
			return live_error(l, "%s: %s", argv[0], why);
		}
	}
	for (size_t i = 0; i < k; i++) {
		if (json)
			printf("{\"x11\":\"0x%" PRIx64 "\",\"window\":%u,\"state\":\"%s\"",
			       w[i].external, w[i].window, vis_visibility_name(w[i].state));
		else
			printf("0x%" PRIx64 " %s", w[i].external, vis_visibility_name(w[i].state));
		if (xn)
			print_x11_name(&xn[i], json);
		fputs(json ? "}\n" : "\n", stdout);
	}
	x11_names_finish(xn, k);
	free(xn);
	free(w);
	if (!k && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}

/* Takes the option flag (e.g. --x11) out of argv; whether it was there. */
static bool take_flag(int *argc, char **argv, const char *flag)
{
	bool found = false;
	int k = 1;
	for (int i = 1; i < *argc; i++)
		if (strcmp(argv[i], flag) == 0)
			found = true;
		else
			argv[k++] = argv[i];
	*argc = k;
	return found;
}

int cmd_states(struct live *l, int argc, char **argv)
{
	struct vis_window_state *states;
	size_t n;
	bool json = false;
	int ret;
	bool x11 = take_flag(&argc, argv, "--x11"), names = take_flag(&argc, argv, "--names");
	if (names && !x11)
		return live_usage(l, argv[0], "--names goes with --x11 (the names are X's)");
	if (x11)
		live_x11_role(l);
	if (begin(l, &argc, argv, 0, "", &json, &ret) < 0)
		return ret;
	if (x11)
		return states_x11(l, argc, argv, json, names);
	if (vis_client_get_states(l->client, &states, &n) < 0)
		return query_failed(l, argc, argv);
	/* The daemon sends them in order already; sorting again costs little and promises it. */
	if (n)
		qsort(states, n, sizeof(*states), by_window);
	for (size_t i = 0; i < n; i++)
		printf(json ? "{\"window\":%u,\"state\":\"%s\"}\n" : "%u %s\n", states[i].window,
		       vis_visibility_name(states[i].state));
	free(states);
	if (!n && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}

/* The LOOK column of tree: shaped, translucent, input-only joined by commas, or "-". */
static void look_name(uint32_t flags, char *buf, size_t len)
{
	static const struct {
		uint32_t flag;
		const char *name;
	} names[] = { { VIS_WINDOW_SHAPED, "shaped" },
		      { VIS_WINDOW_TRANSLUCENT, "translucent" },
		      { VIS_WINDOW_INPUT_ONLY, "input-only" } };
	size_t at = 0;
	buf[0] = '\0';
	for (size_t k = 0; k < sizeof(names) / sizeof(names[0]); k++)
		if ((flags & names[k].flag) && at < len)
			at += (size_t)snprintf(buf + at, len - at, "%s%s", at ? "," : "", names[k].name);
	if (!at)
		snprintf(buf, len, "-");
}

int cmd_tree(struct live *l, int argc, char **argv)
{
	struct vis_window_info *w;
	size_t n;
	bool json = false;
	int ret;
	if (begin(l, &argc, argv, 0, "", &json, &ret) < 0)
		return ret;
	if (vis_client_get_tree(l->client, &w, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++) {
		uint32_t f = w[i].flags;
		const char *state =
			vis_visibility_name(f & VIS_WINDOW_VIEWABLE ? w[i].state : VIS_VISIBILITY_NONE);
		char look[40], external[40];
		look_name(f, look, sizeof(look));
		live_external_name(w[i].ext_namespace, w[i].external, external, sizeof(external));
		if (json)
			printf("{\"window\":%u,\"parent\":%u,\"x\":%d,\"y\":%d,\"width\":%u,"
			       "\"height\":%u,\"mapped\":%s,\"viewable\":%s,\"retained\":%s,"
			       "\"parent_hidden\":%s,\"state\":\"%s\",\"border\":%u,\"shaped\":%s,"
			       "\"translucent\":%s,\"input_only\":%s,\"namespace\":%u,"
			       "\"external\":%" PRIu64 "}\n",
			       w[i].window, w[i].parent, w[i].x, w[i].y, w[i].width, w[i].height,
			       json_bool(f & VIS_WINDOW_MAPPED), json_bool(f & VIS_WINDOW_VIEWABLE),
			       json_bool(f & VIS_WINDOW_RETAINED),
			       json_bool(f & VIS_WINDOW_PARENT_HIDDEN), state, w[i].border,
			       json_bool(f & VIS_WINDOW_SHAPED), json_bool(f & VIS_WINDOW_TRANSLUCENT),
			       json_bool(f & VIS_WINDOW_INPUT_ONLY), w[i].ext_namespace,
			       w[i].external);
		else
			printf("%u %u %d %d %u %u %s %s %s %u %s %s\n", w[i].window, w[i].parent,
			       w[i].x, w[i].y, w[i].width, w[i].height,
			       f & VIS_WINDOW_MAPPED ? "mapped" : "unmapped", state,
			       f & VIS_WINDOW_RETAINED ? "retained" : "-", w[i].border, look, external);
	}
	free(w);
	if (!n && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}

int cmd_region(struct live *l, int argc, char **argv)
{
	struct vis_rect32 *r;
	uint32_t id;
	size_t n;
	bool json = false;
	int ret;
	if (live_expect_args(l, &argc, argv, 1, "ID", &json, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_region(l->client, id, &r, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++)
		printf(json ? "{\"x\":%d,\"y\":%d,\"width\":%u,\"height\":%u}\n" : "%d %d %u %u\n",
		       r[i].x, r[i].y, r[i].width, r[i].height);
	free(r);
	return VISCTL_EXIT_OK;
}

/* Prints n rectangles as " X,Y,W,H" (or JSON arrays [X,Y,W,H] joined by commas). */
static void print_rects(const struct vis_rect32 *r, uint32_t n, bool json)
{
	for (uint32_t i = 0; i < n; i++)
		printf(json ? "%s[%d,%d,%u,%u]" : "%s%d,%d,%u,%u", json ? (i ? "," : "") : " ", r[i].x,
		       r[i].y, r[i].width, r[i].height);
}

int cmd_look(struct live *l, int argc, char **argv)
{
	struct vis_look_info look;
	uint32_t id;
	bool json = false;
	int ret;
	if (live_expect_args(l, &argc, argv, 1, "ID", &json, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_look(l->client, id, &look) < 0)
		return query_failed(l, argc, argv);
	static const char *const modes[] = { "all", "none", "rects" };
	if (json) {
		printf("{\"window\":%u,\"shaped\":%s,\"shape\":[", id, json_bool(look.shaped));
		print_rects(look.shape, look.n_shape, true);
		printf("],\"opaque\":\"%s\",\"opaque_rects\":[", modes[look.mode]);
		print_rects(look.opaque, look.n_opaque, true);
		printf("]}\n");
	} else {
		printf("shape%s", look.shaped ? "" : " box");
		print_rects(look.shape, look.n_shape, false);
		printf("\nopaque%s", look.mode == VIS_OPAQUE_MODE_RECTS ? "" : look.mode ? " none" : " all");
		print_rects(look.opaque, look.n_opaque, false);
		printf("\n");
	}
	free(look.shape);
	free(look.opaque);
	return VISCTL_EXIT_OK;
}

int cmd_repaint(struct live *l, int argc, char **argv)
{
	struct vis_rect32 damage;
	uint32_t *w;
	size_t n;
	bool json = false;
	int ret;
	if (live_expect_args(l, &argc, argv, 4, "X Y W H", &json, &ret) < 0 ||
	    live_coord_arg(l, argv[0], "X", argv[1], &damage.x, &ret) < 0 ||
	    live_coord_arg(l, argv[0], "Y", argv[2], &damage.y, &ret) < 0 ||
	    live_size_arg(l, argv[0], "W", argv[3], &damage.width, &ret) < 0 ||
	    live_size_arg(l, argv[0], "H", argv[4], &damage.height, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_repaint(l->client, damage, &w, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++)
		printf(json ? "{\"window\":%u}\n" : "%u\n", w[i]);
	free(w);
	if (!n && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}

int cmd_lookup(struct live *l, int argc, char **argv)
{
	uint32_t ns = VIS_EXTERNAL_NONE, window;
	uint64_t tag = 0;
	char *pos[2];
	int n = 0, ret;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
			return live_help(argv[0]);
		if (strncmp(a, "--x11=", 6) == 0 || strcmp(a, "--x11") == 0) {
			const char *v = a[5] == '=' ? a + 6 : i + 1 < argc ? argv[++i] : NULL;
			if (!v)
				return live_usage(l, argv[0], "--x11 needs an XID");
			if (live_xid_arg(l, argv[0], v, &tag, &ret) < 0)
				return ret;
			ns = VIS_EXTERNAL_X11;
		} else if (live_is_option(a)) {
			return live_usage(l, argv[0], "unknown option '%s'", a);
		} else if (n == 2) {
			return live_usage(l, argv[0], "unexpected argument '%s'", a);
		} else {
			pos[n++] = argv[i];
		}
	}
	if (ns == VIS_EXTERNAL_NONE) {
		if (n != 2)
			return live_usage(l, argv[0], "expected --x11 XID or NS TAG, got %d arguments",
					  n);
		if (live_parse_u32(pos[0], &ns) < 0 || ns == 0)
			return live_usage(l, argv[0], "NS '%s' is not a number from 1 to 4294967295",
					  pos[0]);
		if (live_parse_u64(pos[1], &tag) < 0)
			return live_usage(l, argv[0],
					  "TAG '%s' is not a 64-bit number (hex 0x... or decimal)",
					  pos[1]);
	} else if (n) {
		return live_usage(l, argv[0], "unexpected argument '%s' after --x11", pos[0]);
	}
	/* External IDs are set by the manager only: a plain client never has one to find. */
	live_x11_role(l);
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_lookup(l->client, ns, tag, &window) < 0)
		return query_failed(l, argc, argv);
	printf("%u\n", window);
	return VISCTL_EXIT_OK;
}
