/* Section 6: the sweep reading top(H_v) from lists computed offline. */
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/*
 * The sweep touches each node in a fixed order, so every node's sequence of inserts and deletes is
 * known before it starts, and so is top(H_v) after each of them. Only the tops after deletions
 * need a list: inserting z makes the top max(top, z), and deleting a window below the top leaves
 * it. So each node gets a run of slots, one per deletion there in schedule order; a window stored
 * at v is alive in v's slots [the first deletion after its insertion, its own deletion). Filling
 * the slots window by window in decreasing z, each slot taking the first window that reaches it,
 * solves the offline extract-max problem; a union-find over "next unfilled slot" fills every slot
 * once (near-linear, Bern's trick).
 *
 * The sweep's deletions, in the order its walks make them, read their slots from one stream in
 * that same order: a sequential read instead of a per-node cursor, which would first have to be
 * read from a node, and which lets each deletion prefetch its top a few events ahead.
 */
#define SOURCE_PREFETCH 0
#define SOURCE_LAZY_DELETE 0
#define SOURCE_AUX 0

/* How far down the stream the top is prefetched: about three deletions' canonical steps. */
#define STREAM_AHEAD 48

/*
 * How many events ahead the numbering prefetches its cursors; twice that, the window's lists (both
 * ends: a list is one to two lines); three times that, where the lists begin.
 */
#define NUMBER_AHEAD 8

/* How far ahead the filling prefetches its union-find's entries. */
#define FILL_AHEAD 4

struct source {
	uint32_t *tops;	  /* per slot: the node's top after that deletion */
	uint32_t *stream; /* the deletions' slots in the sweep's order, then STREAM_AHEAD zeros */
	size_t at, len;
};

#include "sweep-impl.h"

static inline uint32_t source_insert(struct source *src, struct entry *e, uint32_t z)
{
	(void)src;
	return max32(e->top, z);
}

/* The top after the next deletion, as the stream says if z was the top. */
static inline uint32_t source_remove(struct source *src, struct entry *e, uint32_t z)
{
	__builtin_prefetch(&src->tops[src->stream[src->at + STREAM_AHEAD]]);
	uint32_t slot = src->stream[src->at++];
	return e->top == z ? src->tops[slot] : e->top;
}

/* Nothing to prefetch through the node: the stream prefetches its own tops. */
static inline void source_prefetch(const struct source *src, const struct entry *e, uint32_t z,
				   bool del)
{
	(void)src;
	(void)e;
	(void)z;
	(void)del;
}

static inline void source_deleted(struct source *src, uint32_t z)
{
	(void)src;
	(void)z;
}

static void source_free(struct source *src)
{
	vis_bigfree(src->tops);
	vis_bigfree(src->stream);
}

/*
 * The union-find root: the first unfilled slot at or after s, unless a link reaches limit or
 * beyond first, in which case where it lands. The caller wants no slot there, and reading whether
 * it is filled would be a cache miss: links reach far, and most of a window's slots are filled
 * before it comes.
 */
static inline uint32_t next_free(uint32_t *next, uint32_t s, uint32_t limit)
{
	uint32_t r = s;
	while (r < limit && next[r] != r)
		r = next[r];
	while (s != r) {
		uint32_t up = next[s];
		next[s] = r;
		s = up;
	}
	return r;
}

static int source_make(struct source *src, const struct vis_events *ev, struct step *steps,
		       struct sweep *s)
{
	size_t n = ev->n, total;
	uint32_t m = ev->nleaves;
	/*
	 * Window k's canonical entries, in walk order, are canon[first[k] …]; its first slots after
	 * its insertion, after[first[k] …]; its slots, stream[del[k] …]. The union-find takes over
	 * canon's memory.
	 */
	uint32_t *first = malloc((n + 1) * sizeof(*first));
	uint32_t *del = malloc(n * sizeof(*del));
	uint32_t *canon = NULL, *after = NULL, *cursor = s->cand; /* see count_canonical() */
	*src = (struct source){ 0 };
	if (!first || !del || n > (SIZE_MAX / sizeof(*canon) - 1) / vis_segtree_max_canonical(m))
		goto nomem;
	/* Only the pages the lists fill are ever touched. */
	canon = vis_bigalloc((n * vis_segtree_max_canonical(m) + 1) * sizeof(*canon), false);
	if (!canon)
		goto nomem;
	count_canonical(ev, cursor, &total, first, canon);
	if (total >= UINT32_MAX - STREAM_AHEAD) {
		errno = EOVERFLOW;
		goto fail;
	}
	src->tops = vis_bigalloc((total + 1) * sizeof(*src->tops), true);
	src->stream = vis_bigalloc((total + STREAM_AHEAD) * sizeof(*src->stream), false);
	after = vis_bigalloc(total * sizeof(*after) + 1, false);
	if (!src->tops || !src->stream || !after)
		goto nomem;
	memset(src->stream + total, 0, STREAM_AHEAD * sizeof(*src->stream));
	uint32_t sum = 0;
	for (uint32_t i = 0; i < vis_segtree_entries(m); i++) {
		uint32_t c = cursor[i];
		cursor[i] = sum;
		sum += c;
	}

	/* Number each node's deletions in the order the sweep will make them. */
	for (size_t i = 0; i < 2 * n; i++) {
		if (i + NUMBER_AHEAD < 2 * n) {
			uint32_t k = STEP_Z(steps[i + NUMBER_AHEAD].zf) - 1;
			for (uint32_t j = first[k]; j < first[k + 1]; j++)
				__builtin_prefetch(&cursor[canon[j]]);
		}
		if (i + 2 * NUMBER_AHEAD < 2 * n) {
			const struct step *ahead = &steps[i + 2 * NUMBER_AHEAD];
			uint32_t k = STEP_Z(ahead->zf) - 1, j = first[k], end = first[k + 1] - 1;
			__builtin_prefetch(&canon[j]);
			__builtin_prefetch(&canon[end]);
			if (!(ahead->zf & STEP_DELETE)) {
				__builtin_prefetch(&after[j], 1);
				__builtin_prefetch(&after[end], 1);
			}
		}
		if (i + 3 * NUMBER_AHEAD < 2 * n) {
			const struct step *ahead = &steps[i + 3 * NUMBER_AHEAD];
			__builtin_prefetch(&first[STEP_Z(ahead->zf) - 1]);
			if (ahead->zf & STEP_DELETE)
				__builtin_prefetch(&del[STEP_Z(ahead->zf) - 1], 1);
		}
		uint32_t k = STEP_Z(steps[i].zf) - 1;
		if (steps[i].zf & STEP_DELETE) {
			/* A query's deletion walks no node: it has no slots. */
			del[k] = (uint32_t)src->len;
			if (s->query && is_query(s, k + 1))
				continue;
			for (uint32_t j = first[k]; j < first[k + 1]; j++)
				src->stream[src->len++] = cursor[canon[j]]++;
		} else {
			for (uint32_t j = first[k]; j < first[k + 1]; j++)
				after[j] = cursor[canon[j]];
		}
	}
	memset(cursor, 0, vis_segtree_entries(m) * sizeof(*cursor));
	/* The queries' share of the count has no slots: the stream ends early. */
	memset(src->stream + src->len, 0, (total - src->len) * sizeof(*src->stream));

	/* Fill: the highest window alive at a slot is the top there. */
	uint32_t *next = canon;
	for (size_t s = 0; s <= total; s++)
		next[s] = (uint32_t)s;
	for (size_t k = n; k-- > 0;) {
		if (k >= FILL_AHEAD) {
			/* The window FILL_AHEAD later starts its searches there. */
			size_t later = k - FILL_AHEAD;
			for (uint32_t j = first[later]; j < first[later + 1]; j++)
				__builtin_prefetch(&next[after[j]]);
		}
		if (k >= 2 * FILL_AHEAD) {
			size_t later = k - 2 * FILL_AHEAD;
			__builtin_prefetch(src->stream + del[later]);
			__builtin_prefetch(src->stream + del[later] + (first[later + 1] - first[later]) - 1);
		}
		if (s->query && is_query(s, (uint32_t)k + 1))
			continue;
		const uint32_t *from = after + first[k], *to = src->stream + del[k];
		for (uint32_t j = 0; j < first[k + 1] - first[k]; j++) {
			for (uint32_t s = next_free(next, from[j], to[j]); s < to[j];
			     s = next_free(next, s, to[j])) {
				src->tops[s] = (uint32_t)k + 1;
				next[s] = s + 1;
			}
		}
	}
	free(first);
	free(del);
	vis_bigfree(canon);
	vis_bigfree(after);
	return 0;
nomem:
	errno = ENOMEM;
fail:
	free(first);
	free(del);
	vis_bigfree(canon);
	vis_bigfree(after);
	memset(cursor, 0, vis_segtree_entries(m) * sizeof(*cursor));
	source_free(src);
	return -1;
}

int vis_gmv_compute(const struct vis_stack *stack, uint8_t *states)
{
	return sweep_compute(stack, states);
}
