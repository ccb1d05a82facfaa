/*
 * libvis as its users call it: <vis/vis.h> alone. Thousands of seeded random trees of up to 24
 * windows, one in ten up to 64 (nested windows, borders, shapes, opaque regions, input-only
 * windows, off-screen, 1×1 and near the 32-bit limits) take random changes; after each
 * vis_tree_update() every window's state and visible region, the changes listed with their
 * exposures, and the repaint sets of random damaged boxes are held to a pixel painter
 * (libvis-painter.c) over the test's own model of the tree.
 * Bad inputs (test-libvis-bad.c) must fail with errno and change nothing.
 *
 * usage: test-libvis [--trees N] [--seed S] [--live | --through | --switch]
 * (the engine, libvis-live.c: the live engine from the first window, through the core, or tallies
 * up to a few windows; a failure prints the seed and tree to rerun with --seed S --trees 1).
 * First, a chain of 3,000 nested windows on a thread with a small stack: walks do not recurse.
 */
#include <errno.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test-libvis.h"

static uint64_t rng_state;

uint64_t tl_rand(void)
{
	uint64_t x = rng_state;
	x ^= x << 13;
	x ^= x >> 7;
	x ^= x << 17;
	return rng_state = x;
}

int64_t tl_range(int64_t lo, int64_t hi)
{
	return lo + (int64_t)(tl_rand() % (uint64_t)(hi - lo + 1));
}

static uint64_t seed_now;
static unsigned long checks;

void tl_fail(const char *what, long a, long b)
{
	fprintf(stderr, "test-libvis: seed %" PRIu64 ": %s (%ld, %ld)\n", seed_now, what, a, b);
	exit(1);
}

void tl_check(bool ok, const char *what)
{
	checks++;
	if (!ok)
		tl_fail(what, 0, 0);
}

/* A coordinate: mostly around the screen, sometimes near the 32-bit limits. */
static int32_t coord(int32_t span)
{
	int64_t r = tl_range(0, 99);
	if (r < 4)
		return (int32_t)tl_range(INT32_MIN, INT32_MIN + 40);
	if (r < 8)
		return (int32_t)tl_range(INT32_MAX - 40, INT32_MAX);
	if (r < 20)
		return (int32_t)tl_range(-10, span + 4);
	return (int32_t)tl_range(-2, span * 2 / 3);
}

/* A size: mostly a screen's, sometimes 1, sometimes huge. */
static int32_t size(int32_t span)
{
	int64_t r = tl_range(0, 99);
	if (r < 8)
		return 1;
	if (r < 10)
		return (int32_t)tl_range(INT32_MAX - 100, INT32_MAX);
	return (int32_t)tl_range(1, span / 2 + 1);
}

/* A border the size allows: mostly none or a few pixels, sometimes the most there is. */
static int32_t border(int32_t w, int32_t h)
{
	int64_t most = (INT32_MAX - (int64_t)(w > h ? w : h)) / 2, r = tl_range(0, 99);
	if (r < 60)
		return 0;
	if (r < 95)
		return (int32_t)(most < 3 ? most : tl_range(1, 3));
	return (int32_t)most;
}

/* Random rectangles for a look of window m, around its border box. */
static uint32_t rects(const struct pm_win *m, struct vis_rect32 *r)
{
	uint32_t n = (uint32_t)tl_range(0, PM_RECTS);
	int64_t w = m->w < 40 ? m->w : 40, h = m->h < 40 ? m->h : 40, b = m->border < 3 ? m->border : 3;
	for (uint32_t k = 0; k < n; k++) {
		r[k].x = (int32_t)tl_range(-b - 2, w + b);
		r[k].y = (int32_t)tl_range(-b - 2, h + b);
		r[k].width = (uint32_t)(tl_range(0, 9) ? tl_range(1, w + 4) : INT32_MAX);
		r[k].height = (uint32_t)(tl_range(0, 9) ? tl_range(1, h + 4) : INT32_MAX);
	}
	return n;
}

/* A live window's slot at random (0: none yet), or the screen too with screen. */
static int any_window(const struct pm_tree *t, bool screen)
{
	int alive[PM_MAX + 1], n = 0;
	if (screen)
		alive[n++] = 0;
	for (int i = 1; i <= PM_MAX; i++)
		if (t->w[i].alive)
			alive[n++] = i;
	return n ? alive[tl_range(0, n - 1)] : 0;
}

static void forget(struct pm_tree *t, int i)
{
	for (int k = 0; k < t->w[i].n_kids; k++)
		forget(t, t->w[i].kids[k]);
	free(t->w[i].base);
	memset(&t->w[i], 0, sizeof t->w[i]);
}

static void unlink_kid(struct pm_tree *t, int i)
{
	struct pm_win *p = &t->w[t->w[i].parent];
	int k = 0;
	while (p->kids[k] != i)
		k++;
	memmove(&p->kids[k], &p->kids[k + 1], (size_t)(p->n_kids - k - 1) * sizeof *p->kids);
	p->n_kids--;
}

static void put_kid(struct pm_tree *t, int i, int parent, int at)
{
	struct pm_win *p = &t->w[parent];
	memmove(&p->kids[at + 1], &p->kids[at], (size_t)(p->n_kids - at) * sizeof *p->kids);
	p->kids[at] = i;
	p->n_kids++;
	t->w[i].parent = parent;
}

static int kid_index(const struct pm_tree *t, int i)
{
	const struct pm_win *p = &t->w[t->w[i].parent];
	int k = 0;
	while (p->kids[k] != i)
		k++;
	return k;
}

static void must(int rc, const char *what)
{
	if (rc != 0)
		tl_fail(what, rc, errno);
}

static void op_create(struct tl *c)
{
	struct pm_tree *t = &c->t;
	int i = 1;
	while (i <= t->max && t->w[i].alive)
		i++;
	if (i > t->max)
		return;
	int parent = c->flat || tl_range(0, 1) ? 0 : any_window(t, false); /* half top-level */
	struct pm_win *m = &t->w[i];
	*m = (struct pm_win){ .alive = true, .input_only = tl_range(0, 9) == 0 };
	t->dirty = true;
	m->x = coord(t->sw);
	m->y = coord(t->sh);
	m->w = size(t->sw);
	m->h = size(t->sh);
	m->border = m->input_only ? 0 : border(m->w, m->h);
	m->state = VIS_VISIBILITY_NONE;
	m->win = vis_win_create(c->vt, parent ? t->w[parent].win : NULL, m->x, m->y, m->w, m->h,
				m->border, m->input_only ? VIS_WIN_INPUT_ONLY : 0);
	if (!m->win)
		tl_fail("create failed", i, errno);
	must(vis_win_set_data(m->win, (void *)(intptr_t)i), "set-data");
	put_kid(t, i, parent, t->w[parent].n_kids);
	if (tl_range(0, 4)) {
		m->mapped = true;
		must(vis_win_map(m->win), "map");
	}
}

/* One random change, made to libvis and to the model alike. */
static void change(struct tl *c)
{
	struct pm_tree *t = &c->t;
	int i = any_window(t, false), op = (int)tl_range(0, 13);
	if (c->flat && tl_range(0, 1))
		op = 5;
	if (!i || op == 0) {
		op_create(c);
		return;
	}
	struct pm_win *m = &t->w[i];
	/* Each change to the tree makes it dirty; tracking and what this test leaves out do not. */
	bool dirty = t->dirty;
	t->dirty = true;
	switch (op) {
	case 1:
		vis_win_destroy(m->win);
		unlink_kid(t, i);
		forget(t, i);
		break;
	case 2:
		m->mapped = !m->mapped;
		must(m->mapped ? vis_win_map(m->win) : vis_win_unmap(m->win), "map/unmap");
		break;
	case 3:
	case 4: {
		int32_t w = tl_range(0, 1) ? m->w : size(t->sw), h = tl_range(0, 1) ? m->h : size(t->sh);
		int32_t b = m->input_only ? 0 : tl_range(0, 1) ? m->border : border(w, h);
		if ((int64_t)w + 2 * (int64_t)b > INT32_MAX || (int64_t)h + 2 * (int64_t)b > INT32_MAX)
			b = 0;
		m->x = coord(t->sw);
		m->y = coord(t->sh);
		if ((w != m->w || h != m->h || b != m->border) && m->tracked)
			m->n_base = 0; /* ForgetGravity */
		m->w = w;
		m->h = h;
		m->border = b;
		must(vis_win_configure(m->win, m->x, m->y, w, h, b), "configure");
		break;
	}
	case 5:
		/* Across the screen, or a drag of a few pixels, where its boxes before and after
		 * overlap. */
		m->x += (int32_t)tl_range(-5, 5) * (m->x > -1000000 && m->x < 1000000);
		if (tl_range(0, 1) && m->y > -1000000 && m->y < 1000000)
			m->y += (int32_t)tl_range(-5, 5);
		else
			m->y = coord(t->sh);
		must(vis_win_move(m->win, m->x, m->y), "move");
		break;
	case 6: {
		int p = m->parent;
		unlink_kid(t, i);
		bool raise = tl_range(0, 1);
		put_kid(t, i, p, raise ? t->w[p].n_kids : 0);
		must(raise ? vis_win_raise(m->win) : vis_win_lower(m->win), "raise/lower");
		break;
	}
	case 7: {
		int p = m->parent;
		if (t->w[p].n_kids < 2) {
			t->dirty = dirty;
			break;
		}
		int s = i;
		while (s == i)
			s = t->w[p].kids[tl_range(0, t->w[p].n_kids - 1)];
		bool above = tl_range(0, 1);
		unlink_kid(t, i);
		put_kid(t, i, p, kid_index(t, s) + above);
		must(vis_win_restack(m->win, t->w[s].win, above), "restack");
		break;
	}
	case 8: {
		int p = c->flat || tl_range(0, 1) ? 0 : any_window(t, false);
		if (pm_is_ancestor(t, i, p)) {
			t->dirty = dirty;
			break;
		}
		unlink_kid(t, i);
		put_kid(t, i, p, t->w[p].n_kids);
		m->x = coord(t->sw);
		m->y = coord(t->sh);
		must(vis_win_reparent(m->win, p ? t->w[p].win : NULL, m->x, m->y), "reparent");
		break;
	}
	case 9:
	case 10:
		if (m->input_only || !c->looks) {
			t->dirty = dirty;
			break;
		}
		m->shaped = tl_range(0, 3) != 0;
		m->n_shape = m->shaped ? rects(m, m->shape) : 0;
		must(vis_win_set_shape(m->win, m->shaped, m->shape, m->n_shape), "set-shape");
		break;
	case 11:
		if (m->input_only || !c->looks) {
			t->dirty = dirty;
			break;
		}
		m->opaque = (uint32_t)tl_range(0, 2);
		m->n_opq = m->opaque == VIS_OPAQUE_MODE_RECTS ? rects(m, m->opq) : 0;
		must(vis_win_set_opaque(m->win, m->opaque, m->opq, m->n_opq), "set-opaque");
		break;
	case 12:
		/* What it shows now is known only on a tree as the last update left it. */
		t->dirty = dirty;
		m->n_base = 0;
		if (!m->tracked && !dirty)
			tl_baseline(c, i);
		m->tracked = !m->tracked;
		must(vis_win_track_exposure(m->win, m->tracked), "track");
		break;
	default:
		t->dirty = dirty; /* unless a window is created: the tree may be full */
		op_create(c);
		break;
	}
}

/* One tree: changes, an update and the checks, again and again. */
static void one_tree(enum tl_engine engine, bool bad)
{
	struct tl c = { 0 };
	c.t.sw = (int32_t)(tl_range(0, 9) ? tl_range(8, 40) : tl_range(1, 8));
	c.t.sh = (int32_t)(tl_range(0, 9) ? tl_range(8, 28) : tl_range(1, 8));
	c.looks = tl_range(0, 2) != 0;
	c.flat = tl_range(0, 3) == 0;
	c.vt = vis_tree_create(c.t.sw, c.t.sh);
	if (!c.vt)
		tl_fail("vis_tree_create", c.t.sw, c.t.sh);
	tl_engine(c.vt, engine);
	int32_t sw, sh;
	must(vis_tree_screen(c.vt, &sw, &sh), "screen");
	tl_check(sw == c.t.sw && sh == c.t.sh, "screen size");
	/* A tree to start from, its windows nested at random, then rounds of a few changes. */
	c.t.max = tl_range(0, 9) ? 24 : PM_MAX; /* now and then a crowd */
	for (int k = (int)tl_range(1, c.t.max); k > 0; k--)
		op_create(&c);
	int rounds = (int)tl_range(1, 12);
	for (int r = 0; r < rounds; r++) {
		int n = (int)tl_range(1, 4);
		for (int k = 0; k < n; k++)
			change(&c);
		tl_update_and_check(&c);
		if (bad && r == rounds - 1)
			tl_bad_inputs(&c);
	}
	for (int i = 1; i <= PM_MAX; i++)
		free(c.t.w[i].base);
	vis_tree_destroy(c.vt);
}

/*
 * A chain of windows, each inside the last, as deep as the tree: updates and repaints walk it
 * without recursion, on a thread whose stack (128 KiB) a walk recursing once a window would
 * overflow many times over. With tallies (the hook's engine) and without.
 */
#define CHAIN 3000

static void *chain(void *arg)
{
	enum tl_engine engine = *(enum tl_engine *)arg;
	struct vis_tree *t = vis_tree_create(640, 480);
	tl_check(t != NULL, "chain: a tree");
	tl_engine(t, engine);
	struct vis_win *w = NULL;
	for (int i = 0; i < CHAIN; i++) {
		int step = i % 1000 == 0; /* a pixel now and then: edges to walk past */
		w = vis_win_create(t, w, step, step, 600, 400, step, 0);
		tl_check(w && vis_win_map(w) == 0, "chain: a window");
	}
	const struct vis_change *changes;
	const struct vis_repaint *out;
	size_t n;
	struct vis_rect32 d = { 0, 0, 640, 480 };
	for (int round = 0; round < 3; round++) {
		tl_check(vis_tree_update(t, &changes, &n) == 0, "chain: an update");
		tl_check(vis_tree_repaint(t, &d, &out, &n) == 0, "chain: a repaint");
		/* The innermost window hides its ancestors but for their borders and edges. */
		tl_check(n >= 1 && out[n - 1].win == w, "chain: the innermost window on top");
		tl_check(vis_win_state(w) == VIS_VISIBILITY_UNOBSCURED ||
				 vis_win_state(w) == VIS_VISIBILITY_PARTIALLY_OBSCURED,
			 "chain: the innermost window seen");
		vis_win_move(w, round, round);
	}
	vis_tree_destroy(t);
	return NULL;
}

static void deep_chain(enum tl_engine engine)
{
	pthread_attr_t attr;
	pthread_t thread;
	if (pthread_attr_init(&attr) != 0 || pthread_attr_setstacksize(&attr, 128 * 1024) != 0 ||
	    pthread_create(&thread, &attr, chain, &engine) != 0 || pthread_join(thread, NULL) != 0)
		tl_fail("chain: a thread", 0, 0);
	pthread_attr_destroy(&attr);
}

int main(int argc, char **argv)
{
	long trees = 3000;
	uint64_t seed = 1;
	enum tl_engine engine = TL_TALLY;
	static const char *const names[] = { "", " (live)", " (through the core)",
					     " (switching)" };
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--trees") && i + 1 < argc)
			trees = strtol(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
			seed = strtoull(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--live"))
			engine = TL_LIVE;
		else if (!strcmp(argv[i], "--through"))
			engine = TL_THROUGH;
		else if (!strcmp(argv[i], "--switch"))
			engine = TL_SWITCH;
		else {
			fprintf(stderr, "usage: test-libvis [--trees N] [--seed S] "
					"[--live | --through | --switch]\n");
			return 2;
		}
	}
	deep_chain(engine);
	for (long k = 0; k < trees; k++) {
		seed_now = seed + (uint64_t)k;
		rng_state = seed_now * 0x9e3779b97f4a7c15ull | 1;
		one_tree(engine, k % 8 == 0);
	}
	printf("test-libvis: %ld trees from seed %" PRIu64 "%s, %lu checks passed\n", trees, seed,
	       names[engine], checks);
	return 0;
}
