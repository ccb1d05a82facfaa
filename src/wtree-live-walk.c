/*
 * The live recompute's walks of its grid: what hides a window (its seen region), and which
 * windows a changed window covers or uncovers. See vis_wtree_update() in wtree.h.
 */
#include <errno.h>
#include <pixman.h>
#include <stdlib.h>
#include <string.h>

#include "wtree-live.h"
#include "zgrid.h"

/* Sets r (not initialized) to a box, not empty. */
static void init_box(pixman_region32_t *r, struct vis_box box)
{
	pixman_box32_t b = pbox(box);
	pixman_region32_init_rect(r, b.x1, b.y1, (unsigned)(b.x2 - b.x1), (unsigned)(b.y2 - b.y1));
}

/* Whether a clip (on the screen) covers pixels of u; if so, takes them off. */
static bool cut(pixman_region32_t *u, pixman_box32_t clip, bool *ok)
{
	if (pixman_region32_contains_rectangle(u, &clip) == PIXMAN_REGION_OUT)
		return false;
	pixman_region32_t r;
	pixman_region32_init_rect(&r, clip.x1, clip.y1, (unsigned)(clip.x2 - clip.x1),
				  (unsigned)(clip.y2 - clip.y1));
	*ok &= pixman_region32_subtract(u, u, &r);
	pixman_region32_fini(&r);
	return true;
}

/*
 * What is left of a walk's pixels. A walk cuts clip after clip off them, and pixman rebuilds a
 * region at each cut (4,000 instructions a cut at 20 boxes, measured on a cascade's raise), so
 * while they are few they are kept as disjoint boxes, a cut splitting the boxes it meets into at
 * most four each; past LEFT_BOXES, as a region again (pixman's tests binary-search its bands).
 * A coordinate to an array: a cascade's walk tests thousands of clips against 20-60 boxes, most
 * of which each misses, and the compiler tests them four at a time.
 */
#define LEFT_REGION SIZE_MAX

struct left {
	pixman_region32_t *u; /* the pixels when n is LEFT_REGION; what they go back into */
	size_t n, cap;        /* boxes, and the most kept (LEFT_BOXES, fewer in tests) */
	pixman_box32_t ext; /* the boxes' extents, while n > 0 */
	int32_t x1[LEFT_BOXES], y1[LEFT_BOXES], x2[LEFT_BOXES], y2[LEFT_BOXES];
};

static pixman_box32_t left_box(const struct left *l, size_t i)
{
	return (pixman_box32_t){ l->x1[i], l->y1[i], l->x2[i], l->y2[i] };
}

static void left_put(struct left *l, size_t i, pixman_box32_t b)
{
	l->x1[i] = b.x1;
	l->y1[i] = b.y1;
	l->x2[i] = b.x2;
	l->y2[i] = b.y2;
}

/* Sets the extents of the boxes (n > 0). */
static void left_bound(struct left *l)
{
	int32_t x1 = INT32_MAX, y1 = INT32_MAX, x2 = INT32_MIN, y2 = INT32_MIN;
	for (size_t i = 0; i < l->n; i++) {
		x1 = l->x1[i] < x1 ? l->x1[i] : x1;
		y1 = l->y1[i] < y1 ? l->y1[i] : y1;
		x2 = l->x2[i] > x2 ? l->x2[i] : x2;
		y2 = l->y2[i] > y2 ? l->y2[i] : y2;
	}
	l->ext = (pixman_box32_t){ x1, y1, x2, y2 };
}

/* Sets the boxes to b[0 … n), n at most the limit. */
static void left_set(struct left *l, const pixman_box32_t *b, size_t n)
{
	for (size_t i = 0; i < n; i++)
		left_put(l, i, b[i]);
	l->n = n;
	if (n > 0)
		left_bound(l);
}

/* Makes u (finished first) a region of the boxes. false without memory. */
static bool left_region(const struct left *l, pixman_region32_t *u)
{
	pixman_box32_t b[LEFT_BOXES];
	for (size_t i = 0; i < l->n; i++)
		b[i] = left_box(l, i);
	pixman_region32_fini(u);
	return pixman_region32_init_rects(u, b, (int)l->n);
}

/* Takes u's pixels, as boxes when they are few. */
static void left_init(struct left *l, pixman_region32_t *u, size_t cap)
{
	int n;
	const pixman_box32_t *b = pixman_region32_rectangles(u, &n);
	l->u = u;
	l->cap = cap;
	l->n = LEFT_REGION;
	if ((size_t)n <= cap / 2)
		left_set(l, b, (size_t)n);
}

/* Puts the pixels back into u as a region. false without memory. */
static bool left_finish(struct left *l)
{
	return l->n == LEFT_REGION || left_region(l, l->u);
}

static bool left_empty(const struct left *l)
{
	return l->n == LEFT_REGION ? !pixman_region32_not_empty(l->u) : l->n == 0;
}

static bool boxes_meet(const pixman_box32_t *a, const pixman_box32_t *b)
{
	return a->x1 < b->x2 && b->x1 < a->x2 && a->y1 < b->y2 && b->y1 < a->y2;
}

/* The extents of what is left (not empty). */
static struct vis_box left_extents(const struct left *l)
{
	return vbox(l->n == LEFT_REGION ? pixman_region32_extents(l->u) : &l->ext);
}

/*
 * Whether box (not empty) meets what is left. met, unless NULL, gets a byte a box saying whether
 * box meets it, for left_cut() (meaningful while what is left is boxes and does not change).
 */
static bool left_meets(const struct left *l, const pixman_box32_t *box, uint8_t *met)
{
	if (l->n == LEFT_REGION)
		return pixman_region32_contains_rectangle(l->u, box) != PIXMAN_REGION_OUT;
	if (l->n == 0 || !boxes_meet(&l->ext, box))
		return false;
	int32_t x1 = box->x1, y1 = box->y1, x2 = box->x2, y2 = box->y2;
	int any = 0;
	if (!met) {
		for (size_t i = 0; i < l->n; i++)
			any |= (l->x1[i] < x2) & (x1 < l->x2[i]) & (l->y1[i] < y2) & (y1 < l->y2[i]);
		return any;
	}
	for (size_t i = 0; i < l->n; i++) {
		met[i] = (l->x1[i] < x2) & (x1 < l->x2[i]) & (l->y1[i] < y2) & (y1 < l->y2[i]);
		any |= met[i];
	}
	return any;
}

/* Whether a grid cell's pixels meet what is left (a zgrid walk's test of its cells). */
static bool left_meets_cell(const void *arg, struct vis_box cell)
{
	pixman_box32_t b = pbox(cell);
	return left_meets(arg, &b, NULL);
}

/*
 * A walk's misses in a row (steps whose clips missed what is left), and how many wait for a
 * pruning of its cells: see left_prune().
 */
struct misses {
	size_t n, wait;
};

/*
 * After a run of misses, leaves out of a walk the cells that what is left no longer meets (the
 * extents, which a walk is narrowed to, can span many covered cells around a few holes: nested
 * windows under a lowered one), once the misses have cost about what the test costs; a test
 * that left out nothing (a cascade's walks, whose pixels meet every cell they span) doubles the
 * wait for the next.
 */
static void left_prune(const struct left *l, struct vis_zgrid_walk *walk, struct misses *m)
{
	size_t boxes = l->n == LEFT_REGION ? 8 : l->n;
	if (++m->n < 8 + m->wait + walk->n * boxes / 8)
		return;
	m->n = 0;
	if (!vis_zgrid_walk_keep(walk, left_meets_cell, l))
		m->wait = 2 * m->wait + 8;
}

/*
 * Whether a clip (on the screen) covers pixels of what is left; if so, takes them off. met: what
 * left_meets() marked for the clip, or NULL. A met box's first piece takes its place, the others
 * go at the end, and a box left without pieces gets the last box in its place; the extents are
 * found again only when a met box touched them.
 */
static bool left_cut(struct left *l, pixman_box32_t clip, const uint8_t *met, bool *ok)
{
	if (l->n == LEFT_REGION)
		return cut(l->u, clip, ok);
	uint8_t marks[LEFT_BOXES];
	if (!met) {
		if (!left_meets(l, &clip, marks))
			return false;
		met = marks;
	}
	size_t n0 = l->n, gone[LEFT_BOXES], n_gone = 0;
	bool touched = false;
	for (size_t i = 0; i < n0; i++) {
		/* Eight marks at a time: a clip meets one or two of 20-60 boxes. */
		uint64_t eight = 0;
		if (i % 8 == 0 && i + 8 <= n0) {
			memcpy(&eight, &met[i], 8);
			if (!eight) {
				i += 7;
				continue;
			}
		}
		if (!met[i])
			continue;
		pixman_box32_t b = left_box(l, i);
		touched |= b.x1 == l->ext.x1 || b.y1 == l->ext.y1 || b.x2 == l->ext.x2 ||
			   b.y2 == l->ext.y2;
		/* Above the clip, below it, then beside it within its rows. */
		int32_t y1 = b.y1 > clip.y1 ? b.y1 : clip.y1, y2 = b.y2 < clip.y2 ? b.y2 : clip.y2;
		pixman_box32_t piece[4] = {
			{ b.x1, b.y1, b.x2, clip.y1 },
			{ b.x1, y1, clip.x1, y2 },
			{ clip.x2, y1, b.x2, y2 },
			{ b.x1, clip.y2, b.x2, b.y2 },
		};
		size_t k = 0;
		for (int j = 0; j < 4; j++)
			if (piece[j].x1 < piece[j].x2 && piece[j].y1 < piece[j].y2)
				piece[k++] = piece[j];
		if (k == 0) {
			gone[n_gone++] = i;
			continue;
		}
		if (l->n + k - 1 > l->cap)
			goto region;
		left_put(l, i, piece[0]);
		for (size_t j = 1; j < k; j++)
			left_put(l, l->n++, piece[j]);
	}
	/* From the highest: the last box is never one gone. */
	while (n_gone > 0) {
		size_t i = gone[--n_gone];
		if (i != --l->n)
			left_put(l, i, left_box(l, l->n));
	}
	if (touched && l->n > 0)
		left_bound(l);
	return true;
region:;
	/* Too many boxes: the cut on a region of them all (pieces, boxes gone and those not met). */
	bool made = left_region(l, l->u);
	l->n = LEFT_REGION;
	if (!made) {
		*ok = false;
		return true;
	}
	return cut(l->u, clip, ok);
}

/*
 * A window with a look: its kept cut (NULL for a translucent border box, which has none; NULL
 * with *ok false without memory), and its k-th piece on the screen inside its clip, false when
 * the clip leaves nothing of it. The pieces are placed at the border box (look.h); the live
 * engine takes no window under a shaped ancestor, so no other shape clips them.
 */
static const struct vis_look_cut *cut_of(const struct vis_window *w, bool *ok)
{
	if (!w->cut)
		return NULL;
	const struct vis_look_cut *cut = vis_wtree_cut(w);
	if (!cut)
		*ok = false;
	return cut;
}

static bool piece_of(const struct vis_window *w, const struct vis_look_cut *cut, uint32_t k,
		     pixman_box32_t *out)
{
	struct vis_rect r = cut->rects[k];
	struct vis_box b = vis_box_intersect(
		(struct vis_box){ w->box.x1 + r.x, w->box.y1 + r.y, w->box.x1 + r.x + r.w,
				  w->box.y1 + r.y + r.h },
		w->clip);
	*out = pbox(b);
	return !vis_box_empty(b);
}

/*
 * As left_cut() for a window with a look: its opaque pieces alone hide. Their run is banded, by
 * top, so the cut stops at the first below what is left.
 */
static bool left_cut_look(struct left *l, const struct vis_window *w, bool *ok)
{
	const struct vis_look_cut *cut = cut_of(w, ok);
	if (!cut)
		return !*ok;
	bool any = false;
	for (uint32_t k = 0; k < cut->n_opaque && !left_empty(l); k++) {
		pixman_box32_t b;
		if (!piece_of(w, cut, k, &b))
			continue;
		if (b.y1 >= left_extents(l).y2)
			break;
		any |= left_cut(l, b, NULL, ok);
		if (!*ok)
			return true;
	}
	return any;
}

/* left_cut() by an indexed window's pixels that hide (met: for its clip, when it has no look). */
static bool left_cut_slot(struct left *l, const struct live_slot *s, const uint8_t *met, bool *ok)
{
	return s->look ? left_cut_look(l, s->w, ok) : left_cut(l, s->clip, met, ok);
}

/* Takes off u the pixels of an indexed window v that hide what lies below. */
static void cut_window(pixman_region32_t *u, const struct vis_window *v, bool *ok)
{
	if (!wtree_live_has_look(v)) {
		cut(u, pbox(v->clip), ok);
		return;
	}
	const struct vis_look_cut *c = cut_of(v, ok);
	for (uint32_t k = 0; c && *ok && k < c->n_opaque; k++) {
		pixman_box32_t b;
		if (piece_of(v, c, k, &b))
			cut(u, b, ok);
	}
}

/*
 * Sets u (not initialized) to a viewable window's pixels, or with opaque to those that hide
 * what lies below: its clip, or its look's pieces in it (the opaque ones first). false without
 * memory.
 */
static bool pieces_region(const struct vis_window *w, pixman_region32_t *u, bool opaque)
{
	bool ok = true;
	const struct vis_look_cut *cut = wtree_live_has_look(w) ? cut_of(w, &ok) : NULL;
	if (!cut) {
		/* A look without a cut is a translucent border box: nothing of it hides. */
		if (ok && !(opaque && wtree_live_has_look(w)))
			init_box(u, w->clip);
		else
			pixman_region32_init(u);
		return ok;
	}
	uint32_t m = opaque ? cut->n_opaque : cut->n;
	pixman_box32_t *b = malloc((m ? m : 1) * sizeof *b);
	size_t n = 0;
	for (uint32_t k = 0; b && k < m; k++)
		n += piece_of(w, cut, k, &b[n]);
	/* The two runs, opaque and see-through, are each banded: init_rects sorts them together. */
	ok = b && pixman_region32_init_rects(u, b, (int)n);
	if (!b)
		pixman_region32_init(u);
	free(b);
	return ok;
}

static bool pixels_of(const struct vis_window *w, pixman_region32_t *u)
{
	return pieces_region(w, u, false);
}

/* Whether a window sees all its pixels when nothing hides them: none lies outside its clip. */
static int whole_in_clip(const struct vis_window *w)
{
	if (!wtree_live_has_look(w))
		return w->clip.x1 == w->box.x1 && w->clip.y1 == w->box.y1 &&
		       w->clip.x2 == w->box.x2 && w->clip.y2 == w->box.y2;
	int cut = wtree_work_cut(w, w->clip);
	return cut < 0 ? -1 : !cut;
}

static int per_cell(const struct vis_zgrid *grid, pixman_region32_t *u,
		    int (*each)(pixman_region32_t *piece, void *arg), void *arg);
static int hide_cells(const struct vis_wtree_live *lv, uint64_t end, pixman_region32_t *u,
		      bool *hit, size_t *steps, size_t budget);

/*
 * Takes off u every pixel of a viewable window whose key is above end (after w's subtree in
 * pre-order: the windows that can hide w), walking the grid from both ends of that range at
 * once, so that what hides u is found early whether it lies just above w (a cascade) or at the
 * top (a maximized window). Stops once u is empty. Sets *hit when some pixel was taken off.
 * Once the pixels fragment past a walk's boxes, a walk over more than one cell goes on a cell at
 * a time (split), as walk_left() does: a large window punched by many small ones cost a region
 * rebuilt at each cut, O(holes²) (1,000 holes in a chain's levels: 30 ms a query).
 * 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
/* The boxes, in walk's boxes, past which hide() goes on a cell at a time. */
#define SPLIT_BOXES 4

static int hide_split(const struct vis_wtree_live *lv, uint64_t end, pixman_region32_t *u,
		      bool *hit, size_t *steps, size_t budget, bool split)
{
	struct vis_zgrid_walk up, down;
	struct left l;
	left_init(&l, u, lv->left_boxes);
	struct vis_box ext = left_extents(&l);
	bool ok = true, fragmented = false;
	*hit = false;
	if (vis_zgrid_walk_init(&up, &lv->grid, ext, end, true) < 0)
		return -1;
	if (vis_zgrid_walk_init(&down, &lv->grid, ext, UINT64_MAX, false) < 0) {
		vis_zgrid_walk_finish(&up);
		return -1;
	}
	uint64_t lo = end, hi = UINT64_MAX;
	bool go_up = true, go_down = true;
	struct misses misses[2] = { { 0, 0 }, { 0, 0 } };
	while ((go_up || go_down) && !left_empty(&l) && ok && !fragmented) {
		for (int side = 0; side < 2; side++) {
			bool *go = side ? &go_down : &go_up;
			uint64_t key;
			uint32_t slot;
			if (!*go)
				continue;
			if (++*steps > budget) {
				ok = false;
				break;
			}
			if (!vis_zgrid_walk_next(side ? &down : &up, &key, &slot) ||
			    (side ? key <= lo : key >= hi)) {
				*go = false; /* the two walks met: every key between was seen */
				continue;
			}
			*(side ? &hi : &lo) = key;
			if (!left_cut_slot(&l, &lv->slots[slot], NULL, &ok)) {
				left_prune(&l, side ? &down : &up, &misses[side]);
			} else {
				misses[side].n = 0;
				*hit = true;
				if (!ok || left_empty(&l))
					break;
				if (split && l.n == LEFT_REGION && up.n > 1 &&
				    (size_t)pixman_region32_n_rects(l.u) > SPLIT_BOXES * l.cap) {
					fragmented = true;
					break;
				}
				ext = left_extents(&l);
				vis_zgrid_walk_narrow(&up, ext);
				vis_zgrid_walk_narrow(&down, ext);
			}
		}
	}
	vis_zgrid_walk_finish(&up);
	vis_zgrid_walk_finish(&down);
	bool kept = left_finish(&l);
	if (*steps > budget)
		return OVER_BUDGET;
	ok = ok && kept;
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	/* The cells walk again what this walk cut: it took off those pixels already. */
	return fragmented ? hide_cells(lv, end, u, hit, steps, budget) : 0;
}

static int hide(const struct vis_wtree_live *lv, uint64_t end, pixman_region32_t *u, bool *hit,
		size_t *steps, size_t budget)
{
	return hide_split(lv, end, u, hit, steps, budget, true);
}

/* What hide_cells() hands each cell. */
struct hide_arg {
	const struct vis_wtree_live *lv;
	uint64_t end;
	bool *hit;
	size_t *steps, budget;
};

static int hide_cell(pixman_region32_t *piece, void *arg)
{
	struct hide_arg *h = arg;
	bool hit = false;
	int rc = hide_split(h->lv, h->end, piece, &hit, h->steps, h->budget, false);
	*h->hit |= hit;
	return rc;
}

/* hide() over u (a region) in each grid cell apart (per_cell()). */
static int hide_cells(const struct vis_wtree_live *lv, uint64_t end, pixman_region32_t *u,
		      bool *hit, size_t *steps, size_t budget)
{
	struct hide_arg h = { lv, end, hit, steps, budget };
	return per_cell(&lv->grid, u, hide_cell, &h);
}

/* Keeps a region as a seen: its boxes when few, else its extents. */
static void keep_seen(const struct vis_wtree_live *lv, pixman_region32_t *u, struct seen *s)
{
	int n;
	const pixman_box32_t *b = pixman_region32_rectangles(u, &n);
	if ((unsigned)n > lv->seen_boxes) {
		/* The extents of a region touch it on every edge. */
		s->n = SEEN_EXTENTS;
		s->edges = EDGE_LEFT | EDGE_TOP | EDGE_RIGHT | EDGE_BOTTOM;
		s->boxes[0] = *pixman_region32_extents(u);
		return;
	}
	s->n = (uint8_t)n;
	s->edges = 0;
	for (int i = 0; i < n; i++)
		s->boxes[i] = b[i];
}

/*
 * Whether u, pixels a window sees, are all of its own: its whole box, or for one with a look all
 * its pieces, none outside its clip. 1, 0, or -1 without memory.
 */
static int sees_all(const struct vis_window *w, pixman_region32_t *u)
{
	if (!wtree_live_has_look(w)) {
		const pixman_box32_t *e = pixman_region32_extents(u);
		return pixman_region32_n_rects(u) == 1 && e->x1 == w->box.x1 &&
		       e->y1 == w->box.y1 && e->x2 == w->box.x2 && e->y2 == w->box.y2;
	}
	int in = whole_in_clip(w);
	if (in <= 0)
		return in;
	pixman_region32_t p;
	if (!pixels_of(w, &p)) {
		pixman_region32_fini(&p);
		return -1;
	}
	int all = pixman_region32_equal(&p, u);
	pixman_region32_fini(&p);
	return all;
}

/*
 * A candidate's state and seen region from the pixels it sees, u (NULL: none, as after a
 * failed walk): unobscured when they are all its own. false without memory.
 */
static bool settle(const struct vis_wtree_live *lv, struct candidate *c, pixman_region32_t *u)
{
	const struct vis_window *w = c->w;
	c->seen.n = 0;
	c->state = VIS_FULLY_OBSCURED;
	if (!u || !pixman_region32_not_empty(u))
		return true;
	int all = sees_all(w, u);
	c->state = all > 0 ? VIS_UNOBSCURED : VIS_PARTIALLY_OBSCURED;
	keep_seen(lv, u, &c->seen);
	return all >= 0;
}

/*
 * Ends a query that found the pixels u (freed here): walk's result rc, ok false when memory ran
 * out (-1 then). Returns rc.
 */
static int finish(const struct vis_wtree_live *lv, struct candidate *c, pixman_region32_t *u,
		  int rc, bool ok)
{
	if (rc == 0 && (!ok || !settle(lv, c, u))) {
		errno = ENOMEM;
		rc = -1;
	}
	if (rc != 0)
		settle(lv, c, NULL);
	pixman_region32_fini(u);
	return rc;
}

/* The key of the last viewable window of w's subtree (w's own without viewable descendants). */
uint64_t wtree_live_subtree_end(const struct vis_window *w)
{
	/* Flagged so, it has no viewable descendants (wtree-live.h): its children are not read. */
	if (w->live_leaf)
		return w->key;
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
	if (!pixels_of(w, &u)) {
		pixman_region32_fini(&u);
		errno = ENOMEM;
		return -1;
	}
	bool hit;
	int rc = hide(lv, wtree_live_subtree_end(w), &u, &hit, &lv->steps, lv->budget);
	if (rc == 0 && pixman_region32_not_empty(&u)) {
		int whole = hit ? 0 : whole_in_clip(w);
		if (whole < 0) {
			errno = ENOMEM;
			rc = -1;
		}
		c->state = whole > 0 ? VIS_UNOBSCURED : VIS_PARTIALLY_OBSCURED;
		keep_seen(lv, &u, &c->seen);
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
	pixman_region32_t u;
	if (!pixels_of(w, &u)) {
		pixman_region32_fini(&u);
		errno = ENOMEM;
		return -1;
	}
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

/* Whether a window saw pixels of what is left at the last recompute (its seen region meets it). */
static bool saw(const struct vis_wtree_live *lv, const struct vis_window *v, const struct left *l)
{
	if (!v->live_seen)
		return false;
	const struct seen *s = &lv->seen[v->live_seen - 1].seen;
	int n = s->n == SEEN_EXTENTS ? 1 : s->n;
	for (int i = 0; i < n; i++)
		if (s->boxes[i].x1 < s->boxes[i].x2 && s->boxes[i].y1 < s->boxes[i].y2 &&
		    left_meets(l, &s->boxes[i], NULL))
			return true;
	return false;
}

/* Whether w lies in one of the update's changed subtrees (its candidates [0, n_moved)). */
static bool moved(const struct vis_wtree_live *lv, const struct vis_window *w)
{
	return w->live_mark == lv->mark && w->live_cand && w->live_cand <= lv->n_moved;
}

/* Lists the pixels left that v's clip holds as what candidate c gains. false without memory. */
static bool gained(struct vis_wtree_live *lv, struct candidate *c, const struct vis_window *v,
		   const struct left *l)
{
	if (l->n != LEFT_REGION) {
		bool ok = true;
		for (size_t i = 0; ok && i < l->n; i++) {
			pixman_box32_t box = left_box(l, i);
			struct vis_box b = vis_box_intersect(vbox(&box), v->clip);
			if (!vis_box_empty(b))
				ok = wtree_live_gained(lv, c, b) == 0;
		}
		return ok;
	}
	pixman_region32_t r;
	init_box(&r, v->clip);
	bool ok = pixman_region32_intersect(&r, &r, l->u);
	int n = 0;
	const pixman_box32_t *boxes = ok ? pixman_region32_rectangles(&r, &n) : NULL;
	for (int i = 0; ok && i < n; i++)
		ok = wtree_live_gained(lv, c, vbox(&boxes[i])) == 0;
	pixman_region32_fini(&r);
	return ok;
}

/* Sets u (not initialized) to a seen region's pixels on the screen. false without memory. */
static bool seen_region(pixman_region32_t *u, const struct seen *seen, struct vis_box screen)
{
	int n = seen->n == SEEN_EXTENTS ? 1 : seen->n, k = 0;
	pixman_box32_t boxes[SEEN_BOXES];
	/* pixman takes one box, even an empty one, as a rectangle to check. */
	for (int i = 0; i < n; i++) {
		struct vis_box b = vis_box_intersect(vbox(&seen->boxes[i]), screen);
		if (!vis_box_empty(b))
			boxes[k++] = pbox(b);
	}
	return pixman_region32_init_rects(u, boxes, k);
}

/* Takes a seen region's pixels off u. false without memory. */
static bool subtract_seen(pixman_region32_t *u, const struct seen *seen, struct vis_box screen)
{
	pixman_region32_t r;
	if (!seen_region(&r, seen, screen))
		return false;
	bool ok = pixman_region32_subtract(u, u, &r);
	pixman_region32_fini(&r);
	return ok;
}

static int walk_cells(struct vis_wtree_live *lv, struct left *l, uint64_t key, bool losing,
		      bool exact, uint64_t stop);

/*
 * walk_down() over what is left, from key. Once the pixels fragment past a walk's boxes (a box
 * punched by many small windows, whose region pixman rebuilds at each cut), a walk over more
 * than one cell goes on a cell at a time (split), each cell's pixels cut by its own windows alone.
 */
static int walk_left(struct vis_wtree_live *lv, struct left *l, uint64_t key, bool losing,
		     bool exact, uint64_t stop, bool split)
{
	if (left_empty(l))
		return 0;
	struct vis_zgrid_walk walk;
	bool ok = vis_zgrid_walk_init(&walk, &lv->grid, left_extents(l), key, false) == 0;
	bool fragmented = false;
	uint64_t k;
	uint32_t slot;
	struct misses misses = { 0, 0 };
	while (ok && !left_empty(l) && ++lv->steps <= lv->budget && lv->steps <= lv->give_up &&
	       vis_zgrid_walk_next(&walk, &k, &slot) && k > stop) {
		/* The window itself is read only when its clip meets what is left. */
		pixman_box32_t b = lv->slots[slot].clip;
		uint8_t met[LEFT_BOXES];
		if (!left_meets(l, &b, met)) {
			left_prune(l, &walk, &misses);
			continue;
		}
		misses.n = 0;
		struct vis_window *v = lv->slots[slot].w;
		if (losing && moved(lv, v))
			continue; /* changed: recomputed already, and it hides what it did not before */
		for (struct vis_window *a = v; ok && a->parent; a = a->parent)
			if (!losing || saw(lv, a, l))
				ok = wtree_live_take(lv, a, STATE_UNKNOWN, !losing) == 0;
		/* Without descendants, it sees what is left that its clip holds, but for what
		 * changed windows hide now (wtree_live_walk_since()). */
		/* Its gains are its pixels in what is left: its clip's part for one without a look. */
		bool look = lv->slots[slot].look;
		if (ok && !losing && !moved(lv, v)) {
			struct candidate *c = &lv->cands[v->live_cand - 1];
			c->unlisted |= !exact || look;
			if (exact && v->live_leaf && !look)
				ok = gained(lv, c, v, l);
		}
		bool was_boxes = l->n != LEFT_REGION;
		left_cut_slot(l, &lv->slots[slot], l->n == LEFT_REGION ? NULL : met, &ok);
		if (!ok || left_empty(l))
			break;
		if (split && was_boxes && l->n == LEFT_REGION && walk.n > 1) {
			fragmented = true;
			break;
		}
		vis_zgrid_walk_narrow(&walk, left_extents(l));
	}
	vis_zgrid_walk_finish(&walk);
	if (lv->steps > lv->budget)
		return OVER_BUDGET;
	if (lv->steps > lv->give_up)
		return GAVE_UP;
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	/* The windows below k are left to walk, over each cell's pixels. */
	return fragmented ? walk_cells(lv, l, k, losing, exact, stop) : 0;
}

/* Appends boxes to a growing array. false without memory. */
static bool append_boxes(pixman_box32_t **all, size_t *n, size_t *cap, const pixman_box32_t *b,
			 size_t m)
{
	if (m == 0)
		return true; /* *all may be NULL still: no memcpy from or to it */
	if (*n + m > *cap) {
		size_t c = *cap ? 2 * *cap : 64;
		while (c < *n + m)
			c *= 2;
		pixman_box32_t *more = c <= SIZE_MAX / sizeof(*more) ? realloc(*all, c * sizeof(*more))
								       : NULL;
		if (!more)
			return false;
		*all = more;
		*cap = c;
	}
	memcpy(*all + *n, b, m * sizeof(*b));
	*n += m;
	return true;
}

/*
 * Runs each over u's pixels in each grid cell apart (piece: those in the cell, which each may
 * take off), and makes u what the cells leave, disjoint boxes joined once at the end. Stops at
 * the first result other than 0 and returns it; else 0, or -1 (ENOMEM).
 */
static int per_cell(const struct vis_zgrid *grid, pixman_region32_t *u,
		    int (*each)(pixman_region32_t *piece, void *arg), void *arg)
{
	uint32_t r[4];
	if (!pixman_region32_not_empty(u) ||
	    !vis_zgrid_cells(grid, vbox(pixman_region32_extents(u)), r))
		return 0;
	pixman_box32_t *rest = NULL;
	size_t n_rest = 0, cap = 0;
	bool ok = true;
	int rc = 0;
	for (uint32_t y = r[1]; ok && rc == 0 && y <= r[3]; y++)
		for (uint32_t x = r[0]; ok && rc == 0 && x <= r[2]; x++) {
			pixman_box32_t c = pbox(vis_zgrid_cell_box(grid, x, y));
			pixman_region32_t piece;
			pixman_region32_init_rect(&piece, c.x1, c.y1, (unsigned)(c.x2 - c.x1),
						  (unsigned)(c.y2 - c.y1));
			ok = pixman_region32_intersect(&piece, &piece, u);
			if (ok && pixman_region32_not_empty(&piece))
				rc = each(&piece, arg);
			int m = 0;
			const pixman_box32_t *b = pixman_region32_rectangles(&piece, &m);
			ok = ok && (rc != 0 || append_boxes(&rest, &n_rest, &cap, b, (size_t)m));
			pixman_region32_fini(&piece);
		}
	if (rc == 0 && ok) {
		pixman_region32_fini(u);
		ok = pixman_region32_init_rects(u, rest, (int)n_rest);
	}
	free(rest);
	if (rc == 0 && !ok) {
		errno = ENOMEM;
		rc = -1;
	}
	return rc;
}

/* What walk_cells() hands each cell. */
struct walk_arg {
	struct vis_wtree_live *lv;
	uint64_t key, stop;
	bool losing, exact;
};

static int walk_cell(pixman_region32_t *piece, void *arg)
{
	struct walk_arg *w = arg;
	struct left pl;
	left_init(&pl, piece, w->lv->left_boxes);
	int rc = walk_left(w->lv, &pl, w->key, w->losing, w->exact, w->stop, false);
	if (!left_finish(&pl) && rc == 0) {
		errno = ENOMEM;
		rc = -1;
	}
	return rc;
}

/* walk_left() over what is left (a region) in each grid cell apart, from key (per_cell()). */
static int walk_cells(struct vis_wtree_live *lv, struct left *l, uint64_t key, bool losing,
		      bool exact, uint64_t stop)
{
	struct walk_arg w = { lv, key, stop, losing, exact };
	return per_cell(&lv->grid, l->u, walk_cell, &w);
}

/*
 * Walks the grid down from key over u's pixels, taking the windows whose clip meets what is
 * left of them, each with its ancestors (whom their descendants never hide), and taking each
 * one's clip off what is left, until nothing is left. losing (rule 2 of vis_wtree_update()): the
 * pixels are a changed window's, changed windows are passed over, and only the windows that saw
 * some of what is left are taken; else (rule 3) the pixels are what a window saw before it
 * changed, and every window met is taken, as one that may gain pixels; where those are exact
 * (so no window above key hides them), each one without descendants gets the pixels of what is
 * left that its clip holds listed as what it gains. The walk stops at stop (0: at the bottom),
 * leaving in u what no window above stop hides.
 * 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
static int walk_down(struct vis_wtree_live *lv, pixman_region32_t *u, uint64_t key, bool losing,
		     bool exact, uint64_t stop)
{
	struct left l;
	left_init(&l, u, lv->left_boxes);
	int rc = walk_left(lv, &l, key, losing, exact, stop, true);
	if (!left_finish(&l) && rc == 0) {
		errno = ENOMEM;
		rc = -1;
	}
	return rc;
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
	/* While windows with looks are indexed, those changed but not yet out of the grid may hide
	 * by pieces cut for their new size at their old place: the box stays. */
	if (s->n != SEEN_EXTENTS || !v->live_leaf || !v->live_indexed || lv->n_looks)
		return 0;
	struct vis_box b = vis_box_intersect(vbox(&s->boxes[0]), v->clip);
	if (vis_box_empty(b))
		return 0;
	pixman_region32_t u;
	init_box(&u, b);
	bool hit;
	size_t steps = 0;
	int rc = hide(lv, v->key, &u, &hit, &steps, lv->budget);
	if (rc == 0) {
		keep_seen(lv, &u, s);
		s->edges = 0; /* it may hold more than it saw */
		wtree_live_seen_changed(lv, v->live_seen - 1);
	}
	pixman_region32_fini(&u);
	return rc == OVER_BUDGET ? 0 : rc;
}

/*
 * walk_down() over each box of u apart, down to stop: a walk is narrowed to the extents of what
 * is left, which for an L-shaped difference of two boxes would be the whole of the larger one.
 * Each pixel is walked over as in one walk over u (wtree.h's argument is pixel by pixel). left,
 * unless NULL, gets what the walks leave of u.
 */
static int walk_boxes(struct vis_wtree_live *lv, pixman_region32_t *u, uint64_t key, bool losing,
		      bool exact, uint64_t stop, pixman_region32_t *left)
{
	int n;
	const pixman_box32_t *boxes = pixman_region32_rectangles(u, &n);
	/* What the walks leave, disjoint boxes joined once at the end: a union after each walk
	 * would cost the boxes so far each time (4,961 boxes when nested's top window lowers). */
	pixman_box32_t *kept = NULL;
	size_t n_kept = 0, cap = 0;
	int rc = 0;
	for (int i = 0; rc == 0 && i < n; i++) {
		pixman_region32_t one;
		init_box(&one, vbox(&boxes[i]));
		rc = walk_down(lv, &one, key, losing, exact, stop);
		int m = 0;
		const pixman_box32_t *b = left && rc == 0 ? pixman_region32_rectangles(&one, &m) : NULL;
		if (m > 0 && !append_boxes(&kept, &n_kept, &cap, b, (size_t)m)) {
			errno = ENOMEM;
			rc = -1;
		}
		pixman_region32_fini(&one);
	}
	if (rc == 0 && left && n_kept > 0) {
		pixman_region32_t all;
		if (!pixman_region32_init_rects(&all, kept, (int)n_kept) ||
		    !pixman_region32_union(left, left, &all)) {
			errno = ENOMEM;
			rc = -1;
		}
		pixman_region32_fini(&all);
	}
	free(kept);
	return rc;
}

/* The seen grid's entries in the cells u meets: what reading them all would cost. */
static size_t seen_entries(const struct vis_wtree_live *lv, pixman_region32_t *u)
{
	const struct vis_sgrid *g = &lv->seen_grid;
	uint32_t r[4];
	size_t n = 0;
	if (!pixman_region32_not_empty(u) || !vis_sgrid_cells(g, vbox(pixman_region32_extents(u)), r))
		return 0;
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++)
			n += vis_sgrid_cell(g, x, y)->n;
	return n;
}

/*
 * Takes the unchanged windows below key whose seen region (as kept: exact, or a box holding it)
 * meets u, from the seen grid: those rule 2 takes, and perhaps more (wtree.h). 0, -1 (ENOMEM),
 * or OVER_BUDGET.
 */
static int cover_by_seen(struct vis_wtree_live *lv, pixman_region32_t *u, uint64_t key)
{
	const struct vis_sgrid *g = &lv->seen_grid;
	int n;
	const pixman_box32_t *boxes = pixman_region32_rectangles(u, &n);
	for (int b = 0; b < n; b++) {
		struct vis_box q = vbox(&boxes[b]);
		uint32_t r[4];
		if (!vis_sgrid_cells(g, q, r))
			continue;
		for (uint32_t y = r[1]; y <= r[3]; y++)
			for (uint32_t x = r[0]; x <= r[2]; x++) {
				const struct vis_sgrid_cell *c = vis_sgrid_cell(g, x, y);
				for (uint32_t i = 0; i < c->n; i++) {
					const struct vis_sgrid_entry *e = &c->e[i];
					if (!(e->x1 < q.x2 && q.x1 < e->x2 && e->y1 < q.y2 &&
					      q.y1 < e->y2) ||
					    !vis_sgrid_reports(g, e, q, x, y))
						continue;
					const struct seen_window *sw = &lv->seen[e->val];
					if (!sw->w || SEEN_STAMP(sw->stamp) != e->stamp)
						continue;
					struct vis_window *v = sw->w;
					if (v->key >= key || moved(lv, v))
						continue;
					if (++lv->steps > lv->budget)
						return OVER_BUDGET;
					if (wtree_live_take(lv, v, STATE_UNKNOWN, false) < 0)
						return -1;
				}
			}
	}
	return 0;
}

/*
 * Takes the windows that may see fewer pixels because of a changed window that now sees c->seen
 * (rule 2 of vis_wtree_update()). Pixels it saw before as well are left out when its subtree
 * kept its parent: no window lost them to it (wtree.h). 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_cover(struct vis_wtree *tree, struct vis_wtree_live *lv,
			  const struct candidate *c)
{
	if (c->state == VIS_WTREE_STATE_NONE || c->seen.n == 0)
		return 0;
	/* c lies in lv->cands, which take() may move: read first. */
	const struct vis_window *w = c->w;
	pixman_region32_t u;
	if (!seen_region(&u, &c->seen, tree->root.clip)) {
		errno = ENOMEM;
		return -1;
	}
	const struct seen *old = wtree_live_old_seen(lv, w);
	bool ok = true;
	/*
	 * Not when windows with looks are indexed: a window seen through one it moved above hides
	 * from it now pixels it saw before too. Nor when it had a look, then or now: it may hide now
	 * what it saw through before.
	 */
	if (old && seen_exact(old) && wtree_live_kept_parent(w) && !lv->n_looks && !w->live_look &&
	    !w->live_looked)
		ok = subtract_seen(&u, old, tree->root.clip);
	int rc = -1;
	if (ok) {
		/*
		 * The walk, while it costs less than reading the seen grid there would: a step
		 * costs what 40-80 entries do (cascades at 10^5: the grid's walks list only
		 * windows whose clip may meet their box, nearly each a cut), and most walks end
		 * within a hundred steps. The hand-over that fitted walks listing every window of
		 * their cells (512 steps plus a sixteenth of the entries) let a cascade's heaviest
		 * raises reach 0.77 ms at the 99th percentile once they no longer did; this one,
		 * 0.58 ms, the medians within noise.
		 */
		if (lv->seen_grid_ok)
			lv->give_up = lv->steps + (lv->cover_steps ? lv->cover_steps
								   : seen_entries(lv, &u) / 64 + 128);
		rc = walk_boxes(lv, &u, w->key, true, false, 0, NULL);
		lv->give_up = SIZE_MAX;
		if (rc == GAVE_UP) {
			wtree_live_seen_flush(lv);
			rc = cover_by_seen(lv, &u, w->key);
		}
	}
	pixman_region32_fini(&u);
	if (!ok)
		errno = ENOMEM;
	return rc;
}

/*
 * Takes the windows that may see pixels e's window saw (rule 3), and adds the pixels they may
 * gain to exposed: what it saw less what it sees now, when that is exact and its subtree kept
 * its parent (a window that still sees a pixel hides it as before, wtree.h), else all it saw.
 * 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_exposed(struct vis_wtree *tree, struct vis_wtree_live *lv,
			    const struct exposure *e, void *exposed)
{
	if (e->seen.n == 0)
		return 0;
	pixman_region32_t u;
	if (!seen_region(&u, &e->seen, tree->root.clip)) {
		errno = ENOMEM;
		return -1;
	}
	bool ok = true;
	/* Not when windows with looks are indexed: one it moved below sees through it what it
	 * hid. Nor when it had a look, then or now: it may no longer hide what it still sees. */
	if (e->w && moved(lv, e->w) && wtree_live_kept_parent(e->w) && !lv->n_looks &&
	    !e->w->live_look && !e->w->live_looked) {
		const struct candidate *now = &lv->cands[e->w->live_cand - 1];
		if (now->state != STATE_UNKNOWN && seen_exact(&now->seen))
			ok = subtract_seen(&u, &now->seen, tree->root.clip);
	}
	ok = ok && pixman_region32_union(exposed, exposed, &u);
	int rc = ok ? walk_boxes(lv, &u, e->key, false, seen_exact(&e->seen), 0, NULL) : -1;
	pixman_region32_fini(&u);
	if (!ok)
		errno = ENOMEM;
	return rc;
}

/* Past this many changed windows, each candidate's query walks the grid over all its pixels. */
#define SINCE_MOVED_MAX 32

/* The edges of a loose seen box of w that no changed clip now after w's subtree meets. */
static unsigned surviving_edges(const struct vis_wtree_live *lv, const struct candidate *c,
				const struct seen *old)
{
	pixman_box32_t e = old->boxes[0];
	unsigned edges = old->edges;
	uint64_t end = wtree_live_subtree_end(c->w);
	for (size_t i = 0; edges && i < lv->n_moved; i++) {
		const struct vis_window *v = lv->cands[i].w;
		if (!v->live_indexed || v->key <= end)
			continue;
		pixman_box32_t k = lv->slots[v->live_slot].clip;
		if (k.y1 < e.y2 && e.y1 < k.y2) {
			if (k.x1 <= e.x1 && e.x1 < k.x2)
				edges &= ~(unsigned)EDGE_LEFT;
			if (k.x1 < e.x2 && e.x2 <= k.x2)
				edges &= ~(unsigned)EDGE_RIGHT;
		}
		if (k.x1 < e.x2 && e.x1 < k.x2) {
			if (k.y1 <= e.y1 && e.y1 < k.y2)
				edges &= ~(unsigned)EDGE_TOP;
			if (k.y1 < e.y2 && e.y2 <= k.y2)
				edges &= ~(unsigned)EDGE_BOTTOM;
		}
	}
	return edges;
}

/*
 * A window that may only lose pixels (rule 2 alone), partially obscured, whose seen region is
 * loose: a box, with edges known to hold pixels it saw. Those pixels it still sees, unless a
 * changed window now after its subtree covers them: while one such edge meets no changed clip,
 * it sees some pixel still, and not its whole box (which a loose region never was), so it stays
 * partially obscured, and the box still holds what it sees. Returns whether that settled it.
 */
static bool keeps_an_edge(const struct vis_wtree_live *lv, struct candidate *c,
			  const struct seen *old)
{
	if (c->gain || c->w->state != VIS_PARTIALLY_OBSCURED || !old->edges)
		return false;
	unsigned edges = surviving_edges(lv, c, old);
	if (!edges)
		return false;
	c->state = VIS_PARTIALLY_OBSCURED;
	c->seen = *old;
	c->seen.edges = (uint8_t)edges;
	return true;
}

/* The cells settle_loose() walks, with pixels of the window, before it leaves it to its query. */
#define SETTLE_CELLS 4

/* The windows above a window hides_one() looks at before it gives up. */
#define HIDER_STEPS 64

/*
 * Whether an unchanged window after w's subtree (end its last key), without a look, holds a
 * pixel of w in its clip: it hides that pixel now, so w is not unobscured. Looks at the first
 * HIDER_STEPS windows above w in the grid over w's clip: 1, 0 (none found there), or -1
 * (ENOMEM).
 */
static int hides_one(struct vis_wtree_live *lv, const struct vis_window *w, uint64_t end)
{
	bool ok = true;
	const struct vis_look_cut *cut = wtree_live_has_look(w) ? cut_of(w, &ok) : NULL;
	struct vis_zgrid_walk walk;
	if (!ok || vis_zgrid_walk_init(&walk, &lv->grid, w->clip, end, true) < 0) {
		errno = ENOMEM;
		return -1;
	}
	pixman_box32_t clip = pbox(w->clip);
	uint64_t key;
	uint32_t slot;
	int found = 0;
	for (int steps = 0; !found && steps < HIDER_STEPS && vis_zgrid_walk_next(&walk, &key, &slot);
	     steps++) {
		lv->steps++;
		const struct live_slot *s = &lv->slots[slot];
		if (s->look || !boxes_meet(&s->clip, &clip) || moved(lv, s->w))
			continue;
		found = !cut; /* without a cut, w's pixels are its clip */
		for (uint32_t k = 0; !found && cut && k < cut->n; k++) {
			pixman_box32_t b;
			found = piece_of(w, cut, k, &b) && boxes_meet(&b, &s->clip);
		}
	}
	vis_zgrid_walk_finish(&walk);
	return found;
}

/*
 * For a window whose last seen region is loose and which an unchanged window above it hides in
 * part (hides_one()): partially obscured if it sees a pixel anywhere, found a grid cell at a time,
 * the first cell with one ending the search. What a cell shows is walked
 * as a query would, but a query of a large window under many small ones walks them all: a
 * screen-size backdrop under 10,000 windows went over the update's budget at every change that
 * took it. Its seen region stays loose: the extents of its pixels, with the edges the pixels
 * found touch. Only for a window over several cells, and within SETTLE_CELLS of them (a window
 * most of which is hidden, a parent under its descendants in a deep tree, is left to its query).
 * 1 when that settled it, 0 (its query must), -1 (ENOMEM) or OVER_BUDGET.
 */
static int settle_loose(struct vis_wtree_live *lv, struct candidate *c)
{
	const struct vis_window *w = c->w;
	uint32_t r[4];
	/* Within a cell, the query is the same walk. */
	if (!vis_zgrid_cells(&lv->grid, w->clip, r) || (r[0] == r[2] && r[1] == r[3]))
		return 0;
	uint64_t end = wtree_live_subtree_end(w);
	int rc = hides_one(lv, w, end);
	if (rc <= 0)
		return rc;
	pixman_region32_t u;
	if (!pixels_of(w, &u)) {
		pixman_region32_fini(&u);
		errno = ENOMEM;
		return -1;
	}
	pixman_box32_t box = *pixman_region32_extents(&u);
	uint8_t edges = 0;
	bool found = false;
	unsigned tried = 0;
	rc = 0;
	for (uint32_t y = r[1]; rc == 0 && !found && tried < SETTLE_CELLS && y <= r[3]; y++)
		for (uint32_t x = r[0]; rc == 0 && !found && tried < SETTLE_CELLS && x <= r[2];
		     x++) {
			pixman_box32_t cell = pbox(vis_zgrid_cell_box(&lv->grid, x, y));
			pixman_region32_t piece;
			pixman_region32_init_rect(&piece, cell.x1, cell.y1,
						  (unsigned)(cell.x2 - cell.x1),
						  (unsigned)(cell.y2 - cell.y1));
			bool hit;
			if (!pixman_region32_intersect(&piece, &piece, &u)) {
				errno = ENOMEM;
				rc = -1;
			} else if (pixman_region32_not_empty(&piece)) {
				tried++;
				rc = hide(lv, end, &piece, &hit, &lv->steps, lv->budget);
				found = rc == 0 && pixman_region32_not_empty(&piece);
			}
			if (found) {
				const pixman_box32_t *e = pixman_region32_extents(&piece);
				edges = (uint8_t)((e->x1 == box.x1 ? EDGE_LEFT : 0) |
						  (e->y1 == box.y1 ? EDGE_TOP : 0) |
						  (e->x2 == box.x2 ? EDGE_RIGHT : 0) |
						  (e->y2 == box.y2 ? EDGE_BOTTOM : 0));
			}
			pixman_region32_fini(&piece);
		}
	pixman_region32_fini(&u);
	if (rc != 0 || !found)
		return rc; /* none in the cells tried: the query looks at all of them at once */
	c->state = VIS_PARTIALLY_OBSCURED;
	c->seen = (struct seen){ SEEN_EXTENTS, edges, { box } };
	return 1;
}

/*
 * walk_since() for one taken by rule 2 alone, whose seen region is exact: what it saw less the
 * clips of the changed windows now after its subtree, cut as boxes (a raise over a cascade
 * covers thousands of windows' slivers whole, each a few boxes: no region for those).
 */
static int since_losing(struct vis_wtree_live *lv, struct candidate *c, const struct seen *old)
{
	const struct vis_window *w = c->w;
	if (!old) {
		settle(lv, c, NULL); /* it saw nothing, and gains nothing */
		return 0;
	}
	uint64_t end = wtree_live_subtree_end(w);
	/* The common answers first: each box under one changed clip (a raise covering slivers
	 * whole), or none met. */
	bool all_under = true, none_met = true;
	for (int i = 0; i < old->n && (all_under || none_met); i++) {
		const pixman_box32_t *b = &old->boxes[i];
		bool under = false;
		for (size_t j = 0; j < lv->n_moved; j++) {
			const struct vis_window *v = lv->cands[j].w;
			if (!v->live_indexed || v->key <= end)
				continue;
			const struct live_slot *s = &lv->slots[v->live_slot];
			if (boxes_meet(&s->clip, b)) {
				none_met = false;
				under |= !s->look && vis_box_contains(vbox(&s->clip), vbox(b));
			}
		}
		all_under &= under;
	}
	if (all_under) {
		settle(lv, c, NULL);
		return 0;
	}
	if (none_met) {
		c->state = w->state;
		c->seen = *old;
		return 0;
	}
	pixman_region32_t u;
	pixman_region32_init(&u);
	/* Unchanged, it kept its clip, which holds what it saw (and is not read: another line). */
	pixman_box32_t b[SEEN_BOXES];
	size_t n = 0;
	for (int i = 0; i < old->n; i++)
		if (old->boxes[i].x1 < old->boxes[i].x2 && old->boxes[i].y1 < old->boxes[i].y2)
			b[n++] = old->boxes[i];
	struct left l; /* not zeroed: 1 KiB */
	l.u = &u;
	l.cap = lv->left_boxes;
	bool ok = true;
	if (n > l.cap / 2) {
		ok = pixman_region32_init_rects(&u, b, (int)n);
		l.n = LEFT_REGION;
	} else {
		left_set(&l, b, n);
	}
	for (size_t i = 0; ok && i < lv->n_moved && !left_empty(&l); i++) {
		const struct vis_window *v = lv->cands[i].w;
		if (v->live_indexed && v->key > end)
			left_cut_slot(&l, &lv->slots[v->live_slot], NULL, &ok);
	}
	ok = left_finish(&l) && ok;
	return finish(lv, c, &u, 0, ok);
}

int wtree_live_walk_since(struct vis_wtree_live *lv, struct candidate *c, void *exposed)
{
	const struct vis_window *w = c->w;
	const struct seen *old = wtree_live_old_seen(lv, w);
	/* An indexed window's clip is not empty (and a line away: not read for those). */
	if (lv->n_moved > SINCE_MOVED_MAX || (!w->live_indexed && vis_box_empty(w->clip)))
		return wtree_live_walk_query(lv, c);
	if (old && !seen_exact(old)) {
		if (keeps_an_edge(lv, c, old))
			return 0;
		int settled = settle_loose(lv, c);
		return settled != 0 ? (settled > 0 ? 0 : settled) : wtree_live_walk_query(lv, c);
	}
	if (!c->gain)
		return since_losing(lv, c, old);
	pixman_region32_t u;
	bool ok = old ? seen_region(&u, old, w->clip) : (pixman_region32_init(&u), true);
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	/* What rule 3's walks listed as seen of the exposed pixels, for one without descendants
	 * (it may gain pixels: one that cannot went to since_losing()). */
	bool look = wtree_live_has_look(w);
	bool listed = w->live_leaf && !c->unlisted && !look;
	for (uint32_t g = listed ? c->gained : 0; ok && g; g = lv->gains[g - 1].next) {
		pixman_box32_t b = pbox(lv->gains[g - 1].box);
		ok = pixman_region32_union_rect(&u, &u, b.x1, b.y1, (unsigned)(b.x2 - b.x1),
						(unsigned)(b.y2 - b.y1));
	}
	/* Less what changed windows now hide: no unchanged window above it hid those pixels. */
	uint64_t end = wtree_live_subtree_end(w);
	for (size_t i = 0; ok && i < lv->n_moved && pixman_region32_not_empty(&u); i++) {
		const struct vis_window *v = lv->cands[i].w;
		if (v->live_indexed && v->key > end)
			cut_window(&u, v, &ok);
	}
	/* Else what it sees of the exposed pixels, by walking the grid over those alone. */
	int rc = 0;
	if (ok && !listed) {
		pixman_region32_t g;
		if (look)
			ok = pixels_of(w, &g);
		else
			init_box(&g, w->clip);
		ok = ok && pixman_region32_intersect(&g, &g, exposed);
		bool hit;
		if (ok && pixman_region32_not_empty(&g))
			rc = hide(lv, end, &g, &hit, &lv->steps, lv->budget);
		ok = ok && rc == 0 && pixman_region32_union(&u, &u, &g);
		pixman_region32_fini(&g);
	}
	return finish(lv, c, &u, rc, ok);
}

/* The union of the clips above, in one cell of the grid; full once it is the whole cell. */
struct cell_above {
	pixman_region32_t above;
	bool full;
};

/* A window with a look's pixels and those of them that hide, as regions. */
struct look_regions {
	pixman_region32_t pixels, opaque;
};

/*
 * Adds the part of w's clip in cell c to what lies above there; if u, first adds to u what that
 * part shows. For a window with a look (lr), its pixels there show and its opaque ones hide.
 * The work: the boxes read. false without memory.
 */
static bool seen_in_cell(struct cell_above *c, struct vis_box cell, const struct vis_window *w,
			 struct look_regions *lr, pixman_region32_t *u, uint64_t *work)
{
	pixman_box32_t b = pbox(vis_box_intersect(w->clip, cell));
	unsigned width = (unsigned)(b.x2 - b.x1), height = (unsigned)(b.y2 - b.y1);
	uint64_t boxes = (uint64_t)pixman_region32_n_rects(&c->above);
	bool ok = true;
	if (u) {
		pixman_region32_t part;
		pixman_region32_init_rect(&part, b.x1, b.y1, width, height);
		ok = (!lr || pixman_region32_intersect(&part, &part, &lr->pixels)) &&
		     pixman_region32_subtract(&part, &part, &c->above) &&
		     pixman_region32_union(u, u, &part);
		pixman_region32_fini(&part);
		*work += 1 + boxes;
	}
	*work += 1 + boxes;
	if (lr) {
		pixman_region32_t hides;
		pixman_region32_init_rect(&hides, b.x1, b.y1, width, height);
		ok = ok && pixman_region32_intersect(&hides, &hides, &lr->opaque) &&
		     pixman_region32_union(&c->above, &c->above, &hides);
		pixman_region32_fini(&hides);
	} else {
		ok = ok && pixman_region32_union_rect(&c->above, &c->above, b.x1, b.y1, width,
						      height);
	}
	const pixman_box32_t *e = pixman_region32_extents(&c->above);
	if (ok && pixman_region32_n_rects(&c->above) == 1 && e->x1 == cell.x1 && e->y1 == cell.y1 &&
	    e->x2 == cell.x2 && e->y2 == cell.y2) {
		c->full = true; /* nothing below shows here */
		pixman_region32_fini(&c->above);
		pixman_region32_init(&c->above);
	}
	return ok;
}

/*
 * The region method, a grid cell at a time: a union of clips cut by cells has the boxes of its
 * cell alone (a cascade's union of all the windows above has hundreds), and a cell once covered
 * is passed over by every window below, which in a cascade is most cells for most windows.
 */
int wtree_live_seen_from_order(const struct vis_wtree *tree, struct vis_wtree_live *lv,
			       uint64_t budget)
{
	const struct vis_zgrid *g = &lv->grid;
	size_t n_cells = (size_t)g->cols * g->rows;
	struct cell_above *cells = calloc(n_cells, sizeof *cells);
	if (!cells) {
		errno = ENOMEM;
		return -1;
	}
	for (size_t c = 0; c < n_cells; c++)
		pixman_region32_init(&cells[c].above);
	pixman_region32_t u;
	pixman_region32_init(&u);
	uint64_t work = 0;
	bool ok = true;
	for (size_t i = tree->n_order; ok && work <= budget && i-- > 0;) {
		const struct vis_window *w = tree->order[i];
		uint32_t r[4];
		if (!w->live_indexed || !vis_zgrid_cells(g, w->clip, r))
			continue;
		/* Its descendants, which never hide it, lie above it already: only windows without
		 * any get their seen region. */
		bool leaf = w->live_seen && w->live_leaf;
		struct look_regions lr, *look = w->live_look ? &lr : NULL;
		if (look) {
			ok = pieces_region(w, &lr.pixels, false);
			ok = pieces_region(w, &lr.opaque, true) && ok;
		}
		pixman_region32_clear(&u);
		for (uint32_t y = r[1]; ok && y <= r[3]; y++)
			for (uint32_t x = r[0]; ok && x <= r[2]; x++) {
				struct cell_above *c = &cells[(size_t)y * g->cols + x];
				if (!c->full)
					ok = seen_in_cell(c, vis_zgrid_cell_box(g, x, y), w, look,
							  leaf ? &u : NULL, &work);
			}
		if (look) {
			pixman_region32_fini(&lr.pixels);
			pixman_region32_fini(&lr.opaque);
		}
		if (ok && leaf)
			keep_seen(lv, &u, &lv->seen[w->live_seen - 1].seen);
	}
	for (size_t c = 0; c < n_cells; c++)
		pixman_region32_fini(&cells[c].above);
	free(cells);
	pixman_region32_fini(&u);
	if (!ok)
		errno = ENOMEM;
	return ok ? 0 : -1;
}

int wtree_live_walk_moved(struct vis_wtree_live *lv, struct candidate *c, struct vis_box old_clip)
{
	const struct vis_window *w = c->w;
	const struct seen *old = wtree_live_old_seen(lv, w);
	if ((old && !seen_exact(old)) || vis_box_empty(w->clip))
		return wtree_live_walk_query(lv, c);
	pixman_region32_t u, rest;
	bool ok = old ? seen_region(&u, old, w->clip) : (pixman_region32_init(&u), true);
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	init_box(&rest, w->clip);
	if (!vis_box_empty(old_clip)) {
		pixman_region32_t r;
		init_box(&r, old_clip);
		ok = pixman_region32_subtract(&rest, &rest, &r);
		pixman_region32_fini(&r);
	}
	/* The pixels new to its clip, a box at a time: hide() narrows to what is left's extents. */
	int rc = 0, n = 0;
	const pixman_box32_t *boxes = ok ? pixman_region32_rectangles(&rest, &n) : NULL;
	uint64_t end = wtree_live_subtree_end(w);
	for (int i = 0; ok && rc == 0 && i < n; i++) {
		pixman_region32_t g;
		init_box(&g, vbox(&boxes[i]));
		bool hit;
		rc = hide(lv, end, &g, &hit, &lv->steps, lv->budget);
		ok = rc != 0 || pixman_region32_union(&u, &u, &g);
		pixman_region32_fini(&g);
	}
	pixman_region32_fini(&rest);
	return finish(lv, c, &u, rc, ok);
}

int wtree_live_walk_lowered(struct vis_wtree_live *lv, struct candidate *c, struct exposure *e,
			    void *exposed)
{
	const struct vis_window *w = c->w;
	const struct seen *old = wtree_live_old_seen(lv, w);
	if (!old) {
		settle(lv, c, NULL); /* hidden above, hidden below */
		return 0;
	}
	if (!seen_exact(old) || !e)
		return wtree_live_walk_query(lv, c);
	size_t at = (size_t)(c - lv->cands); /* the walks take windows, which may move cands */
	/* What it saw, a box at a time: each walk is narrowed to what is left of its box. */
	pixman_region32_t saw, sees;
	if (!seen_region(&saw, old, w->clip)) {
		errno = ENOMEM;
		return -1;
	}
	pixman_region32_init(&sees);
	int rc = walk_boxes(lv, &saw, e->key, false, true, w->key, &sees);
	bool ok = true;
	/* The windows between its keys were taken, with the pixels each gains: the exposure is
	 * walked, and what it saw less what it sees is exposed for the other queries. */
	/* While windows with looks are indexed, one it went below may see through to it and gain
	 * pixels it still sees: all it saw is exposed. */
	if (rc == 0) {
		e->seen.n = 0;
		ok = (lv->n_looks || pixman_region32_subtract(&saw, &saw, &sees)) &&
		     pixman_region32_union(exposed, exposed, &saw);
	}
	pixman_region32_fini(&saw);
	return finish(lv, &lv->cands[at], &sees, rc, ok);
}
