#include <stdbool.h>

#include "segtree.h"

/* The canonical decomposition, naming nodes by pre-order index or by entry. */
static size_t canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out, bool entries)
{
	/* An explicit stack instead of recursion: the right halves still to visit. */
	struct frame {
		uint32_t v, lo, hi, e;
	} stack[VIS_SEGTREE_MAX_CANONICAL];
	size_t depth = 0, count = 0;
	uint32_t v = 0, lo = 0, hi = m, e = vis_segtree_root_entry(m);
	for (;;) {
		if (a <= lo && hi <= b) {
			out[count++] = entries ? e : v;
		} else {
			uint32_t mid = vis_segtree_mid(lo, hi), rec = v - lo;
			if (b > mid && a < mid)
				stack[depth++] =
					(struct frame){ vis_segtree_right(v, lo, mid), mid, hi, 2 * rec + 1 };
			if (a < mid) {
				v = vis_segtree_left(v);
				hi = mid;
				e = 2 * rec;
			} else {
				v = vis_segtree_right(v, lo, mid);
				lo = mid;
				e = 2 * rec + 1;
			}
			continue;
		}
		if (depth == 0)
			return count;
		depth--;
		v = stack[depth].v;
		lo = stack[depth].lo;
		hi = stack[depth].hi;
		e = stack[depth].e;
	}
}

size_t vis_segtree_canonical(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	return canonical(m, a, b, out, false);
}

size_t vis_segtree_canonical_entries(uint32_t m, uint32_t a, uint32_t b, uint32_t *out)
{
	return canonical(m, a, b, out, true);
}
