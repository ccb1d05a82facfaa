#include <stdlib.h>
#include <time.h>

#include "engine.h"

/*
 * The region method is nearly O(1) a window once the union of the windows above covers the
 * screen, which happens early on desktop-like stacks, but cubic on the grid and quadratic on tiled
 * or cascading stacks; the sweep is O(n log n) on all of them. So run the region method while the
 * forecast of its remaining work (region.c) stays within what the sweep costs, and hand over to
 * the sweep when it does not: a hand-over costs only the work already done, which the forecast
 * keeps small by deciding early (before the horizon of 2026-11-29, below 2 x 10^5 windows the
 * grid, cascades and small uniform stacks were recognised after 33-174 windows; a forecast now
 * speaks for the next 8 times the windows walked, which can take a doubling or three more).
 * The region's finished work is not kept: at every
 * hand-over measured the union had at least as many boxes as windows walked (uniform n = 10^3:
 * 767 boxes after 102 windows; cascade 65 after 33; grid 98 after 98), so sweeping the rest under
 * the union would cost as much as sweeping the whole stack.
 *
 * The sweep's cost is counted in steps, a window times a level of its tree, whose leaves lie
 * between the distinct y edges of the windows it keeps. A screen has at most its height and one
 * of those, so the count starts from that bound; at the first call of the rival's sharpen()
 * (region.c) a pass over the windows (a bit a row) counts the edges themselves: a cascade's tree
 * has 7-9 levels where the bound gives 11-12. Past SWEEP_CACHED_MAX windows the sweep's arrays
 * outgrow the cache, and its time a window grows 2-5-fold, whatever its tree, somewhere between
 * 3 x 10^5 and 7 x 10^5 windows: there it is counted as n ⌈log2 2n⌉ steps.
 *
 * What a step costs is not known before the sweep runs: on the family's first 1,000 scenes
 * (visctl bench --family, seed 1) the sweep took 8-600 ns a step, 75 at the median (steps
 * counted from n and the screen's height alone), and on the few checked a region unit took
 * 0.5-18 ns, so a price in units a step known beforehand (6 on a screen, 40 without, from visctl
 * gen's kinds) is wrong by up to 10 times either way on the scenes nobody tuned it for: the
 * family's worst misses (8.7 times the fastest engine) were such prices. So auto measures both
 * on the scene at hand: the region method's time so far on the monotonic clock, at each
 * checkpoint of its walk (about 40 ns a read), and the sweep's time by samples of the sweep
 * itself, run on every (n / m)th window of the stack and extrapolated by steps (0.7-1.8 times
 * the whole sweep's time on the scenes checked by hand: four of the family's and issue 33's
 * cascade of 10^3). The sweep's time over the walk's time per unit of work so far is the rival in
 * units (measured_units()).
 *
 * Below SAMPLE_MIN × SAMPLE_PART (256) windows the sweep is not measured: its smallest sample
 * would be more than an eighth of it, and on the family's stacks of 100-300 windows the samples
 * took `auto` from 1.16 to 1.39 times the fastest engine at the median. It is priced in time
 * there instead, NS_PER_STEP_GUESS a step, and that time in units at the walk's own time a unit
 * so far: the walk is measured, the sweep estimated, and the rule for an estimate decides
 * (region.c, hand_over(): its cap is twice it). A price in time misses by less than one in
 * units: on those stacks a step of the sweep took 15-132 ns from p5 to p95, but a unit of the
 * walk 0.5-18 ns, so the fixed 6 units a step of before was 0.8-260 times too low or high. On
 * 600 stacks of 100-256 windows for each of the family's seeds 1-5 (the price was chosen on 1
 * and 2), `auto` over the fastest engine went from 1.16-1.20 / 2.03-2.43 / 3.71-6.52 (median /
 * p95 / worst) to 1.13-1.16 / 1.86-1.95 / 3.31-4.05.
 * A sample costs time, so it is taken only where a hand-over is near: when the work reaches half
 * the sweep's steps at 6 units (LATE; on most desktop-like stacks the walk ends before), or when
 * a hand-over is about to be decided. It is sized to take at most an eighth of the walk's time so
 * far (at the last sample's price a step, 100 ns before one), 32 windows at least and an eighth
 * of them at most, and taken again with four times the windows once that fits; so the samples
 * cost about a sixth of the walk's time where the price holds.
 *
 * The rule (region.c, hand_over()), W the walk's time, S' the sweep's as measured, S its true
 * time, R the region method's whole time:
 * - the walk gives up at W = S' (the cap), or at W ≥ S' / 2 when the forecast of the rest (over
 *   the next 8 times the windows walked) exceeds S': a ski rental with advice, which buys at
 *   half the price when the advice says the rental will run long;
 * - early, while the work is at most a quarter of the rival, a forecast that exceeds the rival
 *   is acted on at once: the walk is then cheap to give up, and the grid, whose region method is
 *   cubic, is left after 50-160 windows. This hand-over is measured first when a sample of 32
 *   windows fits in an eighth of the walk's time so far, and decided again on S'.
 *
 * The worst case. Let a = S' / S. Measured, the cases are:
 * - a stack the walk finishes costs R ≤ S' (or the cap would have come): at most a times S;
 * - a hand-over at the cap costs S' + S against min(R, S) with R ≥ S': (1 + a) / min(1, a);
 * - a hand-over on a forecast at W ≥ S' / 2 costs W + S: against R ≥ W, if the forecast was
 *   wrong and R < S, at most 1 + 2 / a; if it was right, against S, at most 1 + a;
 * each with the samples on top, about a sixth of W. So auto is within max(1 + a, 1 + 2 / a,
 * (1 + a) / a) of the faster engine wherever the sweep is measured: 3 when the measurement is
 * exact, and 4 for any a between 2/3 and 3, where the samples checked lie. What the bound does
 * not cover: stacks below 256 windows, decided on the price in time (region.c: the cap at
 * twice the estimate, and a forecast acted on only where it has the walk passing that cap;
 * within max(1 + 2e, 1 + 1/e) where the forecast holds, e the price over the true one: 2.3 at
 * p95 of the prices measured, where the sweep costs more than guessed, and up to 14 at p5,
 * where it costs less, but only where the region method is the slower); and an early
 * hand-over that no sample fitted in, which costs W + S with W at most a quarter of the
 * estimate and rests on the forecast (on the family's seed 1: lattices where the region method
 * was 2-3 times faster). The noise is the
 * clock's: a walk or a sample that the scheduler interrupts is priced dearer, which can move the
 * hand-over, never the states.
 */
#define UNITS_PER_STEP_ON_SCREEN 6
#define UNITS_PER_STEP_UNCLIPPED 40
#define SWEEP_CACHED_MAX ((uint64_t)1 << 18)

/*
 * The sampling, as the comment above says: LATE, the share of the steps at
 * UNITS_PER_STEP_ON_SCREEN the work reaches before the sweep is measured; NS_PER_STEP_GUESS,
 * the price a step in ns that sizes the first sample and prices the sweep where no sample is
 * taken (the family's median is 75 over all its sizes, about 100 below 256 windows, whose
 * stacks have fewer levels to share a window's cost); a sample is at most 1/SAMPLE_SHARE of the
 * walk's time so far, taken again when
 * SAMPLE_GROWTH times the windows fit, of at most 1/SAMPLE_PART of the windows and at least
 * SAMPLE_MIN.
 */
#define LATE 2
#define NS_PER_STEP_GUESS 100
#define SAMPLE_SHARE 8
#define SAMPLE_GROWTH 4
#define SAMPLE_PART 8
#define SAMPLE_MIN 32

/* The levels of a tree over m edges: ⌈log2 m⌉, at least 1. */
static uint64_t levels(uint64_t m)
{
	uint64_t l = 1;
	while (((uint64_t)1 << l) < m)
		l++;
	return l;
}

/* price × steps, saturating. */
static uint64_t priced(uint64_t price, uint64_t steps)
{
	return steps != 0 && price > UINT64_MAX / steps ? UINT64_MAX : price * steps;
}

/* The distinct y edges of n windows clipped to the stack's screen, if any, at most. O(1). */
static uint64_t edges_at_most(const struct vis_stack *stack)
{
	uint64_t edges = 2 * (uint64_t)stack->n;

	if (stack->has_screen && (uint64_t)stack->screen_h + 1 < edges)
		edges = (uint64_t)stack->screen_h + 1;
	return edges;
}

/*
 * The sweep's steps, a window times a level of its tree, over the windows it keeps (those with
 * pixels on the screen), its tree having a leaf between each two of their distinct y edges. With
 * exact, on a screen, the edges are counted, a bit each (O(n + screen height / 64)); otherwise
 * they are bounded by twice the windows kept and the screen's height and one. Past
 * SWEEP_CACHED_MAX windows the sweep's arrays outgrow the cache and its time a window grows
 * 2-5-fold, whatever its tree (somewhere between 3 x 10^5 and 7 x 10^5 windows): there it is
 * n ⌈log2 2n⌉, whose extra levels stand for the misses. 0 if nothing is kept; UINT64_MAX when
 * the count could not be made (no memory).
 */
static uint64_t sweep_steps(const struct vis_stack *stack, bool exact)
{
	uint64_t n = stack->n, kept = 0, edges = 0;
	uint64_t *seen = NULL;

	if (n > SWEEP_CACHED_MAX)
		return n * levels(2 * n);
	exact = exact && stack->has_screen;
	if (exact && (seen = calloc((size_t)stack->screen_h / 64 + 1, sizeof *seen)) == NULL)
		return UINT64_MAX;
	for (size_t i = 0; i < stack->n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		kept++;
		if (exact) {
			seen[b.y1 / 64] |= (uint64_t)1 << (b.y1 % 64);
			seen[b.y2 / 64] |= (uint64_t)1 << (b.y2 % 64);
		}
	}
	if (exact) {
		for (size_t w = 0; w <= (size_t)stack->screen_h / 64; w++)
			edges += (uint64_t)__builtin_popcountll(seen[w]);
		free(seen);
	} else {
		edges = 2 * kept;
		if (stack->has_screen && (uint64_t)stack->screen_h + 1 < edges)
			edges = (uint64_t)stack->screen_h + 1;
	}
	return kept == 0 ? 0 : kept * levels(edges);
}

/* What the rival's sharpen() keeps between calls (vis_auto_compute_priced(), measured_units()). */
struct gauge {
	uint64_t price;   /* units a step, when priced */
	bool exact;       /* the edges counted (sweep_steps()) */
	bool counted;     /* steps counted: */
	uint64_t steps;
	double start;     /* ns: when the walk began */
	double sampled;   /* ns spent on samples */
	double sweep;     /* ns: the sweep's time as the last sample forecasts it; 0 before one */
	size_t sample_n;  /* the windows of the last sample */
};

/* The monotonic clock, in ns. */
static double now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

/*
 * The sweep timed on m windows of the stack, every (n / m)th, its time extrapolated to the whole
 * stack by their steps: ns, or 0 when it could not be measured (no memory, nothing kept).
 */
static double sample_sweep(const struct vis_stack *stack, size_t m, uint64_t steps, bool exact)
{
	size_t stride = stack->n / m;
	struct vis_rect *rects = malloc(m * sizeof *rects);
	uint8_t *see = stack->see_through != NULL ? malloc(m) : NULL;
	uint8_t *states = malloc(m);
	double ns = 0;

	if (rects != NULL && states != NULL && (see != NULL || stack->see_through == NULL)) {
		for (size_t j = 0; j < m; j++) {
			rects[j] = stack->rects[j * stride + stride / 2];
			if (see != NULL)
				see[j] = stack->see_through[j * stride + stride / 2];
		}
		struct vis_stack sub = *stack;
		sub.rects = rects;
		sub.n = m;
		sub.see_through = see;
		uint64_t sub_steps = sweep_steps(&sub, exact);
		double t0 = now_ns();
		int rc = vis_gmv_heap_compute(&sub, states);
		double t = now_ns() - t0;
		if (rc == 0 && sub_steps != 0 && sub_steps != UINT64_MAX && steps != UINT64_MAX)
			ns = t * (double)steps / (double)sub_steps;
	}
	free(rects);
	free(see);
	free(states);
	return ns;
}

/* The rival priced: price × the steps, counted once. */
static uint64_t priced_units(const struct vis_stack *stack, const void *data, uint64_t work,
			     bool handing, bool *measured)
{
	struct gauge *g = (struct gauge *)data;

	(void)work;
	(void)handing;
	*measured = false;
	if (!g->counted) {
		g->steps = sweep_steps(stack, g->exact);
		g->counted = true;
	}
	return priced(g->price, g->steps);
}

/* ns of the sweep in units of the walk's work, which took walk ns for work units. */
static uint64_t in_units(double ns, uint64_t work, double walk)
{
	double units = ns * (double)work / walk;
	return units >= 0x1p63 ? UINT64_MAX / 2 : (uint64_t)units;
}

/*
 * The rival at every checkpoint of the walk: the estimate (price × steps) until the work reaches
 * 1/LATE of the steps at UNITS_PER_STEP_ON_SCREEN or a hand-over is asked for (an early one only
 * where a sample fits), the sweep's time as samples of it forecast it from then on, in units of
 * the region method's work as its walk has priced them so far (its time over its work). See the
 * comment above UNITS_PER_STEP_ON_SCREEN.
 */
static uint64_t measured_units(const struct vis_stack *stack, const void *data, uint64_t work,
			       bool handing, bool *measured)
{
	struct gauge *g = (struct gauge *)data;
	size_t n = stack->n, least = n < SAMPLE_MIN ? n : SAMPLE_MIN;
	size_t most = n / SAMPLE_PART > least ? n / SAMPLE_PART : least;
	uint64_t estimate = priced_units(stack, data, work, handing, measured);

	if (g->steps == 0 || g->steps == UINT64_MAX)
		return estimate;
	double walk = now_ns() - g->start - g->sampled;
	/* Too few windows to sample: the sweep priced in time (still an estimate). */
	if (n < SAMPLE_MIN * SAMPLE_PART)
		return walk > 0 && work > 0
			       ? in_units((double)g->steps * NS_PER_STEP_GUESS, work, walk)
			       : estimate;
	if (g->sweep <= 0 && !handing && work < priced(UNITS_PER_STEP_ON_SCREEN, g->steps) / LATE)
		return estimate;
	double per_step = g->sweep > 0 ? g->sweep / (double)g->steps : NS_PER_STEP_GUESS;
	double fits = (double)n * walk / SAMPLE_SHARE / ((double)g->steps * per_step);
	/* An early hand-over is measured only when a sample fits: it throws little away. */
	if (g->sweep <= 0 && handing && work <= estimate / VIS_RIVAL_EARLY && fits < (double)least)
		return estimate;
	if (g->sample_n == 0 || (fits >= (double)(SAMPLE_GROWTH * g->sample_n) && g->sample_n < most)) {
		size_t m = fits >= (double)most ? most : fits <= (double)least ? least : (size_t)fits;
		double t0 = now_ns();
		double ns = sample_sweep(stack, m, g->steps, g->exact);
		g->sampled += now_ns() - t0;
		g->sample_n = m;
		if (ns > 0)
			g->sweep = ns;
	}
	if (g->sweep <= 0)
		return estimate;
	*measured = true;
	return in_units(g->sweep, work > 0 ? work : 1, walk > 1 ? walk : 1);
}

int vis_auto_compute_priced(const struct vis_stack *stack, uint8_t *states, uint64_t units_per_step)
{
	struct gauge g = { .price = units_per_step };
	struct vis_rival rival = { .data = &g };

	rival.units = priced(units_per_step, stack->n > SWEEP_CACHED_MAX
						     ? sweep_steps(stack, false)
						     : stack->n * levels(edges_at_most(stack)));
	if (stack->n <= SWEEP_CACHED_MAX && stack->has_screen &&
	    (uint64_t)stack->screen_h / 64 <= stack->n) {
		g.exact = true;
		rival.floor = rival.units / 4;
		rival.sharpen = priced_units;
	}
	int rc = vis_region_compute_against(stack, states, &rival);
	if (rc != 1)
		return rc;
	return vis_gmv_heap_compute(stack, states);
}

int vis_auto_compute(const struct vis_stack *stack, uint8_t *states)
{
	struct gauge g = {
		.price = stack->has_screen ? UNITS_PER_STEP_ON_SCREEN : UNITS_PER_STEP_UNCLIPPED,
		.exact = stack->n <= SWEEP_CACHED_MAX && stack->has_screen &&
			 (uint64_t)stack->screen_h / 64 <= stack->n,
		.start = now_ns(),
	};
	struct vis_rival rival = { .sharpen = measured_units, .data = &g };
	uint64_t bound = stack->n * levels(edges_at_most(stack));

	/* Nothing is handed over before the first call (region.c), nor counted or measured. */
	rival.units = priced(g.price, bound);
	rival.floor = priced(UNITS_PER_STEP_ON_SCREEN, bound) / LATE;
	int rc = vis_region_compute_against(stack, states, &rival);
	if (rc != 1)
		return rc;
	return vis_gmv_heap_compute(stack, states);
}
