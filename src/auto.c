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
 * work is measured (docs/ENGINES.md): a unit costs 1.8–3 ns where unions dominate and 5–10 ns where
 * tests do; a step costs 13–78 ns on a screen (random, tiles, nested, cascade, grid: 3–13 units),
 * where the sweep's tree has at most as many leaves as the screen has lines, and 90–120 ns on the
 * unclipped uniform scene (24–60 units). Each price is near the dear end of its range, so that auto
 * never hands over to a sweep that costs more than the region method's rest; the cost is that
 * where the sweep is cheaper than priced (a cascade's, 4–7 units a step), auto keeps the region
 * method while it is forecast to cost up to 3 times the sweep.
 */
#define UNITS_PER_STEP_ON_SCREEN 12
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
