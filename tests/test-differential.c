/*
 * The differential test: seeded scenes of every kind, every engine against the brute force, or
 * against the region method where the brute force would be too slow (the region method being
 * itself checked against the brute force on the smaller scenes). A failure prints how to rerun
 * just that case.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "coords.h"
#include "engine.h"
#include "look.h"
#include "rng.h"
#include "scenes.h"

/* How many scenes of each size every kind gets by default (scaled by --count). */
static const struct {
	size_t n;
	unsigned reps;
} schedule[] = {
	{ 0, 2 },    { 1, 40 },   { 2, 80 },   { 3, 80 },  { 4, 80 },  { 5, 80 },  { 6, 60 },
	{ 7, 60 },   { 8, 60 },   { 10, 50 },  { 12, 50 }, { 16, 40 }, { 20, 30 }, { 24, 30 },
	{ 32, 25 },  { 40, 20 },  { 50, 15 },  { 64, 12 }, { 80, 10 }, { 100, 8 }, { 128, 6 },
	{ 160, 5 },  { 200, 4 },  { 300, 3 },  { 500, 2 }, { 1000, 1 }, { 2000, 1 }, { 3000, 1 },
};

/* Past these, the brute force is not run: its grid or its painting would take too long. */
#define BRUTE_MAX_CELLS (16u << 20)
#define BRUTE_MAX_PAINT (32u << 20)

/*
 * The region method's work budget in union boxes (see vis_region_compute_within()): about a
 * second, reached only by the grid beyond n ≈ 1000, where the brute force is the reference.
 */
#define REGION_MAX_WORK ((uint64_t)150 << 20)

/* What a scene was checked against. */
enum reference {
	REFERENCE_BRUTE,
	REFERENCE_REGION,
	REFERENCE_SWEEP, /* neither was affordable: the engines against each other */
	REFERENCE_NONE,
	REFERENCE_COUNT,
};

/* Printed failure details stop here, so a broken engine does not flood the log. */
#define MAX_REPORTS 20

struct options {
	const char *argv0;
	bool has_seed, has_kind, has_n, verbose;
	uint64_t seed;
	unsigned kind;
	size_t n;
	bool engines[VIS_ENGINE_COUNT];
	double count;
};

struct tally {
	unsigned long scenes, failed, against[REFERENCE_COUNT];
};

static unsigned reports;

/* Whether the brute force is cheap enough here: its grid and its painting stay bounded. */
static bool brute_affordable(const struct vis_stack *stack)
{
	struct vis_coords co;
	double paint = 0;
	bool ok;

	if (stack->n <= 64)
		return true;
	if (vis_coords_init(&co, stack) < 0)
		return false;
	for (size_t i = 0; i < stack->n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		paint += (double)(vis_coords_rank_x(&co, b.x2) - vis_coords_rank_x(&co, b.x1)) *
			 (double)(vis_coords_rank_y(&co, b.y2) - vis_coords_rank_y(&co, b.y1));
	}
	ok = co.nx > 0 && co.ny > 0 &&
	     (double)(co.nx - 1) * (double)(co.ny - 1) <= BRUTE_MAX_CELLS && paint <= BRUTE_MAX_PAINT;
	vis_coords_finish(&co);
	return ok;
}

/* The seed of the rep-th scene of a kind and size: distinct and stable across runs. */
static uint64_t scene_seed(uint64_t base, unsigned kind, size_t n, unsigned rep)
{
	struct vis_rng rng = { base ^ ((uint64_t)kind << 48) ^ ((uint64_t)n << 20) ^ rep };
	return vis_rng_next(&rng) >> 16; /* short enough to type */
}

/* A state's name, or "invalid (v)" for a value no engine may write. */
static const char *state_name(uint8_t s, char *buf, size_t len)
{
	if (s <= VIS_FULLY_OBSCURED)
		return vis_state_name((enum vis_state)s);
	snprintf(buf, len, "invalid (%u)", s);
	return buf;
}

/* Prints how to rerun one case alone. */
static void print_rerun(const struct options *o, unsigned kind, size_t n, uint64_t seed,
			enum vis_engine e)
{
	printf("  rerun: %s --kind %s --n %zu --seed %" PRIu64 " --engine %s --verbose\n",
	       o->argv0, scenes_kind_name(kind), n, seed, vis_engine_name(e));
}

/* Compares an engine's states with the reference's; returns whether they are equal. */
static bool compare(const struct options *o, const struct vis_scene *scene, unsigned kind,
		    uint64_t seed, enum vis_engine e, enum vis_engine ref, const uint8_t *want,
		    const uint8_t *got)
{
	size_t shown = 0, bad = 0;
	char b1[32], b2[32];

	for (size_t i = 0; i < scene->n; i++) {
		if (want[i] == got[i])
			continue;
		if (bad++ == 0 && reports++ < MAX_REPORTS)
			printf("MISMATCH kind %s, n %zu, seed %" PRIu64
			       ", engine %s (reference %s), screen %s%" PRId32 "x%" PRId32 "\n",
			       scenes_kind_name(kind), scene->n, seed, vis_engine_name(e),
			       vis_engine_name(ref), scene->has_screen ? "" : "none ",
			       scene->screen_w, scene->screen_h);
		if (reports <= MAX_REPORTS && shown++ < 5) {
			const struct vis_rect *r = &scene->rects[i];
			printf("  window %zu (x %" PRId32 ", y %" PRId32 ", w %" PRId32
			       ", h %" PRId32 "): expected %s, got %s\n",
			       i, r->x, r->y, r->w, r->h, state_name(want[i], b1, sizeof b1),
			       state_name(got[i], b2, sizeof b2));
		}
	}
	if (bad != 0 && reports <= MAX_REPORTS) {
		printf("  %zu of %zu windows differ\n", bad, scene->n);
		print_rerun(o, kind, scene->n, seed, e);
	}
	return bad == 0;
}

/*
 * An engine that takes an argument (a budget, a price), run on the windows' pieces when they have
 * looks, as vis_compute() runs the others.
 */
static int on_pieces(const struct vis_stack *stack, uint8_t *states,
		     int (*engine)(const struct vis_stack *, uint8_t *, uint64_t), uint64_t arg)
{
	if (stack->looks == NULL)
		return engine(stack, states, arg);
	struct vis_pieces pieces;
	if (vis_pieces_init(&pieces, stack) < 0)
		return -1;
	uint8_t *piece_states = malloc(pieces.stack.n + 1);
	int rc = -1;
	if (piece_states != NULL)
		rc = engine(&pieces.stack, piece_states, arg);
	if (rc == 0)
		vis_pieces_join(&pieces, stack, piece_states, states);
	free(piece_states);
	vis_pieces_finish(&pieces);
	return rc;
}

/* The region method within its budget. */
static int region_within(const struct vis_stack *stack, uint8_t *states)
{
	return on_pieces(stack, states, vis_region_compute_within, REGION_MAX_WORK);
}

/*
 * auto with its sweep step priced at price units (vis_auto_compute_priced()): a price of 0 hands
 * over at the first checkpoint (16 windows), one of 1 wherever a forecast is made on a costly
 * union, UINT64_MAX never, though it still forecasts.
 */
static int auto_priced(const struct vis_stack *stack, uint8_t *states, uint64_t price)
{
	return on_pieces(stack, states, vis_auto_compute_priced, price);
}

/*
 * Runs one engine, reporting an error return; states are poisoned first to catch gaps. The
 * region method runs under a work budget: returns 1 when it gave up, else 0, or -1 on error.
 */
static int run(const struct options *o, const struct vis_stack *stack, unsigned kind,
	       uint64_t seed, enum vis_engine e, uint8_t *states)
{
	int rc;

	memset(states, 0xff, stack->n);
	if (e == VIS_ENGINE_REGION)
		rc = region_within(stack, states);
	else
		rc = vis_compute(e, stack, states);
	if (rc >= 0)
		return rc;
	if (reports++ < MAX_REPORTS) {
		printf("ERROR kind %s, n %zu, seed %" PRIu64 ", engine %s: %s\n",
		       scenes_kind_name(kind), stack->n, seed, vis_engine_name(e), strerror(errno));
		print_rerun(o, kind, stack->n, seed, e);
	}
	return -1;
}

/* Prints the scene in the scene file format, for a rerun with --verbose. */
static void dump(const struct vis_scene *scene, const uint8_t *states)
{
	if (scene->has_screen)
		printf("screen %" PRId32 " %" PRId32 "\n", scene->screen_w, scene->screen_h);
	for (size_t i = 0; i < scene->n; i++) {
		const struct vis_rect *r = &scene->rects[i];
		printf("window %" PRIu32 " %" PRId32 " %" PRId32 " %" PRId32 " %" PRId32 "  # %s\n",
		       scene->ids[i], r->x, r->y, r->w, r->h,
		       states != NULL ? vis_state_name((enum vis_state)states[i]) : "");
		if (scene->looks != NULL && !vis_look_plain(&scene->looks[i])) {
			/* The look's records, as the scene format writes them. */
			struct vis_scene one = { .n = 1, .ids = &scene->ids[i], .rects = (struct vis_rect *)r,
						 .looks = &scene->looks[i] };
			char *text;
			size_t len;
			if (vis_scene_format(&one, &text, &len) == 0) {
				fputs(strchr(text, '\n') + 1, stdout);
				free(text);
			}
		}
	}
}

/*
 * Checks one scene with every selected engine; returns whether all agreed. The reference is the
 * brute force where affordable, else the region method within its budget, else (the grid at
 * large n) the first sweep engine, the others being compared with it.
 */
static bool check_scene(const struct options *o, unsigned kind, size_t n, uint64_t seed,
			enum reference *used)
{
	struct vis_scene scene;
	struct vis_stack stack;
	uint8_t *want = NULL, *got = NULL;
	bool ok = true, have_ref = false, region_over = false;
	enum vis_engine ref = VIS_ENGINE_BRUTE;

	vis_scene_init(&scene);
	if (scenes_make(&scene, kind, n, seed) != 0) {
		printf("ERROR kind %s, n %zu, seed %" PRIu64 ": making the scene: %s\n",
		       scenes_kind_name(kind), n, seed, strerror(errno));
		vis_scene_finish(&scene);
		return false;
	}
	stack = vis_scene_stack(&scene);
	want = malloc(stack.n + 1);
	got = malloc(stack.n + 1);
	if (want == NULL || got == NULL) {
		printf("ERROR: out of memory\n");
		ok = false;
		goto out;
	}

	if (brute_affordable(&stack)) {
		have_ref = run(o, &stack, kind, seed, VIS_ENGINE_BRUTE, want) == 0;
		ok = have_ref;
	}
	/* The engines in order: the region method first, as it may have to be the reference. */
	static const enum vis_engine order[] = { VIS_ENGINE_REGION, VIS_ENGINE_GMV,
						 VIS_ENGINE_GMV_HEAP, VIS_ENGINE_AUTO };
	for (size_t k = 0; k < sizeof order / sizeof order[0]; k++) {
		enum vis_engine e = order[k];
		int rc;

		if (!o->engines[e] && !(e == VIS_ENGINE_REGION && !have_ref))
			continue;
		rc = run(o, &stack, kind, seed, e, have_ref ? got : want);
		if (rc < 0) {
			ok = false;
		} else if (rc > 0) {
			region_over = true;
			if (o->verbose)
				printf("     region method over budget: not checked\n");
		} else if (!have_ref) {
			have_ref = true;
			ref = e;
		} else {
			ok = compare(o, &scene, kind, seed, e, ref, want, got) && ok;
		}
	}
	/*
	 * auto's two outcomes forced, so that each is checked on every kind and size; never handing
	 * over only where the region method kept within its budget, or the grids would take minutes.
	 */
	static const uint64_t prices[] = { 0, 1, UINT64_MAX };
	for (size_t k = 0; have_ref && o->engines[VIS_ENGINE_AUTO] && k < (region_over ? 2u : 3u); k++) {
		memset(got, 0xff, stack.n);
		if (auto_priced(&stack, got, prices[k]) < 0) {
			if (reports++ < MAX_REPORTS)
				printf("ERROR kind %s, n %zu, seed %" PRIu64 ", auto priced at %" PRIu64
				       ": %s\n", scenes_kind_name(kind), stack.n, seed, prices[k],
				       strerror(errno));
			ok = false;
		} else if (!compare(o, &scene, kind, seed, VIS_ENGINE_AUTO, ref, want, got)) {
			printf("  (auto with a sweep step priced at %" PRIu64 " units)\n", prices[k]);
			ok = false;
		}
	}
	if (o->verbose && o->has_seed)
		dump(&scene, have_ref ? want : NULL);
	if (o->verbose)
		printf("%-4s kind %s, n %zu, seed %" PRIu64 ", reference %s\n", ok ? "ok" : "FAIL",
		       scenes_kind_name(kind), n, seed, have_ref ? vis_engine_name(ref) : "none");
	*used = !have_ref ? REFERENCE_NONE : ref == VIS_ENGINE_BRUTE ? REFERENCE_BRUTE
		: ref == VIS_ENGINE_REGION ? REFERENCE_REGION : REFERENCE_SWEEP;
out:
	free(want);
	free(got);
	vis_scene_finish(&scene);
	return ok;
}

/* Prints the options and exits: only for a bad command line. */
static void usage(const char *argv0)
{
	fprintf(stderr,
		"usage: %s [--seed S] [--kind K] [--n N] [--engine NAME]... [--count C] "
		"[--verbose]\n"
		"  --seed S --kind K --n N  rerun one case\n"
		"  --count C                scale the number of scenes by C (default 1)\n",
		argv0);
	exit(2);
}

/* Parses the command line into o. */
static void parse_options(int argc, char **argv, struct options *o)
{
	bool any_engine = false;

	memset(o, 0, sizeof *o);
	o->argv0 = argv[0];
	o->count = 1;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
		char *end;
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
			if (scenes_kind_from_name(v, &o->kind) != 0) {
				fprintf(stderr, "unknown kind %s; kinds:", v);
				for (unsigned k = 0; k < SCENES_KIND_COUNT; k++)
					fprintf(stderr, " %s", scenes_kind_name(k));
				fprintf(stderr, "\n");
				exit(2);
			}
			o->has_kind = true;
			continue;
		} else if (strcmp(a, "--engine") == 0) {
			enum vis_engine e;
			if (vis_engine_from_name(v, &e) != 0) {
				fprintf(stderr, "unknown engine %s\n", v);
				exit(2);
			}
			o->engines[e] = any_engine = true;
			continue;
		} else {
			usage(argv[0]);
		}
		if (errno != 0 || *end != '\0' || end == v)
			usage(argv[0]);
	}
	if (!any_engine) {
		for (int e = 0; e < VIS_ENGINE_COUNT; e++)
			o->engines[e] = true;
	}
}

int main(int argc, char **argv)
{
	struct options o;
	struct tally tally[SCENES_KIND_COUNT] = { 0 }, total = { 0 };
	struct timespec t0, t1;

	setvbuf(stdout, NULL, _IOLBF, 0);
	parse_options(argc, argv, &o);
	clock_gettime(CLOCK_MONOTONIC, &t0);

	if (o.has_seed && o.has_kind && o.has_n) {
		enum reference used;
		bool ok = check_scene(&o, o.kind, o.n, o.seed, &used);
		printf("%d passed, %d failed\n", ok, !ok);
		return ok ? 0 : 1;
	}
	for (unsigned k = 0; k < SCENES_KIND_COUNT; k++) {
		if (o.has_kind && k != o.kind)
			continue;
		for (size_t s = 0; s < sizeof schedule / sizeof schedule[0]; s++) {
			size_t n = o.has_n ? o.n : schedule[s].n;
			double r = schedule[s].reps * o.count + 0.5;
			unsigned reps = r < 1 ? 1 : (unsigned)r;
			for (unsigned rep = 0; rep < reps; rep++) {
				uint64_t seed = scene_seed(o.seed, k, n, rep);
				enum reference used = REFERENCE_NONE;
				tally[k].scenes++;
				if (!check_scene(&o, k, n, seed, &used))
					tally[k].failed++;
				tally[k].against[used]++;
			}
			if (o.has_n)
				break;
		}
	}
	clock_gettime(CLOCK_MONOTONIC, &t1);

	for (unsigned k = 0; k < SCENES_KIND_COUNT; k++) {
		if (tally[k].scenes == 0)
			continue;
		printf("  %-10s %6lu scenes, %lu failed (reference: brute %lu, region %lu, "
		       "sweep %lu, none %lu)\n",
		       scenes_kind_name(k), tally[k].scenes, tally[k].failed,
		       tally[k].against[REFERENCE_BRUTE], tally[k].against[REFERENCE_REGION],
		       tally[k].against[REFERENCE_SWEEP], tally[k].against[REFERENCE_NONE]);
		total.scenes += tally[k].scenes;
		total.failed += tally[k].failed;
	}
	if (reports > MAX_REPORTS)
		printf("(%u failure reports, the first %d printed)\n", reports, MAX_REPORTS);
	printf("differential: %lu scenes, %lu mismatches or errors, %.1f s\n", total.scenes,
	       total.failed,
	       (double)(t1.tv_sec - t0.tv_sec) + (double)(t1.tv_nsec - t0.tv_nsec) / 1e9);
	printf("%lu passed, %lu failed\n", total.scenes - total.failed, total.failed);
	return total.failed == 0 ? 0 : 1;
}
