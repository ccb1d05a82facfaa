/*
 * Unit tests of the banded regions (src/bands.h) against pixman's: boxes taken off a box one after
 * another (every other one with its part written out), on small grids where they share edges,
 * cover each other exactly and take all that is left, on fine ones where the regions grow past
 * those written again whole, and near the 32-bit limits; after each, the same pixels as pixman's
 * region, the invariants (bands sorted, disjoint, coalesced; exact extents), and the areas,
 * clips and intersections of random boxes, and clips less another box.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bands.h"
#include "check.h"
#include "rng.h"

/* The invariants of bands.h. */
static bool well_formed(const struct vis_bands *r)
{
	pixman_box32_t e = { INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN };
	for (size_t i = 0; i < r->n; i++) {
		const pixman_box32_t *b = &r->boxes[i];
		if (b->x1 >= b->x2 || b->y1 >= b->y2)
			return false;
		if (i > 0) {
			const pixman_box32_t *a = &r->boxes[i - 1];
			bool same_band = a->y1 == b->y1;
			if (same_band ? a->y2 != b->y2 || a->x2 >= b->x1 : a->y2 > b->y1)
				return false;
		}
		e.x1 = b->x1 < e.x1 ? b->x1 : e.x1;
		e.y1 = b->y1 < e.y1 ? b->y1 : e.y1;
		e.x2 = b->x2 > e.x2 ? b->x2 : e.x2;
		e.y2 = b->y2 > e.y2 ? b->y2 : e.y2;
	}
	/* Coalesced: two bands that touch differ in their columns. */
	for (size_t i = 0, j; i < r->n; i = j) {
		for (j = i; j < r->n && r->boxes[j].y1 == r->boxes[i].y1; j++)
			;
		size_t k = j;
		while (k < r->n && r->boxes[k].y1 == r->boxes[j].y1)
			k++;
		if (j < r->n && r->boxes[i].y2 == r->boxes[j].y1 && k - j == j - i) {
			size_t m = 0;
			while (m < j - i && r->boxes[i + m].x1 == r->boxes[j + m].x1 &&
			       r->boxes[i + m].x2 == r->boxes[j + m].x2)
				m++;
			if (m == j - i)
				return false;
		}
	}
	if (!r->n)
		return r->ext.x1 == 0 && r->ext.y1 == 0 && r->ext.x2 == 0 && r->ext.y2 == 0;
	return r->ext.x1 == e.x1 && r->ext.y1 == e.y1 && r->ext.x2 == e.x2 && r->ext.y2 == e.y2;
}

/* Whether r holds the pixels of p. */
static bool same_pixels(const struct vis_bands *r, pixman_region32_t *p)
{
	pixman_region32_t q, d;
	pixman_region32_init_rects(&q, r->boxes, (int)r->n);
	pixman_region32_init(&d);
	pixman_region32_subtract(&d, &q, p);
	bool same = !pixman_region32_not_empty(&d);
	pixman_region32_subtract(&d, p, &q);
	same &= !pixman_region32_not_empty(&d);
	pixman_region32_fini(&q);
	pixman_region32_fini(&d);
	return same;
}

/* Whether r holds the pixels of p inside box c. */
static bool same_inside(const struct vis_bands *r, pixman_region32_t *p, pixman_box32_t c)
{
	pixman_region32_t q;
	pixman_region32_init_rect(&q, c.x1, c.y1, (unsigned)(c.x2 - c.x1), (unsigned)(c.y2 - c.y1));
	pixman_region32_intersect(&q, &q, p);
	bool same = same_pixels(r, &q);
	pixman_region32_fini(&q);
	return same;
}

/* A random box in a span of side pixels from origin, on a grid of step, mostly small. */
static pixman_box32_t random_box(struct vis_rng *rng, int64_t origin, int64_t side, int64_t step)
{
	int64_t cells = side / step, most = vis_rng_below(rng, 4) ? cells / 4 + 1 : cells;
	int64_t x1 = vis_rng_range(rng, 0, cells - 1), y1 = vis_rng_range(rng, 0, cells - 1);
	int64_t x2 = vis_rng_range(rng, x1 + 1, x1 + most), y2 = vis_rng_range(rng, y1 + 1, y1 + most);
	x2 = x2 > cells ? cells : x2;
	y2 = y2 > cells ? cells : y2;
	return (pixman_box32_t){ (int32_t)(origin + x1 * step), (int32_t)(origin + y1 * step),
				 (int32_t)(origin + x2 * step), (int32_t)(origin + y2 * step) };
}

static uint64_t pixman_area_in(pixman_region32_t *p, pixman_box32_t b)
{
	pixman_region32_t q;
	pixman_region32_init_rect(&q, b.x1, b.y1, (unsigned)(b.x2 - b.x1), (unsigned)(b.y2 - b.y1));
	pixman_region32_intersect(&q, &q, p);
	int n;
	const pixman_box32_t *bs = pixman_region32_rectangles(&q, &n);
	uint64_t a = 0;
	for (int i = 0; i < n; i++)
		a += (uint64_t)(bs[i].x2 - bs[i].x1) * (uint64_t)(bs[i].y2 - bs[i].y1);
	pixman_region32_fini(&q);
	return a;
}

/* One run: a box, then boxes taken off it until it is empty or steps are done. */
static void run(struct vis_rng *rng, int64_t origin, int64_t side, int64_t step, int steps)
{
	struct vis_bands r, scratch, copy;
	vis_bands_init(&r);
	vis_bands_init(&scratch);
	vis_bands_init(&copy);
	pixman_region32_t p;
	pixman_box32_t start = { (int32_t)origin, (int32_t)origin, (int32_t)(origin + side),
				 (int32_t)(origin + side) };
	CHECK(vis_bands_set_box(&r, start) == 0);
	pixman_region32_init_rect(&p, start.x1, start.y1, (unsigned)(start.x2 - start.x1),
				  (unsigned)(start.y2 - start.y1));
	pixman_box32_t *out = malloc(2 * 64 * 1024 * sizeof *out);
	for (int s = 0; s < steps && r.n; s++) {
		pixman_box32_t b = random_box(rng, origin, side, step);
		if (s % 2 && r.n <= 64 * 1024) {
			/* Taken off with its part written out: the part is what a clip writes. */
			size_t k = vis_bands_clip(&r, b, out);
			CHECK(vis_bands_take(&r, &scratch, b, out + k) == (long)k);
			CHECK(!memcmp(out, out + k, k * sizeof *out));
		} else {
			CHECK(vis_bands_subtract(&r, &scratch, b) == 0);
		}
		pixman_region32_t q;
		pixman_region32_init_rect(&q, b.x1, b.y1, (unsigned)(b.x2 - b.x1),
					  (unsigned)(b.y2 - b.y1));
		pixman_region32_subtract(&p, &p, &q);
		pixman_region32_fini(&q);
		CHECK(well_formed(&r));
		CHECK(same_pixels(&r, &p));
		/* Areas and clips of other boxes. */
		pixman_box32_t c = random_box(rng, origin, side, step);
		CHECK(vis_bands_area_in(&r, c) == pixman_area_in(&p, c));
		if (r.n <= 64 * 1024) {
			size_t k = vis_bands_clip(&r, c, out);
			CHECK(k <= r.n);
			CHECK(vis_bands_set_less(&copy, out, k, (pixman_box32_t){ 0 }) == 0);
			CHECK(well_formed(&copy)); /* with its extents */
			CHECK(same_inside(&copy, &p, c));
			/* Less another box, as a region of its own. */
			pixman_box32_t h = random_box(rng, origin, side, step);
			CHECK(vis_bands_set_less(&copy, out, k, h) == 0);
			CHECK(well_formed(&copy));
			pixman_region32_t want, hr;
			pixman_region32_init(&want);
			pixman_region32_intersect_rect(&want, &p, c.x1, c.y1,
						       (unsigned)(c.x2 - c.x1),
						       (unsigned)(c.y2 - c.y1));
			pixman_region32_init_rect(&hr, h.x1, h.y1, (unsigned)(h.x2 - h.x1),
						  (unsigned)(h.y2 - h.y1));
			pixman_region32_subtract(&want, &want, &hr);
			CHECK(same_pixels(&copy, &want));
			pixman_region32_fini(&hr);
			pixman_region32_fini(&want);
		}
		CHECK(vis_bands_copy(&copy, &r) == 0);
		CHECK(copy.n == r.n && same_pixels(&copy, &p));
		/* The region inside another box, as a region of its own. */
		CHECK(vis_bands_intersect(&copy, &r, c) == 0);
		CHECK(well_formed(&copy));
		CHECK(same_inside(&copy, &p, c));
	}
	free(out);
	pixman_region32_fini(&p);
	vis_bands_finish(&r);
	vis_bands_finish(&scratch);
	vis_bands_finish(&copy);
}

int main(void)
{
	struct vis_rng rng = { 42 };
	for (int k = 0; k < 4000; k++) {
		/* Small grids (shared edges, exact covers), fine ones, and near the 32-bit edges. */
		switch (k % 4) {
		case 0:
			run(&rng, 0, 8, 1, 40);
			break;
		case 1:
			run(&rng, 100, 4000, 7, 80);
			break;
		case 2:
			run(&rng, INT32_MIN, 64, 1, 40);
			break;
		default:
			run(&rng, INT32_MAX - 64, 64, 8, 40);
			break;
		}
	}
	/* An empty box changes nothing; a box off the region neither. */
	struct vis_bands r, s;
	vis_bands_init(&r);
	vis_bands_init(&s);
	CHECK(vis_bands_set_box(&r, (pixman_box32_t){ 5, 5, 5, 9 }) == 0 && r.n == 0);
	CHECK(vis_bands_set_box(&r, (pixman_box32_t){ 0, 0, 10, 10 }) == 0 && r.n == 1);
	CHECK(vis_bands_subtract(&r, &s, (pixman_box32_t){ 10, 0, 20, 10 }) == 0 && r.n == 1);
	CHECK(vis_bands_subtract(&r, &s, (pixman_box32_t){ 0, 0, 10, 10 }) == 0 && r.n == 0);
	CHECK(well_formed(&r));
	vis_bands_finish(&r);
	vis_bands_finish(&s);
	if (failures)
		fprintf(stderr, "test-bands: %d checks failed\n", failures);
	else
		printf("test-bands: all checks passed\n");
	return failures != 0;
}
