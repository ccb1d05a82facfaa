/* The shape of the segment tree the sweeps share. */
#ifndef VIS_SEGTREE_H
#define VIS_SEGTREE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/*
 * A segment tree over m leaves (elementary intervals 0 … m − 1), laid out in pre-order so that a
 * subtree is one contiguous block: the deep end of a root-to-leaf path, where the cache misses are,
 * stays within a few lines. Node 0 covers [0, m); a node covering [lo, hi) with hi − lo ≥ 2 splits
 * at mid = lo + (hi − lo) / 2, its left child (v + 1) covering [lo, mid) and its right child
 * (v + 2 (mid − lo)) covering [mid, hi). There are 2m − 1 nodes; the height is ⌈log2 m⌉.
 * A range [a, b) is stored at its canonical nodes: the maximal nodes whose interval lies inside it,
 * at most two a level.
 *
 * The sweeps store a node's fields in its parent, next to its sibling's, so that a walk reading a
 * node's record finds both children there: a canonical child then costs no further read. Internal
 * node v covering [lo, hi) (hi − lo ≥ 2) has record v − lo (0 … m − 2, still in pre-order), which
 * holds the entries 2 (v − lo) of its left child and 2 (v − lo) + 1 of its right child; the root's
 * entry is 2 (m − 1). Leaves have entries but no record.
 */

/* The entry of the root of a tree over m ≥ 1 leaves. O(1). */
static inline uint32_t vis_segtree_root_entry(uint32_t m)
{
	return 2 * (m - 1);
}

/* The number of entries of a tree over m leaves (0 for m = 0), like its number of nodes. O(1). */
static inline size_t vis_segtree_entries(uint32_t m)
{
	return m ? 2 * (size_t)m - 1 : 0;
}

#define VIS_SEGTREE_MAX_CANONICAL 64
#define VIS_SEGTREE_MAX_HEIGHT 32

/* The most canonical nodes a range can have in a tree over m ≥ 1 leaves: 2 ⌈log2 m⌉, or 1. O(1). */
static inline size_t vis_segtree_max_canonical(uint32_t m)
{
	unsigned height = m > 1 ? 32 - (unsigned)__builtin_clz(m - 1) : 0;
	return height ? 2 * (size_t)height : 1;
}

static inline uint32_t vis_segtree_mid(uint32_t lo, uint32_t hi)
{
	return lo + (hi - lo) / 2;
}

static inline uint32_t vis_segtree_left(uint32_t v)
{
	return v + 1;
}

static inline uint32_t vis_segtree_right(uint32_t v, uint32_t lo, uint32_t mid)
{
	return v + 2 * (mid - lo);
}

/*
 * Moves node v covering [*lo, *hi) (*hi − *lo ≥ 2) to its right child if right, else to its left
 * one, and returns the child. Without a branch: for ranges in random order a walk's turns are coin
 * tosses that the branch predictor loses, at some 15 cycles each; where consecutive walks turn
 * alike, a branch is cheaper (see near_previous() in sweep-walk.h). O(1).
 */
static inline uint32_t vis_segtree_down(uint32_t v, uint32_t *lo, uint32_t *hi, bool right)
{
	uint32_t mid = vis_segtree_mid(*lo, *hi), mask = -(uint32_t)right;
	v += 1 + (mask & (2 * (mid - *lo) - 1));
	*lo += mask & (mid - *lo);
	*hi = mid + (mask & (*hi - mid));
	return v;
}

/* The number of nodes of a tree over m leaves (0 for m = 0). O(1). */
static inline size_t vis_segtree_nodes(uint32_t m)
{
	return m ? 2 * (size_t)m - 1 : 0;
}

/*
 * Writes the canonical nodes of [a, b) (0 ≤ a < b ≤ m) into out, left to right, and returns their
 * number (at most 2 ⌈log2 m⌉ ≤ VIS_SEGTREE_MAX_CANONICAL). O(log m).
 */
size_t vis_segtree_canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out);

/*
 * As vis_segtree_canonical(), writing the nodes' entries in the order a root-to-leaf walk meets
 * them: where the range is one node, that node; else, below the split node (the deepest node
 * whose interval holds [a, b)), the canonical nodes along the path down to a, top-down (right to
 * left), then those along the path down to b, top-down (left to right). O(log m).
 */
size_t vis_segtree_canonical_entries(uint32_t m, uint32_t a, uint32_t b, uint32_t *out);

#endif
