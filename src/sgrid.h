/*
 * A spatial index of boxes without order: each grid cell keeps a bag of the boxes that meet it,
 * so that finding the boxes that meet a region costs the entries of its cells, and adding one
 * costs its cells. Entries are never removed one by one: each carries a stamp, the caller's
 * word on whether it still stands, and a cell that has doubled since it was last swept drops
 * the entries its caller says are gone.
 */
#ifndef VIS_SGRID_H
#define VIS_SGRID_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rect.h"

struct vis_sgrid_entry {
	int32_t x1, y1, x2, y2; /* the box, inside the area */
	uint32_t val, stamp;
};

struct vis_sgrid_cell {
	struct vis_sgrid_entry *e;
	uint32_t n, cap;
	uint32_t swept; /* entries after the last sweep */
};

/* The cells: as zgrid.h's, at most VIS_SGRID_SIDE along each side of the area. */
struct vis_sgrid {
	struct vis_box area;
	unsigned shift;
	uint32_t cols, rows;
	struct vis_sgrid_cell *cells;
	size_t entries;
};

#define VIS_SGRID_SIDE 16

/* Whether an entry (val, stamp) still stands, for a sweep. */
typedef bool (*vis_sgrid_live_fn)(const void *arg, uint32_t val, uint32_t stamp);

/* Sets up an empty index over area (not empty). 0, or -1 with ENOMEM. O(cells). */
int vis_sgrid_init(struct vis_sgrid *g, struct vis_box area);

/* Frees the index's memory. */
void vis_sgrid_finish(struct vis_sgrid *g);

/*
 * Adds box (cut to the area; nothing if that is empty) as (val, stamp) to every cell it meets,
 * first sweeping a cell that has doubled since its last sweep with live(arg, …). 0, or -1 with
 * ENOMEM (the box then in some of its cells). O(cells it meets), amortized.
 */
int vis_sgrid_insert(struct vis_sgrid *g, struct vis_box box, uint32_t val, uint32_t stamp,
		     vis_sgrid_live_fn live, const void *arg);

/* The cells box meets, as column and row ranges [r[0], r[2]] × [r[1], r[3]]; false when none. */
bool vis_sgrid_cells(const struct vis_sgrid *g, struct vis_box box, uint32_t r[4]);

static inline const struct vis_sgrid_cell *vis_sgrid_cell(const struct vis_sgrid *g, uint32_t col,
							   uint32_t row)
{
	return &g->cells[(size_t)row * g->cols + col];
}

/*
 * Whether an entry e met by a query box q is reported by the cell (col, row): by the one cell
 * holding the top-left corner of e ∩ q, so that a walk over q's cells reports it once.
 */
static inline bool vis_sgrid_reports(const struct vis_sgrid *g, const struct vis_sgrid_entry *e,
				     struct vis_box q, uint32_t col, uint32_t row)
{
	int64_t x = e->x1 > q.x1 ? e->x1 : q.x1, y = e->y1 > q.y1 ? e->y1 : q.y1;
	return (uint64_t)((x - g->area.x1) >> g->shift) == col &&
	       (uint64_t)((y - g->area.y1) >> g->shift) == row;
}

/* For self-checks: whether every cell box meets holds (box, val, stamp). */
bool vis_sgrid_holds(const struct vis_sgrid *g, struct vis_box box, uint32_t val, uint32_t stamp);

#endif
