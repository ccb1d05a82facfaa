#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "classify.h"
#include "heap.h"
#include "segtree.h"

/*
 * The overlap sweep's tree. Windows are z = k + 1. At each node, two heaps in one shared block
 * each (sized by a counting pass): the windows stored there (max-heap, always topped by a live
 * window, since a deletion cleans every node it is stored at) and the unmarked candidates stored
 * there (a max-heap of UINT32_MAX − z, i.e. a min-heap of z, cleaned lazily: a candidate marked
 * through one node stays in its others until it surfaces). Invariants after every event:
 * - submax: the highest window stored in the subtree (exact);
 * - submin: at most the lowest unmarked candidate stored in the subtree (UINT32_MAX if none).
 */
struct overlap {
	uint32_t *submax, *submin;
	uint32_t *maxoff, *maxlen, *minoff, *minlen;
	uint32_t *maxheap, *minheap;
	uint8_t *deleted, *marked, *cand; /* by z */
	uint32_t a, b, z, q;             /* the current event; q: highest overlap found */
};

static inline uint32_t max32(uint32_t a, uint32_t b)
{
	return a > b ? a : b;
}

static inline uint32_t min32(uint32_t a, uint32_t b)
{
	return a < b ? a : b;
}

static inline uint32_t max_top(const struct overlap *o, uint32_t v)
{
	return o->maxlen[v] ? o->maxheap[o->maxoff[v]] : 0;
}

/* Drops dead windows from the top of v's heaps, then returns its lowest candidate. */
static inline uint32_t clean(struct overlap *o, uint32_t v)
{
	uint32_t *mx = o->maxheap + o->maxoff[v];
	while (o->maxlen[v] && o->deleted[mx[0]])
		vis_heap_pop(mx, &o->maxlen[v]);
	uint32_t *mn = o->minheap + o->minoff[v];
	while (o->minlen[v]) {
		uint32_t t = UINT32_MAX - mn[0];
		if (!o->deleted[t] && !o->marked[t])
			return t;
		vis_heap_pop(mn, &o->minlen[v]);
	}
	return UINT32_MAX;
}

/* Recomputes v's aggregates from its heaps and its children's. */
static inline void aggregate(struct overlap *o, uint32_t v, uint32_t lo, uint32_t hi)
{
	uint32_t mn = clean(o, v), mx = max_top(o, v);
	if (hi - lo > 1) {
		uint32_t u = vis_segtree_left(v), w = vis_segtree_right(v, lo, vis_segtree_mid(lo, hi));
		mx = max32(mx, max32(o->submax[u], o->submax[w]));
		mn = min32(mn, min32(o->submin[u], o->submin[w]));
	}
	o->submax[v] = mx;
	o->submin[v] = mn;
}

/* Marks the unmarked candidates stored at v that lie below the current window. */
static inline void mark_at(struct overlap *o, uint32_t v)
{
	uint32_t *mn = o->minheap + o->minoff[v];
	while (o->minlen[v]) {
		uint32_t t = UINT32_MAX - mn[0];
		if (t >= o->z && !o->deleted[t] && !o->marked[t])
			break;
		if (t < o->z)
			o->marked[t] = 1;
		vis_heap_pop(mn, &o->minlen[v]);
	}
}

/* Marks every unmarked candidate below the current window stored in v's subtree. */
static void mark_below(struct overlap *o, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (o->submin[v] >= o->z)
		return;
	mark_at(o, v);
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		mark_below(o, vis_segtree_left(v), lo, mid);
		mark_below(o, vis_segtree_right(v, lo, mid), mid, hi);
	}
	aggregate(o, v, lo, hi);
}

static void insert(struct overlap *o, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (o->a <= lo && hi <= o->b) {
		/* Everything in this subtree overlaps the window. */
		o->q = max32(o->q, o->submax[v]);
		mark_below(o, v, lo, hi);
		vis_heap_push(o->maxheap + o->maxoff[v], &o->maxlen[v], o->z);
		if (o->cand[o->z])
			vis_heap_push(o->minheap + o->minoff[v], &o->minlen[v], UINT32_MAX - o->z);
		aggregate(o, v, lo, hi);
		return;
	}
	/* What is stored here spans v's interval, which meets the window's. */
	o->q = max32(o->q, max_top(o, v));
	mark_at(o, v);
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (o->a < mid)
		insert(o, vis_segtree_left(v), lo, mid);
	if (o->b > mid)
		insert(o, vis_segtree_right(v, lo, mid), mid, hi);
	aggregate(o, v, lo, hi);
}

static void delete(struct overlap *o, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (!(o->a <= lo && hi <= o->b)) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		if (o->a < mid)
			delete(o, vis_segtree_left(v), lo, mid);
		if (o->b > mid)
			delete(o, vis_segtree_right(v, lo, mid), mid, hi);
	}
	aggregate(o, v, lo, hi);
}

/* Lays the per-node heaps out in one block each, sized by the windows each node will hold. */
static int layout(struct overlap *o, const struct vis_events *ev, size_t first, size_t nodes)
{
	uint32_t canon[VIS_SEGTREE_MAX_CANONICAL];
	size_t maxsum = 0, minsum = 0;
	for (size_t k = first; k < ev->n; k++) {
		size_t c = vis_segtree_canonical(ev->nleaves, ev->lo[k], ev->hi[k], canon);
		for (size_t j = 0; j < c; j++) {
			o->maxoff[canon[j]]++;
			if (o->cand[k + 1])
				o->minoff[canon[j]]++;
		}
		maxsum += c;
		minsum += o->cand[k + 1] ? c : 0;
	}
	if (maxsum > UINT32_MAX) {
		errno = EOVERFLOW;
		return -1;
	}
	uint32_t sx = 0, sn = 0;
	for (size_t v = 0; v < nodes; v++) {
		uint32_t cx = o->maxoff[v], cn = o->minoff[v];
		o->maxoff[v] = sx;
		o->minoff[v] = sn;
		sx += cx;
		sn += cn;
	}
	o->maxheap = malloc(maxsum * sizeof(uint32_t) + 1);
	o->minheap = malloc(minsum * sizeof(uint32_t) + 1);
	if (!o->maxheap || !o->minheap) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

/* Marks the candidates some higher window overlaps; returns 0 or -1 (ENOMEM). */
static int overlap_sweep(struct overlap *o, const struct vis_events *ev, size_t first)
{
	size_t n = ev->n, nodes = vis_segtree_nodes(ev->nleaves);
	uint32_t m = ev->nleaves;
	int rc = -1;
	uint32_t *sched = malloc(2 * n * sizeof(*sched));
	o->submax = calloc(nodes, sizeof(uint32_t));
	o->submin = malloc(nodes * sizeof(uint32_t));
	o->maxoff = calloc(nodes, sizeof(uint32_t));
	o->maxlen = calloc(nodes, sizeof(uint32_t));
	o->minoff = calloc(nodes, sizeof(uint32_t));
	o->minlen = calloc(nodes, sizeof(uint32_t));
	o->deleted = calloc(n + 1, 1);
	o->marked = calloc(n + 1, 1);
	if (!sched || !o->submax || !o->submin || !o->maxoff || !o->maxlen || !o->minoff ||
	    !o->minlen || !o->deleted || !o->marked) {
		errno = ENOMEM;
		goto out;
	}
	for (size_t v = 0; v < nodes; v++)
		o->submin[v] = UINT32_MAX;
	if (layout(o, ev, first, nodes) < 0)
		goto out;
	if (vis_events_schedule(ev, VIS_ORDER_OVERLAP, sched) < 0)
		goto out;
	for (size_t i = 0; i < 2 * n; i++) {
		uint32_t k = VIS_EV_WINDOW(sched[i]);
		if (k < first)
			continue; /* below every candidate: cannot matter */
		o->z = k + 1;
		o->a = ev->lo[k];
		o->b = ev->hi[k];
		if (VIS_EV_IS_DELETE(sched[i])) {
			o->deleted[o->z] = 1;
			delete(o, 0, 0, m);
		} else {
			o->q = 0;
			insert(o, 0, 0, m);
			if (o->cand[o->z] && o->q > o->z)
				o->marked[o->z] = 1;
		}
	}
	rc = 0;
out:
	free(sched);
	free(o->submax);
	free(o->submin);
	free(o->maxoff);
	free(o->maxlen);
	free(o->minoff);
	free(o->minlen);
	free(o->maxheap);
	free(o->minheap);
	free(o->deleted);
	return rc;
}

int vis_classify(const struct vis_stack *stack, const struct vis_events *ev,
		 const uint8_t *visible, uint8_t *states)
{
	for (size_t i = 0; i < stack->n; i++)
		states[i] = VIS_FULLY_OBSCURED;
	size_t n = ev->n, first = n;
	struct overlap o = { 0 };
	o.cand = calloc(n + 1, 1);
	if (!o.cand) {
		errno = ENOMEM;
		return -1;
	}
	for (size_t k = 0; k < n; k++) {
		if (!visible[k])
			continue;
		states[ev->idx[k]] = VIS_PARTIALLY_OBSCURED;
		if (vis_stack_on_screen(stack, ev->idx[k])) {
			o.cand[k + 1] = 1;
			first = first < k ? first : k;
		}
	}
	int rc = 0;
	if (first < n) {
		rc = overlap_sweep(&o, ev, first);
		for (size_t k = first; rc == 0 && k < n; k++)
			if (o.cand[k + 1] && !o.marked[k + 1])
				states[ev->idx[k]] = VIS_UNOBSCURED;
	}
	free(o.marked);
	free(o.cand);
	return rc;
}
