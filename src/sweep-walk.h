/*
 * The walks of one event through the tree, part of sweep-impl.h (which includes it where the
 * sweep's state and the summaries' updates are defined): LEFT-INSERT, RIGHT-DELETE, and the
 * prefetches that run ahead of them.
 */

/* Inlined into each walk kind's function, so that the kind is a constant there. */
#define WALK_INLINE static inline __attribute__((always_inline))

/*
 * LEFT-INSERT at a canonical node; S is the highest top among its ancestors. Returns whether its
 * summary changed: most insertions land under a higher top and change nothing.
 */
WALK_INLINE bool insert_at(struct sweep *s, struct head *hd, const struct summary *kid,
			   uint32_t S, struct summary *out)
{
	/* Read l before the update: z is visible here iff it beats what was visible. */
	uint32_t old_top = hd->top, old_l = max32(children_l(kid), old_top);
	if (!set_top(s, hd, source_insert(s->src, hd, s->z)))
		return false;
	if (s->z > old_l && s->z > S)
		report(s, s->z);
	return update_changed(s, hd->top, kid, out);
}

/* RIGHT-REPORT: reports the unreported windows above S now visible in v's subtree. */
static void right_report(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, uint32_t S,
			 struct summary *out)
{
	if (out->h <= S)
		return;
	struct summary *kid;
	struct head *hd = head_at(s, v, lo, hi, &kid);
	uint32_t t = hd->top;
	if (t > S) {
		/* Visible within the subtree: tested against the children, not against l_v. */
		if (!s->reported[t] && t > children_l(kid))
			report(s, t);
		S = t;
	}
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		right_report(s, vis_segtree_left(v), lo, mid, S, &kid[0]);
		right_report(s, vis_segtree_right(v, lo, mid), mid, hi, S, &kid[1]);
	}
	update(s, hd->top, kid, out);
}

/*
 * RIGHT-DELETE at canonical node v covering [lo, hi); S as for insert_at(). Returns whether its
 * summary changed: removing a window that was not the top changes nothing, exposes nothing.
 */
WALK_INLINE bool delete_at(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, struct head *hd,
			   struct summary *kid, uint32_t S, struct summary *out)
{
	uint32_t old_top = hd->top;
	bool was_visible = old_top == s->z && s->z > S && s->z > children_l(kid);
	if (!set_top(s, hd, source_remove(s->src, hd, s->z)))
		return false;
	bool changed = update_changed(s, hd->top, kid, out);
	/* The deletion may expose S itself here, which RIGHT-REPORT never looks at. */
	if (S && S > out->l)
		report(s, S);
	if (was_visible) {
		right_report(s, v, lo, hi, S, out);
		changed = true;
	}
	return changed;
}

/*
 * What a walk does: an event's work, or, ahead of it, prefetching what it will read. The sweep
 * waits on memory, and an event's nodes do not depend on the data, so the records of the nodes an
 * event will visit are prefetched several events ahead, and the top source's entries at its
 * canonical nodes (found through those records, by then in the cache) a few events ahead.
 */
enum walk_kind {
	WALK_INSERT,
	WALK_DELETE,
	WALK_PREFETCH_NODES,
	WALK_PREFETCH_SOURCE,
	WALK_NUMBER, /* source_number() at each canonical node */
};

#define PREFETCH_NODES_AHEAD 8
#define PREFETCH_SOURCE_AHEAD 2

/*
 * Below this much tree the caches hold it (screen-bound scenes have a few thousand leaves
 * whatever n is), and the prefetching walks would only add their instructions.
 */
#define PREFETCH_MIN_BYTES ((size_t)8 << 20)

/* Whether a tree over m leaves is large enough for prefetching to pay. */
static inline bool prefetch_pays(uint32_t m)
{
	return (size_t)m * (sizeof(struct node) + sizeof(struct head)) >= PREFETCH_MIN_BYTES;
}

/* Prefetches an internal node's record, which may straddle two lines. */
static inline void prefetch_node(const struct node *nd)
{
	__builtin_prefetch(nd);
	__builtin_prefetch((const char *)(nd + 1) - 1);
}

/* The walk's step at canonical node v covering [lo, hi) for the event of step st. */
WALK_INLINE bool at_canonical(struct sweep *s, enum walk_kind kind, const struct step *st,
			      uint32_t v, uint32_t lo, uint32_t hi, uint32_t S,
			      struct summary *out)
{
	struct summary *kid;
	struct head *hd = head_at(s, v, lo, hi, &kid);
	switch (kind) {
	case WALK_INSERT:
		return insert_at(s, hd, kid, S, out);
	case WALK_DELETE:
		return delete_at(s, v, lo, hi, hd, kid, S, out);
	case WALK_PREFETCH_NODES:
		if (hi - lo == 1)
			__builtin_prefetch(hd);
		else
			prefetch_node(&s->node[v - lo]);
		return false;
	case WALK_PREFETCH_SOURCE:
		source_prefetch(s->src, hd, STEP_Z(st->zf), st->zf & STEP_DELETE);
		return false;
	case WALK_NUMBER:
		source_number(s->src, hd);
		return false;
	}
	return false;
}

/* The walk's step at path node nd: S gathers its top, or its record is prefetched. */
WALK_INLINE uint32_t at_path(enum walk_kind kind, const struct node *nd, uint32_t S)
{
	if (kind == WALK_PREFETCH_NODES)
		prefetch_node(nd);
	return kind == WALK_INSERT || kind == WALK_DELETE ? max32(S, nd->hd.top) : S;
}

/*
 * The walk of one event, without recursion: the nodes it passes through (those that meet [a, b)
 * without lying inside it) form a path from the root to the split node, then at most one path
 * below each of its children, along which the range's ends run. Each path node has at most one
 * canonical child off the path. Going down gathers S and does the canonical steps; coming back up
 * refreshes the path nodes below a changed child, deepest first.
 */
struct hop {
	struct node *nd;
	struct summary *out; /* where the node's summary lives */
	bool changed;	     /* whether a child's summary changed */
};

/* Refreshes the path nodes hop[from … d) deepest first; changed: whether the deepest's child did. */
WALK_INLINE bool climb(struct sweep *s, enum walk_kind kind, struct hop *hop, size_t from, size_t d,
		       bool changed)
{
	if (kind != WALK_INSERT && kind != WALK_DELETE)
		return false;
	while (d-- > from) {
		changed |= hop[d].changed;
		changed = changed &&
			  update_changed(s, hop[d].nd->hd.top, hop[d].nd->kid, hop[d].out);
	}
	return changed;
}

/*
 * The path below one child of the split node, whose interval [lo, hi) holds the end a (left) or b
 * (right) of the range and lies inside it on the other side; pushes its nodes from hop[d].
 */
WALK_INLINE bool walk_side(struct sweep *s, enum walk_kind kind, const struct step *st, bool left,
			   uint32_t v, uint32_t lo, uint32_t hi, uint32_t S, struct summary *out,
			   struct hop *hop, size_t d)
{
	size_t from = d;
	for (;;) {
		if (left ? st->lo <= lo : hi <= st->hi)
			break;
		struct node *nd = &s->node[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		S = at_path(kind, nd, S);
		hop[d] = (struct hop){ nd, out, false };
		if (left && st->lo < mid) {
			/* [mid, hi) lies inside the range. */
			hop[d].changed = at_canonical(s, kind, st, vis_segtree_right(v, lo, mid),
						      mid, hi, S, &nd->kid[1]);
			v = vis_segtree_left(v);
			hi = mid;
			out = &nd->kid[0];
		} else if (!left && st->hi > mid) {
			hop[d].changed = at_canonical(s, kind, st, vis_segtree_left(v), lo, mid, S,
						      &nd->kid[0]);
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			out = &nd->kid[1];
		} else if (left) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			out = &nd->kid[1];
		} else {
			v = vis_segtree_left(v);
			hi = mid;
			out = &nd->kid[0];
		}
		d++;
	}
	return climb(s, kind, hop, from, d, at_canonical(s, kind, st, v, lo, hi, S, out));
}

/*
 * Walks the event of step st from the root: LEFT-INSERT, RIGHT-DELETE, or a prefetch. The event's
 * own walk needs set_step(st) first.
 */
WALK_INLINE void walk(struct sweep *s, enum walk_kind kind, const struct step *st, uint32_t m)
{
	struct hop hop[2 * VIS_SEGTREE_MAX_HEIGHT];
	uint32_t v = 0, lo = 0, hi = m, S = 0;
	struct summary *out = &s->root;
	size_t d = 0;
	bool changed;
	for (;;) {
		if (st->lo <= lo && hi <= st->hi) {
			changed = at_canonical(s, kind, st, v, lo, hi, S, out);
			break;
		}
		struct node *nd = &s->node[v - lo];
		uint32_t mid = vis_segtree_mid(lo, hi);
		S = at_path(kind, nd, S);
		hop[d++] = (struct hop){ nd, out, false };
		if (st->hi <= mid) {
			v = vis_segtree_left(v);
			hi = mid;
			out = &nd->kid[0];
		} else if (st->lo >= mid) {
			v = vis_segtree_right(v, lo, mid);
			lo = mid;
			out = &nd->kid[1];
		} else {
			changed = walk_side(s, kind, st, true, vis_segtree_left(v), lo, mid, S,
					    &nd->kid[0], hop, d);
			changed |= walk_side(s, kind, st, false, vis_segtree_right(v, lo, mid), mid,
					     hi, S, &nd->kid[1], hop, d);
			break;
		}
	}
	climb(s, kind, hop, 0, d, changed);
}

/* The walks, each a function of its own with its kind built in. */
static void walk_insert(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_INSERT, st, m);
}

static void walk_delete(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_DELETE, st, m);
}

static void prefetch_nodes(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_PREFETCH_NODES, st, m);
}

static void prefetch_source(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_PREFETCH_SOURCE, st, m);
}

static inline void walk_number(struct sweep *s, const struct step *st, uint32_t m)
{
	walk(s, WALK_NUMBER, st, m);
}

/* Whether the sweep will walk the event of step st (see sweep_run). */
static inline bool walks(const struct sweep *s, const struct step *st)
{
	return !(st->zf & STEP_DELETE) || !SOURCE_LAZY_DELETE || s->ntop[STEP_Z(st->zf)] > 0;
}
