/*
 * The live recompute's walks of its grid: what hides a window (its seen region), and which
 * windows a changed window covers or uncovers. See vis_wtree_update() in wtree.h.
 */
#include <errno.h>
#include <pixman.h>

#include "wtree-live.h"
#include "zgrid.h"

/* A box as pixman's. */
static pixman_box32_t pbox(struct vis_box b)
{
	/* Clips lie in the screen, inside 32 bits. */
	return (pixman_box32_t){ (int32_t)b.x1, (int32_t)b.y1, (int32_t)b.x2, (int32_t)b.y2 };
}

/* A pixman box as ours. */
static struct vis_box vbox(const pixman_box32_t *b)
{
	return (struct vis_box){ b->x1, b->y1, b->x2, b->y2 };
}

/* Whether window v's clip covers pixels of u (whose extents are ext); if so, takes them off. */
static bool cut(pixman_region32_t *u, const struct vis_window *v, bool *ok)
{
	pixman_box32_t b = pbox(v->clip);
	if (pixman_region32_contains_rectangle(u, &b) == PIXMAN_REGION_OUT)
		return false;
	pixman_region32_t r;
	pixman_region32_init_rect(&r, b.x1, b.y1, (unsigned)(b.x2 - b.x1), (unsigned)(b.y2 - b.y1));
	*ok &= pixman_region32_subtract(u, u, &r);
	pixman_region32_fini(&r);
	return true;
}

/* Narrows a walk to what is left of u. */
static void narrow(struct vis_zgrid_walk *walk, pixman_region32_t *u)
{
	vis_zgrid_walk_narrow(walk, vbox(pixman_region32_extents(u)));
}

/*
 * Takes off u every pixel of a viewable window whose key is above end (after w's subtree in
 * pre-order: the windows that can hide w), walking the grid from both ends of that range at
 * once, so that what hides u is found early whether it lies just above w (a cascade) or at the
 * top (a maximized window). Stops once u is empty. Sets *hit when some pixel was taken off.
 * 0, or -1 (ENOMEM).
 */
static int hide(const struct vis_wtree_live *lv, uint64_t end, pixman_region32_t *u, bool *hit,
		size_t *steps, size_t budget)
{
	struct vis_zgrid_walk up, down;
	struct vis_box ext = vbox(pixman_region32_extents(u));
	bool ok = true;
	*hit = false;
	if (vis_zgrid_walk_init(&up, &lv->grid, ext, end, true) < 0)
		return -1;
	if (vis_zgrid_walk_init(&down, &lv->grid, ext, UINT64_MAX, false) < 0) {
		vis_zgrid_walk_finish(&up);
		return -1;
	}
	uint64_t lo = end, hi = UINT64_MAX;
	bool go_up = true, go_down = true;
	while ((go_up || go_down) && pixman_region32_not_empty(u) && ok) {
		for (int side = 0; side < 2; side++) {
			bool *go = side ? &go_down : &go_up;
			uint64_t key;
			void *item;
			if (!*go)
				continue;
			if (++*steps > budget) {
				ok = false;
				break;
			}
			if (!vis_zgrid_walk_next(side ? &down : &up, &key, &item) ||
			    (side ? key <= lo : key >= hi)) {
				*go = false; /* the two walks met: every key between was seen */
				continue;
			}
			*(side ? &hi : &lo) = key;
			if (cut(u, item, &ok)) {
				*hit = true;
				if (!pixman_region32_not_empty(u))
					break;
				narrow(&up, u);
				narrow(&down, u);
			}
		}
	}
	vis_zgrid_walk_finish(&up);
	vis_zgrid_walk_finish(&down);
	if (*steps > budget)
		return OVER_BUDGET;
	if (!ok)
		errno = ENOMEM;
	return ok ? 0 : -1;
}

/* Keeps a region as a seen: its boxes when few, else its extents. */
static void keep_seen(pixman_region32_t *u, struct seen *s)
{
	int n;
	const pixman_box32_t *b = pixman_region32_rectangles(u, &n);
	if (n > SEEN_BOXES) {
		s->n = SEEN_EXTENTS;
		s->boxes[0] = vbox(pixman_region32_extents(u));
		return;
	}
	s->n = (uint8_t)n;
	for (int i = 0; i < n; i++)
		s->boxes[i] = vbox(&b[i]);
}

/* The key of the last viewable window of w's subtree (w's own without viewable descendants). */
static uint64_t subtree_end(const struct vis_window *w)
{
	for (;;) {
		const struct vis_window *c = w->top;
		while (c && !c->mapped)
			c = c->below;
		if (!c)
			return w->key;
		w = c;
	}
}

/*
 * A viewable window's state, by X's rule over its pixels (its clip), and what it sees: its clip
 * less the clips of the windows after its subtree. 0, or -1 (ENOMEM).
 */
int wtree_live_walk_query(struct vis_wtree_live *lv, struct candidate *c)
{
	const struct vis_window *w = c->w;
	c->seen.n = 0;
	c->state = VIS_FULLY_OBSCURED;
	if (vis_box_empty(w->clip))
		return 0;
	pixman_region32_t u;
	pixman_box32_t b = pbox(w->clip);
	pixman_region32_init_rect(&u, b.x1, b.y1, (unsigned)(b.x2 - b.x1), (unsigned)(b.y2 - b.y1));
	bool hit;
	int rc = hide(lv, subtree_end(w), &u, &hit, &lv->steps, lv->budget);
	if (rc == 0 && pixman_region32_not_empty(&u)) {
		bool whole = !hit && w->clip.x1 == w->box.x1 && w->clip.y1 == w->box.y1 &&
			     w->clip.x2 == w->box.x2 && w->clip.y2 == w->box.y2;
		c->state = whole ? VIS_UNOBSCURED : VIS_PARTIALLY_OBSCURED;
		keep_seen(&u, &c->seen);
	}
	pixman_region32_fini(&u);
	return rc;
}

int wtree_live_walk_region(const struct vis_wtree *tree, const struct vis_window *w, void *out)
{
	pixman_region32_t *region = out;
	pixman_region32_clear(region);
	if (vis_box_empty(w->clip) || w->look.input_only)
		return 0;
	pixman_box32_t b = pbox(w->clip);
	pixman_region32_t u;
	pixman_region32_init_rect(&u, b.x1, b.y1, (unsigned)(b.x2 - b.x1), (unsigned)(b.y2 - b.y1));
	bool hit;
	/* As X's clip list, its descendants hide it here: every window after it. */
	size_t steps = 0;
	int rc = hide(tree->live, w->key, &u, &hit, &steps, SIZE_MAX);
	if (rc == 0 && pixman_region32_not_empty(&u)) {
		pixman_region32_translate(&u, (int)-w->box.x1, (int)-w->box.y1);
		if (!pixman_region32_copy(region, &u)) {
			errno = ENOMEM;
			rc = -1;
		}
	}
	pixman_region32_fini(&u);
	return rc;
}

/* Whether a window saw pixels of u at the last recompute (its kept seen region meets u's). */
static bool saw(const struct vis_wtree_live *lv, const struct vis_window *v, pixman_region32_t *u)
{
	if (!v->live_seen)
		return false;
	const struct seen *s = &lv->seen[v->live_seen - 1].seen;
	int n = s->n == SEEN_EXTENTS ? 1 : s->n;
	for (int i = 0; i < n; i++) {
		pixman_box32_t b = pbox(s->boxes[i]);
		if (pixman_region32_contains_rectangle(u, &b) != PIXMAN_REGION_OUT)
			return true;
	}
	return false;
}

/*
 * Walks the grid down from key over seen's pixels, taking the windows whose clip meets what is
 * left of them, each with its ancestors (whom their descendants never hide), and taking each
 * one's clip off what is left, until nothing is left. losing (rule 2 of vis_wtree_update()): the
 * pixels are a changed window's, changed windows are passed over, and only the windows that saw
 * some of what is left are taken; else (rule 3) the pixels are what a window saw before it
 * changed, and every window met is taken. 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_down(struct vis_wtree *tree, struct vis_wtree_live *lv, const struct seen *seen,
		     uint64_t key, bool losing)
{
	int n = seen->n == SEEN_EXTENTS ? 1 : seen->n;
	if (n == 0)
		return 0;
	pixman_box32_t boxes[SEEN_BOXES];
	for (int i = 0; i < n; i++)
		boxes[i] = pbox(vis_box_intersect(seen->boxes[i], tree->root.clip));
	pixman_region32_t u;
	if (!pixman_region32_init_rects(&u, boxes, n)) {
		errno = ENOMEM;
		return -1;
	}
	struct vis_zgrid_walk walk;
	bool ok = vis_zgrid_walk_init(&walk, &lv->grid, vbox(pixman_region32_extents(&u)), key,
				      false) == 0;
	uint64_t k;
	void *item;
	while (ok && pixman_region32_not_empty(&u) && ++lv->steps <= lv->budget &&
	       vis_zgrid_walk_next(&walk, &k, &item)) {
		struct vis_window *v = item;
		pixman_box32_t b = pbox(v->clip);
		if (pixman_region32_contains_rectangle(&u, &b) == PIXMAN_REGION_OUT)
			continue;
		if (losing && v->live_mark == lv->mark)
			continue; /* changed: recomputed already, and it hides what it did not before */
		for (struct vis_window *a = v; ok && a->parent; a = a->parent)
			if (!losing || saw(lv, a, &u))
				ok = wtree_live_take(lv, a, STATE_UNKNOWN) == 0;
		cut(&u, v, &ok);
		narrow(&walk, &u);
	}
	vis_zgrid_walk_finish(&walk);
	pixman_region32_fini(&u);
	if (lv->steps > lv->budget)
		return OVER_BUDGET;
	if (!ok)
		errno = ENOMEM;
	return ok ? 0 : -1;
}

/*
 * Narrows a loose seen box (kept after a rebuild or a recompute through the tree) of a window
 * about to leave the grid to what it saw, walking the grid as the last recompute left it: its
 * clip less the windows above it, if it had no descendants then (they would not hide it).
 * Windows already out of the grid hide nothing here: the result still holds what it saw.
 * 0, or -1 (ENOMEM); a walk past its steps leaves the box as it was.
 */
int wtree_live_walk_refine(struct vis_wtree_live *lv, struct vis_window *v)
{
	struct seen *s = &lv->seen[v->live_seen - 1].seen;
	if (s->n != SEEN_EXTENTS || !v->live_leaf || !v->live_indexed)
		return 0;
	struct vis_box b = vis_box_intersect(s->boxes[0], v->clip);
	if (vis_box_empty(b))
		return 0;
	pixman_region32_t u;
	pixman_region32_init_rect(&u, (int)b.x1, (int)b.y1, (unsigned)(b.x2 - b.x1),
				  (unsigned)(b.y2 - b.y1));
	bool hit;
	size_t steps = 0;
	int rc = hide(lv, v->key, &u, &hit, &steps, lv->budget);
	if (rc == 0)
		keep_seen(&u, s);
	pixman_region32_fini(&u);
	return rc == OVER_BUDGET ? 0 : rc;
}

/*
 * Takes the windows that may see fewer pixels because of a changed window that now sees c->seen
 * (rule 2 of vis_wtree_update()). 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_cover(struct vis_wtree *tree, struct vis_wtree_live *lv,
			  const struct candidate *c)
{
	if (c->state == VIS_WTREE_STATE_NONE)
		return 0;
	/* c lies in lv->cands, which take() may move: copied first. */
	struct seen seen = c->seen;
	return wtree_live_walk_down(tree, lv, &seen, c->w->key, true);
}
