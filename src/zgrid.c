/* A spatial index of boxes in stacking order: cells of entries ordered by key, walked merged. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "cells.h"
#include "zgrid.h"

/* Entries per chunk: inserting moves up to this many, a cell's chunk table moves less often. */
#define CHUNK 126

struct chunk {
	uint32_t n;
	uint64_t keys[CHUNK];
	uint32_t vals[CHUNK];
	uint16_t parts[CHUNK]; /* part(): where each entry's box lies in the cell */
};

/*
 * A box's part in a cell (the box meets it), for the walks' test: each edge as the 16th of the
 * cell's side its first or last pixel lies in (a nibble each: x1 x2 y1 y2 from the lowest), so
 * that two parts share a 16th when the boxes share a pixel. Sixteenths, not finer: the parts
 * take two bytes an entry beside its key's eight and its value's four (a byte an edge made the
 * cells' chunks a third larger, random desktops' live structures 346 bytes a window at 10^5
 * against 311), and they are fine enough for what they are for, a walk over a strip of 64
 * pixels in cells of 256.
 */
#define PART_SHIFT(g) ((g)->shift - 4) /* cells are 64 pixels or more (cells.h) */

/* Along one axis, the 16ths of a cell's pixels [c1, c2) that [lo, hi) (meeting it) lies in. */
static uint32_t span(const struct vis_zgrid *g, int64_t lo, int64_t hi, int64_t c1, int64_t c2)
{
	unsigned s = PART_SHIFT(g);
	int64_t a1 = lo > c1 ? lo : c1, a2 = hi < c2 ? hi : c2;
	return (uint32_t)((a1 - c1) >> s) | (uint32_t)((a2 - 1 - c1) >> s) << 4;
}

static uint16_t part(const struct vis_zgrid *g, struct vis_box cell, struct vis_box box)
{
	return (uint16_t)(span(g, box.x1, box.x2, cell.x1, cell.x2) |
			  span(g, box.y1, box.y2, cell.y1, cell.y2) << 8);
}

/*
 * The walks test parts without a branch, four 16-bit lanes at once: with an entry's part spread
 * a nibble a lane (x1, x2, y1, y2), its x1 and y1 flipped, and a walk's part q added as
 * (q.x2 + 1, 16 − q.x1, q.y2 + 1, 16 − q.y1), each lane is 16 or more, its bit 4 set, when
 * that edge of one part does not lie beyond the other's: q.x2 ≥ x1, x2 ≥ q.x1, q.y2 ≥ y1,
 * y2 ≥ q.y1.
 */
#define LANES(a, b, c, d) \
	((uint64_t)(a) | (uint64_t)(b) << 16 | (uint64_t)(c) << 32 | (uint64_t)(d) << 48)
#define LANE_BIT4 LANES(16, 16, 16, 16)

static inline uint64_t spread(uint16_t p)
{
	uint64_t x = p;
	x = (x | x << 24) & 0x000000ff000000ffu;
	return (x | x << 12) & 0x000f000f000f000fu;
}

/* A walk's part, as parts_meet() adds it. */
static uint64_t walk_part(uint16_t q)
{
	uint64_t x1 = q & 0xf, x2 = q >> 4 & 0xf, y1 = q >> 8 & 0xf, y2 = q >> 12;
	return LANES(x2 + 1, 16 - x1, y2 + 1, 16 - y1);
}

/* A walk's part where its box holds the whole cell: every entry meets it, untested. */
#define WHOLE_CELL LANES(16, 16, 16, 16)

/* A walk's part in a cell (its box meets it), as the cursor keeps it. */
static uint64_t cursor_part(const struct vis_zgrid *g, struct vis_box cell, struct vis_box box)
{
	if (box.x1 <= cell.x1 && box.y1 <= cell.y1 && box.x2 >= cell.x2 && box.y2 >= cell.y2)
		return WHOLE_CELL;
	return walk_part(part(g, cell, box));
}

/*
 * Along one axis, the cells [first, last] an interval [lo, hi) meets (at most VIS_ZGRID_SIDE):
 * each one's pixels [c1, c2) and the interval's span in it, as part() gives it; whole when the
 * interval holds the cell's pixels. The cells of a box are those of its two axes.
 */
struct axis_cell {
	int64_t c1, c2;
	uint32_t span;
	bool whole;
};

static void axis_cells(const struct vis_zgrid *g, int64_t origin, int64_t end, uint32_t first,
		       uint32_t last, int64_t lo, int64_t hi, struct axis_cell *a)
{
	int64_t side = (int64_t)1 << g->shift;
	for (uint32_t i = first; i <= last; i++) {
		int64_t c1 = origin + (int64_t)i * side, c2 = c1 + side < end ? c1 + side : end;
		a[i - first] = (struct axis_cell){ c1, c2, span(g, lo, hi, c1, c2),
						   lo <= c1 && hi >= c2 };
	}
}

/* Whether an entry's part and a walk's (walk_part()) share a 16th of the cell. */
static inline bool parts_meet(uint16_t entry, uint64_t walk)
{
	uint64_t d = (spread(entry) ^ LANES(0xf, 0, 0xf, 0)) + walk;
	return (d & LANE_BIT4) == LANE_BIT4;
}

/*
 * A cell: its entries in key order, chunk after chunk, none of them empty, and each chunk's last
 * key beside its pointer, so that finding a key's chunk reads one array, not every chunk probed.
 */
struct vis_zgrid_cell {
	struct chunk **chunks;
	uint64_t *lasts;
	size_t n, cap;
};

int vis_zgrid_init(struct vis_zgrid *g, struct vis_box area, uint32_t side)
{
	unsigned shift = vis_cells_shift(area, side);
	*g = (struct vis_zgrid){ .area = area, .shift = shift };
	g->cols = vis_cells_along(area.x2 - area.x1, shift);
	g->rows = vis_cells_along(area.y2 - area.y1, shift);
	g->cells = calloc((size_t)g->cols * g->rows, sizeof *g->cells);
	if (!g->cells) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

void vis_zgrid_finish(struct vis_zgrid *g)
{
	for (size_t c = 0; g->cells && c < (size_t)g->cols * g->rows; c++) {
		for (size_t i = 0; i < g->cells[c].n; i++)
			free(g->cells[c].chunks[i]);
		free(g->cells[c].chunks);
		free(g->cells[c].lasts);
	}
	free(g->cells);
	g->cells = NULL;
	g->entries = 0;
}

bool vis_zgrid_cells(const struct vis_zgrid *g, struct vis_box b, uint32_t r[4])
{
	return vis_cells_met(g->area, g->shift, b, r);
}

/* The first chunk whose last key is ≥ key (above: > key), or c->n. */
static size_t find_chunk(const struct vis_zgrid_cell *c, uint64_t key, bool above)
{
	size_t lo = 0, hi = c->n;
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		uint64_t last = c->lasts[mid];
		if (last < key || (above && last == key))
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

/* The first place in k whose key is ≥ key (above: > key), or k->n. */
static size_t find_at(const struct chunk *k, uint64_t key, bool above)
{
	size_t lo = 0, hi = k->n;
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		if (k->keys[mid] < key || (above && k->keys[mid] == key))
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

/* Puts a new empty chunk at place i of the cell's table. */
static struct chunk *add_chunk(struct vis_zgrid_cell *c, size_t i)
{
	if (c->n == c->cap) {
		size_t cap = c->cap ? 2 * c->cap : 4;
		struct chunk **t = realloc(c->chunks, cap * sizeof *t);
		if (!t)
			return NULL;
		c->chunks = t;
		uint64_t *l = realloc(c->lasts, cap * sizeof *l);
		if (!l)
			return NULL; /* the table grew: the cell stays as it was */
		c->lasts = l;
		c->cap = cap;
	}
	struct chunk *k = malloc(sizeof *k);
	if (!k)
		return NULL;
	k->n = 0;
	memmove(&c->chunks[i + 1], &c->chunks[i], (c->n - i) * sizeof *c->chunks);
	memmove(&c->lasts[i + 1], &c->lasts[i], (c->n - i) * sizeof *c->lasts);
	c->chunks[i] = k;
	c->lasts[i] = 0;
	c->n++;
	return k;
}

static int cell_insert(struct vis_zgrid_cell *c, uint64_t key, uint32_t val, uint16_t where)
{
	size_t i = c->n ? find_chunk(c, key, false) : 0;
	if (i == c->n && i > 0)
		i--;
	struct chunk *k = c->n ? c->chunks[i] : add_chunk(c, 0);
	if (!k)
		return -1;
	if (k->n == CHUNK) {
		/* Past the last key, a new chunk: building in order fills chunks whole. */
		bool last = i + 1 == c->n && key > k->keys[k->n - 1];
		struct chunk *m = add_chunk(c, i + 1);
		if (!m)
			return -1;
		if (!last) {
			m->n = CHUNK / 2;
			k->n = CHUNK - m->n;
			memcpy(m->keys, &k->keys[k->n], m->n * sizeof *m->keys);
			memcpy(m->vals, &k->vals[k->n], m->n * sizeof *m->vals);
			memcpy(m->parts, &k->parts[k->n], m->n * sizeof *m->parts);
		}
		if (!last)
			c->lasts[i + 1] = m->keys[m->n - 1];
		c->lasts[i] = k->keys[k->n - 1];
		if (last || key > k->keys[k->n - 1]) {
			k = m;
			i++;
		}
	}
	size_t at = find_at(k, key, false);
	memmove(&k->keys[at + 1], &k->keys[at], (k->n - at) * sizeof *k->keys);
	memmove(&k->vals[at + 1], &k->vals[at], (k->n - at) * sizeof *k->vals);
	memmove(&k->parts[at + 1], &k->parts[at], (k->n - at) * sizeof *k->parts);
	k->keys[at] = key;
	k->vals[at] = val;
	k->parts[at] = where;
	k->n++;
	c->lasts[i] = k->keys[k->n - 1];
	return 0;
}

static void cell_remove(struct vis_zgrid_cell *c, uint64_t key)
{
	size_t i = find_chunk(c, key, false);
	if (i == c->n)
		return;
	struct chunk *k = c->chunks[i];
	size_t at = find_at(k, key, false);
	if (at == k->n || k->keys[at] != key)
		return;
	k->n--;
	memmove(&k->keys[at], &k->keys[at + 1], (k->n - at) * sizeof *k->keys);
	memmove(&k->vals[at], &k->vals[at + 1], (k->n - at) * sizeof *k->vals);
	memmove(&k->parts[at], &k->parts[at + 1], (k->n - at) * sizeof *k->parts);
	if (k->n == 0) {
		free(k);
		c->n--;
		memmove(&c->chunks[i], &c->chunks[i + 1], (c->n - i) * sizeof *c->chunks);
		memmove(&c->lasts[i], &c->lasts[i + 1], (c->n - i) * sizeof *c->lasts);
	} else {
		c->lasts[i] = k->keys[k->n - 1];
	}
}

int vis_zgrid_insert(struct vis_zgrid *g, struct vis_box box, uint64_t key, uint32_t val)
{
	uint32_t r[4];
	if (!vis_zgrid_cells(g, box, r))
		return 0;
	struct axis_cell ax[VIS_ZGRID_SIDE], ay[VIS_ZGRID_SIDE];
	axis_cells(g, g->area.x1, g->area.x2, r[0], r[2], box.x1, box.x2, ax);
	axis_cells(g, g->area.y1, g->area.y2, r[1], r[3], box.y1, box.y2, ay);
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			uint16_t where = (uint16_t)(ax[x - r[0]].span | ay[y - r[1]].span << 8);
			if (cell_insert(&g->cells[(size_t)y * g->cols + x], key, val, where) < 0) {
				errno = ENOMEM;
				return -1;
			}
			g->entries++;
		}
	return 0;
}

void vis_zgrid_remove(struct vis_zgrid *g, struct vis_box box, uint64_t key)
{
	uint32_t r[4];
	if (!vis_zgrid_cells(g, box, r))
		return;
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			cell_remove(&g->cells[(size_t)y * g->cols + x], key);
			g->entries--;
		}
}

struct vis_box vis_zgrid_cell_box(const struct vis_zgrid *g, uint32_t col, uint32_t row)
{
	int64_t side = (int64_t)1 << g->shift;
	struct vis_box b = { g->area.x1 + col * side, g->area.y1 + row * side,
			     g->area.x1 + (col + 1) * side, g->area.y1 + (row + 1) * side };
	return vis_box_intersect(b, g->area);
}

static void sift_down(struct vis_zgrid_walk *w, size_t i)
{
	struct vis_zgrid_next *h = w->heap, t = h[i];
	for (;;) {
		size_t l = 2 * i + 1, best = l;
		if (l >= w->n)
			break;
		if (l + 1 < w->n && h[l + 1].order < h[l].order)
			best = l + 1;
		if (t.order <= h[best].order)
			break;
		h[i] = h[best];
		i = best;
	}
	h[i] = t;
}

/* Moves a cursor one entry on in the walk's direction; false when it ran off its cell. */
static bool advance(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c)
{
	if (w->up) {
		if (++c->at == c->cell->chunks[c->chunk]->n) {
			c->chunk++;
			c->at = 0;
		}
		return c->chunk < c->cell->n;
	}
	if (c->at > 0) {
		c->at--;
	} else if (c->chunk > 0) {
		c->chunk--;
		c->at = c->cell->chunks[c->chunk]->n - 1;
	} else {
		return false;
	}
	return true;
}

/*
 * From the cursor's entry on, passes over the entries whose part misses the walk's, and puts the
 * first that remains in *next (the key as the heap orders it); false when it ran off its cell.
 */
static bool settle(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c,
		   struct vis_zgrid_next *next)
{
	const struct vis_zgrid_cell *cell = c->cell;
	uint32_t i = c->chunk, at = c->at;
	if (c->box_count != w->box_count) {
		/* Narrowed since: callers narrow after each hit, most cursors never move again. */
		c->part = cursor_part(w->grid, c->bounds, w->box);
		c->box_count = w->box_count;
	}
	if (c->part == WHOLE_CELL) {
		if (i >= cell->n)
			return false;
		goto found;
	}
	if (w->up) {
		for (; i < cell->n; i++, at = 0) {
			const struct chunk *k = cell->chunks[i];
			for (; at < k->n; at++)
				if (parts_meet(k->parts[at], c->part))
					goto found;
		}
		return false;
	}
	for (;;) {
		const struct chunk *k = cell->chunks[i];
		for (;; at--) {
			if (parts_meet(k->parts[at], c->part))
				goto found;
			if (at == 0)
				break;
		}
		if (i == 0)
			return false;
		at = cell->chunks[--i]->n - 1;
	}
found:
	c->chunk = i;
	c->at = at;
	uint64_t key = cell->chunks[i]->keys[at];
	next->order = w->up ? key : ~key;
	return true;
}

/* Moves a cursor to the next entry of the walk in its cell; false when it ran off the cell. */
static bool step(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c,
		 struct vis_zgrid_next *next)
{
	return advance(w, c) && settle(w, c, next);
}

/* Puts a cursor at the cell's first entry of the walk: above from (up), or below it. */
static bool place(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c, uint64_t from,
		  struct vis_zgrid_next *next)
{
	const struct vis_zgrid_cell *cell = c->cell;
	if (cell->n == 0)
		return false;
	if (!w->up && from == UINT64_MAX) {
		/* From the top, the commonest walk: no search. */
		c->chunk = cell->n - 1;
		c->at = cell->chunks[c->chunk]->n - 1;
		return settle(w, c, next);
	}
	size_t i = find_chunk(cell, from, w->up);
	if (w->up) {
		c->chunk = (uint32_t)i;
		c->at = i < cell->n ? (uint32_t)find_at(cell->chunks[i], from, true) : 0;
		return settle(w, c, next);
	}
	if (i == cell->n) {
		c->chunk = (uint32_t)(i - 1);
		c->at = cell->chunks[i - 1]->n - 1;
		return settle(w, c, next);
	}
	size_t at = find_at(cell->chunks[i], from, false);
	c->chunk = (uint32_t)i;
	c->at = (uint32_t)at;
	if (at > 0) {
		c->at = (uint32_t)(at - 1);
		return settle(w, c, next);
	}
	return step(w, c, next);
}

int vis_zgrid_walk_init(struct vis_zgrid_walk *walk, const struct vis_zgrid *g, struct vis_box box,
			uint64_t from, bool up)
{
	/* Field by field: the inline arrays (2.5 KiB) need no zeros. */
	walk->grid = g;
	walk->box = box;
	walk->box_count = 0;
	walk->up = up;
	walk->last = 0;
	walk->started = false;
	walk->n = 0;
	walk->cursors = walk->inline_cursors;
	walk->heap = walk->inline_heap;
	uint32_t r[4];
	if (!vis_zgrid_cells(g, box, r))
		return 0;
	struct axis_cell ax[VIS_ZGRID_SIDE], ay[VIS_ZGRID_SIDE];
	axis_cells(g, g->area.x1, g->area.x2, r[0], r[2], box.x1, box.x2, ax);
	axis_cells(g, g->area.y1, g->area.y2, r[1], r[3], box.y1, box.y2, ay);
	size_t cells = (size_t)(r[2] - r[0] + 1) * (r[3] - r[1] + 1);
	if (cells > sizeof walk->inline_heap / sizeof *walk->inline_heap) {
		struct vis_zgrid_cursor *c = malloc(cells * (sizeof *c + sizeof *walk->heap));
		if (!c) {
			errno = ENOMEM;
			return -1;
		}
		walk->cursors = c;
		walk->heap = (struct vis_zgrid_next *)(c + cells);
	}
	size_t k = 0;
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++, k++) {
			struct vis_zgrid_cursor *c = &walk->cursors[k];
			c->cell = &g->cells[(size_t)y * g->cols + x];
			if (c->cell->n == 0)
				continue; /* nothing to walk: not read again */
			const struct axis_cell *cx = &ax[x - r[0]], *cy = &ay[y - r[1]];
			c->bounds = (struct vis_box){ cx->c1, cy->c1, cx->c2, cy->c2 };
			c->part = cx->whole && cy->whole ? WHOLE_CELL
							 : walk_part((uint16_t)(cx->span | cy->span << 8));
			c->box_count = 0;
			walk->heap[walk->n].cursor = (uint32_t)k;
			walk->n += place(walk, c, from, &walk->heap[walk->n]);
		}
	for (size_t i = walk->n / 2; i-- > 0;)
		sift_down(walk, i);
	return 0;
}

bool vis_zgrid_walk_next(struct vis_zgrid_walk *walk, uint64_t *key, uint32_t *val)
{
	while (walk->n) {
		struct vis_zgrid_next *top = &walk->heap[0];
		struct vis_zgrid_cursor *c = &walk->cursors[top->cursor];
		uint64_t k = walk->up ? top->order : ~top->order;
		uint32_t v = c->cell->chunks[c->chunk]->vals[c->at];
		if (!step(walk, c, top))
			*top = walk->heap[--walk->n];
		sift_down(walk, 0);
		if (walk->started && k == walk->last)
			continue; /* the same entry through another cell */
		walk->started = true;
		walk->last = k;
		*key = k;
		*val = v;
		return true;
	}
	return false;
}

/* Keeps the walk's first k cursors (the others left out) in a heap again; whether any went. */
static bool shrink(struct vis_zgrid_walk *walk, size_t k)
{
	if (k == walk->n)
		return false;
	walk->n = k;
	for (size_t i = walk->n / 2; i-- > 0;)
		sift_down(walk, i);
	return true;
}

void vis_zgrid_walk_narrow(struct vis_zgrid_walk *walk, struct vis_box box)
{
	if (vis_box_equal(box, walk->box))
		return;
	walk->box = box;
	walk->box_count++;
	size_t k = 0;
	for (size_t i = 0; i < walk->n; i++) {
		/* Its entry stands, listed next whether it meets box or not: the next ones must. */
		const struct vis_zgrid_cursor *c = &walk->cursors[walk->heap[i].cursor];
		if (!vis_box_empty(vis_box_intersect(c->bounds, box)))
			walk->heap[k++] = walk->heap[i];
	}
	shrink(walk, k);
}

bool vis_zgrid_walk_keep(struct vis_zgrid_walk *walk, bool (*meets)(const void *, struct vis_box),
			 const void *arg)
{
	size_t k = 0;
	for (size_t i = 0; i < walk->n; i++)
		if (meets(arg, walk->cursors[walk->heap[i].cursor].bounds))
			walk->heap[k++] = walk->heap[i];
	return shrink(walk, k);
}

void vis_zgrid_walk_finish(struct vis_zgrid_walk *walk)
{
	if (walk->cursors != walk->inline_cursors)
		free(walk->cursors);
	walk->cursors = walk->inline_cursors;
	walk->heap = walk->inline_heap;
	walk->n = 0;
}

bool vis_zgrid_holds(const struct vis_zgrid *g, struct vis_box box, uint64_t key, size_t *cells)
{
	uint32_t r[4];
	*cells = 0;
	if (!vis_zgrid_cells(g, box, r))
		return true;
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			const struct vis_zgrid_cell *c = &g->cells[(size_t)y * g->cols + x];
			size_t i = find_chunk(c, key, false);
			if (i == c->n)
				return false;
			size_t at = find_at(c->chunks[i], key, false);
			if (at == c->chunks[i]->n || c->chunks[i]->keys[at] != key)
				return false;
			(*cells)++;
		}
	return true;
}

size_t vis_zgrid_size(const struct vis_zgrid *g)
{
	size_t n = 0;
	for (size_t c = 0; c < (size_t)g->cols * g->rows; c++)
		for (size_t i = 0; i < g->cells[c].n; i++) {
			const struct chunk *k = g->cells[c].chunks[i];
			n += k->n;
			if (g->cells[c].lasts[i] != k->keys[k->n - 1])
				return SIZE_MAX; /* the table's last key is stale */
			for (size_t j = 1; j < k->n; j++)
				if (k->keys[j - 1] >= k->keys[j])
					return SIZE_MAX; /* out of order */
			if (i > 0 && g->cells[c].chunks[i - 1]->keys[g->cells[c].chunks[i - 1]->n - 1] >=
					     k->keys[0])
				return SIZE_MAX;
		}
	return n;
}
