/*
 * libvis: the tree and its windows, and every change to them, each argument checked as the daemon
 * checks a client's (daemon/server-request.c) before anything changes. Updates and exposures are
 * in libvis-update.c, the queries in libvis-query.c.
 */
#include <errno.h>
#include <stdlib.h>

#include "libvis-private.h"

/* Fails with errno e: the error return of the int functions. */
static int fail(int e)
{
	errno = e;
	return -1;
}

/*
 * The screen box a window of parent (the root for a top-level one) takes at x, y with that inside
 * and border, as vis_wtree_box() would give it after the change.
 */
static struct vis_box box_at(const struct vis_window *parent, int32_t x, int32_t y, int32_t width,
			     int32_t height, int32_t border)
{
	struct vis_box p = parent->parent ? vis_wtree_box(parent) : (struct vis_box){ 0, 0, 0, 0 };
	int64_t x1 = p.x1 + (parent->parent ? parent->look.border : 0) + x;
	int64_t y1 = p.y1 + (parent->parent ? parent->look.border : 0) + y;
	return (struct vis_box){ x1, y1, x1 + width + 2 * (int64_t)border,
				 y1 + height + 2 * (int64_t)border };
}

/* The tallies' walk before a change that keeps the window where it is: a restack, or a look. */
static void in_place_begin(struct vis_win *win, bool restacks)
{
	libvis_tally_begin(win->tree, win, (struct vis_box){ 0, 0, 0, 0 }, false, restacks);
}

VIS_EXPORT struct vis_tree *vis_tree_create(int32_t width, int32_t height)
{
	if (width < 1 || height < 1) {
		errno = EINVAL;
		return NULL;
	}
	struct vis_tree *tree = calloc(1, sizeof *tree);
	pixman_box32_t *damage = malloc(LIBVIS_DAMAGE_BOXES * sizeof *damage);
	if (!tree || !damage) {
		free(tree);
		free(damage);
		errno = ENOMEM;
		return NULL;
	}
	vis_wtree_init(&tree->core, width, height);
	tree->damage = damage;
	pixman_region32_init(&tree->now);
	pixman_region32_init(&tree->exposed);
	pixman_region32_init(&tree->part);
	vis_bands_init(&tree->walk.left);
	vis_bands_init(&tree->walk.scratch);
	vis_bands_init(&tree->walk.listed);
	vis_bands_init(&tree->above);
	tree->tally_max = LIBVIS_TALLY_WINDOWS;
	tree->walk.grid_after = LIBVIS_GRID_AFTER;
	return tree;
}

void libvis_forget(struct vis_window *w)
{
	struct vis_win *win = w->data;
	if (!win)
		return;
	libvis_untrack(win);
	libvis_tally_forget(win->tree, win);
	pixman_region32_fini(&win->region);
	free(win);
	w->data = NULL;
}

/* The core's callback for each window destroyed: its handle goes with it. */
static void window_gone(void *data, struct vis_window *w)
{
	(void)data;
	libvis_forget(w);
}

VIS_EXPORT void vis_tree_destroy(struct vis_tree *tree)
{
	if (!tree)
		return;
	while (tree->core.root.top)
		vis_wtree_destroy(&tree->core, tree->core.root.top, window_gone, NULL);
	vis_wtree_finish(&tree->core);
	vis_pieces_finish(&tree->pieces);
	pixman_region32_fini(&tree->now);
	pixman_region32_fini(&tree->exposed);
	pixman_region32_fini(&tree->part);
	vis_bands_finish(&tree->walk.left);
	vis_bands_finish(&tree->walk.scratch);
	vis_bands_finish(&tree->walk.listed);
	vis_bands_finish(&tree->above);
	for (size_t i = 0; i < tree->walk.cap_saves; i++)
		vis_bands_finish(&tree->walk.saves[i]);
	free(tree->walk.saves);
	free(tree->walk.entered);
	free(tree->touched);
	free(tree->opaque_was);
	free(tree->opaque_is);
	free(tree->damage);
	free(tree->tracked);
	free(tree->list);
	free(tree->changes);
	free(tree->rects);
	free(tree->qrects);
	free(tree->shown.wins);
	free(tree->shown.rects);
	free(tree->kept.wins);
	free(tree->kept.rects);
	free(tree->boxes);
	free(tree->parts);
	free(tree);
}

VIS_EXPORT int vis_tree_screen(const struct vis_tree *tree, int32_t *width, int32_t *height)
{
	if (!tree || !width || !height)
		return fail(EINVAL);
	*width = tree->core.root.width;
	*height = tree->core.root.height;
	return 0;
}

/*
 * Checks a window's inside and border: sides 1 … INT32_MAX (EINVAL), border ≥ 0 (EINVAL), the
 * border box's sides at most INT32_MAX (EOVERFLOW). 0 or -1 with errno.
 */
static int check_size(int32_t width, int32_t height, int32_t border)
{
	if (width < 1 || height < 1 || border < 0)
		return fail(EINVAL);
	if ((int64_t)width + 2 * (int64_t)border > INT32_MAX ||
	    (int64_t)height + 2 * (int64_t)border > INT32_MAX)
		return fail(EOVERFLOW);
	return 0;
}

struct vis_win *libvis_wrap(struct vis_tree *tree, struct vis_window *w)
{
	struct vis_win *win = calloc(1, sizeof *win);
	if (!win) {
		errno = ENOMEM;
		return NULL;
	}
	win->core = w;
	win->tree = tree;
	pixman_region32_init(&win->region);
	w->data = win;
	return win;
}

void libvis_forget_shown(struct vis_win *win)
{
	pixman_region32_clear(&win->region);
	win->known = false;
}

/* The core window under which a window of tree goes: parent's, or the screen for NULL. */
static struct vis_window *parent_of(struct vis_tree *tree, struct vis_win *parent)
{
	return parent ? parent->core : &tree->core.root;
}

VIS_EXPORT struct vis_win *vis_win_create(struct vis_tree *tree, struct vis_win *parent, int32_t x,
					  int32_t y, int32_t width, int32_t height, int32_t border,
					  uint32_t flags)
{
	if (!tree || (parent && parent->tree != tree) || (flags & ~(uint32_t)VIS_WIN_INPUT_ONLY) ||
	    ((flags & VIS_WIN_INPUT_ONLY) && border != 0)) {
		errno = EINVAL;
		return NULL;
	}
	if (check_size(width, height, border) < 0)
		return NULL;
	/* IDs run out (EOVERFLOW) only after 2^32 − 1 windows: the core's errno stands. */
	struct vis_window *w = vis_wtree_create(&tree->core, parent_of(tree, parent), x, y, width,
						height, 0);
	if (!w)
		return NULL;
	struct vis_win *win = libvis_wrap(tree, w);
	if (!win) {
		vis_wtree_destroy(&tree->core, w, NULL, NULL);
		errno = ENOMEM;
		return NULL;
	}
	vis_wtree_set_border(w, border); /* checked above: cannot fail */
	if (flags & VIS_WIN_INPUT_ONLY)
		vis_wtree_set_input_only(w);
	libvis_damage(tree, win);
	libvis_tally_end(tree, win); /* unmapped: only its own pixels to count */
	return win;
}

VIS_EXPORT void vis_win_destroy(struct vis_win *win)
{
	if (!win)
		return;
	struct vis_tree *tree = win->tree;
	libvis_damage(tree, win);
	in_place_begin(win, true);
	vis_wtree_destroy(&tree->core, win->core, window_gone, NULL);
	libvis_tally_end(tree, NULL);
}

/* map and unmap: a change only when the window's flag changes. */
static int set_mapped(struct vis_win *win, bool mapped)
{
	if (!win)
		return fail(EINVAL);
	if (win->core->mapped != mapped) {
		struct vis_window *p = win->core->parent;
		bool shows = mapped && (!p->parent || vis_wtree_viewable(p));
		libvis_tally_begin(win->tree, win, vis_wtree_box(win->core), shows, true);
		win->core->mapped = mapped;
		libvis_damage(win->tree, win);
		libvis_tally_end(win->tree, win);
	}
	return 0;
}

VIS_EXPORT int vis_win_map(struct vis_win *win)
{
	return set_mapped(win, true);
}

VIS_EXPORT int vis_win_unmap(struct vis_win *win)
{
	return set_mapped(win, false);
}

VIS_EXPORT int vis_win_configure(struct vis_win *win, int32_t x, int32_t y, int32_t width,
				 int32_t height, int32_t border)
{
	if (!win)
		return fail(EINVAL);
	struct vis_window *w = win->core;
	if (border != 0 && w->look.input_only)
		return fail(EINVAL);
	if (check_size(width, height, border) < 0)
		return -1;
	bool reshaped = w->width != width || w->height != height || w->look.border != border;
	/* A look cut inside the border box is cut again at another size, before anything changes:
	 * its pieces may not fit the 32-bit plane (EOVERFLOW), or memory run out. */
	struct vis_look_cut cut = { 0 };
	if (w->cut && reshaped) {
		struct vis_look next = w->look;
		next.border = border;
		if (vis_look_cut_fill(&cut, &next, width, height) < 0)
			return -1;
	}
	libvis_damage(win->tree, win); /* where it was */
	libvis_tally_begin_move(win->tree, win, box_at(w->parent, x, y, width, height, border));
	w->x = x;
	w->y = y;
	vis_wtree_set_size(w, width, height, border); /* checked above: cannot fail */
	if (w->cut && reshaped)
		vis_wtree_keep_cut(w, &cut);
	if (reshaped)
		libvis_forget_shown(win); /* its contents are gone: all of it is exposed */
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

VIS_EXPORT int vis_win_move(struct vis_win *win, int32_t x, int32_t y)
{
	if (!win)
		return fail(EINVAL);
	const struct vis_window *w = win->core;
	return vis_win_configure(win, x, y, w->width, w->height, w->look.border);
}

VIS_EXPORT int vis_win_raise(struct vis_win *win)
{
	if (!win)
		return fail(EINVAL);
	in_place_begin(win, true);
	vis_wtree_raise(win->core);
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

VIS_EXPORT int vis_win_lower(struct vis_win *win)
{
	if (!win)
		return fail(EINVAL);
	in_place_begin(win, true);
	vis_wtree_lower(win->core);
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

VIS_EXPORT int vis_win_restack(struct vis_win *win, struct vis_win *sibling, int above)
{
	if (!win || !sibling || sibling == win || sibling->tree != win->tree ||
	    sibling->core->parent != win->core->parent)
		return fail(EINVAL);
	in_place_begin(win, true);
	vis_wtree_restack(win->core, sibling->core, above != 0);
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

VIS_EXPORT int vis_win_reparent(struct vis_win *win, struct vis_win *parent, int32_t x, int32_t y)
{
	if (!win || (parent && parent->tree != win->tree))
		return fail(EINVAL);
	struct vis_window *p = parent_of(win->tree, parent);
	if (vis_wtree_is_ancestor(win->core, p))
		return fail(EINVAL);
	libvis_damage(win->tree, win); /* where it was */
	struct vis_window *w = win->core;
	libvis_tally_begin(win->tree, win, box_at(p, x, y, w->width, w->height, w->look.border),
			   w->mapped && (!p->parent || vis_wtree_viewable(p)), true);
	vis_wtree_reparent(w, p, x, y);
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

/*
 * Copies a look's rectangles into the core's kind, each side 1 … INT32_MAX: into a new array
 * (NULL for n = 0). 0, or -1 with EINVAL, E2BIG or ENOMEM.
 */
static int copy_rects(const struct vis_rect32 *rects, uint32_t n, struct vis_rect **out)
{
	*out = NULL;
	if (n == 0)
		return 0;
	if (!rects)
		return fail(EINVAL);
	if (n > VIS_LOOK_MAX_RECTS)
		return fail(E2BIG);
	for (uint32_t i = 0; i < n; i++)
		if (rects[i].width < 1 || rects[i].height < 1 || rects[i].width > INT32_MAX ||
		    rects[i].height > INT32_MAX)
			return fail(EINVAL);
	struct vis_rect *r = malloc((size_t)n * sizeof *r);
	if (!r)
		return fail(ENOMEM);
	for (uint32_t i = 0; i < n; i++)
		r[i] = (struct vis_rect){ rects[i].x, rects[i].y, (int32_t)rects[i].width,
					  (int32_t)rects[i].height };
	*out = r;
	return 0;
}

/*
 * set-shape (shape true) and set-opaque: checks, cuts the look for the window's size first
 * (EOVERFLOW, ENOMEM), then sets it. 0 or -1 with errno, nothing changed then.
 */
static int set_look(struct vis_win *win, bool shape, uint32_t mode, const struct vis_rect32 *rects,
		    uint32_t n)
{
	if (!win || win->core->look.input_only)
		return fail(EINVAL);
	bool wants_rects = shape ? mode == 1 : mode == VIS_OPAQUE_MODE_RECTS;
	if ((shape && mode > 1) || (!shape && mode > VIS_OPAQUE_MODE_RECTS) ||
	    (!wants_rects && n != 0))
		return fail(EINVAL);
	struct vis_rect *r;
	if (copy_rects(rects, n, &r) < 0)
		return -1;
	struct vis_window *w = win->core;
	struct vis_look next = w->look;
	if (shape) {
		next.shaped = mode == 1;
		next.shape = r;
		next.n_shape = n;
	} else {
		next.opaque = (uint8_t)mode;
		next.opaque_rects = r;
		next.n_opaque = n;
	}
	struct vis_look_cut cut = { 0 };
	if (vis_look_cuts_inside(&next) && vis_look_cut_fill(&cut, &next, w->width, w->height) < 0) {
		free(r);
		return -1;
	}
	in_place_begin(win, false);
	int rc = shape ? vis_wtree_set_shape(w, mode == 1, r, n)
		       : vis_wtree_set_opaque(w, (enum vis_opaque)mode, r, n);
	free(r);
	if (rc < 0) {
		vis_look_cut_finish(&cut);
		libvis_tally_end(win->tree, win); /* nothing changed: the walk puts back what it took */
		return fail(ENOMEM);
	}
	vis_wtree_keep_cut(w, &cut);
	/* The pixels changed inside the border box: it is the damage, as it was and is. */
	libvis_damage(win->tree, win);
	libvis_tally_end(win->tree, win);
	return 0;
}

VIS_EXPORT int vis_win_set_shape(struct vis_win *win, int shaped, const struct vis_rect32 *rects,
				 uint32_t n)
{
	return set_look(win, true, shaped ? 1 : 0, rects, n);
}

VIS_EXPORT int vis_win_set_opaque(struct vis_win *win, uint32_t mode, const struct vis_rect32 *rects,
				  uint32_t n)
{
	return set_look(win, false, mode, rects, n);
}

VIS_EXPORT int vis_win_set_data(struct vis_win *win, void *data)
{
	if (!win)
		return fail(EINVAL);
	win->data = data;
	return 0;
}

VIS_EXPORT void *vis_win_get_data(const struct vis_win *win)
{
	return win ? win->data : NULL;
}

VIS_EXPORT int vis_win_set_external(struct vis_win *win, uint32_t ext_namespace, uint64_t external)
{
	if (!win)
		return fail(EINVAL);
	/* The core checks the rest: EINVAL, EEXIST, ENOMEM. */
	return vis_wtree_set_external(&win->tree->core, win->core, ext_namespace, external);
}

VIS_EXPORT struct vis_win *vis_tree_find_external(const struct vis_tree *tree,
						  uint32_t ext_namespace, uint64_t external)
{
	if (!tree)
		return NULL;
	struct vis_window *w = vis_wtree_find_external(&tree->core, ext_namespace, external);
	return w ? w->data : NULL;
}

VIS_EXPORT int vis_win_state(const struct vis_win *win)
{
	if (!win)
		return fail(EINVAL);
	return win->core->state;
}
