/*
 * The regression cases: every trap and semantic rule of docs/ENGINES.md ("From the paper's
 * rectangles to pixels") as a named scene with its exact expected states, checked against every
 * engine. Each case also runs transposed and
 * mirrored, since a sweep treats its two axes and its two directions differently.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"

#define MAX_WINDOWS 16

/*
 * A case: the windows bottom-to-top and their states as a string, one letter a window:
 * U unobscured, P partially-obscured, F fully-obscured. screen_w == 0 means no screen.
 */
struct regress_case {
	const char *name;
	int32_t screen_w, screen_h;
	const char *want;
	struct vis_rect rects[MAX_WINDOWS];
};

#define MIN INT32_MIN
#define MAX INT32_MAX
#define G30 (1 << 30)

static const struct regress_case cases[] = {
	/* The three event orders at equal x that the notes prove wrong. */
	{ "deletions-before-insertions", 0, 0, "FUU",
	  { { 0, 0, 10, 1 }, { 0, 0, 5, 1 }, { 5, 0, 5, 1 } } },
	{ "equal-right-edges", 0, 0, "FU", { { 1, 0, 4, 1 }, { 0, 0, 5, 1 } } },
	{ "insertions-increasing-z", 0, 0, "FU", { { 0, 0, 5, 1 }, { 0, 0, 6, 1 } } },
	{ "deletions-before-insertions-screen", 10, 1, "FUU",
	  { { 0, 0, 10, 1 }, { 0, 0, 5, 1 }, { 5, 0, 5, 1 } } },
	{ "equal-edges-three-deep", 0, 0, "FFU",
	  { { 2, 0, 3, 1 }, { 1, 0, 4, 1 }, { 0, 0, 5, 1 } } },

	/* Zero area after clipping: dropped, and must not be reported nor hide anything. */
	{ "zero-area-right-of-screen", 10, 1, "UF", { { 0, 0, 10, 1 }, { 10, 0, 5, 1 } } },
	{ "zero-area-left-of-screen", 10, 1, "FU", { { -5, 0, 5, 1 }, { 0, 0, 10, 1 } } },
	{ "zero-area-between", 10, 10, "UFU",
	  { { 0, 0, 5, 10 }, { -3, 10, 20, 4 }, { 5, 0, 5, 10 } } },

	/* Touching windows do not overlap. */
	{ "touching-x", 0, 0, "UU", { { 0, 0, 5, 5 }, { 5, 0, 5, 5 } } },
	{ "touching-y", 0, 0, "UU", { { 0, 0, 5, 5 }, { 0, 5, 5, 5 } } },
	{ "touching-corner", 0, 0, "UU", { { 0, 0, 5, 5 }, { 5, 5, 5, 5 } } },
	{ "touching-around", 0, 0, "UUUUU",
	  { { 2, 2, 2, 2 }, { 0, 0, 6, 2 }, { 0, 4, 6, 2 }, { 0, 2, 2, 2 }, { 4, 2, 2, 2 } } },

	/* The screen. */
	{ "partly-off-screen-alone", 10, 10, "P", { { 5, 5, 10, 10 } } },
	{ "partly-off-screen-left", 10, 10, "P", { { -1, 0, 5, 5 } } },
	{ "partly-off-screen-top", 10, 10, "P", { { 0, -1, 5, 5 } } },
	{ "exactly-screen-size", 10, 10, "U", { { 0, 0, 10, 10 } } },
	{ "ending-at-w-and-h", 10, 10, "U", { { 5, 5, 5, 5 } } },
	{ "ending-at-w-under-screen-edge", 10, 10, "UU", { { 0, 0, 10, 3 }, { 0, 3, 10, 7 } } },
	{ "entirely-off-screen", 10, 10, "F", { { 20, 20, 5, 5 } } },
	{ "touching-screen-right", 10, 10, "F", { { 10, 0, 5, 5 } } },
	{ "touching-screen-bottom", 10, 10, "F", { { 0, 10, 5, 5 } } },
	{ "touching-screen-left", 10, 10, "F", { { -5, 0, 5, 5 } } },
	{ "touching-screen-top", 10, 10, "F", { { 0, -5, 5, 5 } } },
	{ "touching-screen-corner", 10, 10, "FF", { { -5, -5, 5, 5 }, { 10, 10, 1, 1 } } },
	{ "on-screen-part-covered", 10, 10, "FU", { { 5, 0, 10, 10 }, { 5, 0, 5, 10 } } },
	{ "on-screen-part-nearly-covered", 10, 10, "PU", { { 5, 0, 10, 10 }, { 6, 0, 4, 10 } } },
	{ "larger-than-screen", 10, 10, "P", { { -1, -1, 12, 12 } } },
	{ "screen-covered-by-larger", 10, 10, "FP", { { 0, 0, 10, 10 }, { -1, -1, 12, 12 } } },

	/* Covered exactly by abutting windows, or all but one pixel. */
	{ "cover-split-x", 0, 0, "FUU", { { 0, 0, 10, 10 }, { 0, 0, 4, 10 }, { 4, 0, 6, 10 } } },
	{ "cover-split-y", 0, 0, "FUU", { { 0, 0, 10, 10 }, { 0, 0, 10, 4 }, { 0, 4, 10, 6 } } },
	{ "cover-2x2", 0, 0, "FUUUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 4, 3 }, { 4, 0, 6, 3 }, { 0, 3, 4, 7 }, { 4, 3, 6, 7 } } },
	{ "cover-l-shape", 0, 0, "FUUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 4, 10 }, { 4, 0, 6, 3 }, { 4, 3, 6, 7 } } },
	{ "cover-overhanging", 0, 0, "FPUU",
	  { { 2, 2, 6, 6 }, { 0, 0, 5, 10 }, { 5, 0, 5, 5 }, { 3, 5, 7, 7 } } },
	{ "cover-split-x-gap", 0, 0, "PUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 4, 10 }, { 5, 0, 5, 10 } } },
	{ "cover-split-y-gap", 0, 0, "PUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 10, 4 }, { 0, 5, 10, 5 } } },
	{ "cover-2x2-pixel-free", 0, 0, "PUUUUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 4, 3 }, { 4, 0, 6, 3 }, { 0, 3, 4, 7 }, { 5, 3, 5, 7 },
	    { 4, 4, 1, 6 } } },
	{ "cover-l-shape-pixel-free", 0, 0, "PUUUU",
	  { { 0, 0, 10, 10 }, { 0, 0, 4, 10 }, { 4, 0, 6, 3 }, { 5, 3, 5, 7 }, { 4, 4, 1, 6 } } },
	{ "cover-centre-pixel-free", 0, 0, "PUUUU",
	  { { 0, 0, 3, 3 }, { 0, 0, 3, 1 }, { 0, 2, 3, 1 }, { 0, 1, 1, 1 }, { 2, 1, 1, 1 } } },
	{ "cover-on-screen-part", 10, 10, "FUU",
	  { { 5, -5, 10, 20 }, { 5, 0, 2, 10 }, { 7, 0, 3, 10 } } },

	/* A deletion exposing a window higher up the segment tree than the deleted one. */
	{ "exposed-by-deletion", 0, 0, "PU", { { 0, 0, 10, 10 }, { 0, 0, 5, 10 } } },
	{ "exposed-by-two-deletions", 0, 0, "PUU",
	  { { 0, 0, 10, 4 }, { 0, 0, 5, 2 }, { 0, 2, 5, 2 } } },
	{ "exposed-one-column", 0, 0, "PUU",
	  { { 0, 0, 10, 4 }, { 0, 0, 9, 2 }, { 0, 2, 9, 2 } } },

	/* Identical rectangles. */
	{ "identical-two", 0, 0, "FU", { { 3, 4, 5, 6 }, { 3, 4, 5, 6 } } },
	{ "identical-four", 0, 0, "FFFU",
	  { { 3, 4, 5, 6 }, { 3, 4, 5, 6 }, { 3, 4, 5, 6 }, { 3, 4, 5, 6 } } },
	{ "identical-off-screen-part", 10, 10, "FP", { { -1, 0, 5, 5 }, { -1, 0, 5, 5 } } },
	{ "identical-screen-size", 10, 10, "FFU",
	  { { 0, 0, 10, 10 }, { 0, 0, 10, 10 }, { 0, 0, 10, 10 } } },

	/* 1×1 windows. */
	{ "pixel-on-pixel", 0, 0, "FU", { { 0, 0, 1, 1 }, { 0, 0, 1, 1 } } },
	{ "pixels-touching", 0, 0, "UUU", { { 0, 0, 1, 1 }, { 1, 0, 1, 1 }, { 0, 1, 1, 1 } } },
	{ "pixel-under-window", 0, 0, "FU", { { 4, 4, 1, 1 }, { 0, 0, 10, 10 } } },
	{ "pixel-hole", 0, 0, "PU", { { 0, 0, 10, 10 }, { 4, 4, 1, 1 } } },
	{ "pixel-screen-corners", 10, 10, "UUFF",
	  { { 9, 9, 1, 1 }, { 0, 0, 1, 1 }, { 10, 9, 1, 1 }, { -1, -1, 1, 1 } } },
	{ "pixel-screen-1x1", 1, 1, "FUF", { { 0, 0, 1, 1 }, { 0, 0, 1, 1 }, { 1, 0, 1, 1 } } },

	/* Coordinates at the int32 limits: x + w above INT32_MAX, edges beyond ±2^30. */
	{ "limits-halves-touching", 0, 0, "UU", { { MIN, 0, MAX, 1 }, { -1, 0, MAX, 1 } } },
	{ "limits-right-end", 0, 0, "PU", { { MAX - 1, 0, 2, 1 }, { MAX, 0, MAX, 1 } } },
	{ "limits-past-int32-covered", 0, 0, "FU", { { G30, 0, G30 + 5, 1 }, { G30, 0, MAX, 1 } } },
	{ "limits-past-int32-not-covered", 0, 0, "PU",
	  { { G30, 0, MAX, 1 }, { G30, 0, G30 + 5, 1 } } },
	{ "limits-whole-plane", 0, 0, "FU", { { MIN, MIN, MAX, MAX }, { MIN, MIN, MAX, MAX } } },
	{ "limits-one-pixel-free", 0, 0, "PU", { { 0, 0, MAX, 1 }, { 1, 0, MAX, 1 } } },
	{ "limits-corners", 0, 0, "UUUU",
	  { { MIN, MIN, 1, 1 }, { MAX, MAX, 1, 1 }, { MIN, MAX, MAX, MAX },
	    { MAX, MIN, MAX, MAX } } },
	{ "limits-wide-over-narrow", 0, 0, "FUU",
	  { { MAX - 2, MIN, 3, 1 }, { MIN, MIN, 1, 1 }, { 2, MIN, MAX, 1 } } },
	{ "limits-screen-wide", MAX, 1, "PP", { { 0, 0, MAX - 1, 1 }, { 1, 0, MAX, 1 } } },
	{ "limits-screen-exact", MAX, MAX, "U", { { 0, 0, MAX, MAX } } },
	{ "limits-screen-covered", MAX, MAX, "FPPP",
	  { { 0, 0, MAX, MAX }, { -5, -5, MAX, MAX }, { MAX - 10, 0, 20, MAX },
	    { -1, MAX - 6, MAX, 10 } } },
};

#undef MIN
#undef MAX

/* The state a letter of a case's string stands for. */
static uint8_t letter_state(char c)
{
	return c == 'U' ? VIS_UNOBSCURED : c == 'P' ? VIS_PARTIALLY_OBSCURED : VIS_FULLY_OBSCURED;
}

/* The letter of a state an engine wrote, '?' for a value no engine may write. */
static char state_letter(uint8_t s)
{
	return s == VIS_UNOBSCURED ? 'U' : s == VIS_PARTIALLY_OBSCURED ? 'P'
		: s == VIS_FULLY_OBSCURED ? 'F' : '?';
}

enum variant {
	VARIANT_PLAIN,
	VARIANT_TRANSPOSED, /* x and y swapped */
	VARIANT_MIRRORED,   /* x reflected: left edges become right edges */
	VARIANT_COUNT,
};

static const char *const variant_names[VARIANT_COUNT] = { "", " (transposed)", " (mirrored)" };

/*
 * The case's windows under a variant, which leaves every state unchanged. Returns false when a
 * reflected window would leave the int32 range.
 */
static bool make_variant(const struct regress_case *c, size_t n, enum variant v,
			 struct vis_rect *out, struct vis_stack *stack)
{
	bool screen = c->screen_w != 0;

	*stack = (struct vis_stack){ out, n, screen, c->screen_w, c->screen_h, NULL, NULL };
	for (size_t i = 0; i < n; i++) {
		struct vis_rect r = c->rects[i];
		if (v == VARIANT_TRANSPOSED) {
			out[i] = (struct vis_rect){ r.y, r.x, r.h, r.w };
		} else if (v == VARIANT_MIRRORED) {
			/* Pixel p goes to W - 1 - p: [x, x + w) becomes [W - x - w, W - x). */
			int64_t x = (screen ? (int64_t)c->screen_w : 0) - r.x - r.w;
			if (x < INT32_MIN || x > INT32_MAX)
				return false;
			out[i] = (struct vis_rect){ (int32_t)x, r.y, r.w, r.h };
		} else {
			out[i] = r;
		}
	}
	if (v == VARIANT_TRANSPOSED) {
		stack->screen_w = c->screen_h;
		stack->screen_h = c->screen_w;
	}
	return true;
}

/* Runs one engine on one variant of a case and prints the verdict; returns whether it passed. */
static bool check(const struct regress_case *c, const struct vis_stack *stack, enum variant v,
		  enum vis_engine e)
{
	uint8_t got[MAX_WINDOWS];
	char letters[MAX_WINDOWS + 1];
	bool ok = true;

	memset(got, 0xff, sizeof got);
	if (vis_compute(e, stack, got) != 0) {
		printf("FAIL %s%s [%s]: error: %s\n", c->name, variant_names[v], vis_engine_name(e),
		       strerror(errno));
		return false;
	}
	for (size_t i = 0; i < stack->n; i++) {
		letters[i] = state_letter(got[i]);
		ok = ok && got[i] == letter_state(c->want[i]);
	}
	letters[stack->n] = '\0';
	if (ok) {
		printf("ok   %s%s [%s]\n", c->name, variant_names[v], vis_engine_name(e));
		return true;
	}
	printf("FAIL %s%s [%s]: expected %s, got %s\n", c->name, variant_names[v],
	       vis_engine_name(e), c->want, letters);
	for (size_t i = 0; i < stack->n; i++) {
		if (got[i] == letter_state(c->want[i]))
			continue;
		const struct vis_rect *r = &stack->rects[i];
		printf("     window %zu (%d, %d, %d, %d): expected %s, got %s\n", i, r->x, r->y,
		       r->w, r->h, vis_state_name(letter_state(c->want[i])),
		       got[i] <= VIS_FULLY_OBSCURED ? vis_state_name((enum vis_state)got[i])
						    : "invalid");
	}
	return false;
}

int main(int argc, char **argv)
{
	unsigned passed = 0, failed = 0;
	bool engines[VIS_ENGINE_COUNT];
	struct vis_rect rects[MAX_WINDOWS];
	struct vis_stack stack;

	/* Optional engine names restrict the run. */
	for (int e = 0; e < VIS_ENGINE_COUNT; e++)
		engines[e] = argc < 2;
	for (int i = 1; i < argc; i++) {
		enum vis_engine e;
		if (vis_engine_from_name(argv[i], &e) != 0) {
			fprintf(stderr, "usage: %s [ENGINE]...\n", argv[0]);
			return 2;
		}
		engines[e] = true;
	}

	/* The empty stack: every engine must accept it. */
	stack = (struct vis_stack){ rects, 0, false, 0, 0, NULL, NULL };
	for (int e = 0; e < VIS_ENGINE_COUNT; e++) {
		uint8_t none[1];
		if (!engines[e])
			continue;
		if (vis_compute((enum vis_engine)e, &stack, none) == 0) {
			printf("ok   empty-stack [%s]\n", vis_engine_name((enum vis_engine)e));
			passed++;
		} else {
			printf("FAIL empty-stack [%s]: error: %s\n",
			       vis_engine_name((enum vis_engine)e), strerror(errno));
			failed++;
		}
	}

	for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
		const struct regress_case *c = &cases[k];
		size_t n = strlen(c->want);
		for (int v = 0; v < VARIANT_COUNT; v++) {
			if (!make_variant(c, n, (enum variant)v, rects, &stack))
				continue;
			for (int e = 0; e < VIS_ENGINE_COUNT; e++) {
				if (!engines[e])
					continue;
				if (check(c, &stack, (enum variant)v, (enum vis_engine)e))
					passed++;
				else
					failed++;
			}
		}
	}
	printf("%u passed, %u failed\n", passed, failed);
	return failed == 0 ? 0 : 1;
}
