/*
 * The brute force: the oracle the other engines are tested against, so it is written to be
 * obviously correct rather than fast. The distinct edges of the clipped windows cut the plane
 * into a grid of cells, each cell wholly inside or wholly outside every window; painting the
 * opaque windows bottom-to-top leaves each cell owned by the topmost opaque window over it, and a
 * window's pixels in a cell are visible iff no window above it owns the cell.
 */
#include <errno.h>
#include <stdlib.h>

#include "coords.h"
#include "engine.h"

#define NO_OWNER UINT32_MAX

int vis_brute_compute(const struct vis_stack *stack, uint8_t *states)
{
	size_t n = stack->n, cols, rows, cells;
	struct vis_coords co = { 0 };
	uint32_t *owner = NULL;
	size_t *owned = NULL;
	int ret = -1;

	/* Window indices are stored in uint32 cells, NO_OWNER excluded. */
	if (n >= NO_OWNER) {
		errno = EOVERFLOW;
		return -1;
	}
	if (vis_coords_init(&co, stack) < 0)
		return -1;
	cols = co.nx > 0 ? co.nx - 1 : 0;
	rows = co.ny > 0 ? co.ny - 1 : 0;
	if (cols != 0 && rows > SIZE_MAX / sizeof *owner / cols) {
		errno = EOVERFLOW;
		goto out;
	}
	cells = cols * rows;
	owner = malloc((cells + 1) * sizeof *owner);
	if (owner == NULL) {
		errno = ENOMEM;
		goto out;
	}
	for (size_t c = 0; c < cells; c++)
		owner[c] = NO_OWNER;
	owned = calloc(n + 1, sizeof *owned);
	if (owned == NULL) {
		errno = ENOMEM;
		goto out;
	}

	for (size_t i = 0; i < n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b) || !vis_stack_opaque(stack, i))
			continue;
		size_t c1 = vis_coords_rank_x(&co, b.x1), c2 = vis_coords_rank_x(&co, b.x2);
		size_t r1 = vis_coords_rank_y(&co, b.y1), r2 = vis_coords_rank_y(&co, b.y2);
		for (size_t r = r1; r < r2; r++) {
			for (size_t c = c1; c < c2; c++)
				owner[r * cols + c] = (uint32_t)i;
		}
	}

	/*
	 * An opaque window owns every cell of its own where it is the topmost opaque window, so its
	 * visible cells are those it owns, counted in one pass over the grid; only a see-through
	 * window, which owns none, needs its cells read (reading every window's cells made the brute
	 * force 20 times slower on a cascade of 10^3 large windows: 52 ms against 2.6).
	 */
	for (size_t c = 0; c < cells; c++) {
		if (owner[c] != NO_OWNER)
			owned[owner[c]]++;
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		size_t seen = 0;
		if (vis_box_empty(b)) {
			states[i] = VIS_FULLY_OBSCURED;
			continue;
		}
		size_t c1 = vis_coords_rank_x(&co, b.x1), c2 = vis_coords_rank_x(&co, b.x2);
		size_t r1 = vis_coords_rank_y(&co, b.y1), r2 = vis_coords_rank_y(&co, b.y2);
		if (vis_stack_opaque(stack, i))
			seen = owned[i];
		for (size_t r = r1; r < r2 && !vis_stack_opaque(stack, i); r++) {
			for (size_t c = c1; c < c2; c++)
				seen += owner[r * cols + c] == NO_OWNER || owner[r * cols + c] <= i;
		}
		/* Unobscured needs the whole window, not just its on-screen part, to be visible. */
		if (seen == 0)
			states[i] = VIS_FULLY_OBSCURED;
		else if (vis_stack_on_screen(stack, i) && seen == (c2 - c1) * (r2 - r1))
			states[i] = VIS_UNOBSCURED;
		else
			states[i] = VIS_PARTIALLY_OBSCURED;
	}
	ret = 0;
out:
	vis_coords_finish(&co);
	free(owner);
	free(owned);
	return ret;
}
