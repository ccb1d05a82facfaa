/* Section 6: the sweep reading top(H_v) from lists computed offline. */
#include <stddef.h>
#include <stdint.h>
#include <string.h>

/*
 * The sweep touches each node in a fixed order, so every node's sequence of inserts and deletes is
 * known before it starts, and so is top(H_v) after each of them. Each node gets a run of slots,
 * one per operation in schedule order; a window stored at v is alive in v's slots [its insert, its
 * delete). Filling the slots window by window in decreasing z, each slot taking the first window
 * that reaches it, solves the offline extract-max problem; a union-find over "next unfilled slot"
 * fills every slot once (near-linear, Bern's trick).
 *
 * The sweep's canonical steps, in the order its walks make them, read their slots from one stream
 * in that same order: a sequential read instead of a per-node cursor, which lets each step
 * prefetch the top a few events ahead, where the cursor would first have to be read from a node.
 * An event's steps for the insertion and the deletion of one window visit the same nodes in the
 * same order, so their slots pair up in the stream.
 */
#define SOURCE_PREFETCH 0
#define SOURCE_LAZY_DELETE 0
#define SOURCE_AUX 0

/* How far down the stream the top is prefetched: about three events' canonical steps. */
#define STREAM_AHEAD 48

/* How far ahead the numbering prefetches nodes, and the filling its union-find's entries. */
#define NUMBER_AHEAD 32
#define FILL_AHEAD 4

struct source {
	uint32_t *tops;	  /* per slot: the node's top after that operation */
	uint32_t *stream; /* the slots in the sweep's order, then STREAM_AHEAD zeros */
	size_t at, len;
};

#include "sweep-impl.h"

/* The top after the next canonical step, as the stream says. */
static inline uint32_t next_top(struct source *src)
{
	__builtin_prefetch(&src->tops[src->stream[src->at + STREAM_AHEAD]]);
	return src->tops[src->stream[src->at++]];
}

static inline uint32_t source_insert(struct source *src, struct entry *e, uint32_t z)
{
	(void)e;
	(void)z;
	return next_top(src);
}

static inline uint32_t source_remove(struct source *src, struct entry *e, uint32_t z)
{
	(void)e;
	(void)z;
	return next_top(src);
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

/*
 * Numbers the next operation at the node: its slot goes down the stream. Before the sweep begins
 * the entries' tops are free, and each holds the node's next slot meanwhile.
 */
static inline void source_number(struct source *src, struct entry *e)
{
	src->stream[src->len++] = e->top++;
}

static void source_free(struct source *src)
{
	free(src->tops);
	free(src->stream);
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

static int source_make(struct source *src, const struct vis_events *ev, struct step *steps,
		       struct sweep *s)
{
	size_t n = ev->n;
	uint32_t m = ev->nleaves;
	uint32_t canon[VIS_SEGTREE_MAX_CANONICAL];
	/*
	 * Where window k's steps begin down the stream: 3k its insertion's, 3k + 1 its deletion's;
	 * 3k + 2 holds how many canonical nodes it has.
	 */
	uint32_t *pos = malloc(3 * n * sizeof(*pos));
	uint32_t *next = NULL;
	*src = (struct source){ 0 };
	if (!pos)
		goto nomem;

	/* Two slots per (window, canonical node), counted in the entries' tops. */
	size_t total = 0;
	for (size_t k = 0; k < n; k++) {
		size_t c = vis_segtree_canonical_entries(m, ev->lo[k], ev->hi[k], canon);
		for (size_t j = 0; j < c; j++)
			entry_at(s, m, canon[j])->top += 2;
		pos[3 * k + 2] = (uint32_t)c;
		total += c;
	}
	if (2 * total >= UINT32_MAX - STREAM_AHEAD) {
		free(pos);
		errno = EOVERFLOW;
		return -1;
	}
	src->tops = vis_bigalloc((2 * total + 1) * sizeof(*src->tops), true);
	src->stream = vis_bigalloc((2 * total + STREAM_AHEAD) * sizeof(*src->stream), false);
	next = vis_bigalloc((2 * total + 1) * sizeof(*next), false);
	if (!src->tops || !src->stream || !next)
		goto nomem;
	memset(src->stream + 2 * total, 0, STREAM_AHEAD * sizeof(*src->stream));
	uint32_t sum = 0;
	for (uint32_t i = 0; i < vis_segtree_entries(m); i++) {
		struct entry *e = entry_at(s, m, i);
		uint32_t c = e->top;
		e->top = sum;
		sum += c;
	}

	/* Number each node's operations in the order the sweep will make them. */
	bool prefetch = prefetch_pays(m);
	for (size_t i = 0; i < 2 * n; i++) {
		if (prefetch && i + NUMBER_AHEAD < 2 * n)
			prefetch_nodes(s, &steps[i + NUMBER_AHEAD], m);
		uint32_t k = STEP_Z(steps[i].zf) - 1;
		pos[3 * k + !!(steps[i].zf & STEP_DELETE)] = (uint32_t)src->len;
		walk_number(s, &steps[i], m);
	}
	for (uint32_t i = 0; i < vis_segtree_entries(m); i++)
		entry_at(s, m, i)->top = 0;

	/* Fill: the highest window alive at a slot is the top there. */
	for (size_t s = 0; s <= 2 * total; s++)
		next[s] = (uint32_t)s;
	for (size_t k = n; k-- > 0;) {
		if (k >= FILL_AHEAD) {
			/* The window FILL_AHEAD later starts its searches there. */
			const uint32_t *later = src->stream + pos[3 * (k - FILL_AHEAD)];
			for (uint32_t j = 0; j < pos[3 * (k - FILL_AHEAD) + 2]; j++)
				__builtin_prefetch(&next[later[j]]);
		}
		if (k >= 2 * FILL_AHEAD)
			__builtin_prefetch(src->stream + pos[3 * (k - 2 * FILL_AHEAD)]);
		const uint32_t *ins = src->stream + pos[3 * k], *del = src->stream + pos[3 * k + 1];
		for (uint32_t j = 0; j < pos[3 * k + 2]; j++) {
			for (uint32_t s = next_free(next, ins[j]); s < del[j]; s = next_free(next, s)) {
				src->tops[s] = (uint32_t)k + 1;
				next[s] = s + 1;
			}
		}
	}
	free(pos);
	free(next);
	return 0;
nomem:
	free(pos);
	free(next);
	source_free(src);
	errno = ENOMEM;
	return -1;
}

int vis_gmv_compute(const struct vis_stack *stack, uint8_t *states)
{
	return sweep_compute(stack, states);
}
