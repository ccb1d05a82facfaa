/*
 * `visctl snapshot --svg FILE`: a picture of the daemon's windows as this connection sees them
 * (all of them with --role observer or manager, else its own). One get-tree, then a get-region
 * for every window that shows something, all sent before waiting, then the picture
 * (stack-svg.c). The two are not one atomic view: a window gone in between is drawn unfilled.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "idmap.h"
#include "look.h"
#include "live.h"
#include "stack-svg.h"
#include "visctl.h"

/* Requests queued between two waits for the socket, as `visctl load` does. */
#define SNAPSHOT_DRAIN_EVERY 4096

/*
 * Past this many windows no regions are asked for: the daemon computes each in O(n), so asking
 * for all would take quadratic time; the picture then shows outlines only.
 */
#define SNAPSHOT_MAX_REGIONS STACK_SVG_MAX_LABELS

struct snapshot {
	struct stack_svg pic;
	size_t *asked;   /* the picture index of each get-region sent, in sending order */
	size_t n_asked, answered;
	int failed_errno; /* ENOMEM while adding parts */
	struct vis_error error;
	bool failed;     /* a get-region failed for another reason than a vanished window */
};

/* Called with each region reply, in request order: the window's visible parts, made absolute. */
static void on_region(void *data, const struct vis_error *err, const struct vis_rect32 *rects,
		      size_t n)
{
	struct snapshot *s = data;
	size_t i = s->asked[s->answered++];
	struct vis_box box = s->pic.windows[i].inside; /* window coordinates start at its corner */

	if (err) {
		/* A window destroyed since get-tree is no failure: it just shows no parts. */
		if (err->code != VIS_ERROR_WINDOW && !s->failed) {
			s->failed = true;
			s->error = *err;
		}
		return;
	}
	struct vis_box *out = stack_svg_parts(&s->pic, i, n);
	if (out == NULL) {
		s->failed_errno = errno;
		return;
	}
	for (size_t j = 0; j < n; j++)
		out[j] = (struct vis_box){ box.x1 + rects[j].x, box.y1 + rects[j].y,
					   box.x1 + rects[j].x + rects[j].width,
					   box.y1 + rects[j].y + rects[j].height };
}

/*
 * Adds the tree's viewable windows to the picture at their absolute positions (pre-order puts
 * parents first). Windows not drawn are counted in the note. Returns 0, or -1 (ENOMEM).
 */
/*
 * Draws a shaped or translucent window from its look (get-look): its pixels, opaque or see-through,
 * within its border box. Returns 0, or -1 (the connection failed, or memory ran out).
 */
static int add_look(struct vis_client *c, struct stack_svg *pic, uint32_t window, struct vis_box box,
		    int32_t border)
{
	struct vis_look_info info;
	if (vis_client_get_look(c, window, &info) < 0)
		return vis_client_error(c) ? -1 : 0; /* gone meanwhile: drawn as a box */
	struct vis_look look = { .border = border, .shaped = info.shaped != 0,
				 .opaque = (uint8_t)info.mode, .n_shape = info.n_shape,
				 .n_opaque = info.n_opaque };
	struct vis_pieces pieces = { 0 };
	int ret = -1;
	look.shape = malloc((info.n_shape + 1) * sizeof(*look.shape));
	look.opaque_rects = malloc((info.n_opaque + 1) * sizeof(*look.opaque_rects));
	if (!look.shape || !look.opaque_rects)
		goto out;
	for (uint32_t i = 0; i < info.n_shape; i++)
		look.shape[i] = (struct vis_rect){ info.shape[i].x, info.shape[i].y,
						   (int32_t)info.shape[i].width,
						   (int32_t)info.shape[i].height };
	for (uint32_t i = 0; i < info.n_opaque; i++)
		look.opaque_rects[i] = (struct vis_rect){ info.opaque[i].x, info.opaque[i].y,
							  (int32_t)info.opaque[i].width,
							  (int32_t)info.opaque[i].height };
	if (vis_pieces_add(&pieces, &look, box, box, 0) < 0)
		goto out;
	ret = 0;
	for (size_t k = 0; k < pieces.stack.n && ret == 0; k++)
		ret = stack_svg_add_pixels(pic, vis_rect_box(pieces.rects[k]),
					   pieces.see_through[k] != 0);
	/* Known pixels: the faint fill of an unknown translucency is not needed. */
	pic->windows[pic->n - 1].translucent = false;
out:
	vis_pieces_finish(&pieces);
	free(look.shape);
	free(look.opaque_rects);
	free(info.shape);
	free(info.opaque);
	return ret;
}

static int add_windows(struct vis_client *c, struct stack_svg *pic, const struct vis_window_info *w,
		       size_t n)
{
	struct vis_box *abs = malloc((n ? n : 1) * sizeof(*abs));
	struct vis_box *inner = malloc((n ? n : 1) * sizeof(*inner));
	struct vis_idmap placed;
	size_t hidden = 0, orphans = 0, input_only = 0;
	int ret = -1;

	vis_idmap_init(&placed);
	if (abs == NULL || inner == NULL)
		goto out;
	for (size_t i = 0; i < n; i++) {
		const struct vis_box *parent = w[i].parent ? vis_idmap_get(&placed, w[i].parent) : NULL;
		if ((w[i].parent && parent == NULL) || (w[i].flags & VIS_WINDOW_PARENT_HIDDEN)) {
			/* Its parent is not ours to see: where it is cannot be known. */
			orphans++;
			continue;
		}
		/* x, y place the border box in the parent's inside, whose corner placed holds. */
		int64_t x = (parent ? parent->x1 : 0) + w[i].x, y = (parent ? parent->y1 : 0) + w[i].y;
		int64_t b = w[i].border;
		abs[i] = (struct vis_box){ x, y, x + w[i].width + 2 * b, y + w[i].height + 2 * b };
		inner[i] = (struct vis_box){ x + b, y + b, x + b + w[i].width, y + b + w[i].height };
		if (vis_idmap_put(&placed, w[i].window, &inner[i]) < 0)
			goto out;
		if (w[i].flags & VIS_WINDOW_INPUT_ONLY)
			input_only++;
		else if (!(w[i].flags & VIS_WINDOW_VIEWABLE) ||
			 w[i].state > VIS_VISIBILITY_FULLY_OBSCURED)
			hidden++;
		else if (stack_svg_add(pic, w[i].window, w[i].parent, abs[i], (uint8_t)w[i].state) < 0)
			goto out;
		else {
			pic->windows[pic->n - 1].inside = inner[i];
			pic->windows[pic->n - 1].translucent = w[i].flags & VIS_WINDOW_TRANSLUCENT;
			if ((w[i].flags & (VIS_WINDOW_SHAPED | VIS_WINDOW_TRANSLUCENT)) &&
			    pic->n <= STACK_SVG_MAX_LABELS &&
			    add_look(c, pic, w[i].window, abs[i], (int32_t)w[i].border) < 0)
				goto out;
		}
	}
	if (hidden)
		stack_svg_note(pic, "Not drawn: %zu window%s not viewable.", hidden,
			       hidden == 1 ? "" : "s");
	if (input_only)
		stack_svg_note(pic, "Not drawn: %zu input-only window%s (no pixels).", input_only,
			       input_only == 1 ? "" : "s");
	if (orphans)
		stack_svg_note(pic, "Not drawn: %zu window%s under windows this connection cannot see.",
			       orphans, orphans == 1 ? "" : "s");
	ret = 0;
out:
	vis_idmap_finish(&placed);
	free(abs);
	free(inner);
	return ret;
}

/* Asks for the visible region of every window that shows something, then waits. 0, or -1. */
static int fetch_regions(struct vis_client *c, struct snapshot *s)
{
	struct stack_svg *pic = &s->pic;

	if (pic->n > SNAPSHOT_MAX_REGIONS) {
		pic->has_parts = false;
		stack_svg_note(pic, "Visible parts not drawn: more than %d windows.",
			       SNAPSHOT_MAX_REGIONS);
		return 0;
	}
	s->asked = malloc((pic->n ? pic->n : 1) * sizeof(*s->asked));
	if (s->asked == NULL)
		return -1;
	for (size_t i = 0; i < pic->n; i++) {
		if (pic->windows[i].state == VIS_FULLY_OBSCURED)
			continue;
		s->asked[s->n_asked++] = i;
		if (!vis_client_get_region_async(c, pic->windows[i].id, on_region, s))
			return -1;
		if (s->n_asked % SNAPSHOT_DRAIN_EVERY == 0 && live_drain(c) < 0)
			return -1;
	}
	if (vis_client_roundtrip(c) < 0 || s->failed || s->failed_errno)
		return -1;
	return 0;
}

/* Says how to use snapshot, on stdout for --help. */
static int snapshot_help(void)
{
	printf("usage: visctl snapshot --svg FILE\n"
	       "  Draws the daemon's windows into FILE: every viewable window at its place on the\n"
	       "  screen, in the colour of its state, its visible parts filled, its ID. A client\n"
	       "  sees its own windows; use --role observer (or manager) to draw them all.\n");
	return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
}

/* Writes the picture to path; the exit status, having said what went wrong. */
static int write_picture(struct live *l, const struct stack_svg *pic, const char *path)
{
	FILE *f = fopen(path, "w");
	if (f == NULL)
		return live_error(l, "snapshot: %s: cannot write: %s", path, strerror(errno));
	int r = stack_svg_write(pic, f);
	/* A failed write of buffered data (a full disk) shows up only at fclose. */
	if (fclose(f) != 0 || r < 0)
		return live_error(l, "snapshot: %s: write error: %s", path, strerror(errno));
	return VISCTL_EXIT_OK;
}

int cmd_snapshot(struct live *l, int argc, char **argv)
{
	static const char *const titles[] = { "visctl snapshot: this connection's windows",
					      "visctl --role observer snapshot: every window",
					      "visctl --role manager snapshot: every window" };
	const char *path = NULL;

	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)
			return snapshot_help();
		if (strncmp(a, "--svg=", 6) == 0)
			path = a + 6;
		else if (strcmp(a, "--svg") == 0 && i + 1 < argc)
			path = argv[++i];
		else if (strcmp(a, "--svg") == 0)
			return live_usage(l, argv[0], "--svg needs a FILE");
		else if (a[0] == '-')
			return live_usage(l, argv[0], "unknown option '%s'", a);
		else
			return live_usage(l, argv[0], "unexpected argument '%s'", a);
	}
	if (path == NULL || path[0] == '\0')
		return live_usage(l, argv[0], "missing --svg FILE");

	struct vis_client *c = live_connect(l);
	if (c == NULL)
		return VISCTL_EXIT_FAILURE;
	struct vis_window_info *tree;
	size_t n;
	if (vis_client_get_tree(c, &tree, &n) < 0)
		return live_failed(l, "snapshot: get-tree");

	uint32_t role = vis_client_role(c), sw, sh;
	struct snapshot s = { .failed = false };
	int ret = VISCTL_EXIT_OK;
	vis_client_screen(c, &sw, &sh);
	stack_svg_init(&s.pic, titles[role < 3 ? role : 0]);
	s.pic.has_screen = true;
	s.pic.screen_w = sw;
	s.pic.screen_h = sh;
	if (add_windows(c, &s.pic, tree, n) < 0) {
		ret = live_error(l, "snapshot: %s", strerror(ENOMEM));
	} else if (fetch_regions(c, &s) < 0) {
		if (s.failed)
			ret = live_error(l, "snapshot: get-region: %s: %s",
					 vis_error_code_name(s.error.code), s.error.message);
		else if (!vis_client_error(c))
			ret = live_error(l, "snapshot: %s", strerror(s.failed_errno ? s.failed_errno
									      : ENOMEM));
		else
			ret = live_failed(l, "snapshot: get-region");
	} else {
		ret = write_picture(l, &s.pic, path);
	}
	stack_svg_finish(&s.pic);
	free(s.asked);
	free(tree);
	return ret;
}
