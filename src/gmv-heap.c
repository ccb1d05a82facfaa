/* Sections 4–5: the sweep reading top(H_v) from a max-heap per node. */
#include <stdint.h>

/*
 * The heaps live in one block, each node's slice sized by the windows it will ever hold; the
 * node's aux holds its slice's offset, length, and how much of it is in heap order. Deletion is
 * lazy: a "dead" flag per window, set once, and each node pops dead windows off its top when its
 * top is deleted. Since a deleted window was the top of no node except those RIGHT-DELETE
 * visits, every top stays live.
 *
 * The node's top is kept in its entry, so the heap is needed only when the top is deleted.
 * Insertion therefore just appends (one store, where a push would read a parent: a cache miss,
 * the costliest step of the sweep); the appended tail is put into heap order when the top is
 * deleted, in a burst that keeps the heap's top levels in the cache. A tail as long as half the
 * ordered part is cheaper rebuilt with it in linear time, and the rebuild drops the dead windows,
 * which popping would have cost O(log) each: on dense stacks, where every window reaches the top
 * of most of its heaps dead, that was most of the heaps' work and its cache misses.
 */
#define SOURCE_PREFETCH 1
#define SOURCE_LAZY_DELETE 1
#define SOURCE_AUX 3

struct source {
	uint32_t *a;
	uint64_t *dead; /* a bit by z: the heaps test it for every window they sift, at random */
};

#include "sweep-impl.h"

#include "heap.h"

enum { HEAP_OFF, HEAP_LEN, HEAP_ORDERED };

static inline bool is_dead(const struct source *src, uint32_t z)
{
	return src->dead[z / 64] >> (z % 64) & 1;
}

static inline uint32_t source_insert(struct source *src, struct entry *e, uint32_t z)
{
	src->a[e->aux[HEAP_OFF] + e->aux[HEAP_LEN]++] = z;
	return z > e->top ? z : e->top;
}

static inline uint32_t source_remove(struct source *src, struct entry *e, uint32_t z)
{
	/* z is the only new corpse: unless it is the top, nothing changes. */
	if (e->top != z)
		return e->top;
	uint32_t *a = src->a + e->aux[HEAP_OFF];
	uint32_t len = e->aux[HEAP_LEN], ordered = e->aux[HEAP_ORDERED];
	if (2 * (len - ordered) >= ordered) {
		/*
		 * A third of the slice or more is unordered: keeping the live windows and
		 * rebuilding costs O(len), paid for by the appended ones, and sweeps out the dead,
		 * each of which would otherwise cost a pop.
		 */
		uint32_t live = 0;
		for (uint32_t i = 0; i < len; i++) {
			if (!is_dead(src, a[i]))
				a[live++] = a[i];
		}
		vis_heap_build(a, live);
		len = live;
	} else {
		/* The dead among the appended would only be popped again. */
		uint32_t i = ordered;
		for (uint32_t j = ordered; j < len; j++) {
			if (!is_dead(src, a[j]))
				vis_heap_push(a, &i, a[j]);
		}
		len = i;
		while (len && is_dead(src, a[0]))
			vis_heap_pop(a, &len);
	}
	e->aux[HEAP_LEN] = e->aux[HEAP_ORDERED] = len;
	return len ? a[0] : 0;
}

/* Prefetches what source_insert or source_remove will read beyond the entry. */
static inline void source_prefetch(const struct source *src, const struct entry *e, uint32_t z,
				   bool del)
{
	if (!del)
		__builtin_prefetch(src->a + e->aux[HEAP_OFF] + e->aux[HEAP_LEN]);
	else if (e->top == z)
		__builtin_prefetch(src->a + e->aux[HEAP_OFF]);
}

static inline void source_deleted(struct source *src, uint32_t z)
{
	src->dead[z / 64] |= (uint64_t)1 << (z % 64);
}

static void source_free(struct source *src)
{
	vis_bigfree(src->a);
	free(src->dead);
}

static int source_make(struct source *src, const struct vis_events *ev, struct step *steps,
		       struct sweep *s)
{
	(void)steps;
	uint32_t m = ev->nleaves;
	size_t total;
	src->a = NULL;
	src->dead = calloc(ev->n / 64 + 1, sizeof(*src->dead));
	count_canonical(ev, s->cand, &total, NULL, NULL);
	if (total > UINT32_MAX) {
		memset(s->cand, 0, vis_segtree_entries(m) * sizeof(*s->cand));
		free(src->dead);
		errno = EOVERFLOW;
		return -1;
	}
	uint32_t sum = 0;
	for (uint32_t i = 0; i < vis_segtree_entries(m); i++) {
		entry_at(s, m, i)->aux[HEAP_OFF] = sum;
		sum += s->cand[i];
	}
	memset(s->cand, 0, vis_segtree_entries(m) * sizeof(*s->cand));
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
