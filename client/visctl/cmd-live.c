/*
 * The live subcommands that send one change (create, destroy, map, …), each ending with a round
 * trip so that the daemon's verdict is known before visctl exits; and sync.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

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
			return live_help(argv[0]);
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
		} else if (live_is_option(a)) {
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
	if (live_coord_arg(l, argv[0], "X", pos[0], &x, &ret) < 0 ||
	    live_coord_arg(l, argv[0], "Y", pos[1], &y, &ret) < 0 ||
	    live_size_arg(l, argv[0], "W", pos[2], &w, &ret) < 0 ||
	    live_size_arg(l, argv[0], "H", pos[3], &h, &ret) < 0)
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
	if (live_expect_args(l, &argc, argv, 1, "ID", NULL, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0)
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
	if (live_expect_args(l, &argc, argv, 3, "ID X Y", NULL, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    live_coord_arg(l, argv[0], "X", argv[2], &x, &ret) < 0 ||
	    live_coord_arg(l, argv[0], "Y", argv[3], &y, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, vis_client_move(l->client, id, x, y), argc, argv);
}

int cmd_resize(struct live *l, int argc, char **argv)
{
	uint32_t id, w, h;
	int ret;
	if (live_expect_args(l, &argc, argv, 3, "ID W H", NULL, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    live_size_arg(l, argv[0], "W", argv[2], &w, &ret) < 0 ||
	    live_size_arg(l, argv[0], "H", argv[3], &h, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	return finish(l, vis_client_resize(l->client, id, w, h), argc, argv);
}

int cmd_stack(struct live *l, int argc, char **argv)
{
	uint32_t id, sibling, mode;
	int ret;
	if (live_expect_args(l, &argc, argv, 3, "ID above|below SIBLING", NULL, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[3], &sibling, &ret) < 0)
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
	if (live_expect_args(l, &argc, argv, 0, "", NULL, &ret) < 0)
		return ret;
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	if (vis_client_roundtrip(l->client) < 0)
		return query_failed(l, argc, argv);
	return VISCTL_EXIT_OK;
}
