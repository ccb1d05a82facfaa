#include "engine.h"

/*
 * The region method is nearly O(1) a window once the union of the windows above covers the
 * screen, which happens early on desktop-like stacks, but cubic on the grid and quadratic on tiled
 * or cascading stacks; the sweep is O(n log n) on all of them. So run the region method while its
 * work stays within what the sweep would cost, and hand over to the sweep past that: never much
 * slower than the region method where it is cheap, and within a constant of the sweep everywhere.
 * REGION_BOXES_PER_STEP converts one sweep step (a window times a tree level) into union boxes the
 * region method can touch in the same time; measured with `visctl bench`, see README.md.
 */
#define REGION_BOXES_PER_STEP 8

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
