/* libvis's queries over the last update: a window's visible region, the repaint set of a box. */
#include <errno.h>
#include <stdlib.h>

#include "libvis-private.h"

VIS_EXPORT int vis_win_visible_region(struct vis_win *win, const struct vis_rect32 **rects,
				      size_t *n)
{
	if (!win || !rects || !n) {
		errno = EINVAL;
		return -1;
	}
	struct vis_tree *tree = win->tree;
	if (tree->dirty) {
		errno = EAGAIN;
		return -1;
	}
	tree->n_qrects = 0;
	if (vis_wtree_visible_region(&tree->core, win->core, &tree->now) < 0 ||
	    libvis_append_rects(&tree->now, 0, 0, &tree->qrects, &tree->n_qrects,
				&tree->cap_qrects) < 0) {
		errno = ENOMEM;
		return -1;
	}
	*rects = tree->qrects;
	*n = tree->n_qrects;
	return 0;
}

VIS_EXPORT int vis_tree_repaint(struct vis_tree *tree, const struct vis_rect32 *damage,
				const struct vis_repaint **out, size_t *n)
{
	if (!tree || !damage || !out || !n || damage->width < 1 || damage->height < 1 ||
	    damage->width > INT32_MAX || damage->height > INT32_MAX) {
		errno = EINVAL;
		return -1;
	}
	if (tree->dirty) {
		errno = EAGAIN;
		return -1;
	}
	tree->n_qrects = 0;
	if (libvis_walk(tree,
			(struct vis_box){ damage->x, damage->y, (int64_t)damage->x + damage->width,
					  (int64_t)damage->y + damage->height },
			0) < 0)
		return -1;
	size_t k = tree->walk.n_repaint;
	/* The rectangles are in place, each window's after the one's above it; bottom to top is
	 * the other way round. */
	size_t at = 0;
	for (size_t i = 0; i < k; i++) {
		tree->repaint[i].rects = tree->qrects + at;
		at += tree->repaint[i].n_rects;
	}
	for (size_t i = 0; i < k / 2; i++) {
		struct vis_repaint t = tree->repaint[i];
		tree->repaint[i] = tree->repaint[k - 1 - i];
		tree->repaint[k - 1 - i] = t;
	}
	*out = tree->repaint;
	*n = k;
	return 0;
}
