/*
 * The sweep's queries, included by sweep-impl.h before its event loop.
 *
 * Queries: the see-through windows. Query q (range [a, b), canonical nodes C(q)) is visible on a
 * slab iff some leaf of its range has no opaque top above it there, i.e. iff at some u in C(q),
 * q > max(S_u, l_u), S_u the highest top among u's ancestors. As for the occluders, only states
 * after all events at one x count, so queries are tested only then (end of the x's group), and
 * their own events may come in any order among the others at that x. Per node v:
 * - qa[qoff[v] …], a max-heap of the queries with v in C(q), qlen[v] long; its top, Q_v, is
 *   always live: a query reported or deleted is popped lazily, but every node whose top it is
 *   pops it at once (as gmv-heap's dead windows);
 * - qh[v]: the highest query stored in v's subtree that is visible within it (0 if none):
 *   Q_v if Q_v > l_v, and a child's qh if it exceeds top_v. A lower query fails where a higher
 *   one fails, so the maximum is the whole answer: q is visible now iff q = qh[root] or lower and
 *   reported once qh[root] passes it. qh depends on tops and l, so every occluder walk is
 *   followed by a walk refreshing qh on its canonical nodes and their ancestors.
 * - Unobscured: q on the screen, below no opaque window stored over its range once the events at
 *   its x1 are done (the path tops and the canonical nodes' m), and overlapped by no higher opaque
 *   window starting while it is active. Queries overlap one another, so a node holds any number
 *   of candidates: ca[qoff[v] …], a min-heap (stored as ~z in a max-heap) clen[v] long, and
 *   qsubmin[v] the least entry in v's subtree (UINT32_MAX if none). An opaque window's insertion
 *   pops, at the nodes of its walk and inside its canonical subtrees, every entry below it;
 *   entries of queries that ended or were overlapped elsewhere stay until popped so, which keeps
 *   qsubmin a lower bound that every visit it causes pays for with a pop.
 * Cost: O(log n) heap operations of O(log n) for each query's canonical nodes, and one more
 * O(log n) walk for each occluder event: O(N log² N) in all on a stack with see-through windows.
 */

/*
 * The queries' walks: the see-through windows' heaps and summaries,
 * walked by node number with each node's entry at hand. Recursive: they run only on stacks with
 * see-through windows, and their cost is the heaps', not the misses.
 */

/* The top of node v's query heap, 0 if empty. */
static inline uint32_t qtop(const struct sweep *s, uint32_t v)
{
	return s->qlen[v] ? s->qa[s->qoff[v]] : 0;
}

/* Whether query z has left the heaps' account: reported, or deleted unreported. */
static inline bool qgone(const struct sweep *s, uint32_t z)
{
	return is_reported(s, z) || bit_get(s->qdead, z);
}

/* Recomputes qh[v], node v covering [lo, hi) with entry e, from its heap and its children. */
static inline void qupdate(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi,
			   const struct entry *e)
{
	uint32_t q = qtop(s, v), h = q > entry_l(e) ? q : 0;
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		uint32_t c = max32(s->qh[vis_segtree_left(v)], s->qh[vis_segtree_right(v, lo, mid)]);
		if (c > e->top)
			h = max32(h, c);
	}
	s->qh[v] = h;
}

enum qwalk_kind {
	QWALK_REFRESH, /* after an occluder walk over [a, b): tops and l changed there */
	QWALK_PUSH,    /* query z starts: into the heaps of its canonical nodes */
	QWALK_CLEAN,   /* query z is gone: off the heaps it tops */
};

/* Walks [a, b) from node v covering [lo, hi) with entry e, refreshing qh on the way back. */
static void qwalk(struct sweep *s, enum qwalk_kind kind, uint32_t v, uint32_t lo, uint32_t hi,
		  const struct entry *e)
{
	if (s->a <= lo && hi <= s->b) {
		uint32_t *a = s->qa + s->qoff[v];
		if (kind == QWALK_PUSH) {
			vis_heap_push(a, &s->qlen[v], s->z);
		} else if (kind == QWALK_CLEAN) {
			while (s->qlen[v] && qgone(s, a[0]))
				vis_heap_pop(a, &s->qlen[v]);
		}
	} else {
		const struct record *r = &s->rec[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		if (s->a < mid)
			qwalk(s, kind, vis_segtree_left(v), lo, mid, &r->e[0]);
		if (s->b > mid)
			qwalk(s, kind, vis_segtree_right(v, lo, mid), mid, hi, &r->e[1]);
	}
	qupdate(s, v, lo, hi, e);
}

/* Recomputes qsubmin[v], node v covering [lo, hi). */
static inline void qsubmin_update(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	uint32_t mn = s->clen[v] ? ~s->ca[s->qoff[v]] : UINT32_MAX;
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		mn = min32(mn, min32(s->qsubmin[vis_segtree_left(v)],
				     s->qsubmin[vis_segtree_right(v, lo, mid)]));
	}
	s->qsubmin[v] = mn;
}

/* Makes query z a candidate at the canonical nodes of [a, b). */
static void qcand_store(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (s->a <= lo && hi <= s->b) {
		vis_heap_push(s->ca + s->qoff[v], &s->clen[v], ~s->z);
	} else {
		uint32_t mid = vis_segtree_mid(lo, hi);
		if (s->a < mid)
			qcand_store(s, vis_segtree_left(v), lo, mid);
		if (s->b > mid)
			qcand_store(s, vis_segtree_right(v, lo, mid), mid, hi);
	}
	qsubmin_update(s, v, lo, hi);
}

/* Pops node v's candidate entries below z, which overlap opaque window z: none is unobscured. */
static inline void qpop_below(struct sweep *s, uint32_t v)
{
	uint32_t *a = s->ca + s->qoff[v];
	while (s->clen[v] && ~a[0] < s->z) {
		uint32_t c = ~a[0];
		vis_heap_pop(a, &s->clen[v]);
		if (s->cstate[c] == CAND_ACTIVE)
			s->cstate[c] = CAND_OVERLAPPED;
	}
}

/* Pops the candidate entries below z in v's subtree, all of which overlap window z. */
static void qfind_below(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (s->qsubmin[v] >= s->z)
		return;
	qpop_below(s, v);
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		qfind_below(s, vis_segtree_left(v), lo, mid);
		qfind_below(s, vis_segtree_right(v, lo, mid), mid, hi);
	}
	qsubmin_update(s, v, lo, hi);
}

/* Pops the candidate entries below opaque window z stored where they overlap [a, b). */
static void qfind(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (s->qsubmin[v] >= s->z)
		return;
	if (s->a <= lo && hi <= s->b) {
		qfind_below(s, v, lo, hi);
		return;
	}
	qpop_below(s, v);
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (s->a < mid)
		qfind(s, vis_segtree_left(v), lo, mid);
	if (s->b > mid)
		qfind(s, vis_segtree_right(v, lo, mid), mid, hi);
	qsubmin_update(s, v, lo, hi);
}

/* Whether no opaque window above query z is stored over [a, b): on_top() for a query. */
static bool q_on_top(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, const struct entry *e)
{
	if (e->top > s->z)
		return false;
	if (s->a <= lo && hi <= s->b)
		return e->cm < s->z;
	const struct record *r = &s->rec[v - lo];
	uint32_t mid = vis_segtree_mid(lo, hi);
	if (s->a < mid && !q_on_top(s, vis_segtree_left(v), lo, mid, &r->e[0]))
		return false;
	return !(s->b > mid && !q_on_top(s, vis_segtree_right(v, lo, mid), mid, hi, &r->e[1]));
}

/*
 * Sets up the queries' arrays: query[k] says whether kept window k is see-through. Returns 0, or
 * -1 (ENOMEM, EOVERFLOW). O(q log m) for q queries, and O(m) for the per-node arrays.
 */
static int queries_make(struct sweep *s, const struct vis_events *ev, const uint8_t *query)
{
	size_t n = ev->n, nodes = vis_segtree_nodes(ev->nleaves), total = 0;
	uint32_t m = ev->nleaves, out[VIS_SEGTREE_MAX_CANONICAL];
	s->query = calloc(n / 64 + 1, sizeof(*s->query));
	s->qdead = calloc(n / 64 + 1, sizeof(*s->qdead));
	s->qoff = vis_bigalloc(nodes * sizeof(*s->qoff), true);
	s->qlen = vis_bigalloc(nodes * sizeof(*s->qlen), true);
	s->clen = vis_bigalloc(nodes * sizeof(*s->clen), true);
	s->qh = vis_bigalloc(nodes * sizeof(*s->qh), true);
	s->qsubmin = vis_bigalloc(nodes * sizeof(*s->qsubmin), false);
	s->qgroup = malloc(n * sizeof(*s->qgroup));
	if (!s->query || !s->qdead || !s->qoff || !s->qlen || !s->clen || !s->qh || !s->qsubmin ||
	    !s->qgroup) {
		errno = ENOMEM;
		return -1;
	}
	/* qoff counts each node's queries first, then becomes their prefix sums. */
	for (size_t k = 0; k < n; k++) {
		if (!query[k])
			continue;
		s->nquery++;
		bit_set(s->query, (uint32_t)k + 1);
		size_t c = vis_segtree_canonical(m, ev->lo[k], ev->hi[k], out);
		for (size_t j = 0; j < c; j++)
			s->qoff[out[j]]++;
		total += c;
	}
	if (total > UINT32_MAX) {
		errno = EOVERFLOW;
		return -1;
	}
	uint32_t sum = 0;
	for (size_t v = 0; v < nodes; v++) {
		uint32_t c = s->qoff[v];
		s->qoff[v] = sum;
		sum += c;
		s->qsubmin[v] = UINT32_MAX;
	}
	s->qa = vis_bigalloc(total * sizeof(*s->qa) + 1, false);
	s->ca = vis_bigalloc(total * sizeof(*s->ca) + 1, false);
	if (!s->qa || !s->ca) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

/* A query's insertion or deletion: its heaps; the tests wait for the end of its x. */
static void query_event(struct sweep *s, const struct step *st, uint32_t m)
{
	if (st->zf & STEP_DELETE) {
		if (s->cstate[s->z] == CAND_ACTIVE)
			s->cstate[s->z] = CAND_DONE;
		/* A reported query is gone already, and tops no heap. */
		if (!is_reported(s, s->z)) {
			bit_set(s->qdead, s->z);
			qwalk(s, QWALK_CLEAN, 0, 0, m, &s->root);
		}
	} else {
		qwalk(s, QWALK_PUSH, 0, 0, m, &s->root);
		s->qgroup[s->nqgroup++] = *st;
	}
}

/*
 * After all events at one x, the queries' part: the opaque windows that started there (the
 * group, before end_group() empties it) overlap the query candidates they meet; the queries
 * that started there and are on the screen and under no higher opaque window become candidates;
 * then every query visible now is reported, highest first.
 */
static void query_end_group(struct sweep *s, const struct vis_events *ev, const uint8_t *onscreen)
{
	uint32_t m = ev->nleaves, z;
	for (size_t g = 0; g < s->ngroup; g++) {
		set_step(s, &s->group[g]);
		qfind(s, 0, 0, m);
	}
	for (size_t g = 0; g < s->nqgroup; g++) {
		set_step(s, &s->qgroup[g]);
		if (onscreen[s->z - 1] && q_on_top(s, 0, 0, m, &s->root)) {
			s->cstate[s->z] = CAND_ACTIVE;
			qcand_store(s, 0, 0, m);
		}
	}
	s->nqgroup = 0;
	while ((z = s->qh[0]) != 0) {
		bit_set(s->reported, z);
		set_window(s, ev, z - 1);
		qwalk(s, QWALK_CLEAN, 0, 0, m, &s->root);
	}
}
