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

/* Whether a box meets the extents of a region. */
static bool meets(struct vis_box b, const pixman_box32_t *e)
{
	return b.x1 < e->x2 && e->x1 < b.x2 && b.y1 < e->y2 && e->y1 < b.y2;
}

/* The highest mapped child of w whose clip meets e (its subtree's pixels lie in it), or NULL. */
static struct vis_window *top_child(const struct vis_window *w, const pixman_box32_t *e)
{
	struct vis_window *c = w->top;
	while (c && !(c->mapped && meets(c->clip, e)))
		c = c->below;
	return c;
}

/*
 * The viewable window before w in stacking order (pre-order, parents before children) that may
 * have pixels in e, or NULL: the last window of the highest such sibling below w's subtree, else
 * its parent. Subtrees whose clip misses e are passed over. O(siblings + depth).
 */
static struct vis_window *before(const struct vis_window *w, const pixman_box32_t *e)
{
	for (struct vis_window *s = w->below; s; s = s->below) {
		if (!s->mapped || !meets(s->clip, e))
			continue;
		for (struct vis_window *c; (c = top_child(s, e));)
			s = c;
		return s;
	}
	return w->parent->parent ? w->parent : NULL;
}

/* Whether a window's pixels are its clip, all opaque: no look and no shaped ancestor. */
static bool plain(const struct vis_window *w)
{
	if (w->look.shaped || w->look.opaque != VIS_OPAQUE_ALL)
		return false;
	for (const struct vis_window *a = w->parent; a->parent; a = a->parent)
		if (a->look.shaped)
			return false;
	return true;
}

/*
 * The part of w to draw inside c (its clip inside the damage), into tree->part: its pixels
 * there that tree->left still holds; then takes its opaque pixels off tree->left. 0, or -1 with
 * ENOMEM or EOVERFLOW.
 */
static int draw(struct vis_tree *tree, const struct vis_window *w, struct vis_box c)
{
	pixman_box32_t b = { (int32_t)c.x1, (int32_t)c.y1, (int32_t)c.x2, (int32_t)c.y2 };
	if (plain(w)) {
		pixman_region32_t box;
		pixman_region32_init_rect(&box, b.x1, b.y1, (unsigned)(b.x2 - b.x1),
					  (unsigned)(b.y2 - b.y1));
		bool ok = pixman_region32_intersect(&tree->part, &tree->left, &box) &&
			  pixman_region32_subtract(&tree->left, &tree->left, &box);
		pixman_region32_fini(&box);
		return ok ? 0 : -1;
	}
	struct vis_pieces *p = &tree->pieces;
	vis_pieces_reset(p);
	if (vis_wtree_add_pieces(p, w, c, 0) < 0)
		return -1;
	/* Opaque pieces first, then see-through ones: all of them show, the first hide. */
	size_t n = p->stack.n, n_opaque = 0;
	while (n_opaque < n && !p->see_through[n_opaque])
		n_opaque++;
	pixman_region32_t own, opaque;
	pixman_region32_init(&own);
	pixman_region32_init(&opaque);
	bool ok = libvis_reserve(&tree->boxes, &tree->cap_boxes, n + 1,
				 sizeof *tree->boxes) == 0;
	for (size_t k = 0; ok && k < n; k++) {
		struct vis_box r = vis_rect_box(p->rects[k]);
		tree->boxes[k] = (pixman_box32_t){ (int32_t)r.x1, (int32_t)r.y1,
							  (int32_t)r.x2, (int32_t)r.y2 };
	}
	ok = ok && pixman_region32_init_rects(&opaque, tree->boxes, (int)n_opaque) &&
	     pixman_region32_init_rects(&own, tree->boxes, (int)n) &&
	     pixman_region32_intersect(&tree->part, &tree->left, &own) &&
	     pixman_region32_subtract(&tree->left, &tree->left, &opaque);
	pixman_region32_fini(&own);
	pixman_region32_fini(&opaque);
	if (!ok)
		errno = ENOMEM;
	return ok ? 0 : -1;
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
	struct vis_box box = vis_box_intersect(
		(struct vis_box){ damage->x, damage->y, (int64_t)damage->x + damage->width,
				  (int64_t)damage->y + damage->height },
		tree->core.root.clip);
	size_t k = 0;
	tree->n_qrects = 0;
	pixman_region32_clear(&tree->left);
	if (!vis_box_empty(box))
		pixman_region32_union_rect(&tree->left, &tree->left, (int32_t)box.x1,
					   (int32_t)box.y1, (unsigned)(box.x2 - box.x1),
					   (unsigned)(box.y2 - box.y1));
	/* The region method inside the damage, from the top down: what is left of it shows each
	 * window, whose opaque pixels then take their part off it. */
	const pixman_box32_t *e = pixman_region32_extents(&tree->left);
	const struct vis_window *root = &tree->core.root;
	struct vis_window *w = pixman_region32_not_empty(&tree->left) ? top_child(root, e) : NULL;
	for (struct vis_window *c; w && (c = top_child(w, e));)
		w = c;
	for (; w && pixman_region32_not_empty(&tree->left); w = before(w, e)) {
		struct vis_box c = vis_box_intersect(w->clip, box);
		if (w->look.input_only || vis_box_empty(c) || !meets(c, e))
			continue;
		if (draw(tree, w, c) < 0)
			return -1;
		if (!pixman_region32_not_empty(&tree->part))
			continue;
		struct vis_win *win = w->data;
		int64_t x = w->box.x1 + w->look.border, y = w->box.y1 + w->look.border;
		size_t at = tree->n_qrects;
		if (libvis_reserve(&tree->repaint, &tree->cap_repaint, k + 1,
				   sizeof *tree->repaint) < 0 ||
		    libvis_append_rects(&tree->part, x, y, &tree->qrects, &tree->n_qrects,
					&tree->cap_qrects) < 0)
			return -1;
		tree->repaint[k++] = (struct vis_repaint){ .win = win, .data = win->data, .x = x,
							   .y = y,
							   .n_rects = (uint32_t)(tree->n_qrects - at) };
	}
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
