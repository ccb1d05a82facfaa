/* A spatial index of boxes without order: a bag of entries per grid cell, swept as it doubles. */
#include <errno.h>
#include <stdlib.h>

#include "cells.h"
#include "sgrid.h"

int vis_sgrid_init(struct vis_sgrid *g, struct vis_box area)
{
	unsigned shift = vis_cells_shift(area, VIS_SGRID_SIDE);
	*g = (struct vis_sgrid){ .area = area, .shift = shift };
	g->cols = vis_cells_along(area.x2 - area.x1, shift);
	g->rows = vis_cells_along(area.y2 - area.y1, shift);
	g->cells = calloc((size_t)g->cols * g->rows, sizeof *g->cells);
	if (!g->cells) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

void vis_sgrid_finish(struct vis_sgrid *g)
{
	for (size_t c = 0; g->cells && c < (size_t)g->cols * g->rows; c++)
		free(g->cells[c].e);
	free(g->cells);
	g->cells = NULL;
	g->entries = 0;
}

bool vis_sgrid_cells(const struct vis_sgrid *g, struct vis_box b, uint32_t r[4])
{
	return vis_cells_met(g->area, g->shift, b, r);
}

/* Drops the entries that no longer stand. */
static void sweep(struct vis_sgrid *g, struct vis_sgrid_cell *c, vis_sgrid_live_fn live,
		  const void *arg)
{
	uint32_t k = 0;
	for (uint32_t i = 0; i < c->n; i++)
		if (live(arg, c->e[i].val, c->e[i].stamp))
			c->e[k++] = c->e[i];
	g->entries -= c->n - k;
	c->n = c->swept = k;
}

/* Makes room for one more entry in a cell, sweeping it first when it has doubled. */
static int room(struct vis_sgrid *g, struct vis_sgrid_cell *c, vis_sgrid_live_fn live,
		const void *arg)
{
	if (c->n >= 2 * c->swept + 32)
		sweep(g, c, live, arg);
	if (c->n < c->cap)
		return 0;
	if (c->cap > UINT32_MAX / 2) {
		errno = ENOMEM;
		return -1;
	}
	uint32_t cap = c->cap ? 2 * c->cap : 16;
	struct vis_sgrid_entry *e = realloc(c->e, (size_t)cap * sizeof *e);
	if (!e) {
		errno = ENOMEM;
		return -1;
	}
	c->e = e;
	c->cap = cap;
	return 0;
}

int vis_sgrid_insert(struct vis_sgrid *g, struct vis_box box, uint32_t val, uint32_t stamp,
		     vis_sgrid_live_fn live, const void *arg)
{
	box = vis_box_intersect(box, g->area);
	uint32_t r[4];
	if (!vis_sgrid_cells(g, box, r))
		return 0;
	struct vis_sgrid_entry e = { (int32_t)box.x1, (int32_t)box.y1, (int32_t)box.x2,
				     (int32_t)box.y2, val, stamp };
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			struct vis_sgrid_cell *c = &g->cells[(size_t)y * g->cols + x];
			if (room(g, c, live, arg) < 0)
				return -1;
			c->e[c->n++] = e;
			g->entries++;
		}
	return 0;
}

bool vis_sgrid_holds(const struct vis_sgrid *g, struct vis_box box, uint32_t val, uint32_t stamp)
{
	box = vis_box_intersect(box, g->area);
	uint32_t r[4];
	if (!vis_sgrid_cells(g, box, r))
		return true;
	for (uint32_t y = r[1]; y <= r[3]; y++)
		for (uint32_t x = r[0]; x <= r[2]; x++) {
			const struct vis_sgrid_cell *c = vis_sgrid_cell(g, x, y);
			bool found = false;
			for (uint32_t i = 0; !found && i < c->n; i++)
				found = c->e[i].val == val && c->e[i].stamp == stamp &&
					c->e[i].x1 == box.x1 && c->e[i].y1 == box.y1 &&
					c->e[i].x2 == box.x2 && c->e[i].y2 == box.y2;
			if (!found)
				return false;
		}
	return true;
}
