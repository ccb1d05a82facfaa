#include <errno.h>
#include <stdlib.h>

#include "engine.h"
#include "heap.h"
#include "segtree.h"
#include "sweep.h"

/*
 * Sections 4–5: top(H_v) from a max-heap per node. The heaps live in one block, each node's slice
 * sized by the windows it will ever hold. A deleted window is removed from every node it is stored
 * at in one RIGHT-DELETE, so one "dead" flag per window makes lazy deletion exact: each node pops
 * dead windows off its top, and tops are always live.
 */
struct heaps {
	uint32_t *off, *len, *a;
	uint8_t *dead; /* by z */
};

static uint32_t heap_insert(void *ctx, uint32_t v, uint32_t z)
{
	struct heaps *h = ctx;
	uint32_t *a = h->a + h->off[v];
	vis_heap_push(a, &h->len[v], z);
	return a[0];
}

static uint32_t heap_remove(void *ctx, uint32_t v, uint32_t z)
{
	struct heaps *h = ctx;
	uint32_t *a = h->a + h->off[v];
	(void)z;
	while (h->len[v] && h->dead[a[0]])
		vis_heap_pop(a, &h->len[v]);
	return h->len[v] ? a[0] : 0;
}

static void heap_deleted(void *ctx, uint32_t z)
{
	struct heaps *h = ctx;
	h->dead[z] = 1;
}

static void heaps_free(struct vis_top_source *src)
{
	struct heaps *h = src->ctx;
	if (!h)
		return;
	free(h->off);
	free(h->len);
	free(h->a);
	free(h->dead);
	free(h);
	src->ctx = NULL;
}

static int heaps_make(struct vis_top_source *src, const struct vis_events *ev,
		      const uint32_t *sched)
{
	(void)sched;
	size_t nodes = vis_segtree_nodes(ev->nleaves);
	struct heaps *h = calloc(1, sizeof(*h));
	src->ctx = h;
	src->insert = heap_insert;
	src->remove = heap_remove;
	src->deleted = heap_deleted;
	if (!h)
		goto nomem;
	h->off = calloc(nodes + 1, sizeof(*h->off));
	h->len = calloc(nodes + 1, sizeof(*h->len));
	h->dead = calloc(ev->n + 1, 1);
	if (!h->off || !h->len || !h->dead)
		goto nomem;
	uint32_t canon[VIS_SEGTREE_MAX_CANONICAL];
	size_t total = 0;
	for (size_t k = 0; k < ev->n; k++) {
		size_t c = vis_segtree_canonical(ev->nleaves, ev->lo[k], ev->hi[k], canon);
		for (size_t j = 0; j < c; j++)
			h->off[canon[j]]++;
		total += c;
	}
	if (total > UINT32_MAX) {
		heaps_free(src);
		errno = EOVERFLOW;
		return -1;
	}
	uint32_t sum = 0;
	for (size_t v = 0; v < nodes; v++) {
		uint32_t c = h->off[v];
		h->off[v] = sum;
		sum += c;
	}
	h->a = malloc(total * sizeof(*h->a) + 1);
	if (!h->a)
		goto nomem;
	return 0;
nomem:
	heaps_free(src);
	errno = ENOMEM;
	return -1;
}

static const struct vis_top_source_ops heap_ops = { heaps_make, heaps_free };

int vis_gmv_heap_compute(const struct vis_stack *stack, uint8_t *states)
{
	return vis_sweep_compute(stack, &heap_ops, states);
}
