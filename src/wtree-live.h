/*
 * The live recompute's structures, private to src/wtree-*.c: what the tree's other parts tell it
 * (a window destroyed, a recompute that did not go through it) and ask of it (a visible region).
 */
#ifndef VIS_WTREE_LIVE_H
#define VIS_WTREE_LIVE_H

#include <pixman.h>

#include "sgrid.h"
#include "wtree-work.h"
#include "zgrid.h"

/* The damage boxes kept for a recompute that does not go live; past them, a full one. */
#define LIVE_DAMAGE 64

/*
 * A seen region is kept as up to SEEN_BOXES boxes, or as its extents (n = SEEN_EXTENTS). Boxes
 * on the screen fit in 32 bits: 8 take the room of 4 of ours.
 */
#define SEEN_BOXES 8
#define SEEN_EXTENTS 0xff

/* The most boxes a walk keeps what is left of its pixels in, before a region (wtree-live-walk.c). */
#define LEFT_BOXES 64

/* A state not known yet, for a window taken to be recomputed. */
#define STATE_UNKNOWN 0xff

/* What a walk returns when the update's budget ran out: it goes through the tree instead. */
#define OVER_BUDGET (-2)

/* What a walk returns past its own steps (give_up): the caller finds its windows another way. */
#define GAVE_UP (-3)

/* Pixels that a window (or a destroyed one) saw: its seen region, or a box holding it. */
struct seen {
	uint8_t n;
	uint8_t edges; /* of a loose one: the edges of its box known to hold pixels of it */
	pixman_box32_t boxes[SEEN_BOXES];
};

/* The edges of a box, as in struct seen's edges. */
#define EDGE_LEFT 1
#define EDGE_TOP 2
#define EDGE_RIGHT 4
#define EDGE_BOTTOM 8

/* A box as pixman's (boxes here lie on the screen, inside 32 bits), and back. */
static inline pixman_box32_t pbox(struct vis_box b)
{
	return (pixman_box32_t){ (int32_t)b.x1, (int32_t)b.y1, (int32_t)b.x2, (int32_t)b.y2 };
}

static inline struct vis_box vbox(const pixman_box32_t *b)
{
	return (struct vis_box){ b->x1, b->y1, b->x2, b->y2 };
}

/*
 * A viewable window that is not fully obscured, with what it saw at the last recompute. stamp
 * grows by 2 with each (SEEN_STAMP bits), so that the seen grid's entries made before no longer
 * stand; its low bit, SEEN_PENDING, says the entry waits in the pending list to be put in the
 * grid.
 */
struct seen_window {
	struct vis_window *w;
	struct seen seen;
	uint32_t stamp;
};

#define SEEN_PENDING 1u
#define SEEN_STAMP(s) ((s) & ~SEEN_PENDING)

/* Whether a seen region is exact (its boxes), not a box holding it. */
static inline bool seen_exact(const struct seen *s)
{
	return s->n != SEEN_EXTENTS;
}

/*
 * Pixels that a window saw until a change: the windows below key may see them now. w: the
 * window, still there (a changed one), or NULL (destroyed).
 */
struct exposure {
	uint64_t key;
	struct vis_window *w;
	struct seen seen;
};

/*
 * A window whose state the update recomputes, with the result until it commits. gain: it may
 * see pixels it did not (rule 3 took it), so its query must look for them; one taken by rule 2
 * alone sees what it saw less what changed windows now hide. gained: for one without viewable
 * descendants that rule 3 met, the first of the boxes it sees of the pixels exposed (1-based in
 * the update's gains, chained; 0: none), unless unlisted: a walk over pixels not known exactly
 * met it.
 */
struct candidate {
	struct vis_window *w;
	uint8_t state;
	bool gain, unlisted;
	uint32_t gained;
	struct seen seen;
};

/* A box of pixels a window gains, and the next of its boxes (1-based; 0: none). */
struct gained_box {
	struct vis_box box;
	uint32_t next;
};

/*
 * An indexed window, in a dense array the grid's entries point into: walks test the clip here,
 * in a few MiB, and read the window (a cache miss) only when the clip meets their pixels.
 */
struct live_slot {
	pixman_box32_t clip;
	struct vis_window *w;
	bool look; /* its pixels are its look's pieces in its clip: only the opaque ones hide */
};

/* Whether a window's pixels are other than its clip, all opaque (input-only ones have none). */
static inline bool wtree_live_has_look(const struct vis_window *w)
{
	return !w->look.input_only && (w->look.shaped || w->look.opaque != VIS_OPAQUE_ALL);
}

/* Whether an ancestor of w has a shape, which clips w's pixels: the live engine does not cut
 * windows by their ancestors' shapes (the recompute through the tree does, UNDER). */
static inline bool wtree_live_under_shape(const struct vis_window *w)
{
	for (const struct vis_window *a = w->parent; a && a->parent; a = a->parent)
		if (a->look.shaped)
			return true;
	return false;
}

/*
 * The invariants, while valid: every viewable window has a key, growing in pre-order (the others
 * 0); the grid holds the clip of every viewable window with pixels (not input-only), under its
 * key, flagged live_indexed, with its slot (live_slot) holding its clip and whether it has a
 * look; seen lists every viewable window that is not fully obscured, with a region holding the
 * pixels it saw at the last recompute (exact, or its clip when not known); no viewable window
 * lies under a shaped ancestor (its pixels are its clip, or its look's pieces in its clip, of
 * which the opaque ones hide what lies below). Whatever the validity, dirty
 * lists the windows noted since the last recompute, changed those the last one may have changed
 * (state ≠ old_state only among them), exposures what windows destroyed since saw.
 */
struct vis_wtree_live {
	bool valid;
	struct vis_zgrid grid;
	struct live_slot *slots; /* the grid's values index these */
	size_t n_slots, cap_slots;
	uint32_t *free_slots; /* room for cap_slots */
	size_t n_free;
	/* Entries of windows that saw nothing since are free (w NULL), listed in free_seen (room for
	 * cap_seen), and taken first: freeing one touches no other window. */
	struct seen_window *seen;
	size_t n_seen, cap_seen;
	uint32_t *free_seen;
	size_t n_free_seen;
	/* The seen regions' boxes, by where they lie (values: seen entries, with their stamps), while
	 * seen_grid_ok: which windows saw pixels of a region, in the region's cells alone. Entries
	 * whose region changed wait in pending (room for cap_seen) until a walk reads the grid: most
	 * updates never do, and putting boxes in cells costs a cache miss each. */
	struct vis_sgrid seen_grid;
	bool seen_grid_ok;
	uint32_t *pending;
	size_t n_pending;
	struct vis_window **dirty;
	size_t n_dirty, cap_dirty;
	struct vis_window **changed;
	size_t n_changed, cap_changed;
	bool changed_all;
	struct exposure *exposures;
	size_t n_exposures, cap_exposures;
	struct candidate *cands;
	size_t n_cands, cap_cands;
	struct gained_box *gains;
	size_t n_gains, cap_gains;
	struct vis_box damage[LIVE_DAMAGE];
	size_t n_damage;
	bool damage_all;
	bool changed_lost; /* changed could not list them all: the next recompute goes through all */
	uint32_t mark;
	/* An update's walks take at most budget steps in all, past which it gives up (NOT_LIVE);
	 * a walk that may end another way takes steps up to give_up (else SIZE_MAX). */
	size_t steps, budget, give_up;
	/* The windows of the changed subtrees: cands[0 … n_moved) during an update. */
	size_t n_moved;
	size_t fixed_budget; /* a budget set by wtree_live_tune(), or 0 */
	size_t cover_steps;  /* rule 2's walks' steps set by wtree_live_tune(), or 0 */
	unsigned seen_boxes; /* the boxes a seen region keeps: SEEN_BOXES, or fewer in tests */
	size_t left_boxes;   /* the boxes a walk keeps what is left in: LEFT_BOXES, or fewer */
	size_t min_windows;  /* the windows below which updates go through the tree */
	size_t grid_windows; /* the windows when the grid was built, for its side (grid_side()) */
	size_t n_looks;      /* indexed windows with a look */
	/* Updates left to go through the tree after one could not go live, before the structures
	 * are built again: where updates cost more than that, rebuilding each time costs more. */
	unsigned cooldown;
	/* Set while a recompute through the tree keeps the structures (keys, grid) valid. */
	bool keeping;
	/* The boxes of the changed subtrees' windows before the update, put back for it. */
	struct saved_boxes *saved;
	size_t n_saved, cap_saved;
};

struct saved_boxes {
	struct vis_window *w;
	uint64_t key; /* 0: none (not viewable) */
	struct vis_box box, clip, inner;
};

/* The keys of a recompute's order: position i of n gets key_of(i), spaced for insertions. */
#define WTREE_KEY_BASE ((uint64_t)1 << 62)
#define WTREE_KEY_SPAN ((uint64_t)1 << 61)

static inline uint64_t wtree_key_of(size_t i, size_t n)
{
	return WTREE_KEY_BASE + (uint64_t)(i + 1) * (WTREE_KEY_SPAN / ((uint64_t)n + 1));
}

/*
 * Takes a window to recompute (once), its state given or STATE_UNKNOWN, flagged as one that may
 * gain pixels (gain, which sticks). 0, or -1 (ENOMEM).
 */
int wtree_live_take(struct vis_wtree_live *lv, struct vis_window *w, uint8_t state, bool gain);

/* Adds a box of pixels a candidate gains. 0, or -1 (ENOMEM). */
int wtree_live_gained(struct vis_wtree_live *lv, struct candidate *c, struct vis_box box);

/* What a window saw at the last recompute, or NULL when it saw nothing. */
static inline const struct seen *wtree_live_old_seen(const struct vis_wtree_live *lv,
						     const struct vis_window *w)
{
	return w->live_seen ? &lv->seen[w->live_seen - 1].seen : NULL;
}

/* After a seen entry's region changed: its old boxes in the seen grid no longer stand, and it
 * waits to be put there. */
void wtree_live_seen_changed(struct vis_wtree_live *lv, size_t at);

/* Puts the pending entries' boxes in the seen grid, before a walk reads it. */
void wtree_live_seen_flush(struct vis_wtree_live *lv);

/* Whether w's changed subtree kept its parent: no window of it left or joined another's. */
bool wtree_live_kept_parent(const struct vis_window *w);

/* The key of the last viewable window of w's subtree (w's own without viewable descendants). */
uint64_t wtree_live_subtree_end(const struct vis_window *w);

/*
 * The walks (wtree-live-walk.c): a window's state and seen region (query); the windows that see
 * fewer pixels because of a changed window c (cover, rule 2), or that may see pixels a window saw
 * before it changed (walk_down, rule 3: seen under key); a loose seen box narrowed on the grid as
 * the last recompute left it (refine); a visible region for vis_wtree_visible_region() (region).
 * 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_query(struct vis_wtree_live *lv, struct candidate *c);
int wtree_live_walk_cover(struct vis_wtree *tree, struct vis_wtree_live *lv,
			  const struct candidate *c);
int wtree_live_walk_exposed(struct vis_wtree *tree, struct vis_wtree_live *lv,
			    const struct exposure *e, void *exposed);
int wtree_live_walk_refine(struct vis_wtree_live *lv, struct vis_window *v);

/*
 * An unchanged window's state and seen region from what it saw (when that is exact): less the
 * clips of the changed windows now above its subtree, plus, if it may gain pixels, what it sees
 * of exposed (a pixman region holding every pixel a window may gain: wtree_live_walk_exposed()'s
 * pixels), found by walking the grid over that alone. Else as wtree_live_walk_query().
 * 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_since(struct vis_wtree_live *lv, struct candidate *c, void *exposed);
int wtree_live_walk_region(const struct vis_wtree *tree, const struct vis_window *w,
			   void *region);

/*
 * After a rebuild, makes the seen regions of the windows without viewable descendants exact,
 * from the top of the order down (the region method: the union of the clips above each), until
 * the work (the union's boxes, read at each step) passes budget: the windows below keep their
 * clips. 0, or -1 (ENOMEM).
 */
int wtree_live_seen_from_order(const struct vis_wtree *tree, struct vis_wtree_live *lv,
			       uint64_t budget);

/*
 * The state and seen region of the one window an update changed, whose clip was old_clip, that
 * kept its place among the others in the order (the same windows lie above it): if what it saw
 * is exact, it sees what it saw inside its new clip and what a walk finds of the rest of its
 * clip. Else as wtree_live_walk_query(). 0, or -1 (ENOMEM), or OVER_BUDGET.
 */
int wtree_live_walk_moved(struct vis_wtree_live *lv, struct candidate *c, struct vis_box old_clip);

/*
 * The same for one lowered, its clip as it was, whose exposure is e (under its old key; NULL
 * when it saw nothing): the windows above it are those that were and those between its keys,
 * so it sees what it saw less their clips. The one walk that finds them takes them as rule 3's
 * walk over e would (which it replaces: e is emptied, and what the window no longer sees is
 * added to exposed).
 */
int wtree_live_walk_lowered(struct vis_wtree_live *lv, struct candidate *c, struct exposure *e,
			    void *exposed);

/* Frees a tree's live structures; NULL is a no-op. */
void vis_wtree_live_destroy(struct vis_wtree_live *live);

/* Drops the live structures' validity: a recompute through the tree rewrites the boxes. */
void wtree_live_invalidate(struct vis_wtree *tree);

/* Takes a window about to be freed out of the live structures (its seen pixels are exposed). */
void wtree_live_forget(struct vis_wtree *tree, struct vis_window *w);

/*
 * After a recompute that went through the whole tree (vis_wtree_compute() or
 * vis_wtree_compute_damaged(), wk its work): the live structures no longer go with the boxes,
 * and the windows whose state changed are listed for vis_wtree_changes().
 */
void wtree_live_computed(struct vis_wtree *tree, const struct vis_wtree_work *wk);

/*
 * Whether a recompute through the tree runs for the live update, which keeps its structures:
 * the keys stay, and instead of wtree_live_computed() the windows it recomputed get their clips
 * as seen regions (wtree_live_repair(), wk its work).
 */
bool wtree_live_keeping(const struct vis_wtree *tree);
void wtree_live_repair(struct vis_wtree *tree, const struct vis_wtree_work *wk);

/* Whether the order (tree->order, positions) is stale: the last recompute was a live one. */
bool wtree_live_order_stale(const struct vis_wtree *tree);

/* Whether the live structures hold every viewable window's clip under its key (then none has a
 * look), so that a visible region can be walked from the grid whatever the last recompute. */
bool wtree_live_indexed(const struct vis_wtree *tree);


/* For self-checks: NULL when the live structures, if valid, meet their invariants, else what
 * is wrong. O(n · cells). */
const char *wtree_live_check(const struct vis_wtree *tree);

/*
 * For tests: the steps an update's walks may take (0: the default, n + 256), so that updates
 * can be made to give up; the boxes a seen region keeps before it is kept as its extents (1 to
 * SEEN_BOXES; 0: SEEN_BOXES), so that small trees have loose regions; the boxes a walk keeps
 * what is left of its pixels in (2 to LEFT_BOXES; 0: LEFT_BOXES), so that small trees' walks
 * fragment past them (wtree-live-walk.c); the steps after which rule 2's walks leave their
 * windows to the seen grid (0: as the grid's entries there say), so that small trees use it.
 */
void wtree_live_tune(struct vis_wtree *tree, size_t steps, unsigned seen_boxes,
		     unsigned left_boxes, size_t cover_steps);

#endif
