/* Random bounding shapes for X windows, shared by the tools that test visd against X. */
#ifndef VIS_TESTS_XORG_SHAPE_H
#define VIS_TESTS_XORG_SHAPE_H

#include <stdbool.h>
#include <stdint.h>
#include <xcb/xcb.h>

#include "rng.h"

/*
 * A random bounding shape for a w×h window with border width border, in the window's coordinates
 * (the border's outer corner at -border, -border): nothing, the border box in two abutting
 * halves, a corner of it, or the box and a piece reaching past it. Writes at most 2 rectangles
 * into r and returns how many; *past_box says whether one reaches past the border box, where X
 * counts a band it cannot see as obscured (test-xorg.c). Draws one number from rng.
 */
uint32_t xorg_random_shape(struct vis_rng *rng, uint32_t w, uint32_t h, uint32_t border,
			   xcb_rectangle_t r[2], bool *past_box);

#endif
