/*
 * The window tree's scratch and its sweep, private to src/wtree-*.c: the recomputes
 * (wtree-compute.c) keep a work in the tree; the queries (wtree-query.c) make their own.
 */
#ifndef VIS_WTREE_WORK_H
#define VIS_WTREE_WORK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "look.h"
#include "rect.h"
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
 * The zero work is empty and valid.
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

/* The per-position flags of a work. */
enum {
	CHANGED = 1,  /* new to the order, or its box or clip is not the last recompute's */
	CUT = 2,      /* its clip is not its box: unless shaped, it is never unobscured */
	CHILDREN = 4, /* it has viewable children with pixels that can be seen */
	PARENT = 8,   /* affected, with children: its own sweep without its depth's children */
	SCAN = 16,    /* last partially obscured: what covers it outside within is looked up */
	CLEAR = 32,   /* its pixels are not its whole box, all opaque (a shape, see-through, none) */
	INPUT = 64,   /* input-only: no pixels, no state, never affected */
	UNDER = 128,  /* under a shaped ancestor, whose shape clips it (with CLEAR) */
};

/* Whether a look leaves the window's pixels other than its whole border box, all opaque. Inline:
 * flattening asks it of every window with a border. */
static inline bool wtree_work_look_clear(const struct vis_look *look)
{
	return look->input_only || look->shaped || look->opaque != VIS_OPAQUE_ALL;
}

/* A box as the engines' rectangle; its sides fit in 32 bits (a clip's do). */
static inline struct vis_rect wtree_work_box_rect(struct vis_box b)
{
	return (struct vis_rect){ (int32_t)b.x1, (int32_t)b.y1, (int32_t)(b.x2 - b.x1),
				  (int32_t)(b.y2 - b.y1) };
}

/*
 * Makes room in wk for count windows, keeping its block when it is large enough and doubling it
 * at least otherwise. 0, or -1 with ENOMEM (wk is then as it was).
 */
int wtree_work_reserve(struct vis_wtree_work *wk, size_t count);

/* Frees what wk holds (not wk itself), for a work the caller keeps. */
void wtree_work_finish(struct vis_wtree_work *wk);

/* Makes room for n piece states. 0, or -1 with ENOMEM. */
int wtree_work_reserve_piece_states(struct vis_wtree_work *wk, size_t n);

/*
 * Adds window w, at position i, clipped to c, to wk's pieces, numbered i: its look's pieces (none
 * for an input-only window), or c for a window whose pixels are its whole box, all opaque.
 * 0, or -1 with ENOMEM or EOVERFLOW.
 */
int wtree_work_add_pieces(struct vis_wtree_work *wk, const struct vis_window *w, size_t i,
			  struct vis_box c);

/*
 * Whether the clip c, and the shapes of w's shaped ancestors (which clip their descendants, as
 * in X), cut pixels away from window w: 1, 0, or -1 with ENOMEM or EOVERFLOW.
 */
int wtree_work_cut(const struct vis_window *w, struct vis_box c);

/*
 * Runs the default engine over the windows of wk at positions first … n − 1 with pixels inside
 * within, each clipped to within (wk->clips; wk->depths and wk->flags' CLEAR with max_depth);
 * writes each one's state (its pixels' inside within) to state_of[pos] (fully obscured for the
 * others, and those below first). With max_depth 0, over all of them in pre-order: exact for
 * windows without children. With max_depth d, exact for the windows at depth d, whose
 * descendants must not hide them while the later windows' must: each window at depth d goes above
 * its descendants, which keep their place above the windows before it. A descendant that its
 * parent's pixels hold, all opaque, hides nothing more than the parent and is left out: without
 * CLEAR windows, every window deeper than d is. With pieces, CLEAR windows are cut into pieces
 * (look.h) and input-only ones have none; without, there are none and every window is one
 * rectangle. 0, or -1 with ENOMEM.
 */
int wtree_work_sweep(const struct vis_wtree *tree, struct vis_wtree_work *wk, bool pieces,
		     size_t first, size_t n, uint32_t max_depth, struct vis_box within,
		     uint8_t *state_of);

#endif
