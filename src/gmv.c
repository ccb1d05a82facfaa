/* Section 6: the sweep reading top(H_v) from lists computed offline. */
#include <stdint.h>

/*
 * The sweep touches each node in a fixed order, so every node's sequence of inserts and deletes is
 * known before it starts, and so is top(H_v) after each of them. Each node gets a run of slots,
 * one per operation in schedule order; a window stored at v is alive in v's slots [its insert, its
 * delete). Filling the slots window by window in decreasing z, each slot taking the first window
 * that reaches it, solves the offline extract-max problem; a union-find over "next unfilled slot"
 * fills every slot once (near-linear, Bern's trick). The node's aux holds its next slot.
 */
#define SOURCE_LAZY_DELETE 0
#define SOURCE_AUX 2

struct source {
	uint32_t *tops; /* per slot: the node's top after that operation */
};

#include "sweep-impl.h"


static inline uint32_t source_insert(struct source *src, struct head *hd, uint32_t z)
{
	(void)z;
	return src->tops[hd->aux[0]++];
}

static inline uint32_t source_remove(struct source *src, struct head *hd, uint32_t z)
{
	(void)z;
	return src->tops[hd->aux[0]++];
}

static inline void source_deleted(struct source *src, uint32_t z)
{
	(void)src;
	(void)z;
}

static void source_free(struct source *src)
{
	free(src->tops);
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

static int source_make(struct source *src, const struct vis_events *ev, const uint32_t *sched,
		       struct sweep *s)
{
	size_t n = ev->n;
	uint32_t m = ev->nleaves;
	uint32_t canon[VIS_SEGTREE_MAX_CANONICAL];
	uint32_t *wstart = malloc((n + 1) * sizeof(*wstart)); /* window → its canonical run */
	uint32_t *wnode = NULL, *ins = NULL, *del = NULL, *next = NULL;
	src->tops = NULL;
	if (!wstart)
		goto nomem;

	/* Canonical nodes per window, and two slots per (window, node). */
	size_t total = 0;
	for (size_t k = 0; k < n; k++)
		total += vis_segtree_canonical_slots(m, ev->lo[k], ev->hi[k], canon);
	if (2 * total >= UINT32_MAX) {
		free(wstart);
		errno = EOVERFLOW;
		return -1;
	}
	wnode = malloc(total * sizeof(*wnode) + 1);
	ins = malloc(total * sizeof(*ins) + 1);
	del = malloc(total * sizeof(*del) + 1);
	src->tops = calloc(2 * total + 1, sizeof(*src->tops));
	next = malloc((2 * total + 1) * sizeof(*next));
	if (!wnode || !ins || !del || !src->tops || !next)
		goto nomem;
	size_t at = 0;
	for (size_t k = 0; k < n; k++) {
		wstart[k] = (uint32_t)at;
		size_t c = vis_segtree_canonical_slots(m, ev->lo[k], ev->hi[k], wnode + at);
		for (size_t j = 0; j < c; j++)
			head_of_slot(s, wnode[at + j])->aux[0] += 2;
		at += c;
	}
	wstart[n] = (uint32_t)at;
	/* Runs in any order: internal nodes, then leaves. */
	uint32_t sum = 0;
	for (uint32_t i = 0; i + 1 < m; i++) {
		uint32_t c = s->node[i].hd.aux[0];
		s->node[i].hd.aux[0] = s->node[i].hd.aux[1] = sum;
		sum += c;
	}
	for (uint32_t i = 0; i < m; i++) {
		uint32_t c = s->leaf[i].aux[0];
		s->leaf[i].aux[0] = s->leaf[i].aux[1] = sum;
		sum += c;
	}

	/* Number each node's operations in the order the sweep will make them. */
	for (size_t i = 0; i < 2 * n; i++) {
		uint32_t k = VIS_EV_WINDOW(sched[i]);
		uint32_t *slot = VIS_EV_IS_DELETE(sched[i]) ? del : ins;
		for (uint32_t j = wstart[k]; j < wstart[k + 1]; j++)
			slot[j] = head_of_slot(s, wnode[j])->aux[1]++;
	}

	/* Fill: the highest window alive at a slot is the top there. */
	for (size_t s = 0; s <= 2 * total; s++)
		next[s] = (uint32_t)s;
	for (size_t k = n; k-- > 0;) {
		for (uint32_t j = wstart[k]; j < wstart[k + 1]; j++) {
			for (uint32_t s = next_free(next, ins[j]); s < del[j]; s = next_free(next, s)) {
				src->tops[s] = (uint32_t)k + 1;
				next[s] = s + 1;
			}
		}
	}
	free(wstart);
	free(wnode);
	free(ins);
	free(del);
	free(next);
	return 0;
nomem:
	free(wstart);
	free(wnode);
	free(ins);
	free(del);
	free(next);
	source_free(src);
	errno = ENOMEM;
	return -1;
}

int vis_gmv_compute(const struct vis_stack *stack, uint8_t *states)
{
	return sweep_compute(stack, states);
}
