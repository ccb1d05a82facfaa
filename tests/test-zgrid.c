/*
 * Unit tests of the stacking-order grid (src/zgrid.h) against a list: a walk lists, in key
 * order and once each, every entry beyond its start whose box meets what it asks about, however
 * it is narrowed or pruned, on areas whose cells are small (64 pixels) and large, with
 * boxes on the cells' edges, of one pixel, and the area's whole width.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "rng.h"
#include "zgrid.h"

struct entry {
	struct vis_box box;
	uint64_t key;
	bool in; /* in the grid */
};

static bool meets(struct vis_box a, struct vis_box b)
{
	return !vis_box_empty(vis_box_intersect(a, b));
}

/* A coordinate in [lo, hi), often on or beside a cell's edge. */
static int64_t coord(struct vis_rng *rng, int64_t lo, int64_t hi, int64_t side)
{
	int64_t c = vis_rng_range(rng, lo, hi - 1);
	if (vis_rng_below(rng, 3) == 0) {
		c = lo + (c - lo) / side * side + vis_rng_range(rng, -1, 1);
		c = c < lo ? lo : c >= hi ? hi - 1 : c;
	}
	return c;
}

/* A box inside area (not empty): a pixel, a sliver, a cell's size or up to the whole area. */
static struct vis_box random_box(struct vis_rng *rng, struct vis_box area, int64_t side)
{
	int64_t x = coord(rng, area.x1, area.x2, side), y = coord(rng, area.y1, area.y2, side);
	int64_t aw = area.x2 - area.x1, ah = area.y2 - area.y1, w, h;
	switch (vis_rng_below(rng, 4)) {
	case 0: w = h = 1; break;
	case 1: w = vis_rng_range(rng, 1, 8), h = vis_rng_range(rng, 1, ah); break;
	case 2: w = vis_rng_range(rng, 1, 2 * side), h = vis_rng_range(rng, 1, 2 * side); break;
	default: w = vis_rng_range(rng, 1, aw), h = vis_rng_range(rng, 1, ah); break;
	}
	struct vis_box b = { x, y, x + w, y + h };
	return vis_box_intersect(b, area);
}

/* What a walk is asked about: a box that may stick out of the area. */
static struct vis_box random_query(struct vis_rng *rng, struct vis_box area, int64_t side)
{
	struct vis_box b = random_box(rng, area, side);
	if (vis_rng_below(rng, 8) == 0)
		b.x1 -= vis_rng_range(rng, 1, side);
	if (vis_rng_below(rng, 8) == 0)
		b.y2 += vis_rng_range(rng, 1, side);
	return b;
}

/* A sub-box of b (not empty), as walks narrow to what is left of their pixels. */
static struct vis_box shrink(struct vis_rng *rng, struct vis_box b)
{
	int64_t x1 = vis_rng_range(rng, b.x1, b.x2 - 1), y1 = vis_rng_range(rng, b.y1, b.y2 - 1);
	int64_t x2 = vis_rng_range(rng, x1 + 1, b.x2), y2 = vis_rng_range(rng, y1 + 1, b.y2);
	return (struct vis_box){ x1, y1, x2, y2 };
}

static bool cell_meets_box(const void *arg, struct vis_box cell)
{
	return meets(*(const struct vis_box *)arg, cell);
}

/*
 * One walk from `from` over q, checked against the list: keys in order, each once, beyond from;
 * every entry that meets what the walk asks about when the walk passes its key is listed. The
 * walk is narrowed (or pruned to the cells meeting a box) now and then; while it was never
 * narrowed, every entry listed lies within a 16th of a cell's side of q.
 */
static void check_walk(const struct vis_zgrid *g, const struct entry *e, size_t n, struct vis_box q,
		       uint64_t from, bool up, int64_t unit, struct vis_rng *rng)
{
	struct vis_zgrid_walk walk;
	if (vis_zgrid_walk_init(&walk, g, q, from, up) < 0) {
		CHECK(!"walk_init failed");
		return;
	}
	bool *listed = calloc(n, sizeof *listed);
	/* The box asked about when the walk passed each key: what it asks about only shrinks. */
	struct vis_box now = q;
	bool narrowed = false;
	uint64_t last = from, key;
	uint32_t val;
	while (vis_zgrid_walk_next(&walk, &key, &val)) {
		CHECK(up ? key > last : key < last);
		CHECK(val < n && e[val].in && e[val].key == key);
		if (val >= n)
			break;
		CHECK(!listed[val]);
		listed[val] = true;
		if (!narrowed) {
			struct vis_box near = { q.x1 - unit + 1, q.y1 - unit + 1, q.x2 + unit - 1,
						q.y2 + unit - 1 };
			CHECK(meets(e[val].box, near));
		}
		/* Entries passed over between the last key and this one must have missed now. */
		for (size_t i = 0; i < n; i++)
			if (e[i].in && !listed[i] && (up ? e[i].key > last && e[i].key < key
						       : e[i].key < last && e[i].key > key))
				CHECK(!meets(e[i].box, now));
		last = key;
		if (vis_rng_below(rng, 6) == 0 && !vis_box_empty(vis_box_intersect(now, g->area))) {
			now = shrink(rng, vis_box_intersect(now, g->area));
			narrowed = true;
			vis_zgrid_walk_narrow(&walk, now);
			if (vis_rng_below(rng, 2) == 0) {
				/* Pruned to the cells that meet a part of it, some cells it meets
				 * left out: what it asks about is that part now. */
				struct vis_box part = shrink(rng, now);
				vis_zgrid_walk_keep(&walk, cell_meets_box, &part);
				now = part;
			}
		}
	}
	/* The rest, beyond the last key listed. */
	for (size_t i = 0; i < n; i++)
		if (e[i].in && !listed[i] && (up ? e[i].key > last : e[i].key < last))
			CHECK(!meets(e[i].box, now));
	vis_zgrid_walk_finish(&walk);
	free(listed);
}

static void test_area(struct vis_box area, uint64_t seed, size_t n, size_t walks)
{
	struct vis_rng rng = { seed };
	struct vis_zgrid g;
	if (vis_zgrid_init(&g, area, VIS_ZGRID_SIDE) < 0) {
		CHECK(!"init failed");
		return;
	}
	int64_t side = (int64_t)1 << g.shift;
	/* Parts are kept in 16ths of a cell's side: a listed entry lies that close to the box. */
	int64_t unit = (int64_t)1 << (g.shift - 4);
	struct entry *e = calloc(n, sizeof *e);
	uint64_t key = 1000;
	for (size_t i = 0; i < n; i++) {
		/* Some boxes twice: identical boxes under different keys. */
		e[i].box = i > 0 && vis_rng_below(&rng, 10) == 0 ? e[i - 1].box
								 : random_box(&rng, area, side);
		e[i].key = key += vis_rng_range(&rng, 1, 1000);
	}
	/* Inserted out of order, so that chunks split in the middle. */
	for (size_t k = 0; k < n; k++) {
		size_t i = (k * 7919) % n;
		CHECK(vis_zgrid_insert(&g, e[i].box, e[i].key, (uint32_t)i) == 0);
		e[i].in = true;
	}
	for (size_t w = 0; w < walks; w++) {
		/* Some entries leave and come back elsewhere: the parts go with their entries. */
		for (int m = 0; m < 4; m++) {
			size_t i = vis_rng_below(&rng, n);
			if (e[i].in) {
				vis_zgrid_remove(&g, e[i].box, e[i].key);
				e[i].in = false;
			} else {
				e[i].box = random_box(&rng, area, side);
				CHECK(vis_zgrid_insert(&g, e[i].box, e[i].key, (uint32_t)i) == 0);
				e[i].in = true;
			}
		}
		bool up = vis_rng_below(&rng, 2);
		uint64_t from = up ? (vis_rng_below(&rng, 4) ? e[vis_rng_below(&rng, n)].key : 0)
				   : (vis_rng_below(&rng, 4) ? e[vis_rng_below(&rng, n)].key
							      : UINT64_MAX);
		check_walk(&g, e, n, random_query(&rng, area, side), from, up, unit, &rng);
	}
	size_t in = 0, cells = 0;
	for (size_t i = 0; i < n; i++) {
		size_t k;
		in += e[i].in;
		if (e[i].in) {
			CHECK(vis_zgrid_holds(&g, e[i].box, e[i].key, &k));
			cells += k;
		}
	}
	CHECK(vis_zgrid_size(&g) == cells);
	CHECK(g.entries == cells);
	vis_zgrid_finish(&g);
	free(e);
}

int main(void)
{
	/* A screen (cells of 256: parts in 16-pixel steps), a small area (cells of 64, fewer than
	 * 16 a side), an area of a million pixels off the origin (cells of 2^17), and one near the
	 * 32-bit limits. */
	const struct vis_box areas[] = {
		{ 0, 0, 3840, 2160 },
		{ 0, 0, 100, 37 },
		{ -1000, 7, 1100000, 1100007 },
		{ INT32_MAX - 5000, INT32_MIN, INT32_MAX, INT32_MIN + 3000 },
	};
	for (size_t a = 0; a < sizeof areas / sizeof *areas; a++)
		for (uint64_t seed = 1; seed <= 4; seed++)
			test_area(areas[a], seed * 101 + a, seed == 4 ? 3000 : 400, 150);
	printf("zgrid: %s\n", failures ? "FAILED" : "ok");
	return failures != 0;
}
