#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "classify.h"
#include "segtree.h"
#include "sweep.h"

/*
 * A node of the sweep's segment tree. Invariants, after every event (z = 0 means none):
 * - top: the highest window stored at the node;
 * - l: the lowest window visible at some leaf of the subtree, counting only windows stored in the
 *   subtree: max(min(l of the children), top), top at a leaf; 0 if some leaf has nothing;
 * - h: an upper bound on the highest unreported window that is the top of a subtree node and
 *   visible within the subtree (0 if none). It is exact except for windows reported during the
 *   current event, whose nodes are refreshed right after it (section 6).
 */
struct node {
	uint32_t top, l, h;
};

struct sweep {
	struct node *node;
	uint8_t *reported; /* by z */
	uint32_t *newly;   /* windows reported during the current event */
	size_t nnewly;
	const struct vis_top_source *src;
	uint32_t a, b, z; /* the current event's leaf range and window */
};

static inline uint32_t max32(uint32_t a, uint32_t b)
{
	return a > b ? a : b;
}

static inline uint32_t min32(uint32_t a, uint32_t b)
{
	return a < b ? a : b;
}

/* The lowest visible window below node v, within its subtree (0 at a leaf: nothing is below). */
static inline uint32_t children_l(const struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (hi - lo == 1)
		return 0;
	uint32_t mid = vis_segtree_mid(lo, hi);
	return min32(s->node[vis_segtree_left(v)].l, s->node[vis_segtree_right(v, lo, mid)].l);
}

/* Recomputes l and h of node v from its top and its children's. */
static inline void update(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	struct node *nd = &s->node[v];
	uint32_t cl = 0, ch = 0;
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		const struct node *u = &s->node[vis_segtree_left(v)];
		const struct node *w = &s->node[vis_segtree_right(v, lo, mid)];
		cl = min32(u->l, w->l);
		ch = max32(u->h, w->h);
	}
	uint32_t t = nd->top;
	nd->l = max32(cl, t);
	if (ch < t)
		ch = 0; /* t spans the whole subtree: everything under it is hidden */
	if (t > cl && !s->reported[t])
		ch = max32(ch, t);
	nd->h = ch;
}

static inline void report(struct sweep *s, uint32_t z)
{
	if (!s->reported[z]) {
		s->reported[z] = 1;
		s->newly[s->nnewly++] = z;
	}
}

/* LEFT-INSERT: S is the highest top among v's ancestors. */
static void left_insert(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, uint32_t S)
{
	struct node *nd = &s->node[v];
	if (s->a <= lo && hi <= s->b) {
		/* Read l before the update: z is visible here iff it beats what was visible. */
		uint32_t old_l = max32(children_l(s, v, lo, hi), nd->top);
		nd->top = s->src->insert(s->src->ctx, v, s->z);
		if (s->z > old_l && s->z > S)
			report(s, s->z);
		update(s, v, lo, hi);
		return;
	}
	uint32_t mid = vis_segtree_mid(lo, hi);
	S = max32(S, nd->top);
	if (s->a < mid)
		left_insert(s, vis_segtree_left(v), lo, mid, S);
	if (s->b > mid)
		left_insert(s, vis_segtree_right(v, lo, mid), mid, hi, S);
	update(s, v, lo, hi);
}

/* RIGHT-REPORT: reports the unreported windows above S now visible in v's subtree. */
static void right_report(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, uint32_t S)
{
	struct node *nd = &s->node[v];
	if (nd->h <= S)
		return;
	uint32_t t = nd->top;
	if (t > S) {
		/* Visible within the subtree: tested against the children, not against l_v. */
		if (!s->reported[t] && t > children_l(s, v, lo, hi))
			report(s, t);
		S = t;
	}
	if (hi - lo > 1) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		right_report(s, vis_segtree_left(v), lo, mid, S);
		right_report(s, vis_segtree_right(v, lo, mid), mid, hi, S);
	}
	update(s, v, lo, hi);
}

/* RIGHT-DELETE: S is the highest top among v's ancestors. */
static void right_delete(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi, uint32_t S)
{
	struct node *nd = &s->node[v];
	if (s->a <= lo && hi <= s->b) {
		bool was_visible = nd->top == s->z && s->z > S && s->z > children_l(s, v, lo, hi);
		nd->top = s->src->remove(s->src->ctx, v, s->z);
		update(s, v, lo, hi);
		/* The deletion may expose S itself here, which RIGHT-REPORT never looks at. */
		if (S && S > nd->l)
			report(s, S);
		if (was_visible)
			right_report(s, v, lo, hi, S);
		return;
	}
	uint32_t mid = vis_segtree_mid(lo, hi);
	S = max32(S, nd->top);
	if (s->a < mid)
		right_delete(s, vis_segtree_left(v), lo, mid, S);
	if (s->b > mid)
		right_delete(s, vis_segtree_right(v, lo, mid), mid, hi, S);
	update(s, v, lo, hi);
}

/* Recomputes h on the canonical nodes of [a, b) and their ancestors. */
static void refresh(struct sweep *s, uint32_t v, uint32_t lo, uint32_t hi)
{
	if (!(s->a <= lo && hi <= s->b)) {
		uint32_t mid = vis_segtree_mid(lo, hi);
		if (s->a < mid)
			refresh(s, vis_segtree_left(v), lo, mid);
		if (s->b > mid)
			refresh(s, vis_segtree_right(v, lo, mid), mid, hi);
	}
	update(s, v, lo, hi);
}

int vis_sweep_run(const struct vis_events *ev, const uint32_t *sched,
		  const struct vis_top_source *src, uint8_t *visible)
{
	size_t n = ev->n;
	uint32_t m = ev->nleaves;
	if (n == 0)
		return 0;
	struct sweep s = { .src = src };
	s.node = calloc(vis_segtree_nodes(m), sizeof(*s.node));
	s.reported = calloc(n + 1, 1);
	s.newly = malloc(n * sizeof(*s.newly));
	if (!s.node || !s.reported || !s.newly) {
		free(s.node);
		free(s.reported);
		free(s.newly);
		errno = ENOMEM;
		return -1;
	}
	for (size_t i = 0; i < 2 * n; i++) {
		uint32_t k = VIS_EV_WINDOW(sched[i]);
		s.z = k + 1;
		s.a = ev->lo[k];
		s.b = ev->hi[k];
		if (VIS_EV_IS_DELETE(sched[i])) {
			if (src->deleted)
				src->deleted(src->ctx, s.z);
			right_delete(&s, 0, 0, m, 0);
		} else {
			left_insert(&s, 0, 0, m, 0);
		}
		/* Section 6: a newly reported window no longer counts in h anywhere. */
		for (size_t j = 0; j < s.nnewly; j++) {
			uint32_t r = s.newly[j] - 1;
			s.a = ev->lo[r];
			s.b = ev->hi[r];
			refresh(&s, 0, 0, m);
		}
		s.nnewly = 0;
	}
	for (size_t k = 0; k < n; k++)
		visible[k] = s.reported[k + 1];
	free(s.node);
	free(s.reported);
	free(s.newly);
	return 0;
}

int vis_sweep_compute(const struct vis_stack *stack, const struct vis_top_source_ops *ops,
		      uint8_t *states)
{
	struct vis_events ev;
	if (vis_events_init(&ev, stack, 0) < 0)
		return -1;
	int rc = -1;
	struct vis_top_source src = { 0 };
	uint32_t *sched = malloc(2 * ev.n * sizeof(*sched) + 1);
	uint8_t *visible = calloc(ev.n + 1, 1);
	if (!sched || !visible) {
		errno = ENOMEM;
		goto out;
	}
	if (vis_events_schedule(&ev, VIS_ORDER_VISIBILITY, sched) < 0)
		goto out;
	if (ops->make(&src, &ev, sched) < 0)
		goto out;
	rc = vis_sweep_run(&ev, sched, &src, visible);
	ops->free(&src);
	if (rc == 0)
		rc = vis_classify(stack, &ev, visible, states);
out:
	free(sched);
	free(visible);
	vis_events_finish(&ev);
	return rc;
}
