/* Rectangles of the window stack. */
#ifndef VIS_RECT_H
#define VIS_RECT_H

#include <stdbool.h>
#include <stdint.h>

/*
 * A window's rectangle: it covers the integer pixels [x, x + w) × [y, y + h).
 * x, y inclusive; x + w, y + h exclusive. w, h ≥ 1 and at most INT32_MAX, so the
 * exclusive edges may exceed INT32_MAX: compute them with vis_rect_box().
 * Two rectangles that only touch (B.x == A.x + A.w) do not overlap.
 */
struct vis_rect {
	int32_t x, y;
	int32_t w, h;
};

/*
 * A half-open box with 64-bit edges: pixels [x1, x2) × [y1, y2).
 * Empty when x1 >= x2 or y1 >= y2.
 */
struct vis_box {
	int64_t x1, y1, x2, y2;
};

/* The box of a rectangle's pixels. O(1). */
static inline struct vis_box vis_rect_box(struct vis_rect r)
{
	struct vis_box b = { r.x, r.y, (int64_t)r.x + r.w, (int64_t)r.y + r.h };
	return b;
}

/* Whether a box holds no pixel. O(1). */
static inline bool vis_box_empty(struct vis_box b)
{
	return b.x1 >= b.x2 || b.y1 >= b.y2;
}

/* The pixels two boxes share (possibly empty). O(1). */
static inline struct vis_box vis_box_intersect(struct vis_box a, struct vis_box b)
{
	struct vis_box r = {
		a.x1 > b.x1 ? a.x1 : b.x1, a.y1 > b.y1 ? a.y1 : b.y1,
		a.x2 < b.x2 ? a.x2 : b.x2, a.y2 < b.y2 ? a.y2 : b.y2,
	};
	return r;
}

/* The smallest box holding a and b; an empty one adds nothing. O(1). */
static inline struct vis_box vis_box_hull(struct vis_box a, struct vis_box b)
{
	if (vis_box_empty(a))
		return b;
	if (vis_box_empty(b))
		return a;
	struct vis_box r = {
		a.x1 < b.x1 ? a.x1 : b.x1, a.y1 < b.y1 ? a.y1 : b.y1,
		a.x2 > b.x2 ? a.x2 : b.x2, a.y2 > b.y2 ? a.y2 : b.y2,
	};
	return r;
}

/* Whether two boxes have the same edges. O(1). */
static inline bool vis_box_equal(struct vis_box a, struct vis_box b)
{
	return a.x1 == b.x1 && a.y1 == b.y1 && a.x2 == b.x2 && a.y2 == b.y2;
}

/* Whether box a holds every pixel of box b (b non-empty). O(1). */
static inline bool vis_box_contains(struct vis_box a, struct vis_box b)
{
	return a.x1 <= b.x1 && a.y1 <= b.y1 && b.x2 <= a.x2 && b.y2 <= a.y2;
}

#endif
