/* The distinct x and y edges of a stack, for mapping edges to their ranks. */
#ifndef VIS_COORDS_H
#define VIS_COORDS_H

#include <stddef.h>
#include <stdint.h>

#include "stack.h"

/*
 * The distinct edges of the windows' screen-clipped, non-empty boxes, sorted: x[0 … nx) and
 * y[0 … ny). Ranks preserve order, so boxes mapped onto them keep every overlap and containment.
 */
struct vis_coords {
	int64_t *x, *y;
	size_t nx, ny;
};

/* Collects the edges. Returns 0, or -1 (ENOMEM, EOVERFLOW). O(n log n). */
int vis_coords_init(struct vis_coords *coords, const struct vis_stack *stack);

/* Frees the arrays. O(1). */
void vis_coords_finish(struct vis_coords *coords);

/* The rank of x edge v, which must be one of them. O(log n). */
size_t vis_coords_rank_x(const struct vis_coords *coords, int64_t v);

/* The rank of y edge v, which must be one of them. O(log n). */
size_t vis_coords_rank_y(const struct vis_coords *coords, int64_t v);

#endif
