/*
 * X's visibility rule applied one pixel at a time, straight from a vis_wtree's windows: the
 * oracle test-wtree.c checks the engines with, and x11-desk's brute force over a real X tree.
 * Nothing here is fast; everything is meant to be obviously what X does.
 *
 * A window's border box starts at its parent's inside's corner + (x, y); the inside starts border
 * pixels further in; shape and opaque rectangles are relative to the inside's corner. The screen
 * is the tree's root: (0, 0) to (root.width, root.height), exclusive.
 */
#ifndef VIS_TESTS_ORACLE_H
#define VIS_TESTS_ORACLE_H

#include <stdint.h>

#include "wtree.h"

/* The screen coordinates of w's border box's top-left corner. */
void oracle_corner(const struct vis_window *w, int64_t *bx, int64_t *by);
/* Whether (x, y) is in the union of r[0 … n). */
int oracle_in_rects(const struct vis_rect *r, uint32_t n, int64_t x, int64_t y);
/* Whether pixel (px, py) of the screen is one of w's own (its shape in its border box). */
int oracle_pixel_of(const struct vis_window *w, int64_t px, int64_t py);
/* Whether pixel (px, py) is an opaque pixel of w's own (its look's opaque mode). */
int oracle_opaque_of(const struct vis_window *w, int64_t px, int64_t py);
/* Whether pixel (px, py) is inside the screen and every ancestor's inside (and shape). */
int oracle_inside_chain(const struct vis_window *w, int64_t px, int64_t py);
/* Whether w and all its ancestors are mapped. */
int oracle_viewable(const struct vis_window *w);

/*
 * Every window's state by painting the screen: states[k] for the k-th window of the tree in
 * pre-order over all windows, mapped or not (vis_wtree_next() from tree->root.bottom; at most
 * tree->count). A window's pixels are oracle_pixel_of() ∩ oracle_inside_chain(); one of them is
 * covered when an opaque pixel there belongs to a viewable window later in pre-order that is not
 * its descendant (a later sibling's or an ancestor's later sibling's subtree: X's rule). The
 * state is 0 (unobscured) when every pixel of its own is uncovered and inside the chain, 2 (fully
 * obscured) when none is (or it has no pixel), else 1; VIS_WTREE_STATE_NONE for windows not
 * viewable and input-only ones. Returns the number of windows, or -1 when memory ran out.
 * O(Σ areas · depth) with the shapes' sizes: for small screens and tests.
 */
long oracle_paint(const struct vis_wtree *tree, uint8_t *states);

#endif
