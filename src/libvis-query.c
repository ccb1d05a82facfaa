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

/*
 * The repaint set of q, inside the box the walk after the last change went over: what that walk
 * listed, each window's part clipped to q (exactly what a walk over q would list), bottom to
 * top, into tree->shown. 0, or -1 with ENOMEM.
 */
static int from_kept(struct vis_tree *tree, struct vis_box q)
{
	struct libvis_set *kept = &tree->kept, *set = &tree->shown;
	set->n = set->n_rects = 0;
	if (libvis_reserve(&set->wins, &set->cap, kept->n, sizeof *set->wins) < 0 ||
	    libvis_reserve(&set->rects, &set->cap_rects, kept->n_rects, sizeof *set->rects) < 0)
		return -1;
	size_t end = kept->n_rects;
	if (vis_box_equal(q, tree->kept_box)) {
		/* The whole box: the parts as listed, which stay until the next change. */
		for (size_t i = kept->n; i-- > 0;) {
			end -= kept->wins[i].n_rects;
			set->wins[set->n] = kept->wins[i];
			set->wins[set->n++].rects = kept->rects + end;
		}
		return 0;
	}
	for (size_t i = kept->n; i-- > 0;) {
		const struct vis_repaint *e = &kept->wins[i];
		end -= e->n_rects;
		/* q in the window's coordinates, where its rectangles are. */
		int64_t x1 = q.x1 - e->x, y1 = q.y1 - e->y, x2 = q.x2 - e->x, y2 = q.y2 - e->y;
		size_t at = set->n_rects;
		for (uint32_t k = 0; k < e->n_rects; k++) {
			const struct vis_rect32 *r = &kept->rects[end + k];
			int64_t a = r->x > x1 ? r->x : x1, b = r->y > y1 ? r->y : y1;
			int64_t c = (int64_t)r->x + r->width, d = (int64_t)r->y + r->height;
			c = c < x2 ? c : x2;
			d = d < y2 ? d : y2;
			if (a < c && b < d)
				set->rects[set->n_rects++] = (struct vis_rect32){
					(int32_t)a, (int32_t)b, (uint32_t)(c - a), (uint32_t)(d - b) };
		}
		if (set->n_rects > at) {
			set->wins[set->n] = *e;
			set->wins[set->n].n_rects = (uint32_t)(set->n_rects - at);
			set->wins[set->n++].rects = set->rects + at;
		}
	}
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
	struct vis_box q = vis_box_intersect(
		(struct vis_box){ damage->x, damage->y, (int64_t)damage->x + damage->width,
				  (int64_t)damage->y + damage->height },
		tree->core.root.clip);
	struct libvis_set *set = &tree->shown;
	if (tree->kept_ok && !vis_box_empty(q) && vis_box_contains(tree->kept_box, q)) {
		if (from_kept(tree, q) < 0)
			return -1;
	} else {
		if (libvis_walk(tree, q, 0, set, NULL) < 0)
			return -1;
		/* Top first; bottom to top is the other way round. */
		for (size_t i = 0; i < set->n / 2; i++) {
			struct vis_repaint t = set->wins[i];
			set->wins[i] = set->wins[set->n - 1 - i];
			set->wins[set->n - 1 - i] = t;
		}
		size_t at = set->n_rects;
		for (size_t i = 0; i < set->n; i++) {
			at -= set->wins[i].n_rects;
			set->wins[i].rects = set->rects + at;
		}
	}
	for (size_t i = 0; i < set->n; i++)
		set->wins[i].data = set->wins[i].win->data;
	*out = set->wins;
	*n = set->n;
	return 0;
}
