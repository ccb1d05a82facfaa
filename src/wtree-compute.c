/* The window tree's states, visible regions and repaint sets, computed with the core's engines. */
#include <errno.h>
#include <pixman.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "look.h"
#include "wtree.h"

/*
 * The scratch of a recompute, kept in the tree from one recompute to the next: the arrays are
 * carved out of one block, allocated again only when the tree outgrows it. The arrays indexed by
 * position in the order (cap ≥ the viewable windows) copy what the passes after flattening read,
 * so that those passes stream through memory instead of visiting windows: only flattening visits
 * every window, and only the windows whose state changes are visited again. affected lists the
 * positions of the windows whose states are recomputed, bottom to top; hidden, the windows that
 * are not viewable but whose state or old_state is not "none", the only ones outside the order
 * whose states change.
 *
 * Windows whose pixels are not their whole box, all opaque (a shape, an opaque region other than
 * all, input-only: CLEAR) are cut into pieces (look.h) for the engine; while no viewable window is
 * CLEAR (n_clear = 0), every window is one rectangle and the pieces are never touched.
 */
struct vis_wtree_work {
	void *block;
	size_t cap;
	struct vis_box *clips;  /* per position: the window's clip */
	size_t *index;          /* each input rectangle's position */
	size_t *affected, n_affected;
	struct vis_window **hidden;
	size_t n_hidden;
	struct vis_rect *rects; /* the engine's input (cap + 4: a lookup adds up to 4 boxes) */
	uint32_t *depths;       /* per position: its depth */
	uint8_t *flags;         /* per position: the flags below */
	uint8_t *last;          /* per position: its state from the last recompute */
	uint8_t *old;           /* per position: its old_state before this recompute, to undo */
	uint8_t *raw;           /* per position: the state before the box rule (X's comparison) */
	uint8_t *level;         /* per position: the result of one depth's sweep */
	uint8_t *states;        /* the engine's output (cap + 4) */
	size_t n_clear;         /* viewable CLEAR windows */
	struct vis_pieces pieces;  /* the engine's input when some are */
	uint8_t *piece_states;     /* its output, cap_piece_states long */
	size_t cap_piece_states;
};

enum {
	CHANGED = 1,  /* new to the order, or its box or clip is not the last recompute's */
	CUT = 2,      /* its clip is not its box: unless shaped, it is never unobscured */
	CHILDREN = 4, /* it has viewable children with pixels that can be seen */
	PARENT = 8,   /* affected, with children: its own sweep without its depth's children */
	SCAN = 16,    /* last partially obscured: what covers it outside within is looked up */
	CLEAR = 32,   /* its pixels are not its whole box, all opaque (a shape, see-through, none) */
	INPUT = 64,   /* input-only: no pixels, no state, never affected */
};

/* Whether a look leaves the window's pixels other than its whole border box, all opaque. */
static bool look_clear(const struct vis_look *look)
{
	return look->input_only || look->shaped || look->opaque != VIS_OPAQUE_ALL;
}

/*
 * How many windows the lookups of SCAN windows may visit in all, per viewable window, before the
 * others grow within instead: the lookups cost O(n) at most, a few nanoseconds a visit, about what
 * flattening costs a window, while growing within costs engine work, up to the full recompute's.
 * Measured with bench-wtree (medians after one move): the partially obscured windows of a desktop
 * are the few near its top, and 1 to 64 take them all (0 costs random desktops 10%); on cascades
 * and tiles, where most windows are partially obscured, 0 to 16 are within the noise, and 64
 * makes a move on a 1,000-window cascade 2.5 times slower.
 */
#define SCAN_VISITS_PER_WINDOW 4

/*
 * Makes room in wk for count windows, keeping its block when it is large enough and doubling it
 * at least otherwise. 0, or -1 with ENOMEM (wk is then as it was).
 */
static int work_reserve(struct vis_wtree_work *wk, size_t count)
{
	if (wk->block && count <= wk->cap)
		return 0;
	size_t n = count > 2 * wk->cap ? count : 2 * wk->cap;
	n = n ? n : 1;
	/* Widest first, so that every array is aligned: the sizes above rects are multiples of 8. */
	size_t per = sizeof *wk->clips + sizeof *wk->index + sizeof *wk->affected +
		     sizeof *wk->hidden + sizeof *wk->rects + sizeof *wk->depths + 6;
	size_t extra = 4 * (sizeof *wk->rects + 1);
	char *b = n <= (SIZE_MAX - extra) / per ? malloc(n * per + extra) : NULL;
	if (!b) {
		errno = ENOMEM;
		return -1;
	}
	free(wk->block);
	wk->block = b;
	wk->cap = n;
	wk->clips = (struct vis_box *)(void *)b;
	b += n * sizeof *wk->clips;
	wk->index = (size_t *)(void *)b;
	b += n * sizeof *wk->index;
	wk->affected = (size_t *)(void *)b;
	b += n * sizeof *wk->affected;
	wk->hidden = (struct vis_window **)(void *)b;
	b += n * sizeof *wk->hidden;
	wk->rects = (struct vis_rect *)(void *)b;
	b += (n + 4) * sizeof *wk->rects;
	wk->depths = (uint32_t *)(void *)b;
	b += n * sizeof *wk->depths;
	uint8_t **bytes[] = { &wk->flags, &wk->last, &wk->old, &wk->raw, &wk->level, &wk->states };
	for (size_t k = 0; k < sizeof bytes / sizeof *bytes; k++) {
		*bytes[k] = (uint8_t *)b;
		b += n;
	}
	return 0;
}

void vis_wtree_work_destroy(struct vis_wtree_work *work)
{
	if (work) {
		free(work->block);
		vis_pieces_finish(&work->pieces);
		free(work->piece_states);
	}
	free(work);
}

/* The pre-order successor of w among viewable windows: unmapped subtrees are skipped. */
static struct vis_window *next_viewable(struct vis_window *w)
{
	if (w->mapped && w->bottom)
		return w->bottom;
	for (; w->parent; w = w->parent)
		if (w->above)
			return w->above;
	return NULL;
}

static bool box_equal(struct vis_box a, struct vis_box b)
{
	return a.x1 == b.x1 && a.y1 == b.y1 && a.x2 == b.x2 && a.y2 == b.y2;
}

/* Whether two boxes share a pixel; without branches, as it decides at random in hot loops. */
static bool meets(struct vis_box a, struct vis_box b)
{
	return ((a.x1 > b.x1 ? a.x1 : b.x1) < (a.x2 < b.x2 ? a.x2 : b.x2)) &
	       ((a.y1 > b.y1 ? a.y1 : b.y1) < (a.y2 < b.y2 ? a.y2 : b.y2));
}

/* The smallest box holding a and b (a may be empty). */
static struct vis_box box_hull(struct vis_box a, struct vis_box b)
{
	if (vis_box_empty(a))
		return b;
	return (struct vis_box){ a.x1 < b.x1 ? a.x1 : b.x1, a.y1 < b.y1 ? a.y1 : b.y1,
				 a.x2 > b.x2 ? a.x2 : b.x2, a.y2 > b.y2 ? a.y2 : b.y2 };
}

/*
 * The part of flatten() for a window with a border or CLEAR: its inner box, its flags (an
 * input-only window is never CHANGED, its state being always "none"). Returns whether it is CLEAR.
 */
static bool flatten_look(struct vis_window *w, uint8_t *flags)
{
	int64_t b = w->look.border;
	struct vis_box in = { w->box.x1 + b, w->box.y1 + b, w->box.x2 - b, w->box.y2 - b };
	w->inner = vis_box_intersect(in, w->clip);
	if (!look_clear(&w->look))
		return false;
	*flags |= CLEAR;
	if (w->look.input_only)
		*flags = (uint8_t)((*flags & ~CHANGED) | INPUT);
	return true;
}

/*
 * Lists the viewable windows in pre-order with their absolute and clipped boxes, and fills the
 * per-position arrays of wk; moves each one's state to old_state (wk->old keeps what it replaces);
 * flags CHANGED the windows new to the order or whose boxes moved (a window other than input-only
 * has a state other than "none" exactly when the last recompute found it viewable and set its
 * boxes); lists the hidden windows of wk.
 *
 * X's geometry: a window's border box starts at its parent's inside's corner + (x, y); its clip is
 * that box clipped to the parent's inner box (the screen for top-level windows), and its inner box,
 * which its children are clipped to, is its inside so clipped. X clips children to a shaped
 * parent's bounding shape too; here they are clipped to its inside's box only.
 */
static int flatten(struct vis_wtree *tree, struct vis_wtree_work *wk)
{
	if (tree->cap_order < tree->count) {
		struct vis_window **order = realloc(tree->order, tree->count * sizeof *order);
		if (!order)
			return -1;
		tree->order = order;
		tree->cap_order = tree->count;
	}
	size_t n = 0, n_clear = 0;
	wk->n_hidden = 0;
	for (struct vis_window *w = tree->root.bottom; w; w = next_viewable(w)) {
		if (!w->mapped) {
			for (struct vis_window *v = w; v; v = vis_wtree_next_within(v, w))
				if (v->state != VIS_WTREE_STATE_NONE ||
				    v->old_state != VIS_WTREE_STATE_NONE)
					wk->hidden[wk->n_hidden++] = v;
			continue;
		}
		const struct vis_window *p = w->parent;
		int64_t b = w->look.border;
		struct vis_box box = { p->box.x1 + p->look.border + w->x,
				       p->box.y1 + p->look.border + w->y, 0, 0 };
		box.x2 = box.x1 + w->width + 2 * b;
		box.y2 = box.y1 + w->height + 2 * b;
		struct vis_box clip = vis_box_intersect(box, p->inner);
		uint8_t last = w->state;
		bool changed = last == VIS_WTREE_STATE_NONE || !box_equal(box, w->box) ||
			       !box_equal(clip, w->clip);
		w->box = box;
		w->clip = clip;
		w->inner = clip;
		w->pos = n;
		wk->old[n] = w->old_state;
		w->old_state = last;
		wk->last[n] = last;
		wk->clips[n] = clip;
		wk->depths[n] = w->depth;
		wk->flags[n] = (uint8_t)((changed ? CHANGED : 0) | (box_equal(box, clip) ? 0 : CUT));
		/* A look costs plain windows one test. */
		if (b || look_clear(&w->look))
			n_clear += flatten_look(w, &wk->flags[n]);
		/* The parent, viewable, is already in the order. */
		if (p->parent && !vis_box_empty(clip))
			wk->flags[p->pos] |= CHILDREN;
		tree->order[n++] = w;
	}
	tree->n_order = n;
	wk->n_clear = n_clear;
	return 0;
}

/* Puts old_state back as it was before flatten(). */
static void unflatten(struct vis_wtree *tree, const struct vis_wtree_work *wk)
{
	for (size_t i = 0; i < tree->n_order; i++)
		tree->order[i]->old_state = wk->old[i];
}

static struct vis_rect box_rect(struct vis_box b)
{
	return (struct vis_rect){ (int32_t)b.x1, (int32_t)b.y1, (int32_t)(b.x2 - b.x1),
				  (int32_t)(b.y2 - b.y1) };
}

/* Makes room for n piece states. 0, or -1 with ENOMEM. */
static int reserve_piece_states(struct vis_wtree_work *wk, size_t n)
{
	if (n < wk->cap_piece_states)
		return 0;
	size_t cap = n + 1 > 2 * wk->cap_piece_states ? n + 1 : 2 * wk->cap_piece_states;
	uint8_t *s = realloc(wk->piece_states, cap);
	if (!s) {
		errno = ENOMEM;
		return -1;
	}
	wk->piece_states = s;
	wk->cap_piece_states = cap;
	return 0;
}

/*
 * Adds window w, at position i, clipped to c, to wk's pieces, numbered i: its look's pieces (none
 * for an input-only window), or c for a window whose pixels are its whole box, all opaque.
 */
static int add_pieces(struct vis_wtree_work *wk, const struct vis_window *w, size_t i,
		      struct vis_box c)
{
	if (!look_clear(&w->look))
		return vis_pieces_add(&wk->pieces, NULL, c, c, (uint32_t)i) < 0 ? -1 : 0;
	return vis_pieces_add(&wk->pieces, &w->look, w->box, c, (uint32_t)i) < 0 ? -1 : 0;
}

/* A window's state from the bits (1 << state) of its pieces' states; none: no pixels. */
static uint8_t join(unsigned met)
{
	if (met == 1u << VIS_UNOBSCURED)
		return VIS_UNOBSCURED;
	if (met == 0 || met == 1u << VIS_FULLY_OBSCURED)
		return VIS_FULLY_OBSCURED;
	return VIS_PARTIALLY_OBSCURED;
}

/*
 * Runs the default engine over wk's pieces and joins their states into state_of[pos] of the
 * windows they belong to (each one's pieces are consecutive); windows without pieces keep theirs.
 */
static int run_pieces(struct vis_wtree_work *wk, uint8_t *state_of)
{
	struct vis_pieces *p = &wk->pieces;
	size_t m = p->stack.n;
	if (reserve_piece_states(wk, m) < 0)
		return -1;
	p->stack.rects = p->rects;
	p->stack.see_through = p->see_through;
	if (vis_compute(VIS_ENGINE_AUTO, &p->stack, wk->piece_states) < 0)
		return -1;
	for (size_t k = 0; k < m;) {
		uint32_t i = p->window[k];
		unsigned met = 0;
		for (; k < m && p->window[k] == i; k++)
			met |= 1u << wk->piece_states[k];
		state_of[i] = join(met);
	}
	return 0;
}

/* Adds the window at position i, clipped to within, to the engine's input: a box or pieces. */
static inline int add(const struct vis_wtree *tree, struct vis_wtree_work *wk, bool pieces,
		      size_t i, struct vis_box within, size_t *m)
{
	struct vis_box c = vis_box_intersect(wk->clips[i], within);
	if (vis_box_empty(c))
		return 0;
	if (pieces)
		return add_pieces(wk, tree->order[i], i, c);
	wk->rects[*m] = box_rect(c);
	wk->index[(*m)++] = i;
	return 0;
}

/*
 * Whether the window at position i, not top-level, lies in its parent's pixels, all opaque (its
 * parent is not CLEAR), so that it hides nothing its parent does not.
 */
static bool covered(const struct vis_wtree *tree, const struct vis_wtree_work *wk, size_t i)
{
	return !(wk->flags[tree->order[i]->parent->pos] & CLEAR);
}

/*
 * Runs the default engine over the windows of wk at positions first … n − 1 with pixels inside
 * within, each clipped to within; writes each one's state (its pixels' inside within) to
 * state_of[pos] (fully obscured for the others, and those below first). With max_depth 0, over
 * all of them in pre-order: exact for windows without children. With max_depth d, exact for the
 * windows at depth d, whose descendants must not hide them while the later windows' must: each
 * window at depth d goes above its descendants, which keep their place above the windows before
 * it. A descendant that its parent's pixels hold, all opaque (covered()), hides nothing more than
 * the parent and is left out: without CLEAR windows, every window deeper than d is.
 * With pieces, CLEAR windows are cut into pieces (look.h) and input-only ones have none; without,
 * there are none and every window is one rectangle.
 */
static int sweep(const struct vis_wtree *tree, struct vis_wtree_work *wk, bool pieces,
		 size_t first, size_t n, uint32_t max_depth, struct vis_box within,
		 uint8_t *state_of)
{
	size_t m = 0;
	memset(state_of, VIS_FULLY_OBSCURED, n);
	if (pieces)
		vis_pieces_reset(&wk->pieces);
	for (size_t i = first; i < n;) {
		size_t end = i + 1;
		if (max_depth && wk->depths[i] >= max_depth) {
			/* Its subtree: deeper windows are reached from their ancestor here. */
			while (end < n && wk->depths[end] > max_depth)
				end++;
			for (size_t k = i + 1; pieces && k < end; k++)
				if (!covered(tree, wk, k) && add(tree, wk, pieces, k, within, &m) < 0)
					return -1;
		}
		if (add(tree, wk, pieces, i, within, &m) < 0)
			return -1;
		i = end;
	}
	if (pieces)
		return run_pieces(wk, state_of);
	struct vis_stack stack = { wk->rects, m, false, 0, 0, NULL, NULL };
	if (vis_compute(VIS_ENGINE_AUTO, &stack, wk->states) < 0)
		return -1;
	for (size_t k = 0; k < m; k++)
		state_of[wk->index[k]] = wk->states[k];
	return 0;
}

/*
 * The position of the highest top-level window whose clip holds within and whose pixels are its
 * whole box, all opaque (not CLEAR), or 0. Every window below it is fully obscured inside within
 * (it is none of their descendants); as desktops tend to have such a window near the top, the
 * engines need only the windows from there up.
 */
static size_t cover(const struct vis_wtree_work *wk, size_t n, struct vis_box within)
{
	if (vis_box_empty(within))
		return n;
	for (size_t i = n; i-- > 0;)
		if (wk->depths[i] == 1 && !(wk->flags[i] & CLEAR) &&
		    vis_box_contains(wk->clips[i], within))
			return i;
	return 0;
}

/*
 * Lists in wk->affected the windows whose state may have changed (never an input-only one, which
 * has none): all of them without damage;
 * else those CHANGED, and those whose clip meets a damage box (see vis_wtree_compute_damaged()),
 * bounds being the hull of the damage on the screen, but for those fully obscured below a
 * top-level window whose clip holds bounds: that window covers their pixels in the damage, and
 * nothing changed elsewhere, so they stay fully obscured (most windows of a desktop).
 */
static void select_affected(const struct vis_wtree *tree, const struct vis_box *damage,
			    size_t n_damage, struct vis_box bounds, struct vis_wtree_work *wk)
{
	size_t n = tree->n_order, k = 0, first = damage ? cover(wk, n, bounds) : 0;
	/*
	 * Whether a window meets the damage is as good as random: no branch on it. Up to a few
	 * boxes are all tested; past that, only for the windows that meet their hull.
	 */
	bool few = n_damage <= 4;
	for (size_t i = 0; i < n; i++) {
		struct vis_box c = wk->clips[i];
		bool hit = (wk->flags[i] & CHANGED) || !damage;
		if (i >= first || wk->last[i] != VIS_FULLY_OBSCURED) {
			if (few || meets(c, bounds))
				for (size_t d = 0; d < n_damage; d++)
					hit |= meets(c, damage[d]);
		}
		wk->affected[k] = i;
		k += hit & !(wk->flags[i] & INPUT);
	}
	wk->n_affected = k;
}

/*
 * Sets wk->raw of every affected window to its state before the box rule, as its pixels inside
 * within (a box inside the screen) alone would have it: fully obscured with none there.
 * A window without visible children takes the sweep over all windows; one with them, the sweep
 * for its depth, in which its descendants do not hide it (see sweep()).
 */
static int classify(const struct vis_wtree *tree, struct vis_box within, struct vis_wtree_work *wk)
{
	size_t n = tree->n_order, first = cover(wk, n, within);
	bool pieces = wk->n_clear > 0;
	if (sweep(tree, wk, pieces, first, n, 0, within, wk->raw) < 0)
		return -1;
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		if (i >= first && (wk->flags[i] & CHILDREN) && meets(wk->clips[i], within))
			wk->flags[i] |= PARENT;
	}
	for (uint32_t depth_done = 0;;) {
		uint32_t next = 0;
		for (size_t a = 0; a < wk->n_affected; a++) {
			size_t i = wk->affected[a];
			uint32_t d = wk->depths[i];
			if ((wk->flags[i] & PARENT) && d > depth_done && (!next || d < next))
				next = d;
		}
		if (!next)
			break;
		if (sweep(tree, wk, pieces, first, n, next, within, wk->level) < 0)
			return -1;
		for (size_t a = 0; a < wk->n_affected; a++) {
			size_t i = wk->affected[a];
			if ((wk->flags[i] & PARENT) && wk->depths[i] == next)
				wk->raw[i] = wk->level[i];
		}
		depth_done = next;
	}
	return 0;
}

/*
 * The box to classify the affected windows in: bounds, the damage on the screen, grown to hold the
 * clips of those whose last state says nothing about their pixels outside it (new or moved, and
 * last partially obscured but past the lookup budget; those within it are flagged SCAN), and of
 * the shaped ones: a shape may leave a window no pixels on one side of within's edge, where its
 * state there would say nothing, so that joining the two sides needs pixels cut out; rather than
 * that, they are classified whole.
 */
static struct vis_box select_within(const struct vis_wtree *tree, struct vis_box bounds,
				    struct vis_wtree_work *wk)
{
	size_t n = tree->n_order;
	struct vis_box within = bounds;
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		if (vis_box_empty(wk->clips[i]))
			continue;
		if ((wk->flags[i] & CHANGED) ||
		    ((wk->flags[i] & CLEAR) && tree->order[i]->look.shaped))
			within = box_hull(within, wk->clips[i]);
		else if (wk->last[i] == VIS_PARTIALLY_OBSCURED)
			wk->flags[i] |= SCAN;
	}
	/* A lookup visits the windows above: the highest are the cheapest. */
	uint64_t budget = (uint64_t)SCAN_VISITS_PER_WINDOW * n;
	for (size_t a = wk->n_affected; a-- > 0;) {
		size_t i = wk->affected[a];
		if (!(wk->flags[i] & SCAN))
			continue;
		if (n - i <= budget) {
			budget -= n - i;
		} else {
			wk->flags[i] &= (uint8_t)~SCAN;
			within = box_hull(within, wk->clips[i]);
		}
	}
	return within;
}

/*
 * The state before the box rule of an affected window whose clip sticks out of within, from
 * inside, its state within it, and outside, that of the pixels outside within: the same state in
 * both, or else partially obscured.
 */
static uint8_t combine(uint8_t inside, uint8_t outside)
{
	return inside == outside ? inside : VIS_PARTIALLY_OBSCURED;
}

/*
 * For a SCAN window at position i (not shaped: its pixels are its clip): how the later windows
 * that are not its descendants cover its pixels outside within (unobscured: not at all), looked up
 * when inside does not settle the state. Visits those windows from the top down, stopping at the
 * first whose pixels, its whole clip and opaque, settle it; else runs the engine on those pixels
 * (up to four boxes, at the bottom of a stack) and the windows that meet them, those with a look
 * as their pieces. Returns the state, or -1 with ENOMEM. O(windows above) besides the engine.
 */
static int outside_state(const struct vis_wtree *tree, size_t i, struct vis_box within,
			 uint8_t inside, struct vis_wtree_work *wk)
{
	size_t n = tree->n_order;
	if (inside == VIS_PARTIALLY_OBSCURED)
		return inside;
	/* The clip minus within: the rows above and below within, then left and right of it. */
	struct vis_box c = wk->clips[i], hull = { 0, 0, 0, 0 };
	int64_t top = c.y1 > within.y1 ? c.y1 : within.y1, bottom = c.y2 < within.y2 ? c.y2 : within.y2;
	struct vis_box pieces[4] = {
		{ c.x1, c.y1, c.x2, c.y2 < within.y1 ? c.y2 : within.y1 },
		{ c.x1, c.y1 > within.y2 ? c.y1 : within.y2, c.x2, c.y2 },
		{ c.x1, top, c.x2 < within.x1 ? c.x2 : within.x1, bottom },
		{ c.x1 > within.x2 ? c.x1 : within.x2, top, c.x2, bottom },
	};
	size_t k = 0;
	for (size_t p = 0; p < 4; p++)
		if (!vis_box_empty(pieces[p])) {
			hull = box_hull(hull, pieces[p]);
			pieces[k++] = pieces[p];
		}
	size_t end = i + 1, m = k;
	bool clear = false;
	while (end < n && wk->depths[end] > wk->depths[i])
		end++; /* descendants never obscure */
	/* The windows that meet the pieces go above them in rects, in any order: a piece's state
	 * depends only on the union of their opaque pixels. */
	for (size_t j = n; j-- > end;) {
		struct vis_box b = vis_box_intersect(wk->clips[j], c);
		bool hit = false;
		for (size_t p = 0; p < k && !hit; p++)
			hit = meets(b, pieces[p]);
		if (!hit || (wk->flags[j] & INPUT))
			continue;
		if (!(wk->flags[j] & CLEAR)) {
			if (inside == VIS_UNOBSCURED)
				return VIS_PARTIALLY_OBSCURED; /* ≠ inside: that settles it */
			if (vis_box_contains(b, hull))
				return VIS_FULLY_OBSCURED;
		}
		clear |= (wk->flags[j] & CLEAR) != 0;
		wk->index[m - k] = j;
		wk->rects[m++] = box_rect(b);
	}
	if (m == k)
		return VIS_UNOBSCURED;
	for (size_t p = 0; p < k; p++)
		wk->rects[p] = box_rect(pieces[p]);
	uint8_t *states = wk->states;
	if (clear) {
		/* Some have a look: the same stack, cut into pieces; the first k are the boxes'. */
		vis_pieces_reset(&wk->pieces);
		for (size_t p = 0; p < k; p++)
			if (vis_pieces_add(&wk->pieces, NULL, pieces[p], pieces[p], 0) < 0)
				return -1;
		for (size_t q = k; q < m; q++)
			if (add_pieces(wk, tree->order[wk->index[q - k]], 1,
				       vis_rect_box(wk->rects[q])) < 0)
				return -1;
		struct vis_pieces *pc = &wk->pieces;
		if (reserve_piece_states(wk, pc->stack.n) < 0)
			return -1;
		pc->stack.rects = pc->rects;
		pc->stack.see_through = pc->see_through;
		if (vis_compute(VIS_ENGINE_AUTO, &pc->stack, wk->piece_states) < 0)
			return -1;
		states = wk->piece_states;
	} else {
		struct vis_stack stack = { wk->rects, m, false, 0, 0, NULL, NULL };
		if (vis_compute(VIS_ENGINE_AUTO, &stack, wk->states) < 0)
			return -1;
	}
	uint8_t all = states[0];
	for (size_t p = 1; p < k; p++)
		all = combine(all, states[p]);
	return all;
}

/*
 * Completes wk->raw of the affected windows whose clip sticks out of within: outside it, their
 * pixels keep what covered them. For one last unobscured or fully obscured, its last state says
 * which; one last partially obscured is looked up (SCAN). The others, new, moved or past the
 * budget, lie in within (or have no pixels). 0, or -1 with ENOMEM.
 */
static int complete(const struct vis_wtree *tree, struct vis_box within, struct vis_wtree_work *wk)
{
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		if ((wk->flags[i] & CHANGED) || vis_box_contains(within, wk->clips[i]))
			continue;
		int outside = wk->last[i];
		if ((wk->flags[i] & SCAN) &&
		    (outside = outside_state(tree, i, within, wk->raw[i], wk)) < 0)
			return -1;
		wk->raw[i] = combine(wk->raw[i], (uint8_t)outside);
	}
	return 0;
}

/*
 * Prepares the box rule for the shaped windows among the affected ones: a window the clip cuts
 * pixels away from is never unobscured, as X compares the whole window. The pixels of an unshaped
 * window are its whole box, so a clip other than its box cuts it (CUT); a shaped one's may all lie
 * inside the clip all the same, and then it loses CUT. 0, or -1 with ENOMEM.
 */
static int shaped_cuts(const struct vis_wtree *tree, struct vis_wtree_work *wk)
{
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		if (wk->raw[i] != VIS_UNOBSCURED || (wk->flags[i] & (CUT | CLEAR)) != (CUT | CLEAR))
			continue;
		const struct vis_window *w = tree->order[i];
		if (!w->look.shaped)
			continue;
		vis_pieces_reset(&wk->pieces);
		int cut = vis_pieces_add(&wk->pieces, &w->look, w->box, w->clip, 0);
		if (cut < 0)
			return -1;
		if (!cut)
			wk->flags[i] &= (uint8_t)~CUT;
	}
	return 0;
}

/*
 * Recomputes the states: every window's when damage is NULL, else only those of the windows the
 * damage may have changed. See vis_wtree_compute_damaged().
 */
static int compute(struct vis_wtree *tree, const struct vis_box *damage, size_t n_damage)
{
	if (!tree->work && !(tree->work = calloc(1, sizeof *tree->work))) {
		errno = ENOMEM;
		return -1;
	}
	struct vis_wtree_work *wk = tree->work;
	if (work_reserve(wk, tree->count) < 0)
		return -1;
	struct vis_box screen = tree->root.clip, bounds = { 0, 0, 0, 0 };
	if (tree->stale) {
		damage = NULL; /* the last states do not go with the boxes */
		n_damage = 0;
	}
	for (size_t k = 0; damage && k < n_damage; k++)
		if (meets(damage[k], screen))
			bounds = box_hull(bounds, vis_box_intersect(damage[k], screen));
	if (flatten(tree, wk) < 0)
		return -1;
	tree->stale = true; /* until the states go with the new boxes */
	select_affected(tree, damage, n_damage, bounds, wk);
	struct vis_box within = damage ? select_within(tree, bounds, wk) : screen;
	if (classify(tree, within, wk) < 0 || (damage && complete(tree, within, wk) < 0) ||
	    (wk->n_clear && shaped_cuts(tree, wk) < 0)) {
		unflatten(tree, wk);
		return -1;
	}
	/* Every window, viewable or not, moved its state to old_state: unviewable ones have none. */
	for (size_t i = 0; i < wk->n_hidden; i++) {
		struct vis_window *w = wk->hidden[i];
		w->old_state = w->state;
		w->state = VIS_WTREE_STATE_NONE;
	}
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		uint8_t s = wk->raw[i];
		/* A window the clip cuts into is never unobscured, as X compares the whole window. */
		if (s == VIS_UNOBSCURED && (wk->flags[i] & CUT))
			s = VIS_PARTIALLY_OBSCURED;
		if (s != wk->last[i])
			tree->order[i]->state = s;
	}
	tree->stale = false;
	return 0;
}

int vis_wtree_compute(struct vis_wtree *tree)
{
	return compute(tree, NULL, 0);
}

int vis_wtree_compute_damaged(struct vis_wtree *tree, const struct vis_box *damage,
			      size_t n_damage)
{
	return compute(tree, damage, n_damage);
}

/*
 * Initializes region with the union of the pieces numbered num (only the opaque ones, with
 * opaque), relative to ox, oy. 0, or -1 (region is then still initialized).
 */
static int pieces_region(const struct vis_pieces *p, uint32_t num, bool opaque, int64_t ox,
			 int64_t oy, pixman_region32_t *region)
{
	size_t n = 0;
	pixman_box32_t *boxes = malloc((p->stack.n ? p->stack.n : 1) * sizeof *boxes);
	pixman_region32_init(region);
	if (!boxes)
		return -1;
	for (size_t k = 0; k < p->stack.n; k++) {
		if (p->window[k] != num || (opaque && p->see_through[k]))
			continue;
		struct vis_box b = vis_rect_box(p->rects[k]);
		boxes[n++] = (pixman_box32_t){ (int32_t)(b.x1 - ox), (int32_t)(b.y1 - oy),
					       (int32_t)(b.x2 - ox), (int32_t)(b.y2 - oy) };
	}
	pixman_region32_fini(region);
	bool ok = pixman_region32_init_rects(region, boxes, (int)n);
	free(boxes);
	return ok ? 0 : -1;
}

int vis_wtree_visible_region(const struct vis_wtree *tree, const struct vis_window *window,
			     void *out)
{
	pixman_region32_t *region = out;
	struct vis_box clip = window->clip;
	pixman_region32_clear(region);
	if (window->state == VIS_WTREE_STATE_NONE || window->state == VIS_FULLY_OBSCURED ||
	    vis_box_empty(clip))
		return 0;
	/* Its own pixels, numbered 0, and the later windows' inside its clip, numbered 1. The boxes
	 * lie in the clip, so in window coordinates in [0, INT32_MAX) (the box's sides' range). */
	struct vis_wtree_work wk = { 0 };
	int64_t ox = window->box.x1, oy = window->box.y1;
	int rc = -1;
	if (add_pieces(&wk, window, 0, clip) < 0)
		goto out;
	for (size_t i = window->pos + 1; i < tree->n_order; i++) {
		const struct vis_window *w = tree->order[i];
		if (!w)
			continue;
		struct vis_box c = vis_box_intersect(w->clip, clip);
		if (!vis_box_empty(c) && add_pieces(&wk, w, 1, c) < 0)
			goto out;
	}
	pixman_region32_t own, above;
	bool ok = pieces_region(&wk.pieces, 0, false, ox, oy, &own) == 0;
	ok &= pieces_region(&wk.pieces, 1, true, ox, oy, &above) == 0;
	ok = ok && pixman_region32_subtract(region, &own, &above);
	pixman_region32_fini(&own);
	pixman_region32_fini(&above);
	if (ok)
		rc = 0;
out:
	vis_pieces_finish(&wk.pieces);
	if (rc < 0)
		errno = ENOMEM;
	return rc;
}

long vis_wtree_repaint(const struct vis_wtree *tree, struct vis_box damage,
		       struct vis_window **out)
{
	size_t n = tree->n_order;
	struct vis_wtree_work wk = { 0 };
	bool pieces = false;
	if (work_reserve(&wk, n) < 0)
		return -1;
	for (size_t i = 0; i < n; i++) {
		const struct vis_window *w = tree->order[i];
		wk.clips[i] = w ? w->clip : (struct vis_box){ 0, 0, 0, 0 };
		pieces |= w && look_clear(&w->look);
	}
	long count = -1;
	if (sweep(tree, &wk, pieces, 0, n, 0, damage, wk.raw) == 0) {
		count = 0;
		for (size_t i = 0; i < n; i++)
			if (wk.raw[i] != VIS_FULLY_OBSCURED)
				out[count++] = tree->order[i];
	}
	free(wk.block);
	vis_pieces_finish(&wk.pieces);
	free(wk.piece_states);
	return count;
}
