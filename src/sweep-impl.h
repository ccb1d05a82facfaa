/*
 * The Grove–Murali–Vitter sweep, included by the two engines that differ only in where they read
 * top(H_v) from: gmv-heap.c (per-node heaps, sections 4–5) and gmv.c (offline top lists, section
 * 6). The sweep is memory-latency bound and makes these reads at every canonical node, so each
 * engine gets its own copy with the reads inlined and their state in the node's entry itself.
 * Define SOURCE_AUX (the words of per-node state the source keeps through the sweep, 0 or more),
 * SOURCE_LAZY_DELETE (1 if the source needs no call for a deletion at a node the window does not
 * top), SOURCE_PREFETCH (1 if source_prefetch() does anything) and struct source before
 * including this, and after it:
 *   uint32_t source_insert(struct source *, struct entry *, uint32_t z) -> the node's new top
 *   uint32_t source_remove(struct source *, struct entry *, uint32_t z) -> the node's new top
 *   void source_deleted(struct source *, uint32_t z)   before a window's removals begin
 *   int source_make(struct source *, const struct vis_events *, struct step *steps,
 *                   struct sweep *)                    sets up every entry's aux; 0 or -1
 *   void source_prefetch(const struct source *, const struct entry *, uint32_t z, bool del)
 *                                                      prefetches what the next calls will read
 *   void source_free(struct source *)
 * Windows are named by z = k + 1 for kept window k, 0 standing for none (the paper's −∞).
 *
 * See-through windows (queries) hide nothing, so they never enter the tops, the sources or the
 * occluders' summaries: the sweep above runs on the opaque windows alone, and the queries are a
 * second set stored at their canonical nodes of the same tree, asked against the same tops (see
 * "Queries" below). A stack without any runs the sweep compiled without them.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "bigalloc.h"
#include "engine.h"
#include "events.h"
#include "heap.h"
#include "segtree.h"

/*
 * What a node's ancestors need to know of its subtree. Invariants, after every event (z = 0 means
 * none):
 * - l: the lowest window visible at some leaf of the subtree, counting only windows stored in the
 *   subtree: max(min(l of the children), top), top at a leaf; 0 if some leaf has nothing;
 * - h: an upper bound on the highest unreported window that is the top of a subtree node and
 *   visible within the subtree (0 if none). It is exact except for windows reported during the
 *   current event, whose nodes are refreshed right after it (section 6);
 * - m: the highest window stored in the subtree.
 */
struct summary {
	uint32_t l, h, m;
};

/*
 * A node's entry: top, the highest window stored at it; cl, ch, cm, the least l, greatest h and
 * greatest m of its children's summaries (0 at a leaf), from which its own summary follows; aux,
 * the top source's state.
 */
struct entry {
	uint32_t top;
	uint32_t cl, ch, cm;
#if SOURCE_AUX
	uint32_t aux[SOURCE_AUX];
#endif
};

/*
 * An internal node's record holds its children's entries (segtree.h), one aligned cache line or
 * half of one: a walk reads one line per node it passes through, and none for the canonical
 * children of those nodes, whose entries it has just read. The sweep is bound by those misses.
 */
#define RECORD_ALIGN (2 * sizeof(struct entry) > 32 ? 64 : 32)

struct record {
	struct entry e[2];
} __attribute__((aligned(RECORD_ALIGN)));

struct sweep;
struct source;
struct step;
static inline uint32_t source_insert(struct source *src, struct entry *e, uint32_t z);
static inline uint32_t source_remove(struct source *src, struct entry *e, uint32_t z);
static inline void source_deleted(struct source *src, uint32_t z);
static inline void source_prefetch(const struct source *src, const struct entry *e, uint32_t z,
				   bool del);
static int source_make(struct source *src, const struct vis_events *ev, struct step *steps,
		       struct sweep *s);
static void source_free(struct source *src);

/*
 * Unobscured windows. A window is unobscured iff it is on the screen and no higher window
 * overlaps it, i.e. iff it is the top at every leaf of its range once the events at its x1 are
 * done (the higher windows that start before it or with it are there, those that end there are
 * gone), and no higher window starting later, while it is active, overlaps it. The candidates —
 * windows that passed the first test and are not yet overlapped — are pairwise disjoint, so each
 * tree node holds at most one: cand[v] (0 if none) and submin[v], the lowest candidate in the
 * subtree (UINT32_MAX if none).
 */
enum cand_state {
	CAND_NONE,
	CAND_ACTIVE,
	CAND_DONE, /* ended while a candidate: unobscured */
	CAND_OVERLAPPED,
};

/* Queries, the see-through windows: see sweep-query.h. */

/*
 * An event as the sweep reads it, in schedule order, so that one sequential pass gives the window,
 * its leaf range and whether it is the last event at its x without touching the per-window arrays.
 */
struct step {
	uint32_t zf; /* z | STEP_DELETE | STEP_LAST_AT_X */
	uint32_t lo, hi;
};

#define STEP_DELETE (1u << 31)
#define STEP_LAST_AT_X (1u << 30)
#define STEP_Z(zf) ((zf) & ((1u << 30) - 1))

struct sweep {
	struct record *rec; /* by internal node */
	struct entry root;
	uint64_t *reported; /* a bit by z: few enough lines to stay in the cache */
	uint8_t *ntop; /* by z: the nodes it tops, at most its canonical ones (ntop[0]: junk) */
	uint8_t *cstate;   /* by z: enum cand_state */
	uint32_t *cand, *submin;
	uint32_t *newly; /* windows reported during the current event */
	size_t nnewly;
	struct step *group; /* windows inserted at the current x */
	size_t ngroup;
	uint32_t *found; /* candidates overlapped by the window being checked */
	size_t nfound;
	struct source *src;
	uint32_t a, b, z; /* the current event's leaf range and window */
	/* Queries (see below); all NULL or 0 for a stack without see-through windows. */
	size_t nquery;
	uint64_t *query;  /* a bit by z: a see-through window */
	uint64_t *qdead;  /* a bit by z: a query deleted unreported */
	uint32_t *qoff;	  /* by node: its slices' offset in qa and ca */
	uint32_t *qlen;	  /* by node: the queries in its max-heap qa */
	uint32_t *clen;	  /* by node: the candidates in its min-heap ca */
	uint32_t *qh;	  /* by node: its query summary */
	uint32_t *qsubmin; /* by node: the lowest candidate entry in its subtree */
	uint32_t *qa, *ca;
	struct step *qgroup; /* queries inserted at the current x */
	size_t nqgroup;
};

static inline uint32_t max32(uint32_t a, uint32_t b)
{
	return a > b ? a : b;
}

static inline uint32_t min32(uint32_t a, uint32_t b)
{
	return a < b ? a : b;
}

/* The entry numbered e (segtree.h) of a tree over m leaves. O(1). */
static inline struct entry *entry_at(struct sweep *s, uint32_t m, uint32_t e)
{
	return e == vis_segtree_root_entry(m) ? &s->root : &s->rec[e / 2].e[e % 2];
}

/*
 * Adds to count[e] (by entry number) how many canonical nodes of the windows entry e has; *total
 * gets their sum. Unless first is NULL, first[k] gets the sum over the windows below k
 * (first[n] = *total) and, unless lists is also NULL, lists[first[k] …] window k's canonical
 * entries in walk order (room for at most vis_segtree_max_canonical(m) a window). O(n log n),
 * counted in a dense array rather than in the records, which are several times larger and would
 * fall out of the cache sooner. The sources count in the sweep's cand array, all zero until the
 * sweep begins, and zero it again after: a scratch array of that size would add to the peak.
 */
static void count_canonical(const struct vis_events *ev, uint32_t *count, size_t *total,
			    uint32_t *first, uint32_t *lists)
{
	/* Window k's entries are counted COUNT_AHEAD windows after they are found and prefetched. */
	enum { COUNT_AHEAD = 8, RING = COUNT_AHEAD + 1 };
	uint32_t m = ev->nleaves, ring[RING][VIS_SEGTREE_MAX_CANONICAL];
	size_t len[RING] = { 0 };
	*total = 0;
	for (size_t k = 0; k < ev->n + COUNT_AHEAD; k++) {
		if (k < ev->n) {
			uint32_t *out = ring[k % RING];
			size_t c = vis_segtree_canonical_entries(m, ev->lo[k], ev->hi[k], out);
			for (size_t j = 0; j < c; j++)
				__builtin_prefetch(&count[out[j]], 1);
			if (first)
				first[k] = (uint32_t)*total;
			if (lists)
				memcpy(lists + *total, out, c * sizeof(*out));
			len[k % RING] = c;
			*total += c;
		}
		if (k >= COUNT_AHEAD) {
			const uint32_t *in = ring[(k - COUNT_AHEAD) % RING];
			for (size_t j = 0; j < len[(k - COUNT_AHEAD) % RING]; j++)
				count[in[j]]++;
		}
	}
	if (first)
		first[ev->n] = (uint32_t)*total;
}

static inline bool bit_get(const uint64_t *bits, uint32_t z)
{
	return bits[z / 64] >> (z % 64) & 1;
}

static inline void bit_set(uint64_t *bits, uint32_t z)
{
	bits[z / 64] |= (uint64_t)1 << (z % 64);
}

static inline bool is_reported(const struct sweep *s, uint32_t z)
{
	return bit_get(s->reported, z);
}

/* Whether window z is see-through; only for a sweep with queries (s->query set). */
static inline bool is_query(const struct sweep *s, uint32_t z)
{
	return bit_get(s->query, z);
}

/* A node's l: the lowest window visible at some leaf of its subtree, within the subtree. */
static inline uint32_t entry_l(const struct entry *e)
{
	return max32(e->cl, e->top);
}

/* A node's summary, from its entry. */
static inline struct summary summary_of(const struct sweep *s, const struct entry *e)
{
	uint32_t t = e->top, h = e->ch;
	if (h < t)
		h = 0; /* t spans the whole subtree: everything under it is hidden */
	if (t > e->cl && !is_reported(s, t))
		h = max32(h, t);
	return (struct summary){ entry_l(e), h, max32(e->cm, t) };
}

/* Recomputes an internal node's entry e from its record r. */
static inline void update(const struct sweep *s, struct entry *e, const struct record *r)
{
	struct summary a = summary_of(s, &r->e[0]), b = summary_of(s, &r->e[1]);
	e->cl = min32(a.l, b.l);
	e->ch = max32(a.h, b.h);
	e->cm = max32(a.m, b.m);
}

/*
 * update(), saying whether the entry changed: if not, neither did the node's summary, and the
 * ancestors' summaries stand.
 */
static inline bool update_changed(const struct sweep *s, struct entry *e, const struct record *r)
{
	struct entry old = *e;
	update(s, e, r);
	return old.cl != e->cl || old.ch != e->ch || old.cm != e->cm;
}

/*
 * Sets a node's top, counting the nodes each window tops where a lazily deleting source can use
 * the count; returns whether it changed.
 */
static inline bool set_top(struct sweep *s, struct entry *e, uint32_t top)
{
	if (top == e->top)
		return false;
	if (SOURCE_LAZY_DELETE) {
		s->ntop[e->top]--;
		s->ntop[top]++;
	}
	e->top = top;
	return true;
}

static inline void report(struct sweep *s, uint32_t z)
{
	if (!is_reported(s, z)) {
		s->reported[z / 64] |= (uint64_t)1 << (z % 64);
		s->newly[s->nnewly++] = z;
	}
}

#include "sweep-walk.h"

/*
 * Recomputes h on the ancestors of the canonical nodes of [a, b), node v covering [lo, hi) with
 * entry e among them: the canonical nodes' own summaries follow from their entries.
 */
static void refresh(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, struct entry *e)
{
	if (s->a <= lo && hi <= s->b)
		return;
	struct record *r = &s->rec[v - lo];
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (s->a < mid)
		refresh(s, vis_segtree_left(v), lo, mid, &r->e[0]);
	if (s->b > mid)
		refresh(s, vis_segtree_right(v, lo, mid), mid, hi, &r->e[1]);
	update(s, e, r);
}

/* Whether window z is the top at every leaf of [a, b): S-free since any ancestor above fails. */
static bool on_top(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, const struct entry *e)
{
	if (s->a <= lo && hi <= s->b)
		return e->top == s->z && e->cm < s->z;
	if (e->top > s->z)
		return false;
	const struct record *r = &s->rec[v - lo];
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (s->a < mid && !on_top(s, vis_segtree_left(v), lo, mid, &r->e[0]))
		return false;
	return !(s->b > mid && !on_top(s, vis_segtree_right(v, lo, mid), mid, hi, &r->e[1]));
}

/* Sets the candidate of the canonical nodes of [a, b) to c (0 to clear), keeping submin. */
static void cand_store(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, uint32_t c)
{
	uint32_t mn = UINT32_MAX;
	if (s->a <= lo && hi <= s->b) {
		s->cand[v] = c;
	} else {
		uint32_t mid = vis_segtree_mid(lo, hi);
		if (s->a < mid)
			cand_store(s, vis_segtree_left(v), lo, mid, c);
		if (s->b > mid)
			cand_store(s, vis_segtree_right(v, lo, mid), mid, hi, c);
	}
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		mn = min32(s->submin[vis_segtree_left(v)], s->submin[vis_segtree_right(v, lo, mid)]);
	}
	s->submin[v] = s->cand[v] ? min32(mn, s->cand[v]) : mn;
}

static inline void overlapped(struct sweep *s, uint32_t c)
{
	if (c && c < s->z && s->cstate[c] == CAND_ACTIVE) {
		s->cstate[c] = CAND_OVERLAPPED;
		s->found[s->nfound++] = c;
	}
}

/* Finds the candidates below z in v's subtree (all of which overlap the window). */
static void find_below(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (s->submin[v] >= s->z)
		return;
	overlapped(s, s->cand[v]);
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		find_below(s, vis_segtree_left(v), lo, mid);
		find_below(s, vis_segtree_right(v, lo, mid), mid, hi);
	}
}

/* Finds the candidates below z that overlap [a, b). */
static void find_overlapped(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (s->submin[v] >= s->z)
		return;
	if (s->a <= lo && hi <= s->b) {
		find_below(s, v, lo, hi);
		return;
	}
	overlapped(s, s->cand[v]);
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (s->a < mid)
		find_overlapped(s, vis_segtree_left(v), lo, mid);
	if (s->b > mid)
		find_overlapped(s, vis_segtree_right(v, lo, mid), mid, hi);
}

/* Sets the current window and its leaf range. */
static inline void set_window(struct sweep *s, const struct vis_events *ev, uint32_t k)
{
	s->z = k + 1;
	s->a = ev->lo[k];
	s->b = ev->hi[k];
}

/* Sets the current window and its leaf range from a step. */
static inline void set_step(struct sweep *s, const struct step *st)
{
	s->z = STEP_Z(st->zf);
	s->a = st->lo;
	s->b = st->hi;
}

/*
 * After all events at one x: the windows that started there overlap the candidates they meet,
 * and those on the screen and on top everywhere become candidates.
 */
static void end_group(struct sweep *s, const struct vis_events *ev, const uint8_t *onscreen)
{
	uint32_t m = ev->nleaves;
	for (size_t g = 0; g < s->ngroup; g++) {
		set_step(s, &s->group[g]);
		s->nfound = 0;
		find_overlapped(s, 0, 0, m);
		for (size_t f = 0; f < s->nfound; f++) {
			set_window(s, ev, s->found[f] - 1);
			cand_store(s, 0, 0, m, 0);
		}
	}
	for (size_t g = 0; g < s->ngroup; g++) {
		set_step(s, &s->group[g]);
		if (onscreen[s->z - 1] && on_top(s, 0, 0, m, &s->root)) {
			s->cstate[s->z] = CAND_ACTIVE;
			cand_store(s, 0, 0, m, s->z);
		}
	}
	s->ngroup = 0;
}

static void sweep_free(struct sweep *s)
{
	vis_bigfree(s->rec);
	free(s->reported);
	free(s->ntop);
	free(s->cstate);
	vis_bigfree(s->cand);
	vis_bigfree(s->submin);
	free(s->newly);
	free(s->group);
	free(s->found);
	free(s->query);
	free(s->qdead);
	vis_bigfree(s->qoff);
	vis_bigfree(s->qlen);
	vis_bigfree(s->clen);
	vis_bigfree(s->qh);
	vis_bigfree(s->qsubmin);
	vis_bigfree(s->qa);
	vis_bigfree(s->ca);
	free(s->qgroup);
}

#define STEPS_AHEAD 16

/* The schedule as steps; NULL (ENOMEM) on failure. */
static struct step *make_steps(const struct vis_events *ev, const uint32_t *sched)
{
	size_t count = 2 * ev->n;
	struct step *steps = malloc(count * sizeof(*steps) + 1);
	if (!steps) {
		errno = ENOMEM;
		return NULL;
	}
	int64_t next_x = 0;
	for (size_t i = count; i-- > 0;) {
		if (i >= STEPS_AHEAD) {
			/* The windows' fields are read in x order: at random. */
			uint32_t later = VIS_EV_WINDOW(sched[i - STEPS_AHEAD]);
			__builtin_prefetch(VIS_EV_IS_DELETE(sched[i - STEPS_AHEAD]) ? &ev->x2[later]
										     : &ev->x1[later]);
			__builtin_prefetch(&ev->lo[later]);
			__builtin_prefetch(&ev->hi[later]);
		}
		uint32_t k = VIS_EV_WINDOW(sched[i]);
		bool del = VIS_EV_IS_DELETE(sched[i]);
		int64_t x = del ? ev->x2[k] : ev->x1[k];
		steps[i].zf = (k + 1) | (del ? STEP_DELETE : 0) |
			      (i + 1 == count || x != next_x ? STEP_LAST_AT_X : 0);
		steps[i].lo = ev->lo[k];
		steps[i].hi = ev->hi[k];
		next_x = x;
	}
	return steps;
}

/*
 * Prefetches, ahead of the event of step st (left steps from it on), what later events will read
 * at random: their windows' flags, then their paths' records, then what the top source reads at
 * their canonical nodes, each far enough ahead for the next to find it in the cache.
 */
WALK_INLINE void prefetch_ahead(struct sweep *s, const struct step *st, size_t left,
				const uint8_t *onscreen, uint32_t m, bool queries)
{
	if (PREFETCH_WINDOW_AHEAD < left) {
		/* Read at random z, and out of the L2 on large stacks. */
		const struct step *ahead = st + PREFETCH_WINDOW_AHEAD;
		uint32_t z = STEP_Z(ahead->zf);
		if (SOURCE_LAZY_DELETE)
			__builtin_prefetch(&s->ntop[z]);
		__builtin_prefetch(&s->cstate[z]);
		if (!(ahead->zf & STEP_DELETE))
			__builtin_prefetch(&onscreen[z - 1]);
	}
	if (PREFETCH_NODES_AHEAD < left && !near_previous(st + PREFETCH_NODES_AHEAD) &&
	    walks(s, st + PREFETCH_NODES_AHEAD))
		{
		if (queries)
			prefetch_nodes_inline(s, st + PREFETCH_NODES_AHEAD, m);
		else
			prefetch_nodes(s, st + PREFETCH_NODES_AHEAD, m);
	}
	if (SOURCE_PREFETCH && PREFETCH_SOURCE_AHEAD < left &&
	    !near_previous(st + PREFETCH_SOURCE_AHEAD) && walks(s, st + PREFETCH_SOURCE_AHEAD))
		{
		if (queries)
			walk(s, WALK_PREFETCH_SOURCE, st + PREFETCH_SOURCE_AHEAD, m);
		else
			prefetch_source(s, st + PREFETCH_SOURCE_AHEAD, m);
	}
}

#include "sweep-query.h"

/*
 * The events, in schedule order. Instantiated twice, with queries a constant: a stack without
 * see-through windows runs the loop without a trace of them.
 */
WALK_INLINE void sweep_events(struct sweep *s, const struct vis_events *ev,
			      const struct step *steps, const uint8_t *onscreen, bool queries)
{
	size_t n = ev->n;
	uint32_t m = ev->nleaves;
	bool prefetch = prefetch_pays(m);
	for (size_t i = 0; i < 2 * n; i++) {
		const struct step *st = &steps[i];
		if (prefetch)
			prefetch_ahead(s, st, 2 * n - i, onscreen, m, queries);
		set_step(s, st);
		if (queries && is_query(s, s->z)) {
			query_event(s, st, m);
		} else if (st->zf & STEP_DELETE) {
			source_deleted(s->src, s->z);
			/*
			 * A window that tops no node is hidden wherever it is stored: deleting it
			 * changes no summary and exposes nothing. A source that deletes lazily
			 * need not even visit its nodes (on desktop-like stacks, most windows).
			 */
			if (walks(s, st)) {
				if (queries) {
					walk(s, WALK_DELETE, st, m);
					qwalk(s, QWALK_REFRESH, 0, 0, m, &s->root);
				} else {
					walk_delete(s, st, m);
				}
			}
			if (s->cstate[s->z] == CAND_ACTIVE) {
				s->cstate[s->z] = CAND_DONE;
				cand_store(s, 0, 0, m, 0);
			}
		} else {
			if (queries) {
				walk(s, WALK_INSERT, st, m);
				qwalk(s, QWALK_REFRESH, 0, 0, m, &s->root);
			} else {
				walk_insert(s, st, m);
			}
			s->group[s->ngroup++] = *st;
		}
		/* Section 6: a newly reported window no longer counts in h anywhere. */
		for (size_t j = 0; j < s->nnewly; j++) {
			set_window(s, ev, s->newly[j] - 1);
			refresh(s, 0, 0, m, &s->root);
		}
		s->nnewly = 0;
		if (st->zf & STEP_LAST_AT_X) {
			if (queries)
				query_end_group(s, ev, onscreen);
			end_group(s, ev, onscreen);
		}
	}
}

/*
 * The loop with queries, a function of its own: a second copy inlined into sweep_run() would
 * push it past the compiler's inlining limits, and the plain loop would lose its inlined walks
 * (5% on gmv's grid).
 */
static __attribute__((noinline)) void sweep_events_queries(struct sweep *s,
							   const struct vis_events *ev,
							   const struct step *steps,
							   const uint8_t *onscreen)
{
	sweep_events(s, ev, steps, onscreen, true);
}

/*
 * Runs the sweep over the scheduled events and writes the state of every kept
 * window k into states[ev->idx[k]]; onscreen[k] says whether k lies wholly on the screen.
 * Returns 0, or -1 (ENOMEM). O(n log n) node visits, plus what the top source costs.
 */
static int sweep_run(const struct vis_events *ev, const uint32_t *sched, const uint8_t *onscreen,
		     const uint8_t *query, uint8_t *states)
{
	struct source src;
	size_t n = ev->n, nodes = vis_segtree_nodes(ev->nleaves);
	uint32_t m = ev->nleaves;
	if (n == 0)
		return 0;
	struct sweep s = { .src = &src };
	s.rec = vis_bigalloc(m * sizeof(*s.rec), true); /* m − 1 internal nodes */
	s.reported = calloc(n / 64 + 1, sizeof(*s.reported));
	s.ntop = calloc(n + 1, sizeof(*s.ntop));
	s.cstate = calloc(n + 1, 1);
	s.cand = vis_bigalloc(nodes * sizeof(*s.cand), true);
	s.submin = vis_bigalloc(nodes * sizeof(*s.submin), false);
	s.newly = malloc(n * sizeof(*s.newly));
	s.group = malloc(n * sizeof(*s.group));
	s.found = malloc(n * sizeof(*s.found));
	if (!s.rec || !s.reported || !s.ntop || !s.cstate || !s.cand || !s.submin ||
	    !s.newly || !s.group || !s.found) {
		sweep_free(&s);
		errno = ENOMEM;
		return -1;
	}
	for (size_t v = 0; v < nodes; v++)
		s.submin[v] = UINT32_MAX;
	if (query && queries_make(&s, ev, query) < 0) {
		sweep_free(&s);
		return -1;
	}
	struct step *steps = make_steps(ev, sched);
	if (!steps || source_make(&src, ev, steps, &s) < 0) {
		free(steps);
		sweep_free(&s);
		return -1;
	}
	if (s.nquery)
		sweep_events_queries(&s, ev, steps, onscreen);
	else
		sweep_events(&s, ev, steps, onscreen, false);
	free(steps);
	for (size_t k = 0; k < n; k++) {
		uint32_t z = (uint32_t)k + 1;
		states[ev->idx[k]] = !is_reported(&s, z)	 ? VIS_FULLY_OBSCURED
				     : s.cstate[z] == CAND_DONE ? VIS_UNOBSCURED
								 : VIS_PARTIALLY_OBSCURED;
	}
	source_free(&src);
	sweep_free(&s);
	return 0;
}

/* The engine: events, schedule, sweep. */
static int sweep_compute(const struct vis_stack *stack, uint8_t *states)
{
	for (size_t i = 0; i < stack->n; i++)
		states[i] = VIS_FULLY_OBSCURED;
	struct vis_events ev;
	if (vis_events_init(&ev, stack) < 0)
		return -1;
	int rc = -1;
	uint32_t *sched = malloc(2 * ev.n * sizeof(*sched) + 1);
	uint8_t *onscreen = malloc(ev.n + 1), *query = NULL;
	if (!sched || !onscreen) {
		errno = ENOMEM;
		goto out;
	}
	for (size_t k = 0; k < ev.n; k++)
		onscreen[k] = vis_stack_on_screen(stack, ev.idx[k]);
	/* The queries, if any window kept is see-through. */
	for (size_t k = 0; stack->see_through != NULL && k < ev.n; k++) {
		if (!stack->see_through[ev.idx[k]])
			continue;
		if (!query && !(query = calloc(ev.n, 1))) {
			errno = ENOMEM;
			goto out;
		}
		query[k] = 1;
	}
	if (vis_events_schedule(&ev, sched) < 0)
		goto out;
	rc = sweep_run(&ev, sched, onscreen, query, states);
out:
	free(sched);
	free(onscreen);
	free(query);
	vis_events_finish(&ev);
	return rc;
}
