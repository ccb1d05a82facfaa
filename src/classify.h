/* From the visible set to the three states. */
#ifndef VIS_CLASSIFY_H
#define VIS_CLASSIFY_H

#include <stdint.h>

#include "events.h"
#include "stack.h"

/*
 * Writes every window's state: fully-obscured unless its kept window k has visible[k]; a visible
 * window is unobscured when it lies wholly on the screen and no higher window overlaps it (any
 * overlap hides a pixel), partially-obscured otherwise. The overlap test is a second sweep, with
 * deletions before insertions at equal x, over the windows from the lowest candidate up; each
 * insertion asks for the highest window overlapping it and marks the lower candidates it overlaps.
 * Windows left out of ev are fully-obscured. Returns 0, or -1 (ENOMEM).
 * O(n log² n) time, O(n log n) space.
 */
int vis_classify(const struct vis_stack *stack, const struct vis_events *ev,
		 const uint8_t *visible, uint8_t *states);

#endif
