/* Window trees made in X and in visd alike, their states compared (xorg-tree.c). */
#ifndef VIS_TESTS_XORG_TREE_H
#define VIS_TESTS_XORG_TREE_H

#include <stdbool.h>
#include <stdint.h>
#include <xcb/xcb.h>

/*
 * Runs count random trees (seeds seed0 …) on the W×H screen under root, against the visd at sock
 * (a manager connection); prints each disagreement. *quirks counts the windows whose shape
 * reaches past the border box that X calls partially obscured and visd unobscured. Returns the
 * number of trees that disagreed, or -1 when visd cannot be reached.
 */
int xorg_trees(xcb_connection_t *c, xcb_window_t root, int32_t W, int32_t H, const char *sock,
	       unsigned long count, unsigned long seed0, unsigned long *quirks);

#endif
