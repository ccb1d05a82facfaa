/*
 * See-through rectangles, differentially: seeded stacks (every kind of scenes.h, plus two of
 * this file's own aimed at see-through: nested layers and mixed twins) with a subset of their
 * rectangles marked see-through — none (NULL and an all-zero array), one, all, or a random
 * share — every engine against the brute force. A failure prints the seed, the scene with its
 * marks, and how to rerun that case alone: `test-seethrough --kind K --n N --seed S`.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "engine.h"
#include "rng.h"
#include "scenes.h"

/* This file's own kinds, numbered after scenes.h's. */
enum {
	KIND_LAYERS = SCENES_KIND_COUNT, /* nested layers of see-through over abutting covers */
	KIND_TWINS,			 /* a few rectangles, each many times over, kinds mixed */
	KIND_COUNT,
};

/* How the rectangles are marked see-through. */
enum mark {
	MARK_NULL,   /* see_through == NULL */
	MARK_NONE,   /* an array of zeros */
	MARK_ONE,    /* exactly one */
	MARK_ALL,    /* every one */
	MARK_SOME,   /* each with a probability drawn from the seed */
	MARK_ALTERNATE, /* every other one from the top */
	MARK_COUNT,
};

static const char *const mark_names[MARK_COUNT] = { "null", "none", "one", "all", "some",
						    "alternate" };

/* Scenes per size and kind; sizes stay small: the brute force is cubic. */
static const struct {
	size_t n;
	unsigned reps;
} schedule[] = {
	{ 1, 300 },  { 2, 600 },  { 3, 600 },  { 4, 600 },  { 5, 600 },  { 6, 450 },
	{ 8, 450 },  { 10, 300 }, { 12, 300 }, { 16, 300 }, { 24, 200 }, { 32, 200 },
	{ 48, 150 }, { 64, 100 }, { 100, 60 }, { 150, 40 }, { 300, 6 },
};

#define MAX_REPORTS 10

static unsigned reports;

struct options {
	const char *argv0;
	bool has_seed, has_kind, has_n, verbose;
	uint64_t seed;
	unsigned kind;
	size_t n;
	double count;
};

static const char *kind_name(unsigned kind)
{
	if (kind == KIND_LAYERS)
		return "layers";
	if (kind == KIND_TWINS)
		return "twins";
	return scenes_kind_name(kind);
}

static int kind_from_name(const char *name, unsigned *kind)
{
	if (strcmp(name, "layers") == 0)
		*kind = KIND_LAYERS;
	else if (strcmp(name, "twins") == 0)
		*kind = KIND_TWINS;
	else
		return scenes_kind_from_name(name, kind);
	return 0;
}

/* The seed of the rep-th scene of a kind and size: distinct and stable across runs. */
static uint64_t scene_seed(uint64_t base, unsigned kind, size_t n, unsigned rep)
{
	struct vis_rng rng = { base ^ ((uint64_t)kind << 48) ^ ((uint64_t)n << 20) ^ rep ^
			       0x5ee7ull << 32 };
	return vis_rng_next(&rng) >> 16;
}

/*
 * Nested layers: a few opaque bases, each covered exactly by abutting opaque pieces some of the
 * time, under a tower of rectangles shrinking by 0 or 1 pixel a side (many see-through by the
 * marks), with the odd 1×1 and off-screen one.
 */
static int make_layers(struct vis_scene *scene, size_t n, struct vis_rng *rng)
{
	scene->has_screen = vis_rng_below(rng, 4) != 0;
	scene->screen_w = (int32_t)vis_rng_range(rng, 8, 40);
	scene->screen_h = (int32_t)vis_rng_range(rng, 8, 40);
	struct vis_rect r = { (int32_t)vis_rng_range(rng, -4, 10), (int32_t)vis_rng_range(rng, -4, 10),
			      (int32_t)vis_rng_range(rng, 4, 40), (int32_t)vis_rng_range(rng, 4, 40) };
	for (size_t i = 0; i < n; i++) {
		struct vis_rect q = r;
		switch (vis_rng_below(rng, 8)) {
		case 0: /* a cover of r split in two, pushed as two windows when room allows */
			if (r.w >= 2 && i + 1 < n) {
				int32_t cut = (int32_t)vis_rng_range(rng, 1, r.w - 1);
				struct vis_rect a = { r.x, r.y, cut, r.h };
				if (vis_scene_push(scene, (uint32_t)i + 1, a) != 0)
					return -1;
				i++;
				q = (struct vis_rect){ r.x + cut, r.y, r.w - cut, r.h };
			}
			break;
		case 1: /* a pixel */
			q = (struct vis_rect){ r.x + (int32_t)vis_rng_below(rng, (uint64_t)r.w),
					       r.y + (int32_t)vis_rng_below(rng, (uint64_t)r.h), 1, 1 };
			break;
		case 2: /* off the screen, or touching it from outside */
			q = (struct vis_rect){ -(int32_t)vis_rng_range(rng, 1, 5),
					       (int32_t)vis_rng_range(rng, -3, 10), 1 +
					       (int32_t)vis_rng_below(rng, 2), 3 };
			break;
		case 3: /* a new base */
			r = (struct vis_rect){ (int32_t)vis_rng_range(rng, -4, 10),
					       (int32_t)vis_rng_range(rng, -4, 10),
					       (int32_t)vis_rng_range(rng, 4, 40),
					       (int32_t)vis_rng_range(rng, 4, 40) };
			q = r;
			break;
		default: /* the next layer in */
			if (r.w > 2 && vis_rng_below(rng, 2)) {
				r.x++;
				r.w -= 2;
			}
			if (r.h > 2 && vis_rng_below(rng, 2)) {
				r.y++;
				r.h -= 2;
			}
			q = r;
			break;
		}
		if (vis_scene_push(scene, (uint32_t)i + 1, q) != 0)
			return -1;
	}
	return 0;
}

/* A handful of rectangles (some exactly the screen, some abutting), each repeated at random. */
static int make_twins(struct vis_scene *scene, size_t n, struct vis_rng *rng)
{
	struct vis_rect pool[5];
	scene->has_screen = vis_rng_below(rng, 3) != 0;
	scene->screen_w = (int32_t)vis_rng_range(rng, 4, 12);
	scene->screen_h = (int32_t)vis_rng_range(rng, 4, 12);
	size_t np = 1 + vis_rng_below(rng, 5);
	for (size_t p = 0; p < np; p++) {
		switch (vis_rng_below(rng, 4)) {
		case 0:
			pool[p] = (struct vis_rect){ 0, 0, scene->screen_w, scene->screen_h };
			break;
		case 1: /* abutting the previous one */
			pool[p] = p ? (struct vis_rect){ pool[p - 1].x + pool[p - 1].w, pool[p - 1].y,
							 pool[p - 1].w, pool[p - 1].h }
				    : (struct vis_rect){ 0, 0, 1, 1 };
			break;
		default:
			pool[p] = (struct vis_rect){ (int32_t)vis_rng_range(rng, -2, 10),
						     (int32_t)vis_rng_range(rng, -2, 10),
						     (int32_t)vis_rng_range(rng, 1, 8),
						     (int32_t)vis_rng_range(rng, 1, 8) };
			break;
		}
	}
	for (size_t i = 0; i < n; i++) {
		if (vis_scene_push(scene, (uint32_t)i + 1, pool[vis_rng_below(rng, np)]) != 0)
			return -1;
	}
	return 0;
}

/* Makes the scene and its marks (marks[i] != 0: see-through) from the seed. */
static int make_case(struct vis_scene *scene, uint8_t **marks, enum mark *mark, unsigned kind,
		     size_t n, uint64_t seed)
{
	struct vis_rng rng = { seed ^ 0x9e3779b97f4a7c15ull };
	int rc;
	if (kind == KIND_LAYERS)
		rc = make_layers(scene, n, &rng);
	else if (kind == KIND_TWINS)
		rc = make_twins(scene, n, &rng);
	else
		rc = scenes_make(scene, kind, n, seed);
	if (rc != 0)
		return -1;
	*mark = (enum mark)vis_rng_below(&rng, MARK_COUNT);
	*marks = calloc(scene->n + 1, 1);
	if (*marks == NULL)
		return -1;
	uint64_t p = vis_rng_range(&rng, 1, 99);
	for (size_t i = 0; i < scene->n; i++) {
		switch (*mark) {
		case MARK_ALL:
			(*marks)[i] = 1;
			break;
		case MARK_SOME:
			(*marks)[i] = vis_rng_below(&rng, 100) < p;
			break;
		case MARK_ALTERNATE:
			(*marks)[i] = (scene->n - i) % 2 == 0;
			break;
		default:
			break;
		}
	}
	if (*mark == MARK_ONE && scene->n > 0)
		(*marks)[vis_rng_below(&rng, scene->n)] = 1;
	return 0;
}

/* Prints the scene in the scene format, see-through windows marked in a comment. */
static void dump(const struct vis_scene *scene, const uint8_t *marks, const uint8_t *want,
		 const uint8_t *got)
{
	if (scene->has_screen)
		printf("  screen %" PRId32 " %" PRId32 "\n", scene->screen_w, scene->screen_h);
	for (size_t i = 0; i < scene->n; i++) {
		const struct vis_rect *r = &scene->rects[i];
		printf("  window %" PRIu32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32
		       "  # %s, expected %s, got %s\n",
		       scene->ids[i], r->x, r->y, r->w, r->h, marks[i] ? "see-through" : "opaque",
		       vis_state_name((enum vis_state)want[i]),
		       got[i] <= VIS_FULLY_OBSCURED ? vis_state_name((enum vis_state)got[i])
						    : "invalid");
	}
}

/* Checks one case with every engine against the brute force; returns whether all agreed. */
static bool check_case(const struct options *o, unsigned kind, size_t n, uint64_t seed)
{
	struct vis_scene scene;
	uint8_t *marks = NULL, *want = NULL, *got = NULL;
	enum mark mark;
	bool ok = true;

	vis_scene_init(&scene);
	if (make_case(&scene, &marks, &mark, kind, n, seed) != 0) {
		printf("ERROR kind %s, n %zu, seed %" PRIu64 ": making the case: %s\n",
		       kind_name(kind), n, seed, strerror(errno));
		ok = false;
		goto out;
	}
	/* The windows' rectangles with the marks, and nothing else the scene may carry. */
	struct vis_stack stack = {
		.rects = scene.rects,
		.n = scene.n,
		.has_screen = scene.has_screen,
		.screen_w = scene.screen_w,
		.screen_h = scene.screen_h,
		.see_through = mark == MARK_NULL ? NULL : marks,
	};
	want = malloc(stack.n + 1);
	got = malloc(stack.n + 1);
	if (want == NULL || got == NULL || vis_brute_compute(&stack, want) != 0) {
		printf("ERROR kind %s, n %zu, seed %" PRIu64 ": the brute force: %s\n",
		       kind_name(kind), n, seed, strerror(errno));
		ok = false;
		goto out;
	}
	for (int e = 0; e < VIS_ENGINE_COUNT; e++) {
		if (e == VIS_ENGINE_BRUTE)
			continue;
		memset(got, 0xff, stack.n);
		int rc = vis_compute((enum vis_engine)e, &stack, got);
		bool same = rc == 0 && memcmp(want, got, stack.n) == 0;
		if (same)
			continue;
		ok = false;
		if (reports++ >= MAX_REPORTS)
			continue;
		printf("MISMATCH kind %s, n %zu, seed %" PRIu64 ", marks %s, engine %s%s%s\n",
		       kind_name(kind), n, seed, mark_names[mark],
		       vis_engine_name((enum vis_engine)e), rc ? ": " : "",
		       rc ? strerror(errno) : "");
		if (rc == 0 && (stack.n <= 40 || o->verbose))
			dump(&scene, marks, want, got);
		printf("  rerun: %s --kind %s --n %zu --seed %" PRIu64 " --verbose\n", o->argv0,
		       kind_name(kind), n, seed);
	}
	if (o->verbose)
		printf("%-4s kind %s, n %zu, seed %" PRIu64 ", marks %s\n", ok ? "ok" : "FAIL",
		       kind_name(kind), n, seed, mark_names[mark]);
out:
	free(marks);
	free(want);
	free(got);
	vis_scene_finish(&scene);
	return ok;
}

static void usage(const char *argv0)
{
	fprintf(stderr,
		"usage: %s [--seed S] [--kind K] [--n N] [--count C] [--verbose]\n"
		"  --seed S --kind K --n N  rerun one case\n"
		"  --count C                scale the number of scenes by C (default 1)\n",
		argv0);
	exit(2);
}

static void parse_options(int argc, char **argv, struct options *o)
{
	memset(o, 0, sizeof *o);
	o->argv0 = argv[0];
	o->count = 1;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		char *end = NULL;
		if (strcmp(a, "--verbose") == 0 || strcmp(a, "-v") == 0) {
			o->verbose = true;
			continue;
		}
		if (v == NULL)
			usage(argv[0]);
		i++;
		errno = 0;
		if (strcmp(a, "--seed") == 0) {
			o->seed = strtoull(v, &end, 0);
			o->has_seed = true;
		} else if (strcmp(a, "--n") == 0) {
			o->n = strtoull(v, &end, 0);
			o->has_n = true;
		} else if (strcmp(a, "--count") == 0) {
			o->count = strtod(v, &end);
			if (!(o->count > 0))
				usage(argv[0]);
		} else if (strcmp(a, "--kind") == 0) {
			if (kind_from_name(v, &o->kind) != 0) {
				fprintf(stderr, "unknown kind %s\n", v);
				exit(2);
			}
			o->has_kind = true;
			continue;
		} else {
			usage(argv[0]);
		}
		if (errno != 0 || *end != '\0' || end == v)
			usage(argv[0]);
	}
}

int main(int argc, char **argv)
{
	struct options o;
	unsigned long scenes[KIND_COUNT] = { 0 }, failed[KIND_COUNT] = { 0 }, all = 0, bad = 0;
	struct timespec t0, t1;

	setvbuf(stdout, NULL, _IOLBF, 0);
	parse_options(argc, argv, &o);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	if (o.has_seed && o.has_kind && o.has_n) {
		bool ok = check_case(&o, o.kind, o.n, o.seed);
		printf("%d passed, %d failed\n", ok, !ok);
		return ok ? 0 : 1;
	}
	for (unsigned k = 0; k < KIND_COUNT; k++) {
		if (o.has_kind && k != o.kind)
			continue;
		for (size_t s = 0; s < sizeof schedule / sizeof schedule[0]; s++) {
			size_t n = o.has_n ? o.n : schedule[s].n;
			double r = schedule[s].reps * o.count + 0.5;
			unsigned reps = r < 1 ? 1 : (unsigned)r;
			for (unsigned rep = 0; rep < reps; rep++) {
				scenes[k]++;
				failed[k] += !check_case(&o, k, n, scene_seed(o.seed, k, n, rep));
			}
			if (o.has_n)
				break;
		}
	}
	clock_gettime(CLOCK_MONOTONIC, &t1);
	for (unsigned k = 0; k < KIND_COUNT; k++) {
		if (scenes[k] == 0)
			continue;
		printf("  %-10s %6lu scenes, %lu failed\n", kind_name(k), scenes[k], failed[k]);
		all += scenes[k];
		bad += failed[k];
	}
	printf("see-through: %lu scenes, %lu mismatches or errors, %.1f s\n", all, bad,
	       (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) / 1e9);
	printf("%lu passed, %lu failed\n", all - bad, bad);
	return bad == 0 ? 0 : 1;
}
