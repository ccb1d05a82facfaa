/* The window tree's scratch and its sweep: what the recomputes and the queries share. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "wtree-work.h"

/* Makes room in wk for count windows: one block, so that a recompute allocates nothing. */
int wtree_work_reserve(struct vis_wtree_work *wk, size_t count)
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

/* Frees what a work holds, for the queries' works on the stack and the tree's. */
void wtree_work_finish(struct vis_wtree_work *wk)
{
	free(wk->block);
	vis_pieces_finish(&wk->pieces);
	free(wk->piece_states);
}

void vis_wtree_work_destroy(struct vis_wtree_work *work)
{
	if (work)
		wtree_work_finish(work);
	free(work);
}

/* Makes room for n piece states, kept apart from the block: pieces outnumber windows. */
int wtree_work_reserve_piece_states(struct vis_wtree_work *wk, size_t n)
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

/* Whether some ancestor of w (not the root) has a bounding shape. O(depth). */
static bool under_shape(const struct vis_window *w)
{
	for (const struct vis_window *a = w->parent; a && a->parent; a = a->parent)
		if (a->look.shaped)
			return true;
	return false;
}

/* The first of the banded rects[lo … hi) whose bottom lies below y (hi when none). */
static uint32_t first_below(const struct vis_rect *rects, uint32_t lo, uint32_t hi, int64_t y)
{
	while (lo < hi) {
		uint32_t mid = lo + (hi - lo) / 2;
		if ((int64_t)rects[mid].y + rects[mid].h > y)
			hi = mid;
		else
			lo = mid + 1;
	}
	return lo;
}

/* Appends a box to *out (realloc'd, *cap long, *n used). 0, or -1 with ENOMEM. */
static int append_box(struct vis_box **out, size_t *n, size_t *cap, struct vis_box box)
{
	if (*n == *cap) {
		size_t more = *cap ? 2 * *cap : 16;
		struct vis_box *grown = realloc(*out, more * sizeof(**out));
		if (!grown) {
			errno = ENOMEM;
			return -1;
		}
		*out = grown;
		*cap = more;
	}
	(*out)[(*n)++] = box;
	return 0;
}

/*
 * Cuts boxes[0 … *nb) by one shaped ancestor a: the parts of each inside a's inside and a's
 * pixels, which its kept cut lists (their union is its shape in its border box), into *out
 * (realloc'd, *cap long). O(nb · (log b + p)) for a's b pieces, p of them in the bands a box
 * crosses. 0, or -1 with errno.
 */
static int cut_by(const struct vis_window *a, const struct vis_look_cut *cut,
		  const struct vis_box *boxes, size_t nb, struct vis_box **out, size_t *n_out,
		  size_t *cap)
{
	int64_t b = a->look.border;
	struct vis_box inside = { a->box.x1 + b, a->box.y1 + b, a->box.x2 - b, a->box.y2 - b };
	const uint32_t runs[3] = { 0, cut->n_opaque, cut->n };
	*n_out = 0;
	for (size_t k = 0; k < nb; k++) {
		struct vis_box in = vis_box_intersect(boxes[k], inside);
		if (vis_box_empty(in))
			continue;
		/* Each run of the cut is banded: from the first band reaching below the box's top to
		 * the last starting above its bottom. */
		for (int run = 0; run < 2; run++) {
			uint32_t q = first_below(cut->rects, runs[run], runs[run + 1],
						 in.y1 - a->box.y1);
			for (; q < runs[run + 1]; q++) {
				struct vis_rect r = cut->rects[q];
				struct vis_box piece = { a->box.x1 + r.x, a->box.y1 + r.y,
							 a->box.x1 + r.x + r.w, a->box.y1 + r.y + r.h };
				if (piece.y1 >= in.y2)
					break;
				struct vis_box part = vis_box_intersect(piece, in);
				if (!vis_box_empty(part) && append_box(out, n_out, cap, part) < 0)
					return -1;
			}
		}
	}
	return 0;
}

/*
 * The part of the clip c that w's shaped ancestors leave: their shapes (inside their insides, as
 * X clips children to a parent's bounding shape and inside) cut c into boxes, in *out (malloc'd,
 * *n of them), from the pieces each ancestor keeps, not cut again for every descendant. 0, or -1
 * with ENOMEM.
 */
static int shape_clip(const struct vis_window *w, struct vis_box c, struct vis_box **out,
		      size_t *n)
{
	struct vis_box *boxes = malloc(sizeof(*boxes)), *next = NULL;
	size_t nb = 1, cap_boxes = 1, n_next = 0, cap_next = 0;
	if (!boxes) {
		errno = ENOMEM;
		return -1;
	}
	boxes[0] = c;
	for (const struct vis_window *a = w->parent; a && a->parent && nb; a = a->parent) {
		if (!a->look.shaped)
			continue;
		const struct vis_look_cut *cut = vis_wtree_cut(a);
		if (!cut || cut_by(a, cut, boxes, nb, &next, &n_next, &cap_next) < 0) {
			free(boxes);
			free(next);
			return -1;
		}
		/* The boxes left become the ones to cut by the next shaped ancestor. */
		struct vis_box *t = boxes;
		size_t cap_t = cap_boxes;
		boxes = next;
		cap_boxes = cap_next;
		next = t;
		cap_next = cap_t;
		nb = n_next;
	}
	if (!boxes) {
		/* No box left, and none ever made: the caller needs an array, empty, not NULL. */
		boxes = next;
		next = NULL;
	}
	free(next);
	*out = boxes;
	*n = nb;
	return 0;
}

/* Adds a window's pieces, or says whether it is cut (pieces NULL: to a scratch). */
static int add_window(const struct vis_window *w, size_t i, struct vis_box c,
		      struct vis_pieces *pieces)
{
	const struct vis_look *look = wtree_work_look_clear(&w->look) ? &w->look : NULL;
	if (!under_shape(w)) {
		/* A plain window's clip needs no cutting; a look that cuts inside its box was cut
		 * once, for its size. */
		if (w->cut) {
			const struct vis_look_cut *cut = vis_wtree_cut(w);
			return cut ? vis_pieces_add_cut(pieces, cut, w->box, c, (uint32_t)i) : -1;
		}
		return look ? vis_pieces_add(pieces, look, w->box, c, (uint32_t)i)
			    : vis_pieces_add(pieces, NULL, c, c, (uint32_t)i);
	}
	struct vis_box *within;
	size_t n;
	if (shape_clip(w, c, &within, &n) < 0)
		return -1;
	/* With no boxes left, nothing of it is seen: within is then empty, not absent. */
	int rc = vis_pieces_add_within(pieces, look, w->box, c, within, n, (uint32_t)i);
	free(within);
	return rc;
}

/* Adds a window's pieces: under shaped ancestors, what their shapes leave of them. */
int wtree_work_add_pieces(struct vis_wtree_work *wk, const struct vis_window *w, size_t i,
			  struct vis_box c)
{
	return add_window(w, i, c, &wk->pieces) < 0 ? -1 : 0;
}

int vis_wtree_add_pieces(struct vis_pieces *pieces, const struct vis_window *window,
			 struct vis_box c, uint32_t num)
{
	return add_window(window, num, c, pieces) < 0 ? -1 : 0;
}

int wtree_work_cut(const struct vis_window *w, struct vis_box c)
{
	struct vis_pieces scratch = { 0 };
	int rc = add_window(w, 0, c, &scratch);
	vis_pieces_finish(&scratch);
	return rc;
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
static int run_pieces(struct vis_wtree_work *wk, struct vis_box within, uint8_t *state_of)
{
	struct vis_pieces *p = &wk->pieces;
	size_t m = p->stack.n;
	if (wtree_work_reserve_piece_states(wk, m) < 0)
		return -1;
	p->stack.rects = p->rects;
	p->stack.see_through = p->see_through;
	/* Every piece lies in within: a screen that holds it clips nothing, and tells auto how many
	 * distinct edges the sweep can meet (pieces are many and small: priced as unclipped
	 * rectangles, the region method ran 3 times as long as the sweep would have). */
	struct vis_stack stack = p->stack;
	stack.has_screen = within.x1 >= 0 && within.y1 >= 0 && within.x2 <= INT32_MAX &&
			   within.y2 <= INT32_MAX && !vis_box_empty(within);
	if (stack.has_screen) {
		stack.screen_w = (int32_t)within.x2;
		stack.screen_h = (int32_t)within.y2;
	}
	if (vis_compute(VIS_ENGINE_AUTO, &stack, wk->piece_states) < 0)
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
		return wtree_work_add_pieces(wk, tree->order[i], i, c);
	wk->rects[*m] = wtree_work_box_rect(c);
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
 * The sweep of the recomputes and of the repaint sets (wtree-work.h): with max_depth, each window
 * at that depth goes above its own subtree, which covered() thins out.
 */
int wtree_work_sweep(const struct vis_wtree *tree, struct vis_wtree_work *wk, bool pieces,
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
		return run_pieces(wk, within, state_of);
	struct vis_stack stack = { wk->rects, m, false, 0, 0, NULL, NULL };
	if (vis_compute(VIS_ENGINE_AUTO, &stack, wk->states) < 0)
		return -1;
	for (size_t k = 0; k < m; k++)
		state_of[wk->index[k]] = wk->states[k];
	return 0;
}
