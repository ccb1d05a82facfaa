#include <errno.h>
#include <stdlib.h>

#include "engine.h"
#include "segtree.h"
#include "sweep.h"

/*
 * Section 6: the sweep touches each node in a fixed order, so every node's sequence of inserts and
 * deletes is known before the sweep starts, and so is top(H_v) after each of them. Each node gets
 * a run of slots, one per operation in schedule order; a window stored at v is alive in v's slots
 * [its insert, its delete). Filling the slots window by window in decreasing z, each slot taking
 * the first window that reaches it, solves the offline extract-max problem; a union-find over
 * "next unfilled slot" makes every slot filled once (near-linear, Bern's trick).
 */
struct toplists {
	uint32_t *cur;  /* per node: its next slot */
	uint32_t *tops; /* per slot: the node's top after that operation */
};

static uint32_t list_next(void *ctx, uint32_t v, uint32_t z)
{
	struct toplists *t = ctx;
	(void)z;
	return t->tops[t->cur[v]++];
}

static void lists_free(struct vis_top_source *src)
{
	struct toplists *t = src->ctx;
	if (!t)
		return;
	free(t->cur);
	free(t->tops);
	free(t);
	src->ctx = NULL;
}

/* The union-find root: the first unfilled slot at or after s. */
static inline uint32_t next_free(uint32_t *next, uint32_t s)
{
	uint32_t r = s;
	while (next[r] != r)
		r = next[r];
	while (next[s] != r) {
		uint32_t up = next[s];
		next[s] = r;
		s = up;
	}
	return r;
}

static int lists_make(struct vis_top_source *src, const struct vis_events *ev,
		      const uint32_t *sched)
{
	size_t n = ev->n, nodes = vis_segtree_nodes(ev->nleaves);
	uint32_t m = ev->nleaves;
	struct toplists *t = calloc(1, sizeof(*t));
	src->ctx = t;
	src->insert = list_next;
	src->remove = list_next;
	src->deleted = NULL;
	uint32_t *wstart = malloc((n + 1) * sizeof(*wstart)); /* window → its canonical run */
	uint32_t *wnode = NULL, *ins = NULL, *del = NULL, *next = NULL;
	if (!t || !wstart)
		goto nomem;
	t->cur = calloc(nodes + 1, sizeof(*t->cur));
	if (!t->cur)
		goto nomem;

	/* Canonical nodes per window, and two slots per (window, node). */
	uint32_t canon[VIS_SEGTREE_MAX_CANONICAL];
	size_t total = 0;
	for (size_t k = 0; k < n; k++)
		total += vis_segtree_canonical(m, ev->lo[k], ev->hi[k], canon);
	if (2 * total >= UINT32_MAX) {
		lists_free(src);
		free(wstart);
		errno = EOVERFLOW;
		return -1;
	}
	wnode = malloc(total * sizeof(*wnode) + 1);
	ins = malloc(total * sizeof(*ins) + 1);
	del = malloc(total * sizeof(*del) + 1);
	t->tops = calloc(2 * total + 1, sizeof(*t->tops));
	next = malloc((2 * total + 1) * sizeof(*next));
	if (!wnode || !ins || !del || !t->tops || !next)
		goto nomem;
	size_t at = 0;
	for (size_t k = 0; k < n; k++) {
		wstart[k] = (uint32_t)at;
		size_t c = vis_segtree_canonical(m, ev->lo[k], ev->hi[k], wnode + at);
		for (size_t j = 0; j < c; j++)
			t->cur[wnode[at + j]] += 2;
		at += c;
	}
	wstart[n] = (uint32_t)at;
	uint32_t sum = 0;
	for (size_t v = 0; v < nodes; v++) {
		uint32_t c = t->cur[v];
		t->cur[v] = sum;
		sum += c;
	}

	/* Number each node's operations in the order the sweep will make them. */
	for (size_t i = 0; i < 2 * n; i++) {
		uint32_t k = VIS_EV_WINDOW(sched[i]);
		uint32_t *slot = VIS_EV_IS_DELETE(sched[i]) ? del : ins;
		for (uint32_t j = wstart[k]; j < wstart[k + 1]; j++)
			slot[j] = t->cur[wnode[j]]++;
	}

	/* Fill: the highest window alive at a slot is the top there. */
	for (size_t s = 0; s <= 2 * total; s++)
		next[s] = (uint32_t)s;
	for (size_t k = n; k-- > 0;) {
		for (uint32_t j = wstart[k]; j < wstart[k + 1]; j++) {
			for (uint32_t s = next_free(next, ins[j]); s < del[j]; s = next_free(next, s)) {
				t->tops[s] = (uint32_t)k + 1;
				next[s] = s + 1;
			}
		}
	}

	/* Each cursor now stands at the next node's first slot (runs are in node order): rewind. */
	for (size_t v = nodes; v-- > 1;)
		t->cur[v] = t->cur[v - 1];
	if (nodes)
		t->cur[0] = 0;
	free(wstart);
	free(wnode);
	free(ins);
	free(del);
	free(next);
	return 0;
nomem:
	lists_free(src);
	free(wstart);
	free(wnode);
	free(ins);
	free(del);
	free(next);
	errno = ENOMEM;
	return -1;
}

static const struct vis_top_source_ops list_ops = { lists_make, lists_free };

int vis_gmv_compute(const struct vis_stack *stack, uint8_t *states)
{
	return vis_sweep_compute(stack, &list_ops, states);
}
