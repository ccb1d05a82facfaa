#include <stdbool.h>

#include "segtree.h"

size_t vis_segtree_canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	/* An explicit stack instead of recursion: the right halves still to visit. */
	struct frame {
		uint32_t v, lo, hi;
	} stack[VIS_SEGTREE_MAX_CANONICAL];
	size_t depth = 0, count = 0;
	uint32_t v = 0, lo = 0, hi = m;
	for (;;) {
		if (a <= lo && hi <= b) {
			out[count++] = v;
		} else {
			uint32_t mid = vis_segtree_mid(lo, hi);
			if (b > mid && a < mid)
				stack[depth++] = (struct frame){ vis_segtree_right(v, lo, mid), mid, hi };
			if (a < mid) {
				v = vis_segtree_left(v);
				hi = mid;
			} else {
				v = vis_segtree_right(v, lo, mid);
				lo = mid;
			}
			continue;
		}
		if (depth == 0)
			return count;
		depth--;
		v = stack[depth].v;
		lo = stack[depth].lo;
		hi = stack[depth].hi;
	}
}

/* A node on a walk: its pre-order index, interval [lo, hi) and entry. */
struct node {
	uint32_t v, lo, hi, e;
};

/* Moves an internal node to its left or right child. */
static inline void down(struct node *n, bool left)
{
	uint32_t mid = vis_segtree_mid(n->lo, n->hi), rec = n->v - n->lo;
	if (left) {
		n->v = vis_segtree_left(n->v);
		n->hi = mid;
	} else {
		n->v = vis_segtree_right(n->v, n->lo, mid);
		n->lo = mid;
	}
	n->e = 2 * rec + !left;
}

/*
 * One end's path below the split node, from its child n down to the node whose interval begins at
 * a (left) or ends at b (right), writing the canonical children off the path top-down and that
 * node last.
 */
static size_t side_entries(struct node n, uint32_t a, uint32_t b, bool left, uint32_t *out)
{
	size_t count = 0;
	while (left ? a > n.lo : b < n.hi) {
		uint32_t mid = vis_segtree_mid(n.lo, n.hi);
		/* Whether the child away from the range's end lies inside the range. */
		bool inside = left ? a < mid : b > mid;
		bool go_left = left == inside;
		if (inside)
			out[count++] = 2 * (n.v - n.lo) + go_left; /* the other child */
		down(&n, go_left);
	}
	out[count++] = n.e;
	return count;
}

size_t vis_segtree_canonical_entries(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	struct node n = { 0, 0, m, vis_segtree_root_entry(m) };
	while (!(a <= n.lo && n.hi <= b)) {
		uint32_t mid = vis_segtree_mid(n.lo, n.hi);
		if (a < mid && b > mid) {
			struct node l = n, r = n;
			down(&l, true);
			down(&r, false);
			size_t c = side_entries(l, a, b, true, out);
			return c + side_entries(r, a, b, false, out + c);
		}
		down(&n, b <= mid);
	}
	out[0] = n.e;
	return 1;
}
