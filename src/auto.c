#include <stdlib.h>

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
 * of those, so the count starts from that bound; once a forecast or the work done reaches a
 * quarter of it, a pass over the windows (a bit a row) counts the edges themselves: a cascade's
 * tree has 7-9 levels where the bound gives 11-12. Past SWEEP_CACHED_MAX windows the sweep's
 * arrays outgrow the cache, and its time a window grows 2-5-fold, whatever its tree, somewhere
 * between 3 x 10^5 and 7 x 10^5 windows (where varies from run to run): there it is counted as
 * n ⌈log2 2n⌉ steps, whose extra levels stand for the misses.
 *
 * The price of a step in units of region work is measured (docs/ENGINES.md, every kind, seeds
 * 1-6, n = 10^3 ... 10^6): 2.7-8.7 units on cascades, whose consecutive windows take the same
 * paths through a small tree, 3.1-15.5 on the other kinds on a screen, and 21-64 on the unclipped
 * uniform scene. No price known before the sweep runs tells a cascade from tiles, so a wrong
 * choice costs the ratio of the price to the true one, or its inverse: the price on a screen, 6,
 * sits near the middle of its range in ratio (√(2.7 × 15.5) ≈ 6.5), which keeps the scenes where
 * the region method wins on it (random, tiles, nested, shaped, translucent, seeds 1-6: their whole
 * region work at most 0.74 of the price). Without a screen the price stays 40, near the dear end
 * of 21-64, so that uniform n = 10^4, forecast at 0.49-0.71 of it, keeps the region method that is
 * faster there.
 *
 * The worst case. Let e be the price used over the true one, so that the estimate, timed as region
 * work, is e times the sweep's time S: e is 6 / 15.5 ... 6 / 2.7 on a screen and 40 / 64 ...
 * 40 / 21 without, where measured on visctl gen's kinds. The region method's work is counted so
 * that it bounds its time up to a constant (region.c), and it gives up by twice the estimate, so:
 * - a stack it finishes costs its time R, less than twice the estimate: at most 2e times the
 *   sweep's time S;
 * - a hand-over at the cap costs the work done, twice the estimate, and the sweep: at most
 *   (1 + 2e) S, and 1 + 1 / (2e) times R, which is past the cap;
 * - a hand-over on a forecast costs the work done, which is below the cap, and S: at most
 *   (1 + 2e) S; against R it costs 1 + 1 / e times R if the forecast for the next 8 k windows
 *   holds (R then exceeds the estimate), and that forecast is the one thing the bound rests on
 *   besides e. It is measured over at least k / 2 windows and speaks for 8 k: a wrong one means a
 *   union that stops growing within 16 times the windows it was seen growing over, which is how
 *   the family's worst misses were made before the horizon (13 and 9.6 times, cascades without a
 *   screen, when it spoke for every window left).
 * So auto is within max(1 + 2e, 1 + 1 / e) of the fastest engine wherever the forecast holds:
 * 5.4 at the cheapest sweep measured on a screen (e = 2.2), 4.8 without one. e itself is not
 * measured on the scene at hand; the sweep's first slice, timed, would measure it
 * (docs/ENGINES.md, "The worst case, and what remains"), and the family benchmark (visctl bench
 * --family) shows what the scenes nobody tuned for make of it.
 */
#define UNITS_PER_STEP_ON_SCREEN 6
#define UNITS_PER_STEP_UNCLIPPED 40
#define SWEEP_CACHED_MAX ((uint64_t)1 << 18)

/* The levels of a tree over m edges: ⌈log2 m⌉, at least 1. */
static uint64_t levels(uint64_t m)
{
	uint64_t l = 1;
	while (((uint64_t)1 << l) < m)
		l++;
	return l;
}

/* price × windows × levels, saturating. */
static uint64_t sweep_units(uint64_t price, uint64_t windows, uint64_t levels)
{
	uint64_t steps = windows * levels; /* windows < 2^58: no overflow */
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
 * The sweep's cost over the windows it keeps (those with pixels on the screen), its tree having
 * a leaf between each two of their distinct y edges, which lie on the screen: a bit each. O(n +
 * screen height / 64); made only when the screen is at most 64 bits a window high.
 */
static uint64_t sweep_units_exact(const struct vis_stack *stack, const void *data)
{
	uint64_t price = *(const uint64_t *)data;
	size_t words = (size_t)stack->screen_h / 64 + 1, kept = 0, edges = 0;
	uint64_t *seen = calloc(words, sizeof *seen);

	if (seen == NULL) /* the bound stays: only the choice can suffer */
		return sweep_units(price, stack->n, levels(edges_at_most(stack)));
	for (size_t i = 0; i < stack->n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		kept++;
		seen[b.y1 / 64] |= (uint64_t)1 << (b.y1 % 64);
		seen[b.y2 / 64] |= (uint64_t)1 << (b.y2 % 64);
	}
	for (size_t w = 0; w < words; w++)
		edges += (size_t)__builtin_popcountll(seen[w]);
	free(seen);
	return sweep_units(price, kept, levels(edges));
}

int vis_auto_compute_priced(const struct vis_stack *stack, uint8_t *states, uint64_t units_per_step)
{
	uint64_t n = stack->n;
	struct vis_rival rival = { .data = &units_per_step };

	if (n > SWEEP_CACHED_MAX) {
		rival.units = sweep_units(units_per_step, n, levels(2 * n));
	} else {
		rival.units = sweep_units(units_per_step, n, levels(edges_at_most(stack)));
		if (stack->has_screen && (uint64_t)stack->screen_h / 64 <= n) {
			rival.floor = rival.units / 4;
			rival.sharpen = sweep_units_exact;
		}
	}
	int rc = vis_region_compute_against(stack, states, &rival);
	if (rc != 1)
		return rc;
	return vis_gmv_heap_compute(stack, states);
}

int vis_auto_compute(const struct vis_stack *stack, uint8_t *states)
{
	return vis_auto_compute_priced(stack, states, stack->has_screen ? UNITS_PER_STEP_ON_SCREEN
									 : UNITS_PER_STEP_UNCLIPPED);
}
