#include "engine.h"

/*
 * The region method is nearly O(1) a window once the union of the windows above covers the
 * screen, which happens early on desktop-like stacks, but cubic on the grid and quadratic on tiled
 * or cascading stacks; the sweep is O(n log n) on all of them. So run the region method while its
 * work stays within what the sweep would cost, and hand over to the sweep past that: never much
 * slower than the region method where it is cheap, and within a constant of the sweep everywhere.
 * REGION_BOXES_PER_STEP converts one sweep step (a window times a tree level) into units of region
 * work (see vis_region_compute_within()). Measured on this project's bench scenes when it was
 * set: a unit costs 2–4 ns and a sweep step 35–85 ns, i.e. 12–30 units (the sweep has got faster
 * since, which makes the budget a little generous). At 40 the region method keeps every kind
 * where it beats the sweep (uniform n = 10^4 needs 26 units a step, cascade 29–37) and hands
 * the grid (5,700 units a step at n = 1,000) and small uniform stacks (227) to the sweep early.
 */
#define REGION_BOXES_PER_STEP 40

static uint64_t sweep_steps(size_t n)
{
	uint64_t levels = 1;
	while (((uint64_t)1 << levels) < 2 * (uint64_t)n)
		levels++;
	return (uint64_t)n * levels;
}

int vis_auto_compute(const struct vis_stack *stack, uint8_t *states)
{
	uint64_t budget = REGION_BOXES_PER_STEP * sweep_steps(stack->n);
	int rc = vis_region_compute_within(stack, states, budget);
	if (rc != 1)
		return rc;
	return vis_gmv_heap_compute(stack, states);
}
