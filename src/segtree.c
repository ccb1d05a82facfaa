#include <stdbool.h>

#include "segtree.h"

/* The canonical decomposition, left to right. */
static size_t canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
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

size_t vis_segtree_canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	return canonical(m, a, b, out);
}

/*
 * One end's path below the split node: from node v covering [lo, hi), entry e, down to the node
 * whose interval begins at a (left) or ends at b (right), writing the canonical children off the
 * path top-down and that node last.
 */
static size_t side_entries(uint32_t v, uint32_t lo, uint32_t hi, uint32_t e, uint32_t a,
			   uint32_t b, bool left, uint32_t *out)
{
	size_t count = 0;
	while (left ? a > lo : b < hi) {
		uint32_t mid = vis_segtree_mid(lo, hi), rec = v - lo;
		if (left && a < mid) {
			out[count++] = 2 * rec + 1;
			v = vis_segtree_left(v);
			hi = mid;
			e = 2 * rec;
		} else if (!left && b > mid) {
			out[count++] = 2 * rec;
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = 2 * rec + 1;
		} else if (left) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = 2 * rec + 1;
		} else {
			v = vis_segtree_left(v);
			hi = mid;
			e = 2 * rec;
		}
	}
	out[count++] = e;
	return count;
}

size_t vis_segtree_canonical_entries(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	uint32_t v = 0, lo = 0, hi = m, e = vis_segtree_root_entry(m);
	for (;;) {
		if (a <= lo && hi <= b) {
			out[0] = e;
			return 1;
		}
		uint32_t mid = vis_segtree_mid(lo, hi), rec = v - lo;
		if (b <= mid) {
			v = vis_segtree_left(v);
			hi = mid;
			e = 2 * rec;
		} else if (a >= mid) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = 2 * rec + 1;
		} else {
			size_t c = side_entries(vis_segtree_left(v), lo, mid, 2 * rec, a, b, true, out);
			return c + side_entries(vis_segtree_right(v, lo, mid), mid, hi, 2 * rec + 1, a, b,
						false, out + c);
		}
	}
}
