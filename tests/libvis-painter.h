/*
 * test-libvis's model of a tree, kept beside libvis's through the public API alone, and its
 * painter: X's rule one pixel at a time, as tests/oracle.c has it for the core's trees, written
 * again over this model so that the test needs nothing of libvis but <vis/vis.h>. Nothing here is
 * fast; everything is meant to be obviously what X does.
 */
#ifndef VIS_TESTS_LIBVIS_PAINTER_H
#define VIS_TESTS_LIBVIS_PAINTER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <vis/vis.h>

#define PM_MAX 64  /* windows at most */
#define PM_RECTS 5 /* rectangles of a shape or opaque region at most */

/* A window as the test made it: slot 0 is the screen. Children bottom to top. */
struct pm_win {
	struct vis_win *win;
	bool alive, mapped, input_only, shaped, tracked;
	int parent;
	int kids[PM_MAX];
	int n_kids;
	int32_t x, y, w, h, border;
	uint32_t opaque; /* enum vis_opaque_mode */
	struct vis_rect32 shape[PM_RECTS], opq[PM_RECTS];
	uint32_t n_shape, n_opq;
	/* What libvis must say: the state at the last update; for a tracked window, the pixels
	 * (window coordinates, packed by pm_pack(), sorted) it showed then, as far as it knows. */
	int state;
	uint64_t *base;
	size_t n_base;
};

struct pm_tree {
	int32_t sw, sh;
	int max; /* the windows this tree may have, at most PM_MAX */
	struct pm_win w[PM_MAX + 1];
	bool dirty; /* changed since the last update */
};

/* A painted tree: every window's place in pre-order and what covers each screen pixel. */
struct pm_paint {
	int order[PM_MAX + 1]; /* slots in pre-order over every window, mapped or not */
	int pos[PM_MAX + 1];   /* a slot's index in order */
	int end[PM_MAX + 1];   /* by index: just past the subtree */
	int n;
	int *top; /* by pixel: the last index with an opaque pixel there, or -1 */
};

/* A window-coordinate pixel as one sortable number. */
static inline uint64_t pm_pack(int64_t x, int64_t y)
{
	return (uint64_t)(uint32_t)(int32_t)y << 32 | (uint32_t)(int32_t)x;
}

/* The screen coordinates of a window's inside's corner. */
void pm_inside(const struct pm_tree *t, int i, int64_t *ix, int64_t *iy);
/* Whether a window and its ancestors are mapped. */
bool pm_viewable(const struct pm_tree *t, int i);
/* Whether slot a is slot b or one of its ancestors. */
bool pm_is_ancestor(const struct pm_tree *t, int a, int b);

/* Paints the tree (p->top is allocated: pm_paint_finish()). false when memory ran out. */
bool pm_paint(const struct pm_tree *t, struct pm_paint *p);
void pm_paint_finish(struct pm_paint *p);

/* A window's state by X's rule (enum vis_visibility). */
int pm_state(const struct pm_tree *t, const struct pm_paint *p, int i);

/* The pixels of a viewable window with pixels that it sees, its descendants hiding none of them
 * (X's rule for its state; its visible region is less what they cover), else 0. */
uint64_t pm_seen(const struct pm_tree *t, const struct pm_paint *p, int i);

/*
 * Whether screen pixel (x, y) is visible of window i: its own, inside its ancestors and the
 * screen, and no opaque pixel of a later window in pre-order covers it.
 */
bool pm_visible(const struct pm_tree *t, const struct pm_paint *p, int i, int64_t x, int64_t y);

#endif
