/*
 * The cost of one recompute of the window tree after a single change, as the daemon pays it after
 * a client's request: a generated scene as top-level windows on the 3840×2160 screen (uniform's
 * on a screen of 1,100,000 × 1,100,000, the space its rectangles fill), then random
 * changes of one kind (a move of up to 64 pixels each way, a raise, a lower, an unmap, a map),
 * each followed by a recompute that is timed alone: in full (vis_wtree_compute), from the
 * change's damage (vis_wtree_compute_damaged, the window's box before and after) and live from
 * the notes (vis_wtree_update). The changed window is any window, or the top one (a drag). The
 * shaped and translucent kinds keep their looks (borders, shapes, opaque regions). Prints the
 * median, the 99th percentile and the mean per change; --svg also draws the medians of the first
 * op against n, log-log, one panel per kind (bench-wtree-svg.c), with TEXT from --note under the
 * title (say where the machine was shared). Not a test: run it from a release build,
 *   build-release/tests/bench-wtree [--kinds K,…] [--sizes N,…] [--ops O,…] [--engines E,…]
 *                                   [--moves M] [--seed S] [--svg FILE] [--note TEXT]
 * (ops: move, raise, lower, unmap, map; engines: full, damaged, live) or
 * `meson test -C build-release --benchmark`.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench-time.h"
#include "bench-wtree.h"
#include "rng.h"
#include "wtree.h"

static const char *const op_names[] = { "move", "raise", "lower", "unmap", "map" };
static const char *const engine_names[] = { "full", "damaged", "live" };

/* Recomputes the tree with the engine, from the damage (n boxes) or the notes. */
static int recompute(struct vis_wtree *tree, enum engine engine, const struct vis_box *damage,
		     size_t n)
{
	switch (engine) {
	case FULL:
		return vis_wtree_compute(tree);
	case DAMAGED:
		return vis_wtree_compute_damaged(tree, damage, n);
	default:
		return vis_wtree_update(tree);
	}
}

/* Makes one change of window w, noted and with its damage in damage[*n]. */
static void change(struct vis_wtree *tree, struct vis_window *w, enum op op, struct vis_rng *rng,
		   struct vis_box *damage, size_t *n)
{
	*n = 0;
	if (op == MOVE) {
		int32_t dx = (int32_t)vis_rng_below(rng, 129) - 64;
		int32_t dy = (int32_t)vis_rng_below(rng, 129) - 64;
		/* Stay inside the 32-bit range: generated windows may sit at its edge. */
		if ((dx > 0 && w->x > INT32_MAX - dx) || (dx < 0 && w->x < INT32_MIN - dx))
			dx = -dx;
		if ((dy > 0 && w->y > INT32_MAX - dy) || (dy < 0 && w->y < INT32_MIN - dy))
			dy = -dy;
		damage[(*n)++] = vis_wtree_box(w);
		vis_wtree_note(tree, w);
		w->x += dx;
		w->y += dy;
	} else if (op == RAISE) {
		vis_wtree_raise(w);
	} else if (op == LOWER) {
		vis_wtree_lower(w);
	} else {
		w->mapped = op == MAP;
	}
	damage[(*n)++] = vis_wtree_box(w);
	vis_wtree_note(tree, w);
}

/* Times `moves` recomputes, each after one change; fills the sorted times (µs). */
static int run(const struct vis_scene *scene, enum who who, enum op op, enum engine engine,
	       size_t moves, uint64_t seed, double *us)
{
	struct vis_wtree tree;
	/* A scene with a screen of its own (uniform's space, grid's box) is put on that screen. */
	vis_wtree_init(&tree, scene->has_screen ? scene->screen_w : VIS_GEN_SCREEN_W,
		       scene->has_screen ? scene->screen_h : VIS_GEN_SCREEN_H);
	struct vis_window **wins = malloc((scene->n ? scene->n : 1) * sizeof *wins);
	if (!wins)
		return -1;
	for (size_t i = 0; i < scene->n; i++) {
		struct vis_rect r = scene->rects[i];
		wins[i] = vis_wtree_create(&tree, &tree.root, r.x, r.y, r.w, r.h, 1);
		if (!wins[i])
			return -1;
		wins[i]->mapped = true;
		/* The shaped and translucent kinds give windows looks. */
		const struct vis_look *l = scene->looks ? &scene->looks[i] : NULL;
		if (l && l->input_only)
			vis_wtree_set_input_only(wins[i]);
		else if (l && (vis_wtree_set_border(wins[i], l->border) < 0 ||
			       vis_wtree_set_shape(wins[i], l->shaped, l->shape, l->n_shape) < 0 ||
			       vis_wtree_set_opaque(wins[i], (enum vis_opaque)l->opaque,
						    l->opaque_rects, l->n_opaque) < 0))
			return -1;
	}
	/* The first update goes through the tree and builds the live structures. */
	if (vis_wtree_compute(&tree) < 0 || vis_wtree_update(&tree) < 0)
		return -1;
	struct vis_rng rng = { seed };
	struct vis_box damage[2];
	size_t n;
	for (size_t k = 0; k < moves; k++) {
		struct vis_window *w = who == TOP ? tree.root.top
						  : wins[vis_rng_below(&rng, scene->n)];
		/* A map needs an unmapped window, an unmap a mapped one: the other, untimed. */
		if (op == MAP || op == UNMAP) {
			change(&tree, w, op == MAP ? UNMAP : MAP, &rng, damage, &n);
			if (recompute(&tree, engine, damage, n) < 0)
				return -1;
		}
		change(&tree, w, op, &rng, damage, &n);
		double t0 = bench_now_us();
		int rc = recompute(&tree, engine, damage, n);
		us[k] = bench_now_us() - t0;
		if (rc < 0)
			return -1;
		if (op == UNMAP) {
			change(&tree, w, MAP, &rng, damage, &n);
			if (recompute(&tree, engine, damage, n) < 0)
				return -1;
		}
	}
	vis_wtree_finish(&tree);
	free(wins);
	qsort(us, moves, sizeof *us, bench_cmp_double);
	return 0;
}

/* Appends r to the results kept for the plot, growing them by doubling. */
static int keep(struct wtree_result **results, size_t *n, size_t *cap, struct wtree_result r)
{
	if (*n == *cap) {
		size_t c = *cap ? 2 * *cap : 64;
		struct wtree_result *more = realloc(*results, c * sizeof *more);
		if (!more)
			return -1;
		*results = more;
		*cap = c;
	}
	(*results)[(*n)++] = r;
	return 0;
}

/* Writes the plot to f (path) and closes it; 0, or 1 after saying why on stderr. */
static int write_plot(FILE *f, const char *path, const struct wtree_plot *plot)
{
	if ((bench_wtree_svg_write(f, plot) < 0) | (fclose(f) != 0)) {
		fprintf(stderr, "bench-wtree: %s: write error\n", path);
		return 1;
	}
	return 0;
}

/* Parses a comma-separated list of names into a set of bits; -1 for an unknown name. */
static int parse_set(char *list, const char *const *names, int count)
{
	int set = 0;
	for (char *item = strtok(list, ","); item; item = strtok(NULL, ",")) {
		int k = 0;
		while (k < count && strcmp(item, names[k]) != 0)
			k++;
		if (k == count)
			return -1;
		set |= 1 << k;
	}
	return set;
}

/* The next item of a comma-separated list, or NULL at its end. */
static char *next_item(char **list)
{
	char *s = *list;
	if (!s || !*s)
		return NULL;
	char *comma = strchr(s, ',');
	*list = comma ? comma + 1 : NULL;
	if (comma)
		*comma = '\0';
	return s;
}

int main(int argc, char **argv)
{
	char kinds_default[] = "random,cascade,tiles", sizes_default[] = "1000,10000";
	char ops_default[] = "move", engines_default[] = "full,damaged,live";
	char *kinds = kinds_default, *sizes = sizes_default, *ops = ops_default;
	char *engines = engines_default;
	const char *svg = NULL, *note = NULL;
	size_t moves = 2000;
	uint64_t seed = 1;
	for (int i = 1; i + 1 < argc; i += 2) {
		if (strcmp(argv[i], "--kinds") == 0)
			kinds = argv[i + 1];
		else if (strcmp(argv[i], "--sizes") == 0)
			sizes = argv[i + 1];
		else if (strcmp(argv[i], "--ops") == 0)
			ops = argv[i + 1];
		else if (strcmp(argv[i], "--engines") == 0)
			engines = argv[i + 1];
		else if (strcmp(argv[i], "--moves") == 0)
			moves = strtoul(argv[i + 1], NULL, 10);
		else if (strcmp(argv[i], "--seed") == 0)
			seed = strtoull(argv[i + 1], NULL, 10);
		else if (strcmp(argv[i], "--svg") == 0)
			svg = argv[i + 1];
		else if (strcmp(argv[i], "--note") == 0)
			note = argv[i + 1];
		else
			break;
	}
	int op_set = parse_set(ops, op_names, OP_COUNT);
	int engine_set = parse_set(engines, engine_names, ENGINE_COUNT);
	if (argc % 2 == 0 || moves == 0 || op_set <= 0 || engine_set <= 0) {
		fprintf(stderr, "usage: bench-wtree [--kinds K,…] [--sizes N,…] [--ops O,…] "
				"[--engines E,…] [--moves M] [--seed S]\n"
				"                   [--svg FILE] [--note TEXT]\n"
				"  ops: move, raise, lower, unmap, map; engines: full, damaged, live\n");
		return 2;
	}
	/* Opened first, so that a bad path fails before the run rather than after it. */
	FILE *svg_file = svg ? fopen(svg, "w") : NULL;
	if (svg && !svg_file) {
		fprintf(stderr, "bench-wtree: %s: cannot write: %s\n", svg, strerror(errno));
		return 1;
	}
	double *us = malloc(moves * sizeof *us);
	if (!us)
		return 1;
	/* The plot keeps the first op's cells (move's, unless --ops leaves it out). */
	int plot_op = 0;
	while (!(op_set & 1 << plot_op))
		plot_op++;
	struct wtree_result *results = NULL;
	size_t nresults = 0, cap = 0;
	printf("one recompute after one change (µs): median / p99 / mean; seed %llu, %zu changes\n",
	       (unsigned long long)seed, moves);
	printf("%-8s %7s  %-5s %-4s", "kind", "n", "op", "who");
	for (int e = 0; e < ENGINE_COUNT; e++)
		if (engine_set & 1 << e)
			printf("  %26s", engine_names[e]);
	printf("\n");
	for (char *k; (k = next_item(&kinds));) {
		enum vis_gen_kind kind;
		if (vis_gen_kind_from_name(k, &kind) < 0) {
			fprintf(stderr, "bench-wtree: unknown kind %s\n", k);
			return 2;
		}
		char sizes_copy[256];
		snprintf(sizes_copy, sizeof sizes_copy, "%s", sizes);
		char *list = sizes_copy;
		for (char *s; (s = next_item(&list));) {
			size_t n = strtoul(s, NULL, 10);
			struct vis_scene scene;
			vis_scene_init(&scene);
			if (n == 0 || vis_gen(&scene, kind, n, seed, 0, 0) < 0)
				return 1;
			if (kind == VIS_GEN_UNIFORM) {
				/* Its rectangles fill [0, 1.1 × 10^6)²: a stack on the screen. */
				scene.has_screen = true;
				scene.screen_w = scene.screen_h = 1100000;
			}
			for (int op = 0; op < OP_COUNT; op++) {
				if (!(op_set & 1 << op))
					continue;
				for (int who = ANY; who <= TOP; who++) {
					printf("%-8s %7zu  %-5s %-4s", k, n, op_names[op],
					       who == TOP ? "top" : "any");
					fflush(stdout);
					for (int e = 0; e < ENGINE_COUNT; e++) {
						if (!(engine_set & 1 << e))
							continue;
						if (run(&scene, (enum who)who, (enum op)op, (enum engine)e,
							moves, seed, us) < 0)
							return 1;
						double sum = 0;
						for (size_t i = 0; i < moves; i++)
							sum += us[i];
						if (svg && op == plot_op &&
						    keep(&results, &nresults, &cap, (struct wtree_result){
							    .kind = kind, .n = n, .who = (enum who)who,
							    .engine = (enum engine)e, .median_us = us[moves / 2],
							    .p99_us = us[moves * 99 / 100] }) < 0)
							return 1;
						printf("  %8.1f / %6.1f / %6.1f", us[moves / 2],
						       us[moves * 99 / 100], sum / (double)moves);
						fflush(stdout);
					}
					printf("\n");
				}
			}
			vis_scene_finish(&scene);
		}
	}
	free(us);
	const struct wtree_plot plot = { .results = results, .count = nresults,
					 .op = op_names[plot_op], .moves = moves, .seed = seed,
					 .note = note };
	int rc = svg_file ? write_plot(svg_file, svg, &plot) : 0;
	free(results);
	return rc;
}
