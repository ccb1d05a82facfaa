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
};

/*
 * A cell: its entries in key order, chunk after chunk, none of them empty, and each chunk's last
 * key beside its pointer, so that finding a key's chunk reads one array, not every chunk probed.
 */
struct vis_zgrid_cell {
	struct chunk **chunks;
	uint64_t *lasts;
	size_t n, cap;
};

int vis_zgrid_init(struct vis_zgrid *g, struct vis_box area)
{
	unsigned shift = vis_cells_shift(area, VIS_ZGRID_SIDE);
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

static int cell_insert(struct vis_zgrid_cell *c, uint64_t key, uint32_t val)
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
	k->keys[at] = key;
	k->vals[at] = val;
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
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			if (cell_insert(&g->cells[(size_t)y * g->cols + x], key, val) < 0) {
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

/* Whether cursor a comes before b in the walk's order. */
static bool before(const struct vis_zgrid_walk *w, const struct vis_zgrid_cursor *a,
		   const struct vis_zgrid_cursor *b)
{
	return w->up ? a->key < b->key : a->key > b->key;
}

static void sift_down(struct vis_zgrid_walk *w, size_t i)
{
	for (;;) {
		size_t l = 2 * i + 1, r = l + 1, best = i;
		if (l < w->n && before(w, &w->heap[l], &w->heap[best]))
			best = l;
		if (r < w->n && before(w, &w->heap[r], &w->heap[best]))
			best = r;
		if (best == i)
			return;
		struct vis_zgrid_cursor t = w->heap[i];
		w->heap[i] = w->heap[best];
		w->heap[best] = t;
		i = best;
	}
}

/* Reads the cursor's key; false when it ran off its cell. */
static bool settle(struct vis_zgrid_cursor *c)
{
	if (c->chunk >= c->cell->n)
		return false;
	c->key = c->cell->chunks[c->chunk]->keys[c->at];
	return true;
}

/* Moves a cursor one entry on in the walk's direction; false when it ran off its cell. */
static bool step(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c)
{
	if (w->up) {
		if (++c->at == c->cell->chunks[c->chunk]->n) {
			c->chunk++;
			c->at = 0;
		}
	} else if (c->at > 0) {
		c->at--;
	} else if (c->chunk > 0) {
		c->chunk--;
		c->at = c->cell->chunks[c->chunk]->n - 1;
	} else {
		return false;
	}
	return settle(c);
}

/* Puts a cursor at the cell's first entry of the walk: above from (up), or below it. */
static bool place(const struct vis_zgrid_walk *w, struct vis_zgrid_cursor *c, uint64_t from)
{
	const struct vis_zgrid_cell *cell = c->cell;
	if (cell->n == 0)
		return false;
	if (!w->up && from == UINT64_MAX) {
		/* From the top, the commonest walk: no search. */
		c->chunk = cell->n - 1;
		c->at = cell->chunks[c->chunk]->n - 1;
		return settle(c);
	}
	size_t i = find_chunk(cell, from, w->up);
	if (w->up) {
		c->chunk = i;
		c->at = i < cell->n ? find_at(cell->chunks[i], from, true) : 0;
		return settle(c);
	}
	if (i == cell->n) {
		c->chunk = i - 1;
		c->at = cell->chunks[i - 1]->n - 1;
		return settle(c);
	}
	size_t at = find_at(cell->chunks[i], from, false);
	c->chunk = i;
	c->at = at;
	if (at > 0) {
		c->at = at - 1;
		return settle(c);
	}
	return step(w, c);
}

int vis_zgrid_walk_init(struct vis_zgrid_walk *walk, const struct vis_zgrid *g, struct vis_box box,
			uint64_t from, bool up)
{
	*walk = (struct vis_zgrid_walk){ .box = box, .up = up, .heap = walk->inline_heap };
	uint32_t r[4];
	if (!vis_zgrid_cells(g, box, r))
		return 0;
	size_t cells = (size_t)(r[2] - r[0] + 1) * (r[3] - r[1] + 1);
	if (cells > sizeof walk->inline_heap / sizeof *walk->inline_heap &&
	    !(walk->heap = malloc(cells * sizeof *walk->heap))) {
		walk->heap = walk->inline_heap;
		errno = ENOMEM;
		return -1;
	}
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			struct vis_zgrid_cursor *c = &walk->heap[walk->n];
			c->cell = &g->cells[(size_t)y * g->cols + x];
			c->bounds = vis_zgrid_cell_box(g, x, y);
			walk->n += place(walk, c, from);
		}
	for (size_t i = walk->n / 2; i-- > 0;)
		sift_down(walk, i);
	return 0;
}

bool vis_zgrid_walk_next(struct vis_zgrid_walk *walk, uint64_t *key, uint32_t *val)
{
	while (walk->n) {
		struct vis_zgrid_cursor *top = &walk->heap[0];
		uint64_t k = top->key;
		uint32_t v = top->cell->chunks[top->chunk]->vals[top->at];
		if (!step(walk, top))
			walk->heap[0] = walk->heap[--walk->n];
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
	size_t k = 0;
	for (size_t i = 0; i < walk->n; i++) {
		struct vis_box b = vis_box_intersect(walk->heap[i].bounds, box);
		if (!vis_box_empty(b))
			walk->heap[k++] = walk->heap[i];
	}
	shrink(walk, k);
}

bool vis_zgrid_walk_keep(struct vis_zgrid_walk *walk, bool (*meets)(const void *, struct vis_box),
			 const void *arg)
{
	size_t k = 0;
	for (size_t i = 0; i < walk->n; i++)
		if (meets(arg, walk->heap[i].bounds))
			walk->heap[k++] = walk->heap[i];
	return shrink(walk, k);
}

void vis_zgrid_walk_finish(struct vis_zgrid_walk *walk)
{
	if (walk->heap != walk->inline_heap)
		free(walk->heap);
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
