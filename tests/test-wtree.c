/* Unit test of the window tree: random trees and edits against X's rules applied pixel by pixel. */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <errno.h>
#include <pixman.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "oracle.h"
#include "rng.h"
#include "stack.h"
#include "wtree-live.h"

#define SW 16
#define SH 12
#define MAXW 14
#define CAP 400 /* windows a tree may hold */

static struct vis_wtree tree;
static struct vis_window *wins[CAP];
static int nwins;

/* The oracle: X's model applied to one pixel at a time (oracle.h). */

/* Whether W obscures Q by X's rule: W lies in the subtree of a later sibling of Q or of an
 * ancestor of Q. With own, descendants of Q count too (for Q's own visible pixels). */
static int obscures(const struct vis_window *w, const struct vis_window *q, int own)
{
	if (own && w != q && vis_wtree_is_ancestor(q, w))
		return 1;
	for (const struct vis_window *a = q; a->parent; a = a->parent)
		for (const struct vis_window *s = a->above; s; s = s->above)
			if (vis_wtree_is_ancestor(s, w))
				return 1;
	return 0;
}

/*
 * Whether pixel p of the screen shows a pixel of q's: one of q's inside its ancestors and the
 * screen, not under an opaque pixel of a window that obscures q (own: descendants included).
 */
static int shows(const struct vis_window *q, int64_t px, int64_t py, int own)
{
	if (!oracle_pixel_of(q, px, py) || !oracle_inside_chain(q, px, py))
		return 0;
	for (int i = 0; i < nwins; i++) {
		const struct vis_window *w = wins[i];
		if (w && oracle_viewable(w) && obscures(w, q, own) && oracle_opaque_of(w, px, py) &&
		    oracle_inside_chain(w, px, py))
			return 0;
	}
	return 1;
}

static void check(uint64_t seed)
{
	assert(vis_wtree_compute(&tree) == 0);
	for (int i = 0; i < nwins; i++) {
		struct vis_window *q = wins[i];
		if (!q)
			continue;
		if (!oracle_viewable(q)) {
			assert(q->state == VIS_WTREE_STATE_NONE);
			continue;
		}
		int64_t ax, ay, b2 = 2 * (int64_t)q->look.border;
		oracle_corner(q, &ax, &ay);
		long seen = 0, all = 0, own_all = 0;
		pixman_region32_t reg;
		pixman_region32_init(&reg);
		assert(vis_wtree_visible_region(&tree, q, &reg) == 0);
		for (int64_t y = ay; y < ay + q->height + b2; y++)
			for (int64_t x = ax; x < ax + q->width + b2; x++) {
				all += oracle_pixel_of(q, x, y);
				seen += shows(q, x, y, 0);
				int own = shows(q, x, y, 1);
				own_all += own;
				/* Window coordinates: from the inside's corner. */
				int64_t bw = q->look.border;
				int in = pixman_region32_contains_point(&reg, (int)(x - ax - bw),
									(int)(y - ay - bw), NULL);
				if (own != in) {
					fprintf(stderr, "seed %llu: window %u pixel %lld,%lld own %d "
							"region %d\n",
						(unsigned long long)seed, q->id, (long long)x,
						(long long)y, own, in);
					exit(1);
				}
			}
		/* Nothing in the region outside the border box. */
		int nr;
		const pixman_box32_t *rb = pixman_region32_rectangles(&reg, &nr);
		long area = 0;
		for (int k = 0; k < nr; k++)
			area += (long)(rb[k].x2 - rb[k].x1) * (rb[k].y2 - rb[k].y1);
		assert(area == own_all);
		pixman_region32_fini(&reg);
		int want = q->look.input_only ? VIS_WTREE_STATE_NONE
			 : all == 0	      ? 2
			 : seen == all	      ? 0
			 : seen		      ? 1
					      : 2;
		if (q->state != want) {
			fprintf(stderr, "seed %llu: window %u (depth %u) state %d, X says %d\n",
				(unsigned long long)seed, q->id, q->depth, q->state, want);
			exit(1);
		}
	}
	/* The painter (x11-desk's brute force) agrees, window by window in pre-order. */
	uint8_t painted[CAP];
	long np = oracle_paint(&tree, painted);
	assert(np >= 0 && np <= CAP);
	long kp = 0;
	for (const struct vis_window *w = tree.root.bottom; w; w = vis_wtree_next(w), kp++)
		if (painted[kp] != w->state) {
			fprintf(stderr, "seed %llu: window %u state %d, the painter says %d\n",
				(unsigned long long)seed, w->id, w->state, painted[kp]);
			exit(1);
		}
	assert(kp == np);
	/* Repaint of the whole screen: the windows showing own pixels. */
	struct vis_window *out[CAP];
	long n = vis_wtree_repaint(&tree, (struct vis_box){ 2, 1, SW - 3, SH - 2 }, out);
	assert(n >= 0);
	long k = 0;
	for (size_t i = 0; i < tree.n_order; i++) {
		struct vis_window *q = tree.order[i];
		int any = 0;
		for (int64_t y = 1; y < SH - 2 && !any; y++)
			for (int64_t x = 2; x < SW - 3 && !any; x++)
				any = shows(q, x, y, 1);
		if (any) {
			assert(k < n && out[k] == q);
			k++;
		}
	}
	assert(k == n);
}

/*
 * The incremental recompute against the full one: a twin tree gets every edit the tree gets, with
 * the damage recorded as the daemon records it, and is recomputed with
 * vis_wtree_compute_damaged(); after each batch of edits both must agree on every window.
 */
static struct vis_wtree twin;
static struct vis_window *twins[CAP];
static struct vis_box damage[64];
static size_t n_damage;
static bool damage_all; /* past 64 boxes, as the daemon: a full recompute */
static uint64_t incremental_runs, affected_states, live_runs;

/*
 * How the twin is recomputed: vis_wtree_compute_damaged(), or vis_wtree_update() from the notes
 * (which goes live while no viewable window lies under a shaped ancestor), with looks or with
 * borders only.
 */
static enum engine { DAMAGED, LIVE, LIVE_PLAIN } engine;

/*
 * The kinds of random trees: small ones on a small screen, checked pixel by pixel against X's
 * rules; the same with coordinates near the 32-bit limits and screens up to INT32_MAX wide; and
 * crowds of hundreds of small windows, most of them partially obscured. The last two are only
 * compared with the full recompute.
 */
static enum family { SMALL, EXTREME, CROWD } family;
static const char *const family_names[] = { "", " (extreme)", " (crowd)" };

/* The daemon's damage: the window's box in screen coordinates, before and after each change;
 * the same times are the notes of the live recompute. */
static void damage_of(struct vis_window *w)
{
	vis_wtree_note(&twin, w);
	if (n_damage == sizeof damage / sizeof *damage)
		damage_all = true;
	else
		damage[n_damage++] = vis_wtree_box(w);
}

/*
 * Leaves the twin as a recompute that runs out of memory after flattening leaves it: the boxes and
 * the order new, every state and old_state as they were, the tree stale (and the damage kept, as
 * the daemon keeps it). The next recompute must be a full one, whatever the damage says.
 */
static void fail_recompute(void)
{
	static uint8_t states[CAP][2];
	for (int i = 0; i < nwins; i++)
		if (twins[i]) {
			states[i][0] = twins[i]->state;
			states[i][1] = twins[i]->old_state;
		}
	assert(vis_wtree_compute_damaged(&twin, damage, n_damage) == 0);
	for (int i = 0; i < nwins; i++)
		if (twins[i]) {
			twins[i]->state = states[i][0];
			twins[i]->old_state = states[i][1];
		}
	twin.stale = true;
}

static int index_of(const struct vis_window *w);

/* Whether window i has the same visible region in both trees (the twin's live, maybe). */
static bool same_region(int i)
{
	pixman_region32_t a, b;
	pixman_region32_init(&a);
	pixman_region32_init(&b);
	assert(vis_wtree_visible_region(&tree, wins[i], &a) == 0);
	assert(vis_wtree_visible_region(&twin, twins[i], &b) == 0);
	bool same = pixman_region32_equal(&a, &b);
	pixman_region32_fini(&a);
	pixman_region32_fini(&b);
	return same;
}

/*
 * Recomputes the twin from the damage and compares every window and the order with the tree's;
 * now and then after a failed recompute.
 */
static void compare(uint64_t seed, const char *what)
{
	if (incremental_runs % 13 == 5 && !damage_all)
		fail_recompute();
	if (engine != DAMAGED)
		assert(vis_wtree_update(&twin) == 0);
	else if (damage_all)
		assert(vis_wtree_compute(&twin) == 0);
	else
		assert(vis_wtree_compute_damaged(&twin, damage, n_damage) == 0);
	incremental_runs += !damage_all;
	n_damage = 0;
	damage_all = false;
	struct vis_window *const *changed;
	size_t n_changed;
	bool live = engine != DAMAGED && vis_wtree_changes(&twin, &changed, &n_changed);
	live_runs += live;
	const char *broken = wtree_live_check(&twin);
	if (broken) {
		fprintf(stderr, "seed %llu%s, after %s: the live structures are broken: %s\n",
			(unsigned long long)seed, family_names[family], what, broken);
		exit(1);
	}
	if (live) {
		/* The list holds every window whose state changed. */
		for (int i = 0; i < nwins; i++)
			if (twins[i] && twins[i]->state != twins[i]->old_state) {
				size_t k = 0;
				while (k < n_changed && changed[k] != twins[i])
					k++;
				assert(k < n_changed);
			}
	} else {
		assert(twin.n_order == tree.n_order);
		for (size_t i = 0; i < tree.n_order; i++)
			assert(twin.order[i]->id == tree.order[i]->id && twin.order[i]->pos == i);
	}
	if (family == SMALL)
		for (int i = 0; i < nwins; i++)
			if (wins[i] && !same_region(i)) {
				fprintf(stderr, "seed %llu, after %s: window %u's visible region differs\n",
					(unsigned long long)seed, what, wins[i]->id);
				exit(1);
			}
	/* Keys grow with the order, whichever recompute made them. */
	for (size_t i = 1; i < tree.n_order; i++)
		assert(twins[index_of(tree.order[i - 1])]->key < twins[index_of(tree.order[i])]->key);
	for (int i = 0; i < nwins; i++) {
		const struct vis_window *a = wins[i], *b = twins[i];
		assert(!a == !b);
		if (!a)
			continue;
		affected_states += b->state != b->old_state;
		if (a->state != b->state || a->old_state != b->old_state) {
			fprintf(stderr, "seed %llu%s, after %s: window %u (depth %u) is %d (was %d) "
					"incrementally, %d (was %d) in full\n",
				(unsigned long long)seed, family_names[family], what, a->id,
				a->depth, b->state, b->old_state, a->state, a->old_state);
			exit(1);
		}
	}
}

/* Computes the tree in full (checked against X's rules if small), the twin incrementally. */
static void check_both(uint64_t seed, const char *what)
{
	if (family != SMALL)
		assert(vis_wtree_compute(&tree) == 0);
	else
		check(seed);
	compare(seed, what);
}

/* A live window's index, picked at random; -1 when none is left. */
static int pick(struct vis_rng *r)
{
	int live = 0;
	for (int i = 0; i < nwins; i++)
		live += wins[i] != NULL;
	if (!live)
		return -1;
	int k = (int)vis_rng_below(r, (uint64_t)live);
	for (int i = 0; i < nwins; i++)
		if (wins[i] && k-- == 0)
			return i;
	return -1;
}

static int index_of(const struct vis_window *w)
{
	for (int i = 0; i < nwins; i++)
		if (wins[i] == w)
			return i;
	return -1;
}

static void forget(void *data, struct vis_window *w)
{
	struct vis_window **list = data;
	for (int i = 0; i < nwins; i++)
		if (list[i] == w)
			list[i] = NULL;
}

/* Coordinates that make trouble: the 32-bit limits, zero, one, and a few around the screen. */
static int32_t extreme_coord(struct vis_rng *r)
{
	static const int32_t values[] = { INT32_MIN, INT32_MIN + 1, -INT32_MAX / 2, -2, -1, 0, 1, 2,
					  5, SW - 1, SW, INT32_MAX / 2, INT32_MAX - 1, INT32_MAX };
	return values[vis_rng_below(r, sizeof values / sizeof *values)];
}

static int32_t extreme_size(struct vis_rng *r)
{
	static const int32_t values[] = { 1, 2, 3, SW, INT32_MAX / 2, INT32_MAX - 1, INT32_MAX };
	return values[vis_rng_below(r, sizeof values / sizeof *values)];
}

/* A random geometry: small, on and around the screen, or extreme. */
static void geometry(struct vis_rng *r, int32_t g[4])
{
	if (family == EXTREME && vis_rng_below(r, 4)) {
		g[0] = extreme_coord(r);
		g[1] = extreme_coord(r);
		g[2] = extreme_size(r);
		g[3] = extreme_size(r);
		return;
	}
	if (family == CROWD) {
		g[0] = (int32_t)vis_rng_below(r, 72) - 8;
		g[1] = (int32_t)vis_rng_below(r, 56) - 8;
		g[2] = 4 + (int32_t)vis_rng_below(r, 36);
		g[3] = 3 + (int32_t)vis_rng_below(r, 27);
		return;
	}
	g[0] = (int32_t)vis_rng_below(r, 20) - 4;
	g[1] = (int32_t)vis_rng_below(r, 16) - 4;
	g[2] = 1 + (int32_t)vis_rng_below(r, 12);
	g[3] = 1 + (int32_t)vis_rng_below(r, 10);
}

/*
 * Random looks. Shape and opaque rectangles are relative to the inside's corner and reach into
 * the border and past the border box; a shape may be empty or made of abutting pieces.
 */
static struct vis_rect look_rect(struct vis_rng *r, const struct vis_window *w)
{
	if (family == EXTREME && vis_rng_below(r, 3) == 0)
		return (struct vis_rect){ extreme_coord(r), extreme_coord(r), extreme_size(r),
					  extreme_size(r) };
	int64_t b = w->look.border, sw = w->width + 2 * b + 4, sh = w->height + 2 * b + 4;
	if (sw > 48)
		sw = 48;
	if (sh > 48)
		sh = 48;
	struct vis_rect q;
	q.x = (int32_t)((int64_t)vis_rng_below(r, (uint64_t)sw) - b - 2);
	q.y = (int32_t)((int64_t)vis_rng_below(r, (uint64_t)sh) - b - 2);
	q.w = 1 + (int32_t)vis_rng_below(r, (uint64_t)(sw / 2 + 1));
	q.h = 1 + (int32_t)vis_rng_below(r, (uint64_t)(sh / 2 + 1));
	return q;
}

/* n random rectangles into q, now and then one rectangle cut in two abutting ones; returns n. */
static uint32_t look_rects(struct vis_rng *r, const struct vis_window *w, struct vis_rect *q,
			   uint32_t max)
{
	uint32_t n = (uint32_t)vis_rng_below(r, max + 1);
	for (uint32_t k = 0; k < n; k++)
		q[k] = look_rect(r, w);
	if (n >= 2 && vis_rng_below(r, 2)) {
		/* q[0] and q[1]: one rectangle cut at a random column or row. */
		struct vis_rect a = look_rect(r, w);
		a.w = a.w < 2 ? 2 : a.w;
		a.h = a.h < 2 ? 2 : a.h;
		/* So that the second piece still starts inside the 32-bit range. */
		a.x = a.x > INT32_MAX - 2 ? INT32_MAX - 2 : a.x;
		a.y = a.y > INT32_MAX - 2 ? INT32_MAX - 2 : a.y;
		a.w = (int64_t)a.x + a.w > INT32_MAX ? INT32_MAX - a.x : a.w;
		a.h = (int64_t)a.y + a.h > INT32_MAX ? INT32_MAX - a.y : a.h;
		q[0] = q[1] = a;
		if (vis_rng_below(r, 2)) {
			q[0].w = 1 + (int32_t)vis_rng_below(r, (uint64_t)a.w - 1);
			q[1].x = a.x + q[0].w;
			q[1].w = a.w - q[0].w;
		} else {
			q[0].h = 1 + (int32_t)vis_rng_below(r, (uint64_t)a.h - 1);
			q[1].y = a.y + q[0].h;
			q[1].h = a.h - q[0].h;
		}
	}
	return n;
}

enum look_op { BORDER, SHAPE, OPAQUE };
static const char *const look_names[] = { "border", "shape", "opaque" };

/*
 * Changes window i's look in both trees the same way, with the damage the daemon records: the
 * window's box before and after. Returns the change's name.
 */
static const char *change_look(struct vis_rng *r, enum look_op op, int i)
{
	struct vis_window *a = wins[i], *b = twins[i];
	if (engine == LIVE_PLAIN)
		op = BORDER; /* the live structures hold */
	struct vis_rect q[4];
	damage_of(b);
	switch (op) {
	case BORDER: {
		static const int32_t extreme[] = { 1, 7, INT32_MAX / 4, INT32_MAX / 2 };
		int32_t v = vis_rng_below(r, 3) ? 0 : 1 + (int32_t)vis_rng_below(r, 2);
		if (family == EXTREME && vis_rng_below(r, 2))
			v = extreme[vis_rng_below(r, 4)];
		int ra = vis_wtree_set_border(a, v), rb = vis_wtree_set_border(b, v);
		bool fits = (int64_t)a->width + 2 * (int64_t)v <= INT32_MAX &&
			    (int64_t)a->height + 2 * (int64_t)v <= INT32_MAX;
		assert(ra == rb && (ra == 0) == (fits && (!a->look.input_only || v == 0)));
		break;
	}
	case SHAPE: {
		bool shaped = vis_rng_below(r, 4) != 0;
		uint32_t n = look_rects(r, a, q, 3);
		int ra = vis_wtree_set_shape(a, shaped, q, n);
		int rb = vis_wtree_set_shape(b, shaped, q, n);
		assert(ra == rb && (ra == 0) == !a->look.input_only);
		break;
	}
	case OPAQUE: {
		uint64_t k = vis_rng_below(r, 4);
		enum vis_opaque mode = k < 2 ? VIS_OPAQUE_ALL : k == 2 ? VIS_OPAQUE_NONE
								     : VIS_OPAQUE_RECTS;
		uint32_t n = look_rects(r, a, q, 3);
		int ra = vis_wtree_set_opaque(a, mode, q, n);
		int rb = vis_wtree_set_opaque(b, mode, q, n);
		assert(ra == rb && (ra == 0) == !a->look.input_only);
		break;
	}
	}
	damage_of(b);
	return look_names[op];
}

/* Gives the newest window of both trees a random look: most often none, now and then input-only. */
static void random_look(struct vis_rng *r)
{
	int i = nwins - 1;
	if (vis_rng_below(r, 8) == 0) {
		vis_wtree_set_input_only(wins[i]);
		vis_wtree_set_input_only(twins[i]);
		return;
	}
	for (int op = BORDER; op <= OPAQUE; op++)
		if (vis_rng_below(r, 4) == 0)
			change_look(r, (enum look_op)op, i);
}

/* Creates a window under parent index p (-1: the screen) in both trees, with its damage. */
static void create(int p, const int32_t g[4], bool mapped)
{
	assert(nwins < CAP);
	struct vis_window *a = vis_wtree_create(&tree, p < 0 ? &tree.root : wins[p], g[0], g[1],
						g[2], g[3], 1);
	struct vis_window *b = vis_wtree_create(&twin, p < 0 ? &twin.root : twins[p], g[0], g[1],
						g[2], g[3], 1);
	assert(a && b);
	a->mapped = b->mapped = mapped;
	wins[nwins] = a;
	twins[nwins++] = b;
	damage_of(b);
}

enum op { RESTACK, RAISE, LOWER, REPARENT, MOVE, RESIZE, MAP, UNMAP, DESTROY };
static const char *const op_names[] = { "restack", "raise", "lower", "reparent", "move",
					 "resize", "map", "unmap", "destroy" };

/*
 * Changes window i of both trees, with the damage the daemon records: after a restack or a change
 * of mapping (the box stays), before and after a move, a resize or a reparent, before a
 * destruction. other is the sibling of a restack (above it if x, else below) or the new parent
 * (-1: the screen); x, y the position or the size. Returns the change's name.
 */
static const char *change(enum op op, int i, int other, int32_t x, int32_t y)
{
	struct vis_window *a = wins[i], *b = twins[i];
	switch (op) {
	case RESTACK:
		vis_wtree_restack(a, wins[other], x);
		vis_wtree_restack(b, twins[other], x);
		damage_of(b);
		break;
	case RAISE:
		vis_wtree_raise(a);
		vis_wtree_raise(b);
		damage_of(b);
		break;
	case LOWER:
		vis_wtree_lower(a);
		vis_wtree_lower(b);
		damage_of(b);
		break;
	case REPARENT:
		damage_of(b);
		vis_wtree_reparent(a, other < 0 ? &tree.root : wins[other], x, y);
		vis_wtree_reparent(b, other < 0 ? &twin.root : twins[other], x, y);
		damage_of(b);
		break;
	case MOVE:
	case RESIZE:
		damage_of(b);
		if (op == MOVE) {
			a->x = b->x = x;
			a->y = b->y = y;
		} else {
			/* Through the setter, which keeps the border box's sides within INT32_MAX. */
			int ra = vis_wtree_set_size(a, x, y, a->look.border);
			int rb = vis_wtree_set_size(b, x, y, b->look.border);
			assert(ra == rb);
		}
		damage_of(b);
		break;
	case MAP:
	case UNMAP:
		a->mapped = b->mapped = op == MAP;
		damage_of(b);
		break;
	case DESTROY:
		damage_of(b);
		vis_wtree_destroy(&tree, a, forget, wins);
		vis_wtree_destroy(&twin, b, forget, twins);
		break;
	}
	return op_names[op];
}

/* One random edit of both trees; returns its name. */
static const char *edit(struct vis_rng *r)
{
	int i = pick(r);
	int32_t g[4];
	geometry(r, g);
	if (i < 0 || vis_rng_below(r, 12) == 0) {
		int p = vis_rng_below(r, 3) ? pick(r) : -1;
		if (nwins < CAP) {
			create(p, g, vis_rng_below(r, 6) != 0);
			random_look(r);
			return "create";
		}
		if (i < 0)
			return "nothing";
	}
	struct vis_window *a = wins[i];
	switch (vis_rng_below(r, 12)) {
	case 0: {
		/* Above or below a random sibling. */
		int k = 0;
		for (struct vis_window *s = a->parent->bottom; s; s = s->above)
			k++;
		struct vis_window *s = a->parent->bottom;
		for (int j = (int)vis_rng_below(r, (uint64_t)k); j > 0; j--)
			s = s->above;
		return change(RESTACK, i, index_of(s), (int32_t)vis_rng_below(r, 2), 0);
	}
	case 1:
		return change(RAISE, i, 0, 0, 0);
	case 2:
		return change(LOWER, i, 0, 0, 0);
	case 3: {
		int p = pick(r);
		if (p >= 0 && vis_wtree_is_ancestor(a, wins[p]))
			p = -1;
		/* Half the time where it was on the screen: its pixels stay, whom they hide does not. */
		struct vis_box at = vis_wtree_box(a);
		struct vis_box in = p < 0 ? (struct vis_box){ 0, 0, 0, 0 } : vis_wtree_box(wins[p]);
		int64_t b = p < 0 ? 0 : wins[p]->look.border;
		int64_t x = at.x1 - in.x1 - b, y = at.y1 - in.y1 - b;
		if (vis_rng_below(r, 2) && x >= INT32_MIN && x <= INT32_MAX && y >= INT32_MIN &&
		    y <= INT32_MAX)
			return change(REPARENT, i, p, (int32_t)x, (int32_t)y);
		return change(REPARENT, i, p, g[0], g[1]);
	}
	case 4:
		if (vis_rng_below(r, 2) && family != EXTREME)
			/* A small step: abutting and shared edges come and go. */
			return change(MOVE, i, 0, a->x + (int32_t)vis_rng_below(r, 5) - 2,
				      a->y + (int32_t)vis_rng_below(r, 3) - 1);
		return change(MOVE, i, 0, g[0], g[1]);
	case 5:
		return change(RESIZE, i, 0, g[2], g[3]);
	case 6:
	case 7:
		return change(a->mapped ? UNMAP : MAP, i, 0, 0, 0);
	case 8:
	case 9:
	case 10:
		return change_look(r, (enum look_op)(vis_rng_below(r, 3)), i);
	default:
		return change(DESTROY, i, 0, 0, 0);
	}
}

/* Random trees under random batches of edits, each batch followed by both recomputes. */
static int random_trees(uint64_t first, uint64_t count, int batches)
{
	for (uint64_t seed = first; seed < first + count; seed++) {
		struct vis_rng r = { seed };
		engine = (enum engine)(seed % 3);
		int32_t sw = family == CROWD ? 64 : SW, sh = family == CROWD ? 48 : SH;
		if (family == EXTREME) {
			static const int32_t sides[] = { 1, 3, SW, INT32_MAX - 1, INT32_MAX };
			sw = sides[vis_rng_below(&r, 5)];
			sh = sides[vis_rng_below(&r, 5)];
		}
		vis_wtree_init(&tree, sw, sh);
		vis_wtree_init(&twin, sw, sh);
		/* Small trees go live; now and then updates run out of steps and give up; half
		 * the time seen regions of more than one to three boxes are kept loose; two
		 * thirds of the time walks keep what is left in 2 to 7 boxes before a region
		 * (and go on a grid cell at a time); half the time rule 2's walks hand over to
		 * the seen grid after 1 to 8 steps. */
		assert(vis_wtree_live_from(&twin, 0) == 0);
		wtree_live_tune(&twin, seed % 7 == 3 ? 1 + vis_rng_below(&r, 40) : 0,
				seed % 2 ? 1 + (unsigned)vis_rng_below(&r, 3) : 0,
				seed % 3 ? 2 + (unsigned)vis_rng_below(&r, 6) : 0,
				seed % 4 < 2 ? 1 + vis_rng_below(&r, 8) : 0);
		nwins = 0;
		n_damage = 0;
		damage_all = false;
		int n = family == CROWD ? 100 + (int)vis_rng_below(&r, 200)
					: 1 + (int)vis_rng_below(&r, MAXW);
		for (int i = 0; i < n; i++) {
			int p = vis_rng_below(&r, 3) ? pick(&r) : -1;
			int32_t g[4];
			geometry(&r, g);
			create(p, g, vis_rng_below(&r, 6) != 0);
			random_look(&r);
		}
		check_both(seed, "creation");
		for (int e = 0; e < batches; e++) {
			const char *what = "no change";
			for (int k = (int)vis_rng_below(&r, 4); k > 0; k--)
				what = edit(&r);
			check_both(seed, what);
		}
		vis_wtree_finish(&tree);
		vis_wtree_finish(&twin);
	}
	return (int)count;
}

/* Starts a scripted scene: both trees empty on the small screen. */
static void scene_begin(void)
{
	vis_wtree_init(&tree, SW, SH);
	vis_wtree_init(&twin, SW, SH);
	assert(vis_wtree_live_from(&twin, 0) == 0);
	nwins = 0;
	n_damage = 0;
	damage_all = false;
}

static void scene_end(void)
{
	vis_wtree_finish(&tree);
	vis_wtree_finish(&twin);
}

/* Creates a mapped window under parent index p (-1: the screen); returns its index. */
static int put(int p, int32_t x, int32_t y, int32_t w, int32_t h)
{
	create(p, (int32_t[4]){ x, y, w, h }, true);
	return nwins - 1;
}

/* Window i's state in both trees, which check_both() found equal. */
static int state(int i)
{
	return wins[i]->state;
}

/*
 * Cases random trees reach only by chance, each step checked against X's rules and the full
 * recompute: a window covered exactly by abutting ones, uncovered by one pixel and covered again;
 * identical rectangles; 1×1 windows on the screen's last pixel and just off it; a deep chain
 * unmapped, moved, reparented and cut in its middle; children raised, lowered and restacked, also
 * under an unmapped parent.
 */
static void scripted(void)
{
	enum { U = VIS_UNOBSCURED, P = VIS_PARTIALLY_OBSCURED, F = VIS_FULLY_OBSCURED };
	scene_begin();
	int c = put(-1, 2, 2, 8, 4), a = put(-1, 2, 2, 4, 4), b = put(-1, 6, 2, 4, 4);
	check_both(0, "abutting cover");
	assert(state(c) == F && state(a) == U && state(b) == U);
	check_both(0, change(MOVE, b, 0, 7, 2));
	assert(state(c) == P);
	check_both(0, change(MOVE, b, 0, 6, 2));
	assert(state(c) == F);
	check_both(0, change(RESIZE, a, 0, 4, 3));
	assert(state(c) == P);
	check_both(0, change(RESIZE, a, 0, 4, 4));
	assert(state(c) == F);
	int d = put(-1, 2, 2, 8, 4);
	check_both(0, "identical");
	assert(state(d) == U && state(c) == F && state(a) == F && state(b) == F);
	check_both(0, change(RAISE, c, 0, 0, 0));
	assert(state(c) == U && state(d) == F);
	check_both(0, change(RESTACK, d, c, 1, 0));
	assert(state(d) == U && state(c) == F);
	scene_end();

	scene_begin();
	int big = put(-1, 0, 0, SW, SH), p = put(-1, SW - 1, SH - 1, 1, 1), q = put(-1, SW, SH, 1, 1);
	check_both(0, "1x1");
	assert(state(big) == P && state(p) == U && state(q) == F);
	check_both(0, change(MOVE, q, 0, SW - 1, SH - 1));
	assert(state(q) == U && state(p) == F);
	check_both(0, change(LOWER, q, 0, 0, 0));
	assert(state(q) == F && state(p) == U);
	check_both(0, change(MOVE, big, 0, 1, 0));
	assert(state(big) == P);
	check_both(0, change(MOVE, big, 0, 0, 0));
	scene_end();

	scene_begin();
	int chain[8];
	chain[0] = put(-1, 1, 1, 14, 10);
	for (int k = 1; k < 8; k++)
		chain[k] = put(chain[k - 1], 1, k % 2, 13 - k, 9 - k);
	put(-1, 10, 0, 6, 12);
	check_both(0, "chain");
	check_both(0, change(UNMAP, chain[3], 0, 0, 0));
	for (int k = 3; k < 8; k++)
		assert(state(chain[k]) == VIS_WTREE_STATE_NONE);
	check_both(0, change(MAP, chain[3], 0, 0, 0));
	check_both(0, change(MOVE, chain[3], 0, -1, 1));
	check_both(0, change(REPARENT, chain[5], -1, 0, 0));
	check_both(0, change(RAISE, chain[0], 0, 0, 0));
	check_both(0, change(REPARENT, chain[5], chain[1], 0, 0));
	check_both(0, change(DESTROY, chain[2], 0, 0, 0));
	scene_end();

	/* A child reparented on top of its parent where it was, and back: the parent loses and
	 * gains the pixels the child sees all along. */
	scene_begin();
	int parent = put(-1, 0, 0, 10, 10), child = put(parent, 2, 2, 4, 4);
	check_both(0, "a child");
	check_both(0, change(MOVE, child, 0, 2, 2));
	check_both(0, change(REPARENT, child, -1, 2, 2));
	assert(state(parent) == P && state(child) == U);
	check_both(0, change(MOVE, parent, 0, 0, 0));
	check_both(0, change(REPARENT, child, parent, 2, 2));
	assert(state(parent) == U && state(child) == U);
	scene_end();

	/*
	 * A large window punched by many small ones over several grid cells (a chain's levels),
	 * moved and so walked: what it sees fragments past the walk's boxes and the walk goes on a
	 * cell at a time; its parent too, which its children do not hide.
	 */
	vis_wtree_init(&tree, 192, 128);
	vis_wtree_init(&twin, 192, 128);
	assert(vis_wtree_live_from(&twin, 0) == 0);
	wtree_live_tune(&twin, 0, 1, 2, 0);
	nwins = 0;
	n_damage = 0;
	damage_all = false;
	int frame = put(-1, 0, 0, 192, 128), punched = put(frame, 1, 1, 190, 126);
	struct vis_rng holes = { 7 };
	for (int i = 0; i < 40; i++)
		put(i % 3 ? -1 : frame, (int32_t)vis_rng_below(&holes, 188),
		    (int32_t)vis_rng_below(&holes, 124), 1 + (int32_t)vis_rng_below(&holes, 3),
		    1 + (int32_t)vis_rng_below(&holes, 3));
	check_both(0, "a window punched by many");
	check_both(0, change(MOVE, punched, 0, 2, 1));
	check_both(0, change(MOVE, frame, 0, 1, 0));
	check_both(0, change(RAISE, punched, 0, 0, 0));
	check_both(0, change(LOWER, punched, 0, 0, 0));
	assert(state(frame) == P && state(punched) == P);
	scene_end();

	/* A window lowered past one that misses what it sees, onto one that holds all of it: the
	 * windows now above it are those between its places, not those below. */
	scene_begin();
	int floor_ = put(-1, 0, 0, 10, 10), aside = put(-1, 8, 8, 4, 4);
	int lowered = put(-1, 2, 2, 4, 4), over = put(-1, 3, 3, 4, 4);
	check_both(0, "a stack");
	check_both(0, change(MOVE, lowered, 0, 2, 2));
	check_both(0, change(RESTACK, lowered, aside, 0, 0));
	assert(state(lowered) == P && state(floor_) == P && state(over) == U);
	check_both(0, change(RESTACK, lowered, floor_, 0, 0));
	assert(state(lowered) == F);
	scene_end();

	/* A window lowered to the bottom past 48 tiles that each gain what it hid of them: the walk
	 * that takes them grows the candidates as it goes. */
	scene_begin();
	for (int i = 0; i < 48; i++)
		put(-1, (i % 8) * 2, (i / 8) * 2, 2, 2);
	int cover = put(-1, 0, 0, SW, SH);
	check_both(0, "tiles under a cover");
	check_both(0, change(MOVE, cover, 0, 0, 0));
	check_both(0, change(LOWER, cover, 0, 0, 0));
	assert(state(cover) == F && state(0) == U);
	check_both(0, change(RAISE, cover, 0, 0, 0));
	check_both(0, change(UNMAP, 20, 0, 0, 0));
	check_both(0, change(LOWER, cover, 0, 0, 0));
	assert(state(cover) == P && state(21) == U);
	scene_end();

	/* A window whose seen region is kept loose (two strips, kept as a box) loses one strip and
	 * then the other: while an edge of the box it touched is uncovered, it is partially obscured
	 * without a walk; once both are gone it is walked, and fully obscured. */
	scene_begin();
	wtree_live_tune(&twin, 0, 1, 0, 0);
	int strips = put(-1, 0, 0, 6, 6);
	put(-1, 2, 0, 2, 6);
	int left = put(-1, 0, 0, 2, 6), right = put(-1, 4, 0, 2, 6);
	check_both(0, change(UNMAP, left, 0, 0, 0));
	check_both(0, change(UNMAP, right, 0, 0, 0));
	check_both(0, change(MOVE, strips, 0, 0, 0));
	assert(state(strips) == P);
	check_both(0, change(MAP, left, 0, 0, 0));
	assert(state(strips) == P);
	check_both(0, change(MAP, right, 0, 0, 0));
	assert(state(strips) == F);
	scene_end();

	scene_begin();
	int top = put(-1, 0, 0, 12, 10);
	int k1 = put(top, 0, 0, 6, 6), k2 = put(top, 3, 3, 6, 6), k3 = put(top, 5, 1, 6, 6);
	put(k1, 1, 1, 3, 3);
	put(k2, 0, 0, 6, 6);
	int other = put(-1, 8, 4, 8, 8);
	check_both(0, "children");
	check_both(0, change(RAISE, k1, 0, 0, 0));
	check_both(0, change(LOWER, k3, 0, 0, 0));
	check_both(0, change(RESTACK, k2, k1, 0, 0));
	check_both(0, change(UNMAP, top, 0, 0, 0));
	check_both(0, change(RAISE, k3, 0, 0, 0));
	check_both(0, change(MAP, top, 0, 0, 0));
	check_both(0, change(REPARENT, k2, other, 0, 0));
	check_both(0, change(LOWER, other, 0, 0, 0));
	check_both(0, change(UNMAP, k1, 0, 0, 0));
	check_both(0, change(DESTROY, top, 0, 0, 0));
	scene_end();
}

/* Sets window i's shape in both trees, with its damage; returns the change's name. */
static const char *shape(int i, bool shaped, const struct vis_rect *q, uint32_t n)
{
	damage_of(twins[i]);
	assert(vis_wtree_set_shape(wins[i], shaped, q, n) == 0);
	assert(vis_wtree_set_shape(twins[i], shaped, q, n) == 0);
	damage_of(twins[i]);
	return "shape";
}

static const char *opaque(int i, enum vis_opaque mode, const struct vis_rect *q, uint32_t n)
{
	damage_of(twins[i]);
	assert(vis_wtree_set_opaque(wins[i], mode, q, n) == 0);
	assert(vis_wtree_set_opaque(twins[i], mode, q, n) == 0);
	damage_of(twins[i]);
	return "opaque";
}

static const char *border(int i, int32_t b)
{
	damage_of(twins[i]);
	assert(vis_wtree_set_border(wins[i], b) == 0);
	assert(vis_wtree_set_border(twins[i], b) == 0);
	damage_of(twins[i]);
	return "border";
}

/* A mapped input-only window under parent index p; returns its index. */
static int put_input_only(int p, int32_t x, int32_t y, int32_t w, int32_t h)
{
	create(p, (int32_t[4]){ x, y, w, h }, false);
	vis_wtree_set_input_only(wins[nwins - 1]);
	vis_wtree_set_input_only(twins[nwins - 1]);
	change(MAP, nwins - 1, 0, 0, 0);
	return nwins - 1;
}

/*
 * Looks, step by step: a shape that keeps a window's pixels on the screen when its box is not, or
 * loses one, or is empty, or sticks out of the border box; translucent windows and opaque regions
 * covering exactly in two pieces; borders, which obscure and clip children to the inside; an
 * input-only window, which hides nothing but clips its children; a translucent window whose
 * opaque child hides a window with children of its own.
 */
static void scripted_looks(void)
{
	enum { U = VIS_UNOBSCURED, P = VIS_PARTIALLY_OBSCURED, F = VIS_FULLY_OBSCURED };
	scene_begin();
	int s = put(-1, -2, 0, 6, 4);
	check_both(0, shape(s, true, (struct vis_rect[]){ { 2, 0, 2, 2 } }, 1));
	assert(state(s) == U);
	check_both(0, shape(s, true, (struct vis_rect[]){ { 1, 0, 2, 2 } }, 1));
	assert(state(s) == P);
	check_both(0, shape(s, true, NULL, 0));
	assert(state(s) == F);
	check_both(0, shape(s, false, NULL, 0));
	assert(state(s) == P);
	int t = put(-1, 6, 4, 4, 4);
	check_both(0, shape(t, true, (struct vis_rect[]){ { 0, 0, 3, 3 }, { 10, 10, 5, 5 } }, 2));
	assert(state(t) == U);
	scene_end();

	scene_begin();
	int c = put(-1, 2, 2, 6, 6), o = put(-1, 2, 2, 6, 6);
	check_both(0, opaque(o, VIS_OPAQUE_NONE, NULL, 0));
	assert(state(c) == U && state(o) == U);
	check_both(0, opaque(o, VIS_OPAQUE_RECTS, (struct vis_rect[]){ { 0, 0, 6, 3 } }, 1));
	assert(state(c) == P);
	check_both(0, opaque(o, VIS_OPAQUE_RECTS,
			     (struct vis_rect[]){ { 0, 0, 6, 3 }, { 0, 3, 6, 3 } }, 2));
	assert(state(c) == F);
	check_both(0, shape(o, true, (struct vis_rect[]){ { 0, 0, 6, 5 } }, 1));
	assert(state(c) == P);
	check_both(0, opaque(o, VIS_OPAQUE_ALL, NULL, 0));
	assert(state(c) == P);
	scene_end();

	scene_begin();
	int a = put(-1, 2, 2, 4, 4);
	int k = put(a, 0, 0, 4, 4);
	check_both(0, border(a, 1));
	assert(state(a) == U && state(k) == U);
	int e = put(-1, 7, 2, 3, 3);
	check_both(0, "over the border");
	assert(state(a) == P && state(k) == U);
	check_both(0, change(MOVE, k, 0, 1, 0));
	assert(state(k) == P);
	check_both(0, border(a, 2));
	assert(state(k) == P && state(e) == U);
	scene_end();

	scene_begin();
	int under = put(-1, 0, 0, 4, 4);
	int io = put_input_only(-1, 0, 0, 8, 8);
	int x = put(io, 4, 4, 8, 8);
	check_both(0, "input-only");
	assert(state(under) == U && state(io) == VIS_WTREE_STATE_NONE && state(x) == P);
	check_both(0, change(MOVE, x, 0, 0, 0));
	assert(state(under) == F && state(x) == U);
	scene_end();

	scene_begin();
	int w = put(-1, 0, 0, 8, 8);
	put(w, 0, 0, 2, 2);
	int sib = put(-1, 0, 0, 10, 10);
	check_both(0, opaque(sib, VIS_OPAQUE_NONE, NULL, 0));
	assert(state(w) == U);
	int child = put(sib, 0, 0, 8, 8);
	check_both(0, "translucent parent");
	assert(state(w) == F && state(child) == U && state(sib) == U);
	/* A shaped parent clips its child to its shape, as X does: the child keeps no pixel, and w
	 * shows through the translucent parent again. */
	check_both(0, shape(sib, true, (struct vis_rect[]){ { 9, 9, 1, 1 } }, 1));
	assert(state(w) == U && state(sib) == U && state(child) == F);
	check_both(0, shape(sib, true, (struct vis_rect[]){ { 0, 0, 10, 7 } }, 1));
	assert(state(w) == P && state(child) == P);
	check_both(0, change(RESIZE, child, 0, 8, 7));
	assert(state(w) == P && state(child) == U);
	scene_end();
}

/*
 * External IDs: set once, unique per (namespace, tag), found until the window is destroyed, with
 * its subtree or alone. Enough windows that some pairs share a hash, so the chains are walked,
 * spliced and emptied.
 */
static void externals(void)
{
	enum { N = 150000 };
	static struct vis_window *w[2 * N];
	vis_wtree_init(&tree, 100, 100);
	struct vis_window *top = vis_wtree_create(&tree, &tree.root, 0, 0, 10, 10, 1);
	assert(vis_wtree_find_external(&tree, 1, 7) == NULL);
	assert(vis_wtree_set_external(&tree, top, 0, 7) < 0 && errno == EINVAL);
	assert(vis_wtree_set_external(&tree, top, 1, 0x1e00003) == 0);
	assert(vis_wtree_set_external(&tree, top, 1, 8) < 0 && errno == EINVAL); /* set once */
	assert(vis_wtree_find_external(&tree, 1, 0x1e00003) == top);
	assert(vis_wtree_find_external(&tree, 2, 0x1e00003) == NULL);
	assert(vis_wtree_find_external(&tree, 0, 0) == NULL);
	/* The same tags in two namespaces, under top; the X tags of the top one taken already. */
	for (int i = 0; i < 2 * N; i++) {
		w[i] = vis_wtree_create(&tree, i % 3 ? top : &tree.root, 0, 0, 1, 1, 1);
		uint64_t tag = (uint64_t)(i / 2) * 0x100001ull + ((uint64_t)(i / 2) << 40);
		assert(vis_wtree_set_external(&tree, w[i], 1 + (uint32_t)(i % 2), tag) == 0);
		if (i % 1000 == 0) {
			struct vis_window *other = vis_wtree_create(&tree, &tree.root, 0, 0, 1, 1, 1);
			assert(vis_wtree_set_external(&tree, other, 1 + (uint32_t)(i % 2), tag) < 0 &&
			       errno == EEXIST && other->ext_namespace == 0);
			vis_wtree_destroy(&tree, other, NULL, NULL);
		}
	}
	assert(tree.externals.count < 2 * N + 1); /* some hashes are shared: chains exist */
	for (int i = 0; i < 2 * N; i++) {
		uint64_t tag = (uint64_t)(i / 2) * 0x100001ull + ((uint64_t)(i / 2) << 40);
		assert(vis_wtree_find_external(&tree, 1 + (uint32_t)(i % 2), tag) == w[i]);
	}
	/* Every other one alone, then top with its subtree: what is left is found, the rest not. */
	for (int i = 0; i < 2 * N; i += 2)
		if (i % 3 == 0) {
			vis_wtree_destroy(&tree, w[i], NULL, NULL);
			w[i] = NULL;
		}
	for (int i = 0; i < 2 * N; i++) {
		uint64_t tag = (uint64_t)(i / 2) * 0x100001ull + ((uint64_t)(i / 2) << 40);
		assert(vis_wtree_find_external(&tree, 1 + (uint32_t)(i % 2), tag) == w[i]);
	}
	vis_wtree_destroy(&tree, top, NULL, NULL);
	assert(vis_wtree_find_external(&tree, 1, 0x1e00003) == NULL);
	size_t left = 0;
	for (int i = 0; i < 2 * N; i++) {
		uint64_t tag = (uint64_t)(i / 2) * 0x100001ull + ((uint64_t)(i / 2) << 40);
		struct vis_window *f = vis_wtree_find_external(&tree, 1 + (uint32_t)(i % 2), tag);
		assert(f == (i % 3 == 0 && i % 2 ? w[i] : NULL));
		left += f != NULL;
	}
	/* A freed pair may be taken again. */
	struct vis_window *again = vis_wtree_create(&tree, &tree.root, 0, 0, 1, 1, 1);
	assert(vis_wtree_set_external(&tree, again, 1, 0x1e00003) == 0);
	assert(vis_wtree_find_external(&tree, 1, 0x1e00003) == again);
	assert(left > 0);
	vis_wtree_finish(&tree);
}

/*
 * test-wtree [--scale K] [--first S]: K times as many random trees of each family (default 1),
 * seeds from S on (default 1), for longer runs by hand; a failure prints the seed to rerun from.
 */
static int cmp_id(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return (x > y) - (x < y);
}

/*
 * Window IDs: the counter itself with key 0; with a key, a bijection of 1 … 2^32 − 1 (distinct and
 * never 0 over the first 2^20 and the last 2^12 numbers, and through the walk past 0), whose
 * consecutive values are not neighbours; the tree hands them out in that order.
 */
static void ids(void)
{
	enum { N = 1 << 20, TAIL = 1 << 12 };
	const uint64_t key = 0x243f6a8885a308d3ull;
	uint32_t *v = malloc((N + TAIL) * sizeof *v);
	assert(v);
	size_t near = 0;
	for (uint32_t n = 1; n <= N; n++) {
		assert(vis_wtree_id_permute(0, n) == n);
		v[n - 1] = vis_wtree_id_permute(key, n);
		near += n > 1 && (v[n - 1] - v[n - 2] < 64 || v[n - 2] - v[n - 1] < 64);
	}
	for (uint32_t k = 0; k < TAIL; k++)
		v[N + k] = vis_wtree_id_permute(key, UINT32_MAX - k);
	qsort(v, N + TAIL, sizeof *v, cmp_id);
	assert(v[0] != 0);
	for (size_t i = 1; i < N + TAIL; i++)
		assert(v[i] != v[i - 1]);
	assert(near < 64);
	free(v);
	vis_wtree_init(&tree, 100, 100);
	vis_wtree_set_id_key(&tree, key);
	for (uint32_t n = 1; n <= 100; n++) {
		struct vis_window *w = vis_wtree_create(&tree, &tree.root, 0, 0, 5, 5, 1);
		assert(w && w->id == vis_wtree_id_permute(key, n) && vis_wtree_find(&tree, w->id) == w);
	}
	vis_wtree_finish(&tree);
}

int main(int argc, char **argv)
{
	uint64_t scale = 1, first = 1;
	for (int i = 1; i < argc; i += 2) {
		char *end = NULL;
		uint64_t v = i + 1 < argc ? strtoull(argv[i + 1], &end, 10) : 0;
		if (!end || *end || !v || (strcmp(argv[i], "--scale") && strcmp(argv[i], "--first"))) {
			fprintf(stderr, "usage: test-wtree [--scale K] [--first S]\n");
			return 2;
		}
		*(strcmp(argv[i], "--scale") ? &first : &scale) = v;
	}
	for (engine = DAMAGED; engine <= LIVE; engine++) {
		scripted();
		scripted_looks();
	}
	externals();
	ids();
	int scenes = random_trees(first, 10000 * scale, 10);
	family = EXTREME;
	int extremes = random_trees(first, 20000 * scale, 10);
	family = CROWD;
	int crowds = random_trees(first, 600 * scale, 20);
	family = SMALL;
	/* Coordinates near the 32-bit limits: nesting adds offsets beyond them. */
	vis_wtree_init(&tree, 100, 100);
	struct vis_window *a = vis_wtree_create(&tree, &tree.root, -10, 0, INT32_MAX, 50, 1);
	struct vis_window *b = vis_wtree_create(&tree, a, 5, 0, INT32_MAX, 10, 1);
	struct vis_window *c = vis_wtree_create(&tree, b, 10, 2, 5, 5, 1);
	struct vis_window *d = vis_wtree_create(&tree, a, INT32_MAX - 1, 0, INT32_MAX, 5, 1);
	struct vis_window *e = vis_wtree_create(&tree, d, INT32_MIN, 0, INT32_MAX, 5, 1);
	a->mapped = b->mapped = c->mapped = d->mapped = e->mapped = true;
	assert(vis_wtree_compute(&tree) == 0);
	assert(a->state == 1 && b->state == 1 && c->state == 0 && d->state == 2 && e->state == 2);
	vis_wtree_finish(&tree);
	printf("wtree: the scripted cases and %d random trees with 10 batches of edits each agree "
	       "with X's rules, and the incremental recomputes with the full one there, on %d trees "
	       "with extreme coordinates and on %d crowds (%llu recomputes, %llu of them live, "
	       "%llu states changed)\n",
	       scenes, extremes, crowds, (unsigned long long)incremental_runs,
	       (unsigned long long)live_runs, (unsigned long long)affected_states);
	return 0;
}
