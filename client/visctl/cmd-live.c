/*
 * The live subcommands that send one request: the changes (create, destroy, map, …), which end
 * with a round trip so that the daemon's verdict is known before visctl exits, and the queries
 * (states, tree, region, repaint), which print the reply.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

/* Whether an argument is an option rather than a (possibly negative) number or '-'. */
static int is_option(const char *a)
{
	return a[0] == '-' && a[1] != '\0' && !(a[1] >= '0' && a[1] <= '9');
}

/* Prints a command's usage on stdout for --help; returns the exit status. */
static int help(const char *name)
{
	const struct visctl_command *cmd = visctl_command_find(name);
	printf("usage: visctl %s %s\n", name, cmd ? cmd->usage : "");
	return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
}

/*
 * Checks that argv holds exactly n arguments and no option but --help, naming them (names, e.g.
 * "ID X Y") when the count is wrong. Returns 0, or -1 with *ret the status to exit with.
 */
static int expect_args(struct live *l, int argc, char **argv, int n, const char *names, int *ret)
{
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
			*ret = help(argv[0]);
			return -1;
		}
		if (is_option(argv[i])) {
			*ret = live_usage(l, argv[0], "unknown option '%s'", argv[i]);
			return -1;
		}
	}
	if (argc - 1 != n) {
		*ret = n ? live_usage(l, argv[0], "expected %s, got %d arguments", names, argc - 1)
			 : live_usage(l, argv[0], "unexpected argument '%s'", argv[1]);
		return -1;
	}
	return 0;
}

/* Parses a window ID argument; a usage error when it is not one. */
static int window_arg(struct live *l, const char *name, const char *s, uint32_t *id, int *ret)
{
	if (live_parse_u32(s, id) < 0) {
		*ret = live_usage(l, name, "ID '%s' is not a number from 0 to 4294967295", s);
		return -1;
	}
	return 0;
}

/* Parses a coordinate (signed) argument. */
static int coord_arg(struct live *l, const char *name, const char *what, const char *s,
		     int32_t *v, int *ret)
{
	if (live_parse_i32(s, v) < 0) {
		*ret = live_usage(l, name, "%s '%s' is not a number from -2147483648 to 2147483647",
				  what, s);
		return -1;
	}
	return 0;
}

/* Parses a size argument: 1 … 2^31 − 1, as the daemon takes them. */
static int size_arg(struct live *l, const char *name, const char *what, const char *s,
		    uint32_t *v, int *ret)
{
	if (live_parse_u32(s, v) < 0 || *v < 1 || *v > INT32_MAX) {
		*ret = live_usage(l, name, "%s '%s' is not a number from 1 to 2147483647", what, s);
		return -1;
	}
	return 0;
}

/*
 * Ends a change: a round trip, then the daemon's verdict on request seq (0: not sent). Errors
 * are matched by request number, so an earlier failure never blames this command. Inside a
 * script's batch the daemon holds the request, so the verdict waits for batch-commit.
 */
static int finish(struct live *l, uint32_t seq, int argc, char **argv)
{
	char what[256];
	struct vis_error e;
	if (seq && l->in_batch)
		return VISCTL_EXIT_OK;
	if (!seq || vis_client_roundtrip(l->client) < 0 ||
	    (vis_client_last_error(l->client, &e) && e.seq == seq))
		return live_failed(l, live_describe(argc, argv, what, sizeof(what)));
	return VISCTL_EXIT_OK;
}

/* Reports a failed query, naming it by its command line. */
static int query_failed(struct live *l, int argc, char **argv)
{
	char what[256];
	return live_failed(l, live_describe(argc, argv, what, sizeof(what)));
}

int cmd_create(struct live *l, int argc, char **argv)
{
	uint32_t parent = VIS_WINDOW_ROOT, flags = 0, w, h;
	int32_t x, y;
	char *pos[4];
	int n = 0, ret;

	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *value = NULL;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
			return help(argv[0]);
		if (strcmp(a, "--map") == 0) {
			flags |= VIS_CREATE_MAP;
		} else if (strcmp(a, "--retain") == 0) {
			flags |= VIS_CREATE_RETAIN;
		} else if (strncmp(a, "--parent=", 9) == 0) {
			value = a + 9;
		} else if (strcmp(a, "--parent") == 0) {
			if (i + 1 == argc)
				return live_usage(l, argv[0], "--parent needs an ID");
			value = argv[++i];
		} else if (is_option(a)) {
			return live_usage(l, argv[0], "unknown option '%s'", a);
		} else if (n == 4) {
			return live_usage(l, argv[0], "unexpected argument '%s'", a);
		} else {
			pos[n++] = argv[i];
		}
		if (value && live_parse_u32(value, &parent) < 0)
			return live_usage(l, argv[0],
					  "parent ID '%s' is not a number from 0 to 4294967295", value);
	}
	if (n != 4)
		return live_usage(l, argv[0], "expected X Y W H, got %d arguments", n);
	if (coord_arg(l, argv[0], "X", pos[0], &x, &ret) < 0 ||
	    coord_arg(l, argv[0], "Y", pos[1], &y, &ret) < 0 ||
	    size_arg(l, argv[0], "W", pos[2], &w, &ret) < 0 ||
	    size_arg(l, argv[0], "H", pos[3], &h, &ret) < 0)
		return ret;

	uint32_t window;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_create(l->client, parent, x, y, w, h, flags, &window) < 0)
		return query_failed(l, argc, argv);
	l->created = window;
	printf("%u\n", window);
	return VISCTL_EXIT_OK;
}

/* The commands whose only argument is a window: parse it, send, round trip. */
static int window_request(struct live *l, int argc, char **argv,
			  uint32_t (*send)(struct vis_client *c, uint32_t window))
{
	uint32_t id;
	int ret;
	if (expect_args(l, argc, argv, 1, "ID", &ret) < 0 ||
	    window_arg(l, argv[0], argv[1], &id, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, send(l->client, id), argc, argv);
}

int cmd_destroy(struct live *l, int argc, char **argv)
{
	return window_request(l, argc, argv, vis_client_destroy_window);
}

int cmd_map(struct live *l, int argc, char **argv)
{
	return window_request(l, argc, argv, vis_client_map);
}

int cmd_unmap(struct live *l, int argc, char **argv)
{
	return window_request(l, argc, argv, vis_client_unmap);
}

int cmd_raise(struct live *l, int argc, char **argv)
{
	return window_request(l, argc, argv, vis_client_raise);
}

int cmd_lower(struct live *l, int argc, char **argv)
{
	return window_request(l, argc, argv, vis_client_lower);
}

int cmd_move(struct live *l, int argc, char **argv)
{
	uint32_t id;
	int32_t x, y;
	int ret;
	if (expect_args(l, argc, argv, 3, "ID X Y", &ret) < 0 ||
	    window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    coord_arg(l, argv[0], "X", argv[2], &x, &ret) < 0 ||
	    coord_arg(l, argv[0], "Y", argv[3], &y, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, vis_client_move(l->client, id, x, y), argc, argv);
}

int cmd_resize(struct live *l, int argc, char **argv)
{
	uint32_t id, w, h;
	int ret;
	if (expect_args(l, argc, argv, 3, "ID W H", &ret) < 0 ||
	    window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    size_arg(l, argv[0], "W", argv[2], &w, &ret) < 0 ||
	    size_arg(l, argv[0], "H", argv[3], &h, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, vis_client_resize(l->client, id, w, h), argc, argv);
}

int cmd_stack(struct live *l, int argc, char **argv)
{
	uint32_t id, sibling, mode;
	int ret;
	if (expect_args(l, argc, argv, 3, "ID above|below SIBLING", &ret) < 0 ||
	    window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    window_arg(l, argv[0], argv[3], &sibling, &ret) < 0)
		return ret;
	if (strcmp(argv[2], "above") == 0)
		mode = VIS_RESTACK_ABOVE;
	else if (strcmp(argv[2], "below") == 0)
		mode = VIS_RESTACK_BELOW;
	else
		return live_usage(l, argv[0], "expected above or below, got '%s'", argv[2]);
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, vis_client_restack(l->client, id, mode, sibling), argc, argv);
}

int cmd_sync(struct live *l, int argc, char **argv)
{
	int ret;
	if (expect_args(l, argc, argv, 0, "", &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_roundtrip(l->client) < 0)
		return query_failed(l, argc, argv);
	return VISCTL_EXIT_OK;
}

/* Orders states by window ID, for qsort. */
static int by_window(const void *a, const void *b)
{
	const struct vis_window_state *x = a, *y = b;
	return (x->window > y->window) - (x->window < y->window);
}

int cmd_states(struct live *l, int argc, char **argv)
{
	struct vis_window_state *states;
	size_t n;
	int ret;
	if (expect_args(l, argc, argv, 0, "", &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_states(l->client, &states, &n) < 0)
		return query_failed(l, argc, argv);
	/* The daemon sends them in order already; sorting again costs little and promises it. */
	if (n)
		qsort(states, n, sizeof(*states), by_window);
	for (size_t i = 0; i < n; i++)
		printf("%u %s\n", states[i].window, vis_visibility_name(states[i].state));
	free(states);
	if (!n && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}

int cmd_tree(struct live *l, int argc, char **argv)
{
	struct vis_window_info *w;
	size_t n;
	int ret;
	if (expect_args(l, argc, argv, 0, "", &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_tree(l->client, &w, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++) {
		uint32_t state = w[i].flags & VIS_WINDOW_VIEWABLE ? w[i].state : VIS_VISIBILITY_NONE;
		printf("%u %u %d %d %u %u %s %s\n", w[i].window, w[i].parent, w[i].x, w[i].y,
		       w[i].width, w[i].height,
		       w[i].flags & VIS_WINDOW_MAPPED ? "mapped" : "unmapped",
		       vis_visibility_name(state));
	}
	free(w);
	return VISCTL_EXIT_OK;
}

int cmd_region(struct live *l, int argc, char **argv)
{
	struct vis_rect32 *r;
	uint32_t id;
	size_t n;
	int ret;
	if (expect_args(l, argc, argv, 1, "ID", &ret) < 0 ||
	    window_arg(l, argv[0], argv[1], &id, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_region(l->client, id, &r, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++)
		printf("%d %d %u %u\n", r[i].x, r[i].y, r[i].width, r[i].height);
	free(r);
	return VISCTL_EXIT_OK;
}

int cmd_repaint(struct live *l, int argc, char **argv)
{
	struct vis_rect32 damage;
	uint32_t *w;
	size_t n;
	int ret;
	if (expect_args(l, argc, argv, 4, "X Y W H", &ret) < 0 ||
	    coord_arg(l, argv[0], "X", argv[1], &damage.x, &ret) < 0 ||
	    coord_arg(l, argv[0], "Y", argv[2], &damage.y, &ret) < 0 ||
	    size_arg(l, argv[0], "W", argv[3], &damage.width, &ret) < 0 ||
	    size_arg(l, argv[0], "H", argv[4], &damage.height, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_get_repaint(l->client, damage, &w, &n) < 0)
		return query_failed(l, argc, argv);
	for (size_t i = 0; i < n; i++)
		printf("%u\n", w[i]);
	free(w);
	if (!n && live_sees_nothing(l))
		live_warn_sees_nothing(l, argv[0]);
	return VISCTL_EXIT_OK;
}
