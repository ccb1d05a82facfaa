#include "engine.h"

/*
 * The region method is nearly O(1) a window once the union of the windows above covers the
 * screen, which happens early on desktop-like stacks, but cubic on the grid and quadratic on tiled
 * or cascading stacks; the sweep is O(n log n) on all of them. So run the region method while the
 * forecast of its remaining work (region.c) stays within what the sweep costs, and hand over to
 * the sweep when it does not: a hand-over costs only the work already done, which the forecast
 * keeps small by deciding early (the grid, cascades and small uniform stacks are recognised after
 * 90–180 windows). The region's finished work is not kept: at every hand-over measured the union
 * had at least as many boxes as windows walked (uniform n = 10^3: 767 boxes after 102 windows;
 * cascade 189 after 95; grid 98 after 98), so sweeping the rest under the union would cost as much
 * as sweeping the whole stack.
 *
 * The price of one sweep step (a window times a tree level, n ⌈log2 2n⌉ steps) in units of region
 * work is measured (docs/ENGINES.md, every kind, seeds 1–3, n = 10^3 … 10^6): a step costs 1.7–7.7
 * units on cascades, whose consecutive windows share the sweep's paths, 2.5–13.8 on the other
 * kinds on a screen, and 19–65 on the unclipped uniform scene. No price known before the sweep
 * runs can tell a cascade from tiles, so a wrong choice costs the ratio of the price to the true
 * one, or its inverse: the price on a screen, 6, sits near the middle of its range in ratio
 * (√(1.7 × 13.8) ≈ 4.8), a little toward the dear end, which keeps the forecasts of the scenes
 * where the region method wins (random, tiles, nested, shaped, translucent: at most 3 units a
 * step on seeds 1–6) at half the price or less. A price of 12, the dear end, made auto keep the
 * region method on cascades where it took 2–5 times the sweep's time (seeds 2–5, n = 10^3 … 10^5).
 * Without a screen the price stays 40, near the dear end of 19–65, so that uniform n = 10^4,
 * forecast at 0.48–0.78 of it, keeps the region method that is faster there.
 */
#define UNITS_PER_STEP_ON_SCREEN 6
#define UNITS_PER_STEP_UNCLIPPED 40

/* The steps of the sweep over n windows: n times the levels of a tree over their 2n edges. */
static uint64_t sweep_steps(size_t n)
{
	uint64_t levels = 1;
	while (((uint64_t)1 << levels) < 2 * (uint64_t)n)
		levels++;
	return (uint64_t)n * levels;
}

int vis_auto_compute_priced(const struct vis_stack *stack, uint8_t *states, uint64_t units_per_step)
{
	uint64_t steps = sweep_steps(stack->n);
	uint64_t rival = steps != 0 && units_per_step > UINT64_MAX / steps ? UINT64_MAX
									  : units_per_step * steps;
	int rc = vis_region_compute_against(stack, states, rival);
	if (rc != 1)
		return rc;
	return vis_gmv_heap_compute(stack, states);
}

int vis_auto_compute(const struct vis_stack *stack, uint8_t *states)
{
	return vis_auto_compute_priced(stack, states, stack->has_screen ? UNITS_PER_STEP_ON_SCREEN
									 : UNITS_PER_STEP_UNCLIPPED);
}
