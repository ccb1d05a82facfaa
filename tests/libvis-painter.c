/* test-libvis's painter: X's rule pixel by pixel over the test's model (libvis-painter.h). */
#include <stdlib.h>

#include "libvis-painter.h"

/* The screen coordinates of a window's border box's corner. */
static void corner(const struct pm_tree *t, int i, int64_t *bx, int64_t *by)
{
	*bx = t->w[i].x;
	*by = t->w[i].y;
	for (int a = t->w[i].parent; a != 0; a = t->w[a].parent) {
		*bx += (int64_t)t->w[a].x + t->w[a].border;
		*by += (int64_t)t->w[a].y + t->w[a].border;
	}
}

void pm_inside(const struct pm_tree *t, int i, int64_t *ix, int64_t *iy)
{
	corner(t, i, ix, iy);
	*ix += t->w[i].border;
	*iy += t->w[i].border;
}

bool pm_viewable(const struct pm_tree *t, int i)
{
	for (; i != 0; i = t->w[i].parent)
		if (!t->w[i].mapped)
			return false;
	return true;
}

bool pm_is_ancestor(const struct pm_tree *t, int a, int b)
{
	for (; b != 0; b = t->w[b].parent)
		if (a == b)
			return true;
	return a == 0;
}

static bool in_rects(const struct vis_rect32 *r, uint32_t n, int64_t x, int64_t y)
{
	for (uint32_t k = 0; k < n; k++)
		if (x >= r[k].x && y >= r[k].y && x < (int64_t)r[k].x + r[k].width &&
		    y < (int64_t)r[k].y + r[k].height)
			return true;
	return false;
}

/* Whether screen pixel (x, y) is one of window i's own: its shape in its border box. */
static bool pixel_of(const struct pm_tree *t, int i, int64_t x, int64_t y)
{
	const struct pm_win *w = &t->w[i];
	int64_t bx, by, b = w->border;
	if (w->input_only)
		return false;
	corner(t, i, &bx, &by);
	if (x < bx || y < by || x >= bx + w->w + 2 * b || y >= by + w->h + 2 * b)
		return false;
	return !w->shaped || in_rects(w->shape, w->n_shape, x - bx - b, y - by - b);
}

static bool opaque_of(const struct pm_tree *t, int i, int64_t x, int64_t y)
{
	const struct pm_win *w = &t->w[i];
	if (!pixel_of(t, i, x, y) || w->opaque == VIS_OPAQUE_MODE_NONE)
		return false;
	if (w->opaque == VIS_OPAQUE_MODE_ALL)
		return true;
	int64_t ix, iy;
	pm_inside(t, i, &ix, &iy);
	return in_rects(w->opq, w->n_opq, x - ix, y - iy);
}

/* Whether (x, y) is on the screen and inside every ancestor's inside (and shape). */
static bool inside_chain(const struct pm_tree *t, int i, int64_t x, int64_t y)
{
	if (x < 0 || y < 0 || x >= t->sw || y >= t->sh)
		return false;
	for (int a = t->w[i].parent; a != 0; a = t->w[a].parent) {
		int64_t ix, iy;
		pm_inside(t, a, &ix, &iy);
		if (x < ix || y < iy || x >= ix + t->w[a].w || y >= iy + t->w[a].h)
			return false;
		if (t->w[a].shaped && !in_rects(t->w[a].shape, t->w[a].n_shape, x - ix, y - iy))
			return false;
	}
	return true;
}

/* Whether window i has a pixel of its own off the screen. */
static bool off_screen(const struct pm_tree *t, int i)
{
	const struct pm_win *w = &t->w[i];
	int64_t bx, by, b = w->border;
	corner(t, i, &bx, &by);
	int64_t x1 = bx + w->w + 2 * b, y1 = by + w->h + 2 * b;
	uint32_t n = w->shaped ? w->n_shape : 1;
	for (uint32_t k = 0; k < n; k++) {
		int64_t rx = bx, ry = by, rx1 = x1, ry1 = y1;
		if (w->shaped) {
			const struct vis_rect32 *r = &w->shape[k];
			rx = bx + b + r->x;
			ry = by + b + r->y;
			rx1 = rx + r->width;
			ry1 = ry + r->height;
			rx = rx > bx ? rx : bx;
			ry = ry > by ? ry : by;
			rx1 = rx1 < x1 ? rx1 : x1;
			ry1 = ry1 < y1 ? ry1 : y1;
		}
		if (rx < rx1 && ry < ry1 && (rx < 0 || ry < 0 || rx1 > t->sw || ry1 > t->sh))
			return true;
	}
	return false;
}

/* Appends slot i's subtree in pre-order. */
static void walk(const struct pm_tree *t, int i, int depth, struct pm_paint *p, int *depths)
{
	for (int k = 0; k < t->w[i].n_kids; k++) {
		int c = t->w[i].kids[k];
		p->pos[c] = p->n;
		depths[p->n] = depth;
		p->order[p->n++] = c;
		walk(t, c, depth + 1, p, depths);
	}
}

bool pm_paint(const struct pm_tree *t, struct pm_paint *p)
{
	int depths[PM_MAX + 1];
	p->n = 0;
	walk(t, 0, 1, p, depths);
	for (int i = 0; i < p->n; i++) {
		int j = i + 1;
		while (j < p->n && depths[j] > depths[i])
			j++;
		p->end[i] = j;
	}
	p->top = malloc((size_t)t->sw * (size_t)t->sh * sizeof *p->top);
	if (!p->top)
		return false;
	for (int64_t k = 0; k < (int64_t)t->sw * t->sh; k++)
		p->top[k] = -1;
	for (int k = 0; k < p->n; k++) {
		int i = p->order[k];
		if (!pm_viewable(t, i))
			continue;
		for (int64_t y = 0; y < t->sh; y++)
			for (int64_t x = 0; x < t->sw; x++)
				if (opaque_of(t, i, x, y) && inside_chain(t, i, x, y))
					p->top[y * t->sw + x] = k;
	}
	return true;
}

void pm_paint_finish(struct pm_paint *p)
{
	free(p->top);
	p->top = NULL;
}

/* Window i's own pixels on the screen, into *all, and those of them seen, descendants hiding
 * none (X's rule), into *seen. */
static void count(const struct pm_tree *t, const struct pm_paint *p, int i, long *all, long *seen)
{
	int k = p->pos[i];
	*all = *seen = 0;
	for (int64_t y = 0; y < t->sh; y++)
		for (int64_t x = 0; x < t->sw; x++) {
			if (!pixel_of(t, i, x, y))
				continue;
			(*all)++;
			if (inside_chain(t, i, x, y) && p->top[y * t->sw + x] < p->end[k])
				(*seen)++;
		}
}

int pm_state(const struct pm_tree *t, const struct pm_paint *p, int i)
{
	if (t->w[i].input_only || !pm_viewable(t, i))
		return VIS_VISIBILITY_NONE;
	long all, seen;
	count(t, p, i, &all, &seen);
	/* Pixels off the screen are never seen: such a window is never unobscured. */
	bool off = off_screen(t, i);
	if (all == 0 && !off)
		return VIS_VISIBILITY_FULLY_OBSCURED;
	return seen == all && !off ? VIS_VISIBILITY_UNOBSCURED
	       : seen		   ? VIS_VISIBILITY_PARTIALLY_OBSCURED
				   : VIS_VISIBILITY_FULLY_OBSCURED;
}

uint64_t pm_seen(const struct pm_tree *t, const struct pm_paint *p, int i)
{
	if (t->w[i].input_only || !pm_viewable(t, i))
		return 0;
	long all, seen;
	count(t, p, i, &all, &seen);
	return (uint64_t)seen;
}

bool pm_visible(const struct pm_tree *t, const struct pm_paint *p, int i, int64_t x, int64_t y)
{
	if (t->w[i].input_only || !pm_viewable(t, i) || x < 0 || y < 0 || x >= t->sw ||
	    y >= t->sh)
		return false;
	return pixel_of(t, i, x, y) && inside_chain(t, i, x, y) &&
	       p->top[y * t->sw + x] <= p->pos[i];
}
