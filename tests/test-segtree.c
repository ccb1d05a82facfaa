/* Unit tests of the segment tree's shape and of the sweeps' event preparation. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "segtree.h"
#include "check.h"

/*
 * Records every node's interval and entry (e: the entry its parent gives it) by walking the
 * layout; checks indices are a permutation.
 */
static void walk(uint32_t v, uint32_t lo, uint32_t hi, uint32_t e, uint32_t *nlo, uint32_t *nhi,
		 uint32_t *nent, size_t nodes)
{
	CHECK(v < nodes);
	if (v >= nodes)
		return;
	CHECK(nhi[v] == 0);
	nlo[v] = lo;
	nhi[v] = hi;
	nent[v] = e;
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		/* The branchless descent lands where the layout says. */
		uint32_t llo = lo, lhi = hi, rlo = lo, rhi = hi;
		CHECK(vis_segtree_down(v, &llo, &lhi, false) == vis_segtree_left(v));
		CHECK(llo == lo && lhi == mid);
		CHECK(vis_segtree_down(v, &rlo, &rhi, true) == vis_segtree_right(v, lo, mid));
		CHECK(rlo == mid && rhi == hi);
		walk(vis_segtree_left(v), lo, mid, 2 * (v - lo), nlo, nhi, nent, nodes);
		walk(vis_segtree_right(v, lo, mid), mid, hi, 2 * (v - lo) + 1, nlo, nhi, nent, nodes);
	}
}

static unsigned log2_ceil(uint32_t m)
{
	unsigned h = 0;
	while ((1ull << h) < m)
		h++;
	return h;
}

static void test_layout_and_canonical(void)
{
	for (uint32_t m = 1; m <= 70; m++) {
		size_t nodes = vis_segtree_nodes(m);
		CHECK(vis_segtree_entries(m) == nodes);
		uint32_t *nlo = calloc(nodes, sizeof(*nlo)), *nhi = calloc(nodes, sizeof(*nhi));
		uint32_t *nent = calloc(nodes, sizeof(*nent));
		walk(0, 0, m, vis_segtree_root_entry(m), nlo, nhi, nent, nodes);
		for (size_t v = 0; v < nodes; v++)
			CHECK(nhi[v] > nlo[v]); /* every index used exactly once */
		/* Records are 0 … m − 2 and entries 0 … 2m − 2, each once. */
		uint8_t *seen = calloc(nodes, 1);
		for (size_t v = 0; v < nodes; v++) {
			CHECK(nent[v] < nodes && !seen[nent[v]]);
			if (nent[v] < nodes)
				seen[nent[v]] = 1;
			if (nhi[v] - nlo[v] > 1)
				CHECK(v - nlo[v] + 1 < m);
		}
		free(seen);
		for (uint32_t a = 0; a < m; a++) {
			for (uint32_t b = a + 1; b <= m; b++) {
				uint32_t out[VIS_SEGTREE_MAX_CANONICAL];
				size_t c = vis_segtree_canonical(m, a, b, out);
				uint32_t entries[VIS_SEGTREE_MAX_CANONICAL];
				CHECK(vis_segtree_canonical_entries(m, a, b, entries) == c);
				/*
				 * Walk order: the nodes left of the split node's middle right to
				 * left, then the others left to right.
				 */
				uint32_t v = 0, split = a;
				while (!(a <= nlo[v] && nhi[v] <= b)) {
					uint32_t mid = vis_segtree_mid(nlo[v], nhi[v]);
					if (b <= mid) {
						v = vis_segtree_left(v);
					} else if (a >= mid) {
						v = vis_segtree_right(v, nlo[v], mid);
					} else {
						split = mid;
						break;
					}
				}
				size_t nleft = 0;
				while (nleft < c && nhi[out[nleft]] <= split)
					nleft++;
				for (size_t j = 0; j < c; j++)
					CHECK(entries[j] == nent[out[j < nleft ? nleft - 1 - j : j]]);
				CHECK(c >= 1 && c <= 2 * log2_ceil(m) + (m == 1));
				/* Left to right, abutting, covering exactly [a, b). */
				uint32_t at = a;
				for (size_t j = 0; j < c; j++) {
					CHECK(nlo[out[j]] == at);
					at = nhi[out[j]];
				}
				CHECK(at == b);
				/* Maximal: no canonical node's parent lies inside [a, b). */
				for (size_t j = 0; j < c; j++) {
					for (size_t p = 0; p < nodes; p++) {
						bool parent = nhi[p] - nlo[p] > 1 &&
							      (vis_segtree_left((uint32_t)p) == out[j] ||
							       vis_segtree_right((uint32_t)p, nlo[p],
										 vis_segtree_mid(nlo[p], nhi[p])) == out[j]);
						if (parent)
							CHECK(!(a <= nlo[p] && nhi[p] <= b));
					}
				}
			}
		}
		free(nlo);
		free(nhi);
		free(nent);
	}
	CHECK(vis_segtree_nodes(0) == 0);
}

static void test_events(void)
{
	/* Bottom-to-top; window 1 is off the 10×10 screen, window 3 only touches it. */
	struct vis_rect r[] = {
		{ 0, 0, 10, 1 }, { 20, 20, 5, 5 }, { 0, 0, 5, 1 }, { 10, 0, 3, 3 }, { 5, 0, 5, 1 },
		{ 5, 0, 5, 4 },
	};
	struct vis_stack st = { r, 6, true, 10, 10, NULL, NULL };
	struct vis_events ev;
	CHECK(vis_events_init(&ev, &st) == 0);
	CHECK(ev.n == 4); /* the two zero-area windows are dropped */
	CHECK(ev.idx[0] == 0 && ev.idx[1] == 2 && ev.idx[2] == 4 && ev.idx[3] == 5);
	CHECK(ev.nleaves == 2); /* y edges 0, 1, 4 */
	CHECK(ev.lo[0] == 0 && ev.hi[0] == 1 && ev.lo[3] == 0 && ev.hi[3] == 2);
	uint32_t sched[8];
	CHECK(vis_events_schedule(&ev, sched) == 0);
	/* x=0: insert 1, 0 (decreasing z); x=5: insert 3, 2, then delete 1; x=10: delete 0, 2, 3. */
	uint32_t want[] = { 1 << 1, 0 << 1, 3 << 1, 2 << 1, 1 << 1 | 1, 0 << 1 | 1, 2 << 1 | 1, 3 << 1 | 1 };
	CHECK(memcmp(sched, want, sizeof(want)) == 0);
	vis_events_finish(&ev);

	/* Edges beyond INT32_MAX and below INT32_MIN, without a screen. */
	struct vis_rect big[] = { { INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX },
				  { INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX },
				  { -1, -1, 2, 2 } };
	struct vis_stack bs = { big, 3, false, 0, 0, NULL, NULL };
	CHECK(vis_events_init(&ev, &bs) == 0);
	CHECK(ev.n == 3 && ev.nleaves == 4); /* y edges INT32_MIN, -1, 1, INT32_MAX, 2^32 - 2 */
	CHECK(ev.lo[0] == 0 && ev.hi[0] == 1 && ev.lo[2] == 1 && ev.hi[2] == 2);
	CHECK(ev.lo[1] == 3 && ev.hi[1] == 4);
	CHECK(vis_events_schedule(&ev, sched) == 0);
	CHECK(sched[0] == 0 && sched[5] == (1 << 1 | 1));
	vis_events_finish(&ev);
}

int main(void)
{
	test_layout_and_canonical();
	test_events();
	printf("segtree: %s\n", failures ? "FAILED" : "ok");
	printf("%d passed, %d failed\n", failures ? 0 : 2, failures ? 1 : 0);
	return failures != 0;
}
