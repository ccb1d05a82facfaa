/*
 * A region of the screen as y-x banded boxes, for the walks that take a box off it window after
 * window (libvis's repaint set and tallies): pixman's operations are general, and set up, allocate
 * and free at each call, which costs more than the few boxes a damaged area holds once windows
 * have been taken off it.
 *
 * Invariants, as pixman's regions: boxes are non-empty, x1 < x2 and y1 < y2 (x1, y1 inclusive;
 * x2, y2 exclusive); they form bands, runs of boxes that share y1 and y2, sorted by x and not
 * touching within a band; bands are sorted by y1 and do not overlap; two bands that touch
 * vertically differ in their boxes' x edges (coalesced). ext is the boxes' extents (all zero when
 * there are none).
 */
#ifndef VIS_BANDS_H
#define VIS_BANDS_H

#include <pixman.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

struct vis_bands {
	pixman_box32_t *boxes;
	size_t n, cap;
	pixman_box32_t ext;
};

/* An empty region. O(1). */
void vis_bands_init(struct vis_bands *r);

/* Frees the boxes. O(1). */
void vis_bands_finish(struct vis_bands *r);

/* Makes r the box b (empty when b is). 0, or -1 with ENOMEM (r is then empty). O(1). */
int vis_bands_set_box(struct vis_bands *r, pixman_box32_t b);

/* Makes r the n boxes b, banded and coalesced as a region's, less box h (maybe empty). 0, or -1
 * with ENOMEM (r is then empty). O(n). */
int vis_bands_set_less(struct vis_bands *r, const pixman_box32_t *b, size_t n, pixman_box32_t h);

/* Makes dst a copy of src. 0, or -1 with ENOMEM (dst is then empty). O(n). */
int vis_bands_copy(struct vis_bands *dst, const struct vis_bands *src);

/* a ∩ b: empty (x1 ≥ x2 or y1 ≥ y2) when they do not meet. O(1). */
static inline pixman_box32_t vis_pbox_and(pixman_box32_t a, pixman_box32_t b)
{
	return (pixman_box32_t){ a.x1 > b.x1 ? a.x1 : b.x1, a.y1 > b.y1 ? a.y1 : b.y1,
				 a.x2 < b.x2 ? a.x2 : b.x2, a.y2 < b.y2 ? a.y2 : b.y2 };
}

/* The pixels of a box that is not empty. O(1). */
static inline uint64_t vis_pbox_area(pixman_box32_t b)
{
	return (uint64_t)((int64_t)b.x2 - b.x1) * (uint64_t)((int64_t)b.y2 - b.y1);
}

/* Whether a box shares a pixel with the region's extents. O(1). */
static inline bool vis_bands_meet(const struct vis_bands *r, pixman_box32_t b)
{
	return r->n && b.x1 < r->ext.x2 && r->ext.x1 < b.x2 && b.y1 < r->ext.y2 &&
	       r->ext.y1 < b.y2;
}

/*
 * Takes box b off r, through scratch (another region, for its room). 0, or -1
 * with ENOMEM (r is then unchanged). O(n).
 */
int vis_bands_subtract(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b);

/*
 * Takes box b off r, through scratch, and writes the boxes of r ∩ b to out (as vis_bands_clip()
 * does: banded, coalesced, at most r->n); returns how many, or -1 with ENOMEM (r is then
 * unchanged). One pass where the two calls take two. O(n).
 */
long vis_bands_take(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b,
		    pixman_box32_t *out);

/* Makes dst (not src) src ∩ b. 0, or -1 with ENOMEM (dst is then empty). O(n). */
int vis_bands_intersect(struct vis_bands *dst, const struct vis_bands *src, pixman_box32_t b);

/* The number of pixels r shares with box b. O(n). */
uint64_t vis_bands_area_in(const struct vis_bands *r, pixman_box32_t b);

/*
 * Writes the boxes of r ∩ b to out, y-x banded and coalesced as a region's, and returns how many:
 * at most r->n. O(n).
 */
size_t vis_bands_clip(const struct vis_bands *r, pixman_box32_t b, pixman_box32_t *out);

#endif
