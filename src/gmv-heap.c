/* Sections 4–5: the sweep reading top(H_v) from a max-heap per node. */
#include <stdint.h>

/*
 * The heaps live in one block, each node's slice sized by the windows it will ever hold; the
 * node's aux holds its slice's offset, length, and how much of it is in heap order. Deletion is
 * lazy: a "dead" flag per window, set once, and each node pops dead windows off its top when its
 * top is deleted. Since a deleted window was the top of no node except those RIGHT-DELETE
 * visits, every top stays live.
 *
 * The node's top is cached in its record, so the heap is needed only when the top is deleted.
 * Insertion therefore just appends (one store, where a push would read a parent: a cache miss,
 * the costliest step of the sweep); the appended tail is pushed into heap order when the top is
 * deleted, each element once, in a burst that keeps the heap's top levels in the cache.
 */
#define SOURCE_PREFETCH 1
#define SOURCE_LAZY_DELETE 1
#define SOURCE_AUX 3

struct source {
	uint32_t *a;
	uint8_t *dead; /* by z */
};

#include "sweep-impl.h"

#include "heap.h"

enum { HEAP_OFF, HEAP_LEN, HEAP_ORDERED };

static inline uint32_t source_insert(struct source *src, struct head *hd, uint32_t z)
{
	src->a[hd->aux[HEAP_OFF] + hd->aux[HEAP_LEN]++] = z;
	return z > hd->top ? z : hd->top;
}

static inline uint32_t source_remove(struct source *src, struct head *hd, uint32_t z)
{
	/* z is the only new corpse: unless it is the top, nothing changes. */
	if (hd->top != z)
		return hd->top;
	uint32_t *a = src->a + hd->aux[HEAP_OFF];
	uint32_t len = hd->aux[HEAP_LEN];
	for (uint32_t i = hd->aux[HEAP_ORDERED]; i < len;) {
		uint32_t x = a[i];
		vis_heap_push(a, &i, x);
	}
	do
		vis_heap_pop(a, &len);
	while (len && src->dead[a[0]]);
	hd->aux[HEAP_LEN] = hd->aux[HEAP_ORDERED] = len;
	return len ? a[0] : 0;
}

/* Prefetches what source_insert or source_remove will read beyond the head. */
static inline void source_prefetch(const struct source *src, const struct head *hd, uint32_t z,
				   bool del)
{
	if (!del)
		__builtin_prefetch(src->a + hd->aux[HEAP_OFF] + hd->aux[HEAP_LEN]);
	else if (hd->top == z)
		__builtin_prefetch(src->a + hd->aux[HEAP_OFF]);
}

static inline void source_deleted(struct source *src, uint32_t z)
{
	src->dead[z] = 1;
}

static void source_free(struct source *src)
{
	free(src->a);
	free(src->dead);
}

static inline void source_number(struct source *src, struct head *hd)
{
	(void)src;
	(void)hd;
}

static int source_make(struct source *src, const struct vis_events *ev, struct step *steps,
		       struct sweep *s)
{
	(void)steps;
	uint32_t slots[VIS_SEGTREE_MAX_CANONICAL];
	size_t total = 0;
	src->a = NULL;
	src->dead = calloc(ev->n + 1, 1);
	for (size_t k = 0; k < ev->n; k++) {
		size_t c = vis_segtree_canonical_slots(ev->nleaves, ev->lo[k], ev->hi[k], slots);
		for (size_t j = 0; j < c; j++)
			head_of_slot(s, slots[j])->aux[HEAP_OFF]++;
		total += c;
	}
	if (total > UINT32_MAX) {
		free(src->dead);
		errno = EOVERFLOW;
		return -1;
	}
	/* Slices in any order: internal nodes, then leaves. */
	uint32_t sum = 0;
	for (uint32_t i = 0; i + 1 < ev->nleaves; i++) {
		uint32_t c = s->node[i].hd.aux[HEAP_OFF];
		s->node[i].hd.aux[HEAP_OFF] = sum;
		sum += c;
	}
	for (uint32_t i = 0; i < ev->nleaves; i++) {
		uint32_t c = s->leaf[i].aux[HEAP_OFF];
		s->leaf[i].aux[HEAP_OFF] = sum;
		sum += c;
	}
	src->a = vis_bigalloc(total * sizeof(*src->a), false);
	if (!src->a || !src->dead) {
		source_free(src);
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

int vis_gmv_heap_compute(const struct vis_stack *stack, uint8_t *states)
{
	return sweep_compute(stack, states);
}
