/*
 * The live recompute's structures, private to src/wtree-*.c: what the tree's other parts tell it
 * (a window destroyed, a recompute that did not go through it) and ask of it (a visible region).
 */
#ifndef VIS_WTREE_LIVE_H
#define VIS_WTREE_LIVE_H

#include "wtree-work.h"

/* The keys of a recompute's order: position i of n gets key_of(i), spaced for insertions. */
#define WTREE_KEY_BASE ((uint64_t)1 << 62)
#define WTREE_KEY_SPAN ((uint64_t)1 << 61)

static inline uint64_t wtree_key_of(size_t i, size_t n)
{
	return WTREE_KEY_BASE + (uint64_t)(i + 1) * (WTREE_KEY_SPAN / ((uint64_t)n + 1));
}

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

/* The window's visible region, as vis_wtree_visible_region() gives it, from the live index. */
int wtree_live_region(const struct vis_wtree *tree, const struct vis_window *w, void *region);

/* For self-checks: NULL when the live structures, if valid, meet their invariants, else what
 * is wrong. O(n · cells). */
const char *wtree_live_check(const struct vis_wtree *tree);

/* For tests: the steps an update's walks may take (0: the default, n / 4 + 256), so that updates
 * can be made to give up. */
void wtree_live_tune(struct vis_wtree *tree, size_t steps);

#endif
