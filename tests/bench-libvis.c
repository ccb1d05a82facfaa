/*
 * What a compositor pays a frame: one change (a window moved by up to 64 pixels each way) and the
 * repaint set of the damage it made (the hull of the window's box before and after, on the
 * screen), in process. libvis (vis_win_move, vis_tree_update, vis_tree_repaint) side by side
 * with the region method compositors use today (wlroots' scene, weston): each window keeps its
 * visible region; a change recomputes it, from the top window down, for the windows that meet
 * the damage (their pixels there less the opaque pixels of those above), and the frame's repaint
 * set is then each visible region in the damage, pixman regions throughout. A last column times
 * the repaint set alone by the region method stopped once opaque windows cover the damage, which
 * the compositors do not take. Both take the same changes, alternating op by op; generated
 * scenes (src/gen.h) as top-level windows on the 3840×2160 screen, looks kept (the translucent
 * kind's client-side shadows are opaque regions). Prints a markdown table of the medians per
 * op (libvis's whole op, and its repaint query alone, asked again after it: no clock is read
 * inside a frame). Not a test: run it from a release build,
 *   build-release/tests/bench-libvis [--kinds K,…] [--sizes N,…] [--moves M] [--seed S]
 * or `meson test -C build-release --benchmark bench-libvis`.
 *
 * With --viscomp WxH, libvis's side is viscomp's model (compositor/model.h) of a W×H output: the
 * scenes generated on that output, in a tree whose screen is the model's 16384×16384, under
 * the outside window that covers what the output does not show; the damage lies on the output,
 * as viscomp's does. The region method needs no outside: it keeps the windows on the output.
 */
#include <pixman.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <vis/vis.h>

#include "bench-time.h"
#include "family.h"
#include "gen.h"
#include "libvis-private.h"
#include "rng.h"

static void die(const char *what)
{
	fprintf(stderr, "bench-libvis: %s\n", what);
	exit(1);
}

/* A rectangle list of the scene's as pixman boxes, moved by x, y. */
static void region_of(pixman_region32_t *r, const struct vis_rect *rects, uint32_t n, int64_t x,
		      int64_t y)
{
	pixman_region32_init(r);
	for (uint32_t k = 0; k < n; k++)
		pixman_region32_union_rect(r, r, (int32_t)(x + rects[k].x), (int32_t)(y + rects[k].y),
					   (unsigned)rects[k].w, (unsigned)rects[k].h);
}

/*
 * The region method's windows: their pixels, opaque pixels and visible pixels (what a compositor
 * keeps to know which windows it can see), in screen coordinates.
 */
struct method {
	size_t n;
	pixman_region32_t *own, *opaque, *visible;
	pixman_region32_t above, part, damage;
};

static void method_init(struct method *m, const struct vis_scene *s)
{
	m->n = s->n;
	m->own = calloc(s->n, sizeof *m->own);
	m->opaque = calloc(s->n, sizeof *m->opaque);
	m->visible = calloc(s->n, sizeof *m->visible);
	if (!m->own || !m->opaque || !m->visible)
		die("out of memory");
	for (size_t i = 0; i < s->n; i++) {
		const struct vis_look *l = s->looks ? &s->looks[i] : NULL;
		struct vis_rect r = s->rects[i];
		int64_t b = l ? l->border : 0, ix = (int64_t)r.x + b, iy = (int64_t)r.y + b;
		struct vis_rect box = { r.x, r.y, (int32_t)(r.w + 2 * b), (int32_t)(r.h + 2 * b) };
		region_of(&m->own[i], &box, l && l->input_only ? 0 : 1, 0, 0);
		if (l && l->shaped) {
			pixman_region32_t shape;
			region_of(&shape, l->shape, l->n_shape, ix, iy);
			pixman_region32_intersect(&m->own[i], &m->own[i], &shape);
			pixman_region32_fini(&shape);
		}
		if (l && l->opaque == VIS_OPAQUE_RECTS) {
			region_of(&m->opaque[i], l->opaque_rects, l->n_opaque, ix, iy);
			pixman_region32_intersect(&m->opaque[i], &m->opaque[i], &m->own[i]);
		} else {
			pixman_region32_init(&m->opaque[i]);
			if (!l || l->opaque == VIS_OPAQUE_ALL)
				pixman_region32_copy(&m->opaque[i], &m->own[i]);
		}
	}
	pixman_region32_init(&m->above);
	pixman_region32_init(&m->part);
	pixman_region32_init(&m->damage);
	for (size_t i = m->n; i-- > 0;) {
		pixman_region32_init(&m->visible[i]);
		pixman_region32_intersect_rect(&m->visible[i], &m->own[i], 0, 0,
					       (unsigned)s->screen_w, (unsigned)s->screen_h);
		pixman_region32_subtract(&m->visible[i], &m->visible[i], &m->above);
		pixman_region32_union(&m->above, &m->above, &m->opaque[i]);
	}
}

/*
 * One change under the region method as wlroots' scene keeps it (scene_update_region(), 0.16 on):
 * from the top window down, each window that meets the damage gets its visible pixels there
 * anew, the damage less the opaque pixels of the windows above; returns the windows that can be
 * seen. Its repaint set is then each window's visible pixels in the damage.
 */
static size_t method_update(struct method *m, const pixman_box32_t *damage)
{
	size_t k = 0;
	pixman_region32_t *left = &m->above; /* the damage less the opaque pixels above */
	pixman_region32_fini(left);
	pixman_region32_init_rects(left, damage, 1);
	pixman_region32_fini(&m->damage);
	pixman_region32_init_rects(&m->damage, damage, 1);
	for (size_t i = m->n; i-- > 0;) {
		const pixman_box32_t *e = pixman_region32_extents(&m->own[i]);
		if (e->x1 < damage->x2 && damage->x1 < e->x2 && e->y1 < damage->y2 &&
		    damage->y1 < e->y2) {
			pixman_region32_intersect(&m->part, &m->own[i], left);
			pixman_region32_subtract(&m->visible[i], &m->visible[i], &m->damage);
			pixman_region32_union(&m->visible[i], &m->visible[i], &m->part);
			pixman_region32_subtract(left, left, &m->opaque[i]);
		}
		k += pixman_region32_not_empty(&m->visible[i]);
	}
	return k;
}

/*
 * The region method's repaint set after method_update(), as wlroots' scene renders a frame: the
 * windows that meet the damage, bottom to top, each with its visible pixels there; returns how
 * many show.
 */
static size_t method_repaint_set(struct method *m, const pixman_box32_t *damage)
{
	size_t k = 0;
	for (size_t i = 0; i < m->n; i++) {
		const pixman_box32_t *e = pixman_region32_extents(&m->visible[i]);
		if (e->x1 < damage->x2 && damage->x1 < e->x2 && e->y1 < damage->y2 &&
		    damage->y1 < e->y2) {
			pixman_region32_intersect_rect(&m->part, &m->visible[i], damage->x1,
						       damage->y1,
						       (unsigned)(damage->x2 - damage->x1),
						       (unsigned)(damage->y2 - damage->y1));
			k += pixman_region32_not_empty(&m->part);
		}
	}
	return k;
}

/*
 * The repaint set alone by the region method, stopping once opaque windows cover the damage
 * (which tells nothing of the windows below, whose frames a compositor then cannot withhold):
 * the parts of the windows in damage; returns how many.
 */
static size_t method_repaint(struct method *m, const pixman_box32_t *damage)
{
	size_t k = 0;
	pixman_region32_clear(&m->above);
	for (size_t i = m->n; i-- > 0;) {
		pixman_region32_intersect_rect(&m->part, &m->own[i], damage->x1, damage->y1,
					       (unsigned)(damage->x2 - damage->x1),
					       (unsigned)(damage->y2 - damage->y1));
		pixman_region32_subtract(&m->part, &m->part, &m->above);
		k += pixman_region32_not_empty(&m->part);
		/* Only the opaque pixels in the damage: the union of all would grow to the whole
		 * desktop's, whose copies cost more than the repaint and evict the others' data. */
		pixman_region32_intersect_rect(&m->part, &m->opaque[i], damage->x1, damage->y1,
					       (unsigned)(damage->x2 - damage->x1),
					       (unsigned)(damage->y2 - damage->y1));
		pixman_region32_union(&m->above, &m->above, &m->part);
		if (pixman_region32_contains_rectangle(&m->above, (pixman_box32_t *)damage) ==
		    PIXMAN_REGION_IN)
			break;
	}
	return k;
}

static void method_finish(struct method *m)
{
	for (size_t i = 0; i < m->n; i++) {
		pixman_region32_fini(&m->own[i]);
		pixman_region32_fini(&m->opaque[i]);
		pixman_region32_fini(&m->visible[i]);
	}
	free(m->own);
	free(m->opaque);
	free(m->visible);
	pixman_region32_fini(&m->above);
	pixman_region32_fini(&m->part);
	pixman_region32_fini(&m->damage);
}

/* --viscomp WxH: the output's size (0: no viscomp model), and the model's screen
 * (compositor/model.h's MODEL_SCREEN_SIZE). */
static int32_t viscomp_w, viscomp_h;
#define VISCOMP_SCREEN 16384

/* A look's rectangles as libvis takes them: a new array. */
static struct vis_rect32 *rects32(const struct vis_rect *r, uint32_t n)
{
	struct vis_rect32 *out = malloc((n ? n : 1) * sizeof *out);
	if (!out)
		die("out of memory");
	for (uint32_t k = 0; k < n; k++)
		out[k] = (struct vis_rect32){ r[k].x, r[k].y, (uint32_t)r[k].w, (uint32_t)r[k].h };
	return out;
}

/* The windows up to which libvis keeps tallies (--tally-below; 0: never), or SIZE_MAX: its own. */
static size_t tally_below = SIZE_MAX;

/* The scene as a libvis tree of mapped top-level windows; under --viscomp, viscomp's model: a
 * larger screen, and on top the outside, shaped as what the output does not show. */
static struct vis_tree *tree_of(const struct vis_scene *s, struct vis_win **wins)
{
	struct vis_tree *t = viscomp_w ? vis_tree_create(VISCOMP_SCREEN, VISCOMP_SCREEN)
				       : vis_tree_create(s->screen_w, s->screen_h);
	if (!t)
		die("vis_tree_create");
	if (tally_below != SIZE_MAX)
		libvis_tally_below(t, tally_below);
	for (size_t i = 0; i < s->n; i++) {
		const struct vis_look *l = s->looks ? &s->looks[i] : NULL;
		struct vis_rect r = s->rects[i];
		wins[i] = vis_win_create(t, NULL, r.x, r.y, r.w, r.h, l ? l->border : 0,
					 l && l->input_only ? VIS_WIN_INPUT_ONLY : 0);
		if (!wins[i] || vis_win_map(wins[i]) < 0)
			die("vis_win_create");
		if (l && l->shaped) {
			struct vis_rect32 *rs = rects32(l->shape, l->n_shape);
			if (vis_win_set_shape(wins[i], 1, rs, l->n_shape) < 0)
				die("vis_win_set_shape");
			free(rs);
		}
		if (l && l->opaque != VIS_OPAQUE_ALL) {
			uint32_t k = l->opaque == VIS_OPAQUE_RECTS ? l->n_opaque : 0;
			struct vis_rect32 *rs = rects32(l->opaque_rects, k);
			if (vis_win_set_opaque(wins[i], l->opaque, rs, k) < 0)
				die("vis_win_set_opaque");
			free(rs);
		}
	}
	if (viscomp_w) {
		/* As model_set_shown() makes it: the bands right of and below the output at 0, 0. */
		struct vis_rect32 outside[2] = {
			{ viscomp_w, 0, (uint32_t)(VISCOMP_SCREEN - viscomp_w), (uint32_t)viscomp_h },
			{ 0, viscomp_h, VISCOMP_SCREEN, (uint32_t)(VISCOMP_SCREEN - viscomp_h) },
		};
		struct vis_win *o = vis_win_create(t, NULL, 0, 0, VISCOMP_SCREEN, VISCOMP_SCREEN, 0, 0);
		if (!o || vis_win_map(o) < 0 || vis_win_set_shape(o, 1, outside, 2) < 0)
			die("the outside window");
	}
	const struct vis_change *c;
	size_t n;
	if (vis_tree_update(t, &c, &n) < 0)
		die("vis_tree_update");
	return t;
}

/* The medians of one scene's moves, in µs. */
struct medians {
	double lib, rep, reg, stop;
	double lib99, reg99; /* the 99th percentiles */
};

/* --each: a line for each member of the family. */
static bool each;

/* The share of changes, in percent, that raise a window instead of moving it (--raises). */
static uint64_t raises;

/* Puts the window at i on top of the scene's and the region method's stacks (libvis's is raised
 * in the timed turn); returns its new index. */
static size_t on_top(struct vis_scene *s, struct method *m, struct vis_win **wins, size_t i)
{
	size_t n = s->n, last = n - 1;
#define ROTATE(arr)                                                                     \
	do {                                                                            \
		__typeof__((arr)[0]) t = (arr)[i];                                      \
		memmove(&(arr)[i], &(arr)[i + 1], (last - i) * sizeof (arr)[0]);        \
		(arr)[last] = t;                                                        \
	} while (0)
	ROTATE(s->rects);
	if (s->looks)
		ROTATE(s->looks);
	ROTATE(m->own);
	ROTATE(m->opaque);
	ROTATE(m->visible);
	ROTATE(wins);
#undef ROTATE
	return last;
}

/* The windows below which libvis updates through the tree (--live-from), or SIZE_MAX: its own. */
static size_t live_from = SIZE_MAX;

/* Runs one scene (its screen made w × h when it has none): moves timed on libvis and the region
 * method in turn. */
static struct medians run_scene(struct vis_scene s, size_t moves, uint64_t seed)
{
	size_t n = s.n;
	if (s.screen_w < 1 || s.screen_h < 1)
		die("a scene without a screen");
	struct vis_win **wins = malloc(n * sizeof *wins);
	double *lib = malloc(moves * sizeof *lib), *reg = malloc(moves * sizeof *reg);
	double *rep = malloc(moves * sizeof *rep); /* libvis's repaint query alone */
	double *stop = malloc(moves * sizeof *stop); /* the region method's repaint alone */
	if (!wins || !lib || !reg || !rep || !stop)
		die("out of memory");
	struct vis_tree *t = tree_of(&s, wins);
	if (live_from != SIZE_MAX && vis_wtree_live_from(&t->core, live_from) < 0)
		die("vis_wtree_live_from");
	struct method m;
	method_init(&m, &s);
	struct vis_rng rng = { seed ^ 0x5bd1e995u };
	for (size_t k = 0; k < moves; k++) {
		size_t i = vis_rng_below(&rng, n);
		int32_t dx = (int32_t)vis_rng_range(&rng, -64, 64), dy = (int32_t)vis_rng_range(&rng, -64, 64);
		bool raise = vis_rng_below(&rng, 100) < raises;
		if (raise) {
			/* On top, in place: the arrays keep stacking order (a compositor's lists
			 * move a node in O(1); this is outside the timing). */
			i = on_top(&s, &m, wins, i);
			dx = dy = 0;
		}
		struct vis_rect *r = &s.rects[i];
		int64_t b = s.looks ? s.looks[i].border : 0, w = r->w + 2 * b, h = r->h + 2 * b;
		if ((int64_t)r->x + dx < INT32_MIN / 2 || (int64_t)r->x + dx > INT32_MAX / 2)
			dx = 0;
		if ((int64_t)r->y + dy < INT32_MIN / 2 || (int64_t)r->y + dy > INT32_MAX / 2)
			dy = 0;
		/* The damage: the hull of where it was and is, on the screen. */
		int64_t x1 = r->x + (dx < 0 ? dx : 0), y1 = r->y + (dy < 0 ? dy : 0);
		int64_t x2 = r->x + w + (dx > 0 ? dx : 0), y2 = r->y + h + (dy > 0 ? dy : 0);
		x1 = x1 < 0 ? 0 : x1;
		y1 = y1 < 0 ? 0 : y1;
		x2 = x2 > s.screen_w ? s.screen_w : x2;
		y2 = y2 > s.screen_h ? s.screen_h : y2;
		if (x1 >= x2 || y1 >= y2)
			x1 = y1 = 0, x2 = y2 = 1;
		r->x += dx;
		r->y += dy;
		struct vis_rect32 d = { (int32_t)x1, (int32_t)y1, (uint32_t)(x2 - x1), (uint32_t)(y2 - y1) };
		pixman_box32_t db = { (int32_t)x1, (int32_t)y1, (int32_t)x2, (int32_t)y2 };
		const struct vis_change *c;
		const struct vis_repaint *out;
		size_t nc, nr;
		pixman_region32_translate(&m.own[i], dx, dy);
		pixman_region32_translate(&m.opaque[i], dx, dy);
		/* The three in turn, each first in a third of the moves. */
		for (int turn = 0; turn < 3; turn++) {
			int which = (int)((k + (size_t)turn) % 3);
			double t0 = bench_now_us();
			if (which == 0) {
				if ((raise ? vis_win_raise(wins[i]) : vis_win_move(wins[i], r->x, r->y)) < 0 ||
				    vis_tree_update(t, &c, &nc) < 0 ||
				    vis_tree_repaint(t, &d, &out, &nr) < 0)
					die("libvis failed");
				lib[k] = bench_now_us() - t0;
				/* Its repaint query alone, asked again (it changes nothing): timed
				 * apart, so that no clock read lies inside a frame (one costs about
				 * 20 ns, a tenth of a small frame). */
				double t1 = bench_now_us();
				if (vis_tree_repaint(t, &d, &out, &nr) < 0)
					die("libvis failed");
				rep[k] = bench_now_us() - t1;
			} else if (which == 1) {
				method_update(&m, &db);
				method_repaint_set(&m, &db);
				reg[k] = bench_now_us() - t0;
			} else {
				method_repaint(&m, &db);
				stop[k] = bench_now_us() - t0;
			}
		}
	}
	qsort(lib, moves, sizeof *lib, bench_cmp_double);
	qsort(reg, moves, sizeof *reg, bench_cmp_double);
	qsort(rep, moves, sizeof *rep, bench_cmp_double);
	qsort(stop, moves, sizeof *stop, bench_cmp_double);
	struct medians med = { lib[moves / 2], rep[moves / 2], reg[moves / 2], stop[moves / 2],
			       lib[moves * 99 / 100], reg[moves * 99 / 100] };
	method_finish(&m);
	vis_tree_destroy(t);
	free(wins);
	free(lib);
	free(reg);
	free(rep);
	free(stop);
	return med;
}

/* Runs one generated scene and prints its row. */
static void run(enum vis_gen_kind kind, size_t n, size_t moves, uint64_t seed)
{
	struct vis_scene s;
	vis_scene_init(&s);
	if (vis_gen(&s, kind, n, seed, viscomp_w, viscomp_h) < 0)
		die("vis_gen");
	struct medians m = run_scene(s, moves, seed);
	printf("| %s | %zu | %.2f | %.2f | %.2f | %.2f | %.2f |\n", vis_gen_kind_name(kind), n, m.lib,
	       m.rep, m.reg, m.stop, m.reg > 0 ? m.lib / m.reg : 0);
	fflush(stdout);
	vis_scene_finish(&s);
}

static int cmp_ratio(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/*
 * Draws count members of the scene family (src/family.h: sizes, aspects, overlap, clusters,
 * cascades, lattices, shared edges, nobody tuned libvis for them), n log-uniform in
 * [min_n, max_n], each on its area as the screen, and prints the distribution of libvis's
 * median over the region method's, with the worst member.
 */
static void run_family(size_t count, size_t min_n, size_t max_n, size_t moves, uint64_t seed,
		       size_t only)
{
	double *ratio = malloc((count ? count : 1) * sizeof *ratio);
	double *tail = malloc((count ? count : 1) * sizeof *tail);
	if (!ratio || !tail)
		die("out of memory");
	struct vis_rng rng = { seed };
	double worst = -1;
	char worst_desc[512] = "";
	for (size_t k = 0; k < count; k++) {
		struct vis_family f;
		vis_family_draw(&rng, min_n, max_n, &f);
		struct vis_scene s;
		vis_scene_init(&s);
		uint64_t scene_seed = seed * 1000003u + k;
		if (only != SIZE_MAX && k != only) {
			ratio[k] = tail[k] = 0;
			continue;
		}
		if (vis_family_gen(&s, &f, scene_seed) < 0)
			die("vis_family_gen");
		s.screen_w = f.w;
		s.screen_h = f.h;
		struct medians m = run_scene(s, moves, scene_seed);
		ratio[k] = m.reg > 0 ? m.lib / m.reg : 0;
		tail[k] = m.reg99 > 0 ? m.lib99 / m.reg99 : 0;
		if (each) {
			char desc[400];
			if (vis_family_describe(&f, desc, sizeof desc) < 0)
				desc[0] = 0;
			printf("scene %zu: %s: libvis %.2f µs, region %.2f µs, ratio %.2f, p99 ratio %.2f\n",
			       k, desc, m.lib, m.reg, ratio[k], tail[k]);
		}
		if (ratio[k] > worst) {
			worst = ratio[k];
			int len = snprintf(worst_desc, sizeof worst_desc, "scene %zu: ", k);
			len = len < 0 || (size_t)len >= sizeof worst_desc ? 0 : len;
			int more = vis_family_describe(&f, worst_desc + len, sizeof worst_desc - (size_t)len);
			len += more < 0 ? 0 : more;
			len = (size_t)len >= sizeof worst_desc ? (int)sizeof worst_desc - 1 : len;
			snprintf(worst_desc + len, sizeof worst_desc - (size_t)len,
				 " (libvis %.2f µs, region %.2f µs)", m.lib, m.reg);
		}
		vis_scene_finish(&s);
	}
	qsort(ratio, count, sizeof *ratio, cmp_ratio);
	qsort(tail, count, sizeof *tail, cmp_ratio);
	size_t over1 = 0, over2 = 0;
	for (size_t k = 0; k < count; k++)
		over1 += ratio[k] > 1, over2 += ratio[k] > 2;
	printf("family seed %llu, %zu scenes, n %zu..%zu, %zu moves each: libvis / region method "
	       "median %.2f, p95 %.2f, worst %.2f; %zu scenes above 1, %zu above 2\n"
	       "their 99th percentiles: median %.2f, p95 %.2f, worst %.2f\n"
	       "worst: %s\n",
	       (unsigned long long)seed, count, min_n, max_n, moves, ratio[count / 2],
	       ratio[count * 95 / 100 < count ? count * 95 / 100 : count - 1], ratio[count - 1],
	       over1, over2, tail[count / 2],
	       tail[count * 95 / 100 < count ? count * 95 / 100 : count - 1], tail[count - 1],
	       worst_desc);
	free(ratio);
	free(tail);
}

int main(int argc, char **argv)
{
	const char *kinds = "random,tiles,cascade,translucent", *sizes = "10,100,1000,10000";
	size_t moves = 2000, family = 0, min_n = 10, max_n = 10000, only = SIZE_MAX;
	uint64_t seed = 1;
	for (int i = 1; i < argc; i++) {
		if (!strcmp(argv[i], "--kinds") && i + 1 < argc)
			kinds = argv[++i];
		else if (!strcmp(argv[i], "--sizes") && i + 1 < argc)
			sizes = argv[++i];
		else if (!strcmp(argv[i], "--moves") && i + 1 < argc)
			moves = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--seed") && i + 1 < argc)
			seed = strtoull(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--family") && i + 1 < argc)
			family = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--min-n") && i + 1 < argc)
			min_n = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--max-n") && i + 1 < argc)
			max_n = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--only") && i + 1 < argc)
			only = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--live-from") && i + 1 < argc)
			live_from = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--tally-below") && i + 1 < argc)
			tally_below = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--each"))
			each = true;
		else if (!strcmp(argv[i], "--raises") && i + 1 < argc)
			raises = strtoul(argv[++i], NULL, 10);
		else if (!strcmp(argv[i], "--viscomp") && i + 1 < argc) {
			if (sscanf(argv[++i], "%dx%d", &viscomp_w, &viscomp_h) != 2 || viscomp_w < 1 ||
			    viscomp_h < 1 || viscomp_w >= VISCOMP_SCREEN || viscomp_h >= VISCOMP_SCREEN)
				die("--viscomp WxH: an output of 1 … 16383 pixels a side");
		}
		else
			die("usage: bench-libvis [--kinds K,...] [--sizes N,...] [--moves M] [--seed S]\n"
			    "       bench-libvis --family COUNT [--min-n N] [--max-n N] [--moves M] "
			    "[--seed S] [--only K] [--each]\n       (either also [--live-from N] [--tally-below N] [--raises PERCENT]; the first also "
			    "[--viscomp WxH])");
	}
	if (moves < 1)
		die("--moves must be at least 1");
	if (family) {
		if (viscomp_w)
			die("--viscomp: not with --family");
		if (min_n < 1 || max_n < min_n)
			die("--min-n must be at least 1 and at most --max-n");
		run_family(family, min_n, max_n, moves, seed, only);
		return 0;
	}
	printf("| kind | windows | libvis µs | of which repaint µs | region method µs | "
	       "its repaint alone, early stop µs | ratio |\n"
	       "|---|---|---|---|---|---|---|\n");
	char kbuf[256];
	snprintf(kbuf, sizeof kbuf, "%s", kinds);
	for (char *ks = NULL, *k = strtok_r(kbuf, ",", &ks); k; k = strtok_r(NULL, ",", &ks)) {
		enum vis_gen_kind kind;
		if (vis_gen_kind_from_name(k, &kind) < 0)
			die("unknown kind");
		char sbuf[256];
		snprintf(sbuf, sizeof sbuf, "%s", sizes);
		for (char *ss = NULL, *n = strtok_r(sbuf, ",", &ss); n; n = strtok_r(NULL, ",", &ss))
			run(kind, strtoul(n, NULL, 10), moves, seed);
	}
	return 0;
}
