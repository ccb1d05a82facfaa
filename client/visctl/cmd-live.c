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
	uint32_t parent = VIS_WINDOW_ROOT, flags = 0, w, h, border = 0;
	uint32_t ext_ns = VIS_EXTERNAL_NONE;
	uint64_t external = 0;
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
		} else if (strcmp(a, "--input-only") == 0) {
			flags |= VIS_CREATE_INPUT_ONLY;
		} else if (strncmp(a, "--border=", 9) == 0 || strcmp(a, "--border") == 0) {
			const char *b = a[8] == '=' ? a + 9 : NULL;
			if (!b && i + 1 == argc)
				return live_usage(l, argv[0], "--border needs a width");
			if (!b)
				b = argv[++i];
			if (live_parse_u32(b, &border) < 0 || border > INT32_MAX)
				return live_usage(l, argv[0],
						  "border '%s' is not a number from 0 to 2147483647", b);
		} else if (strncmp(a, "--x11=", 6) == 0 || strcmp(a, "--x11") == 0 ||
			   strncmp(a, "--external=", 11) == 0 || strcmp(a, "--external") == 0) {
			/* What the window mirrors: an X window, or any namespace's tag. */
			bool x11 = a[2] == 'x';
			const char *eq = strchr(a, '='), *v = eq ? eq + 1 : NULL;
			if (!v && i + 1 == argc)
				return live_usage(l, argv[0], "%s needs %s", a, x11 ? "an XID" : "NS:TAG");
			if (!v)
				v = argv[++i];
			if (ext_ns != VIS_EXTERNAL_NONE)
				return live_usage(l, argv[0], "one external ID at most (--x11 or --external)");
			if (x11 ? live_xid_arg(l, argv[0], v, &external, &ret) < 0
				: live_external_arg(l, argv[0], v, &ext_ns, &external, &ret) < 0)
				return ret;
			if (x11)
				ext_ns = VIS_EXTERNAL_X11;
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
	if (vis_client_create_external(l->client, parent, x, y, w, h, border, flags, ext_ns,
				       external, &window) < 0)
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

/*
 * Reads "X,Y,W,H" (window coordinates: X, Y signed 32-bit, W, H 1 … 2^31 − 1). Returns 0, or -1
 * with *ret the usage status after saying why.
 */
static int rect_arg(struct live *l, const char *name, int k, const char *s, struct vis_rect32 *r,
		    int *ret)
{
	char buf[64], *f[4], *save = NULL;
	int n = 0;
	if (strlen(s) >= sizeof(buf))
		goto bad;
	strcpy(buf, s);
	/* Exactly three commas: strtok would let ",," and a trailing comma pass. */
	for (const char *p = s; *p; p++)
		n += *p == ',';
	if (n != 3)
		goto bad;
	n = 0;
	for (char *t = strtok_r(buf, ",", &save); t && n < 4; t = strtok_r(NULL, ",", &save))
		f[n++] = t;
	if (n != 4 || live_parse_i32(f[0], &r->x) < 0 || live_parse_i32(f[1], &r->y) < 0 ||
	    live_parse_u32(f[2], &r->width) < 0 || live_parse_u32(f[3], &r->height) < 0 ||
	    r->width < 1 || r->height < 1 || r->width > INT32_MAX || r->height > INT32_MAX)
		goto bad;
	return 0;
bad:
	*ret = live_usage(l, name,
			  "rectangle %d '%s' is not X,Y,W,H (X, Y from -2147483648 to 2147483647, "
			  "W, H from 1 to 2147483647)",
			  k, s);
	return -1;
}

/*
 * Reads the rectangles argv[first …] into a new array (*n of them). Returns 0, or -1 with *ret
 * set.
 */
static int rects_args(struct live *l, int argc, char **argv, int first, struct vis_rect32 **out,
		      uint32_t *n, int *ret)
{
	*n = 0;
	*out = malloc((size_t)(argc > first ? argc - first : 1) * sizeof(**out));
	if (!*out) {
		*ret = live_error(l, "out of memory");
		return -1;
	}
	for (int i = first; i < argc; i++)
		if (rect_arg(l, argv[0], i - first + 1, argv[i], &(*out)[(*n)++], ret) < 0) {
			free(*out);
			return -1;
		}
	return 0;
}

/* Takes --help and the ID of the shape, opaque and border commands; the rest stays in argv. */
static int look_window(struct live *l, int argc, char **argv, const char *names, uint32_t *id,
		       int *ret)
{
	for (int i = 1; i < argc; i++)
		if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
			*ret = live_help(argv[0]);
			return -1;
		}
	if (argc < 2) {
		*ret = live_usage(l, argv[0], "expected %s", names);
		return -1;
	}
	return live_window_arg(l, argv[0], argv[1], id, ret);
}

int cmd_shape(struct live *l, int argc, char **argv)
{
	uint32_t id, n;
	struct vis_rect32 *rects;
	int ret;
	if (look_window(l, argc, argv, "ID [X,Y,W,H ...] or ID --box", &id, &ret) < 0)
		return ret;
	bool box = argc == 3 && strcmp(argv[2], "--box") == 0;
	for (int i = 2; i < argc && !box; i++)
		if (live_is_option(argv[i]))
			return live_usage(l, argv[0], "unknown option '%s'", argv[i]);
	if (box)
		n = 0, rects = NULL;
	else if (rects_args(l, argc, argv, 2, &rects, &n, &ret) < 0)
		return ret;
	if (!live_connect(l)) {
		free(rects);
		return VISCTL_EXIT_FAILURE;
	}
	uint32_t seq = vis_client_set_shape(l->client, id, box ? 0 : 1, rects, n);
	free(rects);
	return finish(l, seq, argc, argv);
}

int cmd_opaque(struct live *l, int argc, char **argv)
{
	uint32_t id, n = 0, mode;
	struct vis_rect32 *rects = NULL;
	int ret;
	if (look_window(l, argc, argv, "ID none|all|X,Y,W,H ...", &id, &ret) < 0)
		return ret;
	if (argc < 3)
		return live_usage(l, argv[0], "expected none, all or rectangles X,Y,W,H after the ID");
	for (int i = 2; i < argc; i++)
		if (live_is_option(argv[i]))
			return live_usage(l, argv[0], "unknown option '%s'", argv[i]);
	if (argc == 3 && strcmp(argv[2], "none") == 0) {
		mode = VIS_OPAQUE_MODE_NONE;
	} else if (argc == 3 && strcmp(argv[2], "all") == 0) {
		mode = VIS_OPAQUE_MODE_ALL;
	} else {
		mode = VIS_OPAQUE_MODE_RECTS;
		if (rects_args(l, argc, argv, 2, &rects, &n, &ret) < 0)
			return ret;
	}
	if (!live_connect(l)) {
		free(rects);
		return VISCTL_EXIT_FAILURE;
	}
	uint32_t seq = vis_client_set_opaque(l->client, id, mode, rects, n);
	free(rects);
	return finish(l, seq, argc, argv);
}

/* The tree's record of window id, or NULL (err says why); *all is the caller's to free. */
static const struct vis_window_info *find_info(struct live *l, uint32_t id,
					       struct vis_window_info **all)
{
	size_t n;
	*all = NULL;
	if (vis_client_get_tree(l->client, all, &n) < 0)
		return NULL;
	for (size_t i = 0; i < n; i++)
		if ((*all)[i].window == id)
			return &(*all)[i];
	return NULL;
}

int cmd_border(struct live *l, int argc, char **argv)
{
	uint32_t id, border;
	int ret;
	if (live_expect_args(l, &argc, argv, 2, "ID B", NULL, &ret) < 0 ||
	    live_window_arg(l, argv[0], argv[1], &id, &ret) < 0)
		return ret;
	if (live_parse_u32(argv[2], &border) < 0 || border > INT32_MAX)
		return live_usage(l, argv[0], "B '%s' is not a number from 0 to 2147483647", argv[2]);
	if (!live_connect(l))
		return VISCTL_EXIT_FAILURE;
	/* configure takes the whole geometry: keep the window's own. In a batch the tree is that
	 * before the batch, so a border after a move in the same batch would undo the move. */
	if (l->in_batch)
		return live_usage(l, argv[0], "border cannot be used inside a batch");
	struct vis_window_info *all;
	const struct vis_window_info *w = find_info(l, id, &all);
	if (!w) {
		free(all);
		if (vis_client_error(l->client))
			return query_failed(l, argc, argv);
		return live_error(l, "border %u: no such window %u", border, id);
	}
	uint32_t seq = vis_client_configure(l->client, id, w->x, w->y, w->width, w->height, border);
	free(all);
	return finish(l, seq, argc, argv);
}
