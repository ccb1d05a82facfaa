/* Unit test of the window tree: random trees and edits against X's rules applied pixel by pixel. */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <pixman.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rng.h"
#include "wtree.h"

#define SW 16
#define SH 12
#define MAXW 14

static struct vis_wtree tree;
static struct vis_window *wins[MAXW * 4];
static int nwins;

/* Whether pixel (px, py) of the screen is inside w and every ancestor of it, and the screen. */
static int inside_chain(const struct vis_window *w, int64_t px, int64_t py)
{
	if (px < 0 || py < 0 || px >= SW || py >= SH)
		return 0;
	for (; w->parent; w = w->parent) {
		int64_t ax = 0, ay = 0;
		for (const struct vis_window *a = w; a->parent; a = a->parent)
			ax += a->x, ay += a->y;
		if (px < ax || py < ay || px >= ax + w->width || py >= ay + w->height)
			return 0;
	}
	return 1;
}

static int viewable(const struct vis_window *w)
{
	for (; w->parent; w = w->parent)
		if (!w->mapped)
			return 0;
	return 1;
}

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

/* Whether pixel p of the screen shows q (own: q's own pixels, not its descendants'). */
static int shows(const struct vis_window *q, int64_t px, int64_t py, int own)
{
	if (!inside_chain(q, px, py))
		return 0;
	for (int i = 0; i < nwins; i++) {
		const struct vis_window *w = wins[i];
		if (w && viewable(w) && obscures(w, q, own) && inside_chain(w, px, py))
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
		if (!viewable(q)) {
			assert(q->state == VIS_WTREE_STATE_NONE);
			continue;
		}
		int64_t ax = 0, ay = 0;
		for (const struct vis_window *a = q; a->parent; a = a->parent)
			ax += a->x, ay += a->y;
		long seen = 0, all = 0;
		pixman_region32_t reg;
		pixman_region32_init(&reg);
		assert(vis_wtree_visible_region(&tree, q, &reg) == 0);
		for (int64_t y = ay; y < ay + q->height; y++)
			for (int64_t x = ax; x < ax + q->width; x++) {
				all++;
				seen += shows(q, x, y, 0);
				int own = shows(q, x, y, 1);
				int in = pixman_region32_contains_point(&reg, (int)(x - ax),
									(int)(y - ay), NULL);
				if (own != in) {
					fprintf(stderr, "seed %llu: window %u pixel %lld,%lld own %d "
							"region %d\n",
						(unsigned long long)seed, q->id, (long long)x,
						(long long)y, own, in);
					exit(1);
				}
			}
		pixman_region32_fini(&reg);
		int want = seen == all ? 0 : seen ? 1 : 2;
		if (q->state != want) {
			fprintf(stderr, "seed %llu: window %u (depth %u) state %d, X says %d\n",
				(unsigned long long)seed, q->id, q->depth, q->state, want);
			exit(1);
		}
	}
	/* Repaint of the whole screen: the windows showing own pixels. */
	struct vis_window *out[MAXW * 4];
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

static struct vis_window *pick(struct vis_rng *r)
{
	int live = 0;
	for (int i = 0; i < nwins; i++)
		live += wins[i] != NULL;
	if (!live)
		return NULL;
	int k = (int)vis_rng_below(r, (uint64_t)live);
	for (int i = 0; i < nwins; i++)
		if (wins[i] && k-- == 0)
			return wins[i];
	return NULL;
}

static void forget(void *data, struct vis_window *w)
{
	(void)data;
	for (int i = 0; i < nwins; i++)
		if (wins[i] == w)
			wins[i] = NULL;
}

int main(void)
{
	int scenes = 0;
	for (uint64_t seed = 1; seed <= 3000; seed++) {
		struct vis_rng r;
		r.state = seed;
		vis_wtree_init(&tree, SW, SH);
		nwins = 0;
		int n = 1 + (int)vis_rng_below(&r, MAXW);
		for (int i = 0; i < n; i++) {
			struct vis_window *p = vis_rng_below(&r, 3) ? pick(&r) : NULL;
			if (!p)
				p = &tree.root;
			struct vis_window *w = vis_wtree_create(
				&tree, p, (int32_t)vis_rng_below(&r, 20) - 4, (int32_t)vis_rng_below(&r, 16) - 4,
				1 + (int32_t)vis_rng_below(&r, 12), 1 + (int32_t)vis_rng_below(&r, 10), 1);
			w->mapped = vis_rng_below(&r, 6) != 0;
			wins[nwins++] = w;
		}
		check(seed);
		/* Edits, each followed by a check: restack, raise, lower, reparent, move, destroy. */
		for (int e = 0; e < 6; e++) {
			struct vis_window *w = pick(&r);
			if (!w)
				break;
			switch (vis_rng_below(&r, 7)) {
			case 0:
				if (w->parent->bottom != w)
					vis_wtree_restack(w, w->parent->bottom, vis_rng_below(&r, 2));
				break;
			case 1:
				vis_wtree_raise(w);
				break;
			case 2:
				vis_wtree_lower(w);
				break;
			case 3: {
				struct vis_window *p = pick(&r);
				if (!p || vis_wtree_is_ancestor(w, p))
					p = &tree.root;
				vis_wtree_reparent(w, p, (int32_t)vis_rng_below(&r, 10) - 2, 1);
				break;
			}
			case 4:
				w->x += (int32_t)vis_rng_below(&r, 5) - 2;
				break;
			case 5:
				w->mapped = !w->mapped;
				break;
			default:
				vis_wtree_destroy(&tree, w, forget, NULL);
			}
			check(seed);
		}
		vis_wtree_finish(&tree);
		scenes++;
	}
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
	printf("wtree: %d random trees with 6 edits each agree with X's rules\n", scenes);
	return 0;
}
