/* The cells a grid cuts an area into (zgrid.h, sgrid.h): squares of 2^shift pixels. */
#ifndef VIS_CELLS_H
#define VIS_CELLS_H

#include <stdbool.h>
#include <stdint.h>

#include "rect.h"

/* The cells along a length of pixels. */
static inline uint32_t vis_cells_along(int64_t length, unsigned shift)
{
	return (uint32_t)((length + ((int64_t)1 << shift) - 1) >> shift);
}

/* The smallest shift (from 64 pixels) that cuts area (not empty) into at most side cells a side. */
static inline unsigned vis_cells_shift(struct vis_box area, uint32_t side)
{
	unsigned shift = 6;
	while (vis_cells_along(area.x2 - area.x1, shift) > side ||
	       vis_cells_along(area.y2 - area.y1, shift) > side)
		shift++;
	return shift;
}

/* The cells box meets, as column and row ranges [r[0], r[2]] × [r[1], r[3]]; false when none. */
static inline bool vis_cells_met(struct vis_box area, unsigned shift, struct vis_box b,
				 uint32_t r[4])
{
	b = vis_box_intersect(b, area);
	if (vis_box_empty(b))
		return false;
	r[0] = (uint32_t)((b.x1 - area.x1) >> shift);
	r[1] = (uint32_t)((b.y1 - area.y1) >> shift);
	r[2] = (uint32_t)((b.x2 - 1 - area.x1) >> shift);
	r[3] = (uint32_t)((b.y2 - 1 - area.y1) >> shift);
	return true;
}

#endif
