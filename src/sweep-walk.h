/*
 * The walks of one event through the tree, part of sweep-impl.h (which includes it where the
 * sweep's state and the summaries' updates are defined): LEFT-INSERT, RIGHT-DELETE, and the
 * prefetches that run ahead of them.
 */

/* Inlined into each walk kind's function, so that the kind is a constant there. */
#define WALK_INLINE static inline __attribute__((always_inline))

/*
 * LEFT-INSERT at a canonical node with entry e; S is the highest top among its ancestors. Returns
 * whether its entry changed: most insertions land under a higher top and change nothing.
 */
WALK_INLINE bool insert_at(struct sweep *s, struct entry *e, uint32_t S)
{
	/* Read l before the update: z is visible here iff it beats what was visible. */
	uint32_t old_l = entry_l(e);
	if (!set_top(s, e, source_insert(s->src, e, s->z)))
		return false;
	if (s->z > old_l && s->z > S)
		report(s, s->z);
	return true;
}

/* RIGHT-REPORT: reports the unreported windows above S now visible in v's subtree. */
static void right_report(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, struct entry *e,
			 uint32_t S)
{
	if (summary_of(s, e).h <= S)
		return;
	uint32_t t = e->top;
	if (t > S) {
		/* Visible within the subtree: tested against the children, not against l_v. */
		if (!is_reported(s, t) && t > e->cl)
			report(s, t);
		S = t;
	}
	if (hi - lo > 1) {
		struct record *r = &s->rec[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		right_report(s, vis_segtree_left(v), lo, mid, &r->e[0], S);
		right_report(s, vis_segtree_right(v, lo, mid), mid, hi, &r->e[1], S);
		update(s, e, r);
	}
}

/*
 * RIGHT-DELETE at canonical node v covering [lo, hi) with entry e; S as for insert_at(). Returns
 * whether its entry changed: removing a window that was not the top changes nothing, exposes
 * nothing.
 */
WALK_INLINE bool delete_at(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, struct entry *e,
			   uint32_t S)
{
	bool was_visible = e->top == s->z && s->z > S && s->z > e->cl;
	if (!set_top(s, e, source_remove(s->src, e, s->z)))
		return false;
	/* The deletion may expose S itself here, which RIGHT-REPORT never looks at. */
	if (S && S > entry_l(e))
		report(s, S);
	if (was_visible)
		right_report(s, v, lo, hi, e, S);
	return true;
}

/*
 * What a walk does: an event's work, or, ahead of it, prefetching what it will read. The sweep
 * waits on memory, and an event's nodes do not depend on the data, so the records of the nodes an
 * event will visit are prefetched several events ahead (prefetch_nodes), and what the top source
 * reads at their canonical nodes (found through those records, by then in the cache) a few events
 * ahead.
 */
enum walk_kind {
	WALK_INSERT,
	WALK_DELETE,
	WALK_PREFETCH_SOURCE,
};

#define PREFETCH_NODES_AHEAD 16
#define PREFETCH_SOURCE_AHEAD 2
/* Far enough that walks() finds a window's ntop in the cache at PREFETCH_NODES_AHEAD. */
#define PREFETCH_WINDOW_AHEAD (2 * PREFETCH_NODES_AHEAD)

/*
 * Below this much tree the caches hold it (screen-bound scenes have a few thousand leaves
 * whatever n is), and the prefetching walks would only add their instructions.
 */
#define PREFETCH_MIN_BYTES ((size_t)8 << 20)

/* Leaves apart below which consecutive events share all but the last few levels of their paths. */
#define PREFETCH_NEAR_LEAVES 32

/*
 * Whether the event of step st (not the first) runs within a few leaves of the one before it, as
 * stacks of thin bars in y order do: its paths are then those just walked, in the cache, and
 * computing them again to prefetch them, and what the source reads there, would only add
 * instructions (a fifth of the sweep on the grid).
 */
static inline bool near_previous(const struct step *st)
{
	uint32_t d_lo = st->lo > st[-1].lo ? st->lo - st[-1].lo : st[-1].lo - st->lo;
	uint32_t d_hi = st->hi > st[-1].hi ? st->hi - st[-1].hi : st[-1].hi - st->hi;
	return d_lo < PREFETCH_NEAR_LEAVES && d_hi < PREFETCH_NEAR_LEAVES;
}

/* Whether a tree over m leaves is large enough for prefetching to pay. */
static inline bool prefetch_pays(uint32_t m)
{
	return (size_t)m * sizeof(struct record) >= PREFETCH_MIN_BYTES;
}

/* The walk's step at canonical node v covering [lo, hi), with entry e, for the event of step st. */
WALK_INLINE bool at_canonical(struct sweep *s, enum walk_kind kind, const struct step *st,
			      uint32_t v, uint32_t lo, uint32_t hi, struct entry *e, uint32_t S)
{
	switch (kind) {
	case WALK_INSERT:
		return insert_at(s, e, S);
	case WALK_DELETE:
		return delete_at(s, v, lo, hi, e, S);
	case WALK_PREFETCH_SOURCE:
		source_prefetch(s->src, e, STEP_Z(st->zf), st->zf & STEP_DELETE);
		return false;
	}
	return false;
}

/* The walk's step at a path node with entry e: S gathers its top. */
WALK_INLINE uint32_t at_path(enum walk_kind kind, const struct entry *e, uint32_t S)
{
	return kind == WALK_PREFETCH_SOURCE ? S : max32(S, e->top);
}

/*
 * The walk of one event, without recursion: the nodes it passes through (those that meet [a, b)
 * without lying inside it) form a path from the root to the split node, then at most one path
 * below each of its children, along which the range's ends run. Each path node has at most one
 * canonical child off the path. Going down gathers S and does the canonical steps; coming back up
 * refreshes the path nodes below a changed child, deepest first. The canonical steps come in the
 * order vis_segtree_canonical_entries() lists them, which gmv's stream of slots relies on.
 */
struct hop {
	struct entry *e;  /* the node's entry */
	struct record *r; /* its children's */
	bool changed;	  /* whether a child's summary changed */
};

/* Refreshes the path nodes hop[from … d) deepest first; changed: whether the deepest's child did. */
WALK_INLINE bool climb(struct sweep *s, enum walk_kind kind, struct hop *hop, size_t from, size_t d,
		       bool changed)
{
	if (kind != WALK_INSERT && kind != WALK_DELETE)
		return false;
	while (d-- > from) {
		changed |= hop[d].changed;
		changed = changed && update_changed(s, hop[d].e, hop[d].r);
	}
	return changed;
}

/*
 * The path below one child of the split node, whose interval [lo, hi) holds the end a (left) or b
 * (right) of the range and lies inside it on the other side; pushes its nodes from hop[d].
 */
WALK_INLINE bool walk_side(struct sweep *s, enum walk_kind kind, const struct step *st, bool left,
			   uint32_t v, uint32_t lo, uint32_t hi, uint32_t S, struct entry *e,
			   struct hop *hop, size_t d)
{
	size_t from = d;
	for (;;) {
		if (left ? st->lo <= lo : hi <= st->hi)
			break;
		struct record *r = &s->rec[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		S = at_path(kind, e, S);
		hop[d] = (struct hop){ e, r, false };
		if (left && st->lo < mid) {
			/* [mid, hi) lies inside the range. */
			hop[d].changed = at_canonical(s, kind, st, vis_segtree_right(v, lo, mid),
						      mid, hi, &r->e[1], S);
			v = vis_segtree_left(v);
			hi = mid;
			e = &r->e[0];
		} else if (!left && st->hi > mid) {
			hop[d].changed = at_canonical(s, kind, st, vis_segtree_left(v), lo, mid,
						      &r->e[0], S);
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = &r->e[1];
		} else if (left) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = &r->e[1];
		} else {
			v = vis_segtree_left(v);
			hi = mid;
			e = &r->e[0];
		}
		d++;
	}
	return climb(s, kind, hop, from, d, at_canonical(s, kind, st, v, lo, hi, e, S));
}

/*
 * Walks the event of step st from the root: LEFT-INSERT, RIGHT-DELETE, or a prefetch. The event's
 * own walk needs set_step(st) first.
 */
WALK_INLINE void walk(struct sweep *s, enum walk_kind kind, const struct step *st, uint32_t m)
{
	struct hop hop[2 * VIS_SEGTREE_MAX_HEIGHT];
	uint32_t v = 0, lo = 0, hi = m, S = 0;
	struct entry *e = &s->root;
	size_t d = 0;
	bool changed;
	for (;;) {
		if (st->lo <= lo && hi <= st->hi) {
			changed = at_canonical(s, kind, st, v, lo, hi, e, S);
			break;
		}
		struct record *r = &s->rec[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		S = at_path(kind, e, S);
		hop[d++] = (struct hop){ e, r, false };
		if (st->hi <= mid) {
			v = vis_segtree_left(v);
			hi = mid;
			e = &r->e[0];
		} else if (st->lo >= mid) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			e = &r->e[1];
		} else {
			changed = walk_side(s, kind, st, true, vis_segtree_left(v), lo, mid, S,
					    &r->e[0], hop, d);
			changed |= walk_side(s, kind, st, false, vis_segtree_right(v, lo, mid), mid,
					     hi, S, &r->e[1], hop, d);
			break;
		}
	}
	climb(s, kind, hop, 0, d, changed);
}

/*
 * The walks, each a function of its own with its kind built in, for the plain event loop: with
 * one caller each, the compiler inlines them there whatever their size. The loop with queries
 * (sweep_events_queries()) inlines walk() itself rather than be a second caller.
 */
static void walk_insert(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_INSERT, st, m);
}

static void walk_delete(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_DELETE, st, m);
}

/*
 * Prefetches the records on the path from node v covering [lo, hi) toward leaf x that an event
 * over [a, b) passes through. Its turns are data, not branches: this walk has nothing else to do,
 * and a walk's turns are coin tosses that would cost it a misprediction a level.
 */
static inline void prefetch_path(const struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi,
				 uint32_t a, uint32_t b, uint32_t x)
{
	while (!(a <= lo && hi <= b)) {
		__builtin_prefetch(&s->rec[v - lo]);
		v = vis_segtree_down(v, &lo, &hi, x >= vis_segtree_mid(lo, hi));
	}
}

/*
 * Prefetches the records of the path nodes of the event of step st: down to the split node once,
 * then along each side.
 */
WALK_INLINE void prefetch_nodes_inline(struct sweep *s, const struct step *st, uint32_t m)
{
	uint32_t a = st->lo, b = st->hi, v = 0, lo = 0, hi = m, mid;
	for (;;) {
		if (a <= lo && hi <= b)
			return;
		__builtin_prefetch(&s->rec[v - lo]);
		mid = vis_segtree_mid(lo, hi);
		if (a < mid && b > mid)
			break;
		v = vis_segtree_down(v, &lo, &hi, a >= mid);
	}
	prefetch_path(s, vis_segtree_left(v), lo, mid, a, b, a);
	prefetch_path(s, vis_segtree_right(v, lo, mid), mid, hi, a, b, b - 1);
}

static void prefetch_nodes(struct sweep *s, const struct step *st, uint32_t m)
{
	prefetch_nodes_inline(s, st, m);
}

static void prefetch_source(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_PREFETCH_SOURCE, st, m);
}

/* Whether the sweep will walk the event of step st (see sweep_run). */
static inline bool walks(const struct sweep *s, const struct step *st)
{
	return !(st->zf & STEP_DELETE) || !SOURCE_LAZY_DELETE || s->ntop[STEP_Z(st->zf)] > 0;
}
