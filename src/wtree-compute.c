/* The window tree's states, full and damaged recomputes, computed with the core's engines. */
#include <errno.h>
#include <stdlib.h>

#include "engine.h"
#include "wtree-live.h"

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
 * How many windows the lookups that need the engine with pieces may take in all, as a share of
 * the viewable windows (1 / LOOKUP_ENGINE_SHARE), before the others grow within instead. Such a
 * lookup cuts every window with a look that meets the clip outside within into pieces and sweeps
 * them: per window, about what the full recompute pays, and one lookup takes dozens of windows,
 * as translucent windows and shadows are large. Without a limit, a move of any window of a
 * 1,000-window translucent desktop made several such lookups and cost 3 times the full recompute.
 * Measured with bench-wtree there (medians after one move): no such lookups, or n/8 windows, make
 * moves of the top window (a drag) 1.6 times slower, as within then grows to most of the screen;
 * n/4 keeps their cost, and moves of any window cost what the full recompute does (n/3 and n/2:
 * 3% and 6% more).
 */
#define LOOKUP_ENGINE_SHARE 4

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

/* Whether two boxes share a pixel; without branches, as it decides at random in hot loops. */
static bool meets(struct vis_box a, struct vis_box b)
{
	return ((a.x1 > b.x1 ? a.x1 : b.x1) < (a.x2 < b.x2 ? a.x2 : b.x2)) &
	       ((a.y1 > b.y1 ? a.y1 : b.y1) < (a.y2 < b.y2 ? a.y2 : b.y2));
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
	if (!wtree_work_look_clear(&w->look))
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
 * which its children are clipped to, is its inside so clipped. As X, a shaped window clips its
 * descendants to its bounding shape too: they are flagged UNDER (and CLEAR), and cut into pieces
 * by what the shapes above them leave (wtree-work.c).
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
	/* The live update's keys, in the grid already: the same order (wtree-live.h). */
	bool keep_keys = wtree_live_keeping(tree);
	wk->n_hidden = 0;
	for (struct vis_window *w = tree->root.bottom; w; w = next_viewable(w)) {
		if (!w->mapped) {
			for (struct vis_window *v = w; v; v = vis_wtree_next_within(v, w)) {
				v->key = keep_keys ? v->key : 0;
				if (v->state != VIS_WTREE_STATE_NONE ||
				    v->old_state != VIS_WTREE_STATE_NONE)
					wk->hidden[wk->n_hidden++] = v;
			}
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
		bool changed = last == VIS_WTREE_STATE_NONE || !vis_box_equal(box, w->box) ||
			       !vis_box_equal(clip, w->clip);
		w->box = box;
		w->clip = clip;
		w->inner = clip;
		w->pos = n;
		if (!keep_keys)
			w->key = wtree_key_of(n, tree->count);
		wk->old[n] = w->old_state;
		w->old_state = last;
		wk->last[n] = last;
		wk->clips[n] = clip;
		wk->depths[n] = w->depth;
		wk->flags[n] = (uint8_t)((changed ? CHANGED : 0) | (vis_box_equal(box, clip) ? 0 : CUT));
		/* A look costs plain windows one test. */
		bool clear = (b || wtree_work_look_clear(&w->look)) && flatten_look(w, &wk->flags[n]);
		/* A shaped ancestor clips it to its shape: its pixels are no box either. */
		if (p->parent && (p->look.shaped || (wk->flags[p->pos] & UNDER))) {
			wk->flags[n] |= CLEAR | UNDER;
			clear = true;
		}
		n_clear += clear;
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

/* The position just past the subtree of the window at position i: its descendants, which never
 * obscure it. */
static size_t subtree_end(const struct vis_wtree_work *wk, size_t n, size_t i)
{
	size_t end = i + 1;
	while (end < n && wk->depths[end] > wk->depths[i])
		end++;
	return end;
}

/*
 * Settles, without its depth's sweep, the state of each PARENT window that the sweep over all
 * windows found seeing some of its pixels inside within: with its descendants left out it sees
 * them still, so it is unobscured there unless a later window outside its subtree meets them,
 * looked up from the top down. Its pixels must be its clip, all opaque, and so must be those of
 * the window met (else the lookup leaves it to the sweep), and the lookups visit
 * SCAN_VISITS_PER_WINDOW windows a window in all. A chain of nested windows needed a sweep per
 * level, each over most of the tree: 64 levels over 1,000 windows cost 58 ms a recompute.
 */
static void settle_parents(const struct vis_wtree *tree, struct vis_box within,
			   struct vis_wtree_work *wk)
{
	size_t n = tree->n_order;
	uint64_t budget = (uint64_t)SCAN_VISITS_PER_WINDOW * n;
	for (size_t a = wk->n_affected; a-- > 0;) {
		size_t i = wk->affected[a];
		uint8_t raw = wk->raw[i];
		if (!(wk->flags[i] & PARENT) || (wk->flags[i] & CLEAR) ||
		    raw == VIS_FULLY_OBSCURED)
			continue;
		if (raw == VIS_UNOBSCURED) {
			/* Not even its descendants hide any of them. */
			wk->flags[i] &= (uint8_t)~PARENT;
			continue;
		}
		size_t end = subtree_end(wk, n, i);
		if (n - end > budget)
			break;
		struct vis_box mine = vis_box_intersect(wk->clips[i], within);
		bool met = false, unknown = false;
		for (size_t j = n; j-- > end && !met && !unknown;) {
			budget--;
			if ((wk->flags[j] & INPUT) || !meets(wk->clips[j], mine))
				continue;
			unknown = wk->flags[j] & CLEAR;
			met = !unknown;
		}
		if (unknown)
			continue;
		wk->raw[i] = met ? VIS_PARTIALLY_OBSCURED : VIS_UNOBSCURED;
		wk->flags[i] &= (uint8_t)~PARENT;
	}
}

/*
 * Sets wk->raw of every affected window to its state before the box rule, as its pixels inside
 * within (a box inside the screen) alone would have it: fully obscured with none there.
 * A window without visible children takes the sweep over all windows; one with them, the sweep
 * for its depth, in which its descendants do not hide it (see wtree_work_sweep()), unless that
 * sweep settles it (settle_parents()).
 */
static int classify(const struct vis_wtree *tree, struct vis_box within, struct vis_wtree_work *wk)
{
	size_t n = tree->n_order, first = cover(wk, n, within);
	bool pieces = wk->n_clear > 0;
	if (wtree_work_sweep(tree, wk, pieces, first, n, 0, within, wk->raw) < 0)
		return -1;
	for (size_t a = 0; a < wk->n_affected; a++) {
		size_t i = wk->affected[a];
		if (i >= first && (wk->flags[i] & CHILDREN) && meets(wk->clips[i], within))
			wk->flags[i] |= PARENT;
	}
	settle_parents(tree, within, wk);
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
		if (wtree_work_sweep(tree, wk, pieces, first, n, next, within, wk->level) < 0)
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

/* The parts of the clip c outside within, into parts: the rows above and below within, then left
 * and right of it, those not empty. Returns how many, and their hull. */
static size_t outside_parts(struct vis_box c, struct vis_box within, struct vis_box parts[4],
			    struct vis_box *hull)
{
	int64_t top = c.y1 > within.y1 ? c.y1 : within.y1, bottom = c.y2 < within.y2 ? c.y2 : within.y2;
	struct vis_box all[4] = {
		{ c.x1, c.y1, c.x2, c.y2 < within.y1 ? c.y2 : within.y1 },
		{ c.x1, c.y1 > within.y2 ? c.y1 : within.y2, c.x2, c.y2 },
		{ c.x1, top, c.x2 < within.x1 ? c.x2 : within.x1, bottom },
		{ c.x1 > within.x2 ? c.x1 : within.x2, top, c.x2, bottom },
	};
	size_t k = 0;
	*hull = (struct vis_box){ 0, 0, 0, 0 };
	for (size_t p = 0; p < 4; p++)
		if (!vis_box_empty(all[p])) {
			*hull = vis_box_hull(*hull, all[p]);
			parts[k++] = all[p];
		}
	return k;
}


/*
 * What the lookup of the SCAN window at position i (outside_state()) may cost beyond its visits:
 * 0 when a window with its whole clip opaque covers the clip's parts outside within, or when no
 * window with a look meets them; else the number of windows that meet them, which the engine would
 * take, those with a look as pieces. An upper bound: within only grows after, and the state inside
 * within may settle the lookup before the engine. O(windows above).
 */
static size_t lookup_cost(const struct vis_wtree *tree, const struct vis_wtree_work *wk, size_t i,
			  struct vis_box within)
{
	struct vis_box parts[4], hull, c = wk->clips[i];
	size_t n = tree->n_order, k = outside_parts(c, within, parts, &hull), met = 0;
	size_t end = subtree_end(wk, n, i);
	bool clear = false;
	for (size_t j = n; j-- > end;) {
		struct vis_box b = vis_box_intersect(wk->clips[j], c);
		bool hit = false;
		for (size_t p = 0; p < k && !hit; p++)
			hit = meets(b, parts[p]);
		if (!hit || (wk->flags[j] & INPUT))
			continue;
		if (!(wk->flags[j] & CLEAR) && vis_box_contains(b, hull))
			return 0;
		clear |= (wk->flags[j] & CLEAR) != 0;
		met++;
	}
	return clear ? met : 0;
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
		    ((wk->flags[i] & CLEAR) &&
		     (tree->order[i]->look.shaped || (wk->flags[i] & UNDER))))
			within = vis_box_hull(within, wk->clips[i]);
		else if (wk->last[i] == VIS_PARTIALLY_OBSCURED)
			wk->flags[i] |= SCAN;
	}
	/* A lookup visits the windows above: the highest are the cheapest. */
	uint64_t budget = (uint64_t)SCAN_VISITS_PER_WINDOW * n;
	size_t engine = n / LOOKUP_ENGINE_SHARE;
	for (size_t a = wk->n_affected; a-- > 0;) {
		size_t i = wk->affected[a];
		if (!(wk->flags[i] & SCAN))
			continue;
		if (n - i <= budget) {
			budget -= n - i;
			/* Only windows with a look make a lookup cost more than its visits. */
			size_t cost = wk->n_clear ? lookup_cost(tree, wk, i, within) : 0;
			if (cost <= engine) {
				engine -= cost;
				continue;
			}
		}
		wk->flags[i] &= (uint8_t)~SCAN;
		within = vis_box_hull(within, wk->clips[i]);
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
	struct vis_box c = wk->clips[i], hull, pieces[4];
	size_t k = outside_parts(c, within, pieces, &hull), end = subtree_end(wk, n, i), m = k;
	bool clear = false;
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
		wk->rects[m++] = wtree_work_box_rect(b);
	}
	if (m == k)
		return VIS_UNOBSCURED;
	for (size_t p = 0; p < k; p++)
		wk->rects[p] = wtree_work_box_rect(pieces[p]);
	uint8_t *states = wk->states;
	if (clear) {
		/* Some have a look: the same stack, cut into pieces; the first k are the boxes'. */
		vis_pieces_reset(&wk->pieces);
		for (size_t p = 0; p < k; p++)
			if (vis_pieces_add(&wk->pieces, NULL, pieces[p], pieces[p], 0) < 0)
				return -1;
		for (size_t q = k; q < m; q++)
			if (wtree_work_add_pieces(wk, tree->order[wk->index[q - k]], 1,
				       vis_rect_box(wk->rects[q])) < 0)
				return -1;
		struct vis_pieces *pc = &wk->pieces;
		if (wtree_work_reserve_piece_states(wk, pc->stack.n) < 0)
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
		const struct vis_window *w = tree->order[i];
		/* Under a shaped ancestor even a window its clip holds may be cut by the shape. */
		bool under = wk->flags[i] & UNDER;
		if (wk->raw[i] != VIS_UNOBSCURED ||
		    !(under || ((wk->flags[i] & (CUT | CLEAR)) == (CUT | CLEAR) && w->look.shaped)))
			continue;
		int cut = wtree_work_cut(w, w->clip);
		if (cut < 0)
			return -1;
		wk->flags[i] = (uint8_t)(cut ? wk->flags[i] | CUT : wk->flags[i] & ~CUT);
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
	if (wtree_work_reserve(wk, tree->count) < 0)
		return -1;
	wtree_live_invalidate(tree); /* the boxes it indexes are about to move */
	struct vis_box screen = tree->root.clip, bounds = { 0, 0, 0, 0 };
	if (tree->stale) {
		damage = NULL; /* the last states do not go with the boxes */
		n_damage = 0;
	}
	for (size_t k = 0; damage && k < n_damage; k++)
		if (meets(damage[k], screen))
			bounds = vis_box_hull(bounds, vis_box_intersect(damage[k], screen));
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
	if (wtree_live_keeping(tree))
		wtree_live_repair(tree, wk);
	else
		wtree_live_computed(tree, wk);
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
