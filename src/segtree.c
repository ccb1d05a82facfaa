#include <stdbool.h>

#include "segtree.h"

/* The canonical decomposition, naming nodes by pre-order index or by storage slot. */
static size_t canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out, bool slots)
{
	/* An explicit stack instead of recursion: the right halves still to visit. */
	struct frame {
		uint32_t v, lo, hi;
	} stack[VIS_SEGTREE_MAX_CANONICAL];
	size_t depth = 0, count = 0;
	uint32_t v = 0, lo = 0, hi = m;
	for (;;) {
		if (a <= lo && hi <= b) {
			out[count++] = slots ? vis_segtree_slot(v, lo, hi) : v;
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
	return canonical(m, a, b, out, false);
}

size_t vis_segtree_canonical_slots(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	return canonical(m, a, b, out, true);
}
