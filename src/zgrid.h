/* A spatial index of boxes in stacking order: which boxes meet a region, lowest or highest first. */
#ifndef VIS_ZGRID_H
#define VIS_ZGRID_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rect.h"

struct vis_zgrid_cell;

/*
 * The area (a screen) is cut into cells of 2^shift × 2^shift pixels, at most ZGRID_SIDE along
 * each side; an entry (a box inside the area, a key, a value) is in every cell its box meets,
 * and each cell keeps its entries ordered by key, in chunks of a few hundred (so that inserting
 * and removing cost a chunk's length, not a cell's). Keys are unique among the entries: an
 * entry is its key. Walking the entries that meet a box in key order merges the cells the box
 * meets, so it costs the entries of those cells it passes over, not the index's size, and it can
 * stop at any point: the caller reads the highest entries first and stops once they hide what it
 * asks about. Each cell entry also holds its box's part in the cell, in 16ths of the cell's side
 * rounded outwards (a nibble an edge), so that a walk passes over an entry that misses its box in
 * the cell itself, a few instructions, not a merge step: a cascade's walks over a strip of 64
 * pixels met 90% of such entries in cells of 256.
 */
struct vis_zgrid {
	struct vis_box area;
	unsigned shift;
	uint32_t cols, rows;
	struct vis_zgrid_cell *cells;
	size_t entries; /* cell entries in all: an entry once per cell it meets */
};

/* The most cells along a side: a window meets a few, so that a cell holds few to pass over. */
#define VIS_ZGRID_SIDE 16

/* Sets up an empty index over area (not empty), at most side cells (1 … VIS_ZGRID_SIDE) along
 * each side. 0, or -1 with ENOMEM. O(cells). */
int vis_zgrid_init(struct vis_zgrid *g, struct vis_box area, uint32_t side);

/* Frees the index's memory. O(entries). */
void vis_zgrid_finish(struct vis_zgrid *g);

/*
 * Adds an entry for box (not empty, inside the area) under key, not in the index. 0, or -1 with
 * ENOMEM, having added it to some of its cells: the index must then be rebuilt. O(cells it meets
 * × (chunk + log entries)); O(cells) when the key is the highest of its cells (building in order).
 */
int vis_zgrid_insert(struct vis_zgrid *g, struct vis_box box, uint64_t key, uint32_t val);

/* Removes the entry added for box under key. O(cells it meets × (chunk + log entries)). */
void vis_zgrid_remove(struct vis_zgrid *g, struct vis_box box, uint64_t key);

/* A cursor in one cell: the chunk and the place in it of its next entry. */
struct vis_zgrid_cursor {
	const struct vis_zgrid_cell *cell;
	struct vis_box bounds; /* the cell's pixels */
	uint64_t part;         /* the walk's box in the cell, as the entries' parts are tested */
	uint32_t chunk, at;
	uint32_t box_count; /* the walk's box_count when part was found */
};

/* A cursor's next key in a walk's heap (upwards the key, downwards its complement: the least
 * comes first either way), 16 bytes where the cursor takes 64. */
struct vis_zgrid_next {
	uint64_t order;
	uint32_t cursor;
};

/*
 * A walk over the entries whose cells meet a box, each once, in key order: upwards, the keys above
 * from; downwards, those below it. The cells' next keys form a heap. Every entry that meets the
 * box is listed; one listed need not meet it (its part in a cell is kept coarse): the caller tests
 * its own boxes.
 */
struct vis_zgrid_walk {
	const struct vis_zgrid *grid;
	struct vis_box box; /* what it was started or last narrowed to */
	uint32_t box_count; /* boxes so far: a cursor's part is found again when it moves on */
	bool up;
	uint64_t last;
	bool started;
	size_t n; /* the cells walked: cursors in the heap */
	struct vis_zgrid_cursor *cursors;
	struct vis_zgrid_next *heap;
	struct vis_zgrid_cursor inline_cursors[32];
	struct vis_zgrid_next inline_heap[32];
};

/* Starts a walk over the cells box meets. 0, or -1 with ENOMEM. O(cells × log entries). */
int vis_zgrid_walk_init(struct vis_zgrid_walk *walk, const struct vis_zgrid *g, struct vis_box box,
			uint64_t from, bool up);

/* The next entry: true with its key and value, or false at the end. O(log cells) amortized. */
bool vis_zgrid_walk_next(struct vis_zgrid_walk *walk, uint64_t *key, uint32_t *val);

/*
 * Leaves out the cells outside box from now on: what the caller still asks about has shrunk.
 * O(cells), O(1) when box is the one it was narrowed to last (callers narrow after every hit).
 */
void vis_zgrid_walk_narrow(struct vis_zgrid_walk *walk, struct vis_box box);

/*
 * Leaves out the cells whose pixels meets(arg, pixels) says false for: finer than a box.
 * Returns whether it left out any. O(cells).
 */
bool vis_zgrid_walk_keep(struct vis_zgrid_walk *walk, bool (*meets)(const void *, struct vis_box),
			 const void *arg);

/* Frees a walk's memory. */
void vis_zgrid_walk_finish(struct vis_zgrid_walk *walk);

/* The cells box meets, as column and row ranges [r[0], r[2]] × [r[1], r[3]]; false when none. */
bool vis_zgrid_cells(const struct vis_zgrid *g, struct vis_box box, uint32_t r[4]);

/* A cell's pixels (those in the area). */
struct vis_box vis_zgrid_cell_box(const struct vis_zgrid *g, uint32_t col, uint32_t row);

/* For self-checks: whether every cell box meets holds key (and how many those are). O(cells). */
bool vis_zgrid_holds(const struct vis_zgrid *g, struct vis_box box, uint64_t key, size_t *cells);

/* For self-checks: the entries the cells hold, or SIZE_MAX when a cell is out of order (or
 * its table of last keys is stale). */
size_t vis_zgrid_size(const struct vis_zgrid *g);

#endif
