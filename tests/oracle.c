/* X's visibility rule pixel by pixel (oracle.h). */
#include <stdbool.h>
#include <stdlib.h>

#include "oracle.h"

void oracle_corner(const struct vis_window *w, int64_t *bx, int64_t *by)
{
	*bx = w->x;
	*by = w->y;
	for (const struct vis_window *a = w->parent; a->parent; a = a->parent) {
		*bx += (int64_t)a->x + a->look.border;
		*by += (int64_t)a->y + a->look.border;
	}
}

int oracle_in_rects(const struct vis_rect *r, uint32_t n, int64_t x, int64_t y)
{
	for (uint32_t k = 0; k < n; k++)
		if (x >= r[k].x && y >= r[k].y && x < (int64_t)r[k].x + r[k].w &&
		    y < (int64_t)r[k].y + r[k].h)
			return 1;
	return 0;
}

int oracle_pixel_of(const struct vis_window *w, int64_t px, int64_t py)
{
	const struct vis_look *l = &w->look;
	int64_t bx, by, b = l->border;
	if (l->input_only)
		return 0;
	oracle_corner(w, &bx, &by);
	if (px < bx || py < by || px >= bx + w->width + 2 * b || py >= by + w->height + 2 * b)
		return 0;
	return !l->shaped || oracle_in_rects(l->shape, l->n_shape, px - bx - b, py - by - b);
}

int oracle_opaque_of(const struct vis_window *w, int64_t px, int64_t py)
{
	const struct vis_look *l = &w->look;
	if (!oracle_pixel_of(w, px, py) || l->opaque == VIS_OPAQUE_NONE)
		return 0;
	if (l->opaque == VIS_OPAQUE_ALL)
		return 1;
	int64_t bx, by;
	oracle_corner(w, &bx, &by);
	return oracle_in_rects(l->opaque_rects, l->n_opaque, px - bx - l->border,
			       py - by - l->border);
}

/* The tree's root, whose size is the screen's. */
static const struct vis_window *root_of(const struct vis_window *w)
{
	while (w->parent)
		w = w->parent;
	return w;
}

int oracle_inside_chain(const struct vis_window *w, int64_t px, int64_t py)
{
	const struct vis_window *root = root_of(w);
	if (px < 0 || py < 0 || px >= root->width || py >= root->height)
		return 0;
	for (const struct vis_window *a = w->parent; a->parent; a = a->parent) {
		int64_t ax, ay, b = a->look.border;
		oracle_corner(a, &ax, &ay);
		if (px < ax + b || py < ay + b || px >= ax + b + a->width ||
		    py >= ay + b + a->height)
			return 0;
		/* A shaped ancestor clips its descendants to its shape, as X does. */
		if (a->look.shaped &&
		    !oracle_in_rects(a->look.shape, a->look.n_shape, px - ax - b, py - ay - b))
			return 0;
	}
	return 1;
}

int oracle_viewable(const struct vis_window *w)
{
	for (; w->parent; w = w->parent)
		if (!w->mapped)
			return 0;
	return 1;
}

/* Whether w has a pixel of its own off the screen (its border box, or its shape in it). */
static bool pixels_off_screen(const struct vis_window *w)
{
	const struct vis_window *root = root_of(w);
	int64_t bx, by, b = w->look.border;
	oracle_corner(w, &bx, &by);
	int64_t x1 = bx + w->width + 2 * b, y1 = by + w->height + 2 * b;
	uint32_t n = w->look.shaped ? w->look.n_shape : 1;
	for (uint32_t k = 0; k < n; k++) {
		int64_t rx = bx, ry = by, rx1 = x1, ry1 = y1;
		if (w->look.shaped) {
			const struct vis_rect *r = &w->look.shape[k];
			rx = bx + b + r->x;
			ry = by + b + r->y;
			rx1 = rx + r->w;
			ry1 = ry + r->h;
			rx = rx > bx ? rx : bx;
			ry = ry > by ? ry : by;
			rx1 = rx1 < x1 ? rx1 : x1;
			ry1 = ry1 < y1 ? ry1 : y1;
		}
		if (rx < rx1 && ry < ry1 &&
		    (rx < 0 || ry < 0 || rx1 > root->width || ry1 > root->height))
			return true;
	}
	return false;
}

/* w's border box clipped to the screen, as x0 ≤ x < x1, y0 ≤ y < y1 (possibly empty). */
static void on_screen(const struct vis_window *w, int64_t sw, int64_t sh, int64_t b[4])
{
	int64_t bx, by, bw = 2 * (int64_t)w->look.border;
	oracle_corner(w, &bx, &by);
	b[0] = bx < 0 ? 0 : bx;
	b[1] = by < 0 ? 0 : by;
	b[2] = bx + w->width + bw > sw ? sw : bx + w->width + bw;
	b[3] = by + w->height + bw > sh ? sh : by + w->height + bw;
}

long oracle_paint(const struct vis_wtree *tree, uint8_t *states)
{
	int64_t sw = tree->root.width, sh = tree->root.height;
	size_t n = 0;
	for (const struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w))
		n++;
	const struct vis_window **win = malloc((n ? n : 1) * sizeof *win);
	size_t *end = malloc((n ? n : 1) * sizeof *end);
	long *top = malloc((size_t)(sw * sh) * sizeof *top);
	if (!win || !end || !top) {
		free(win);
		free(end);
		free(top);
		return -1;
	}
	size_t k = 0;
	for (const struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w))
		win[k++] = w;
	/* end[k]: the index just past k's subtree, the first later window no deeper than it. */
	for (size_t i = 0; i < n; i++) {
		size_t j = i + 1;
		while (j < n && win[j]->depth > win[i]->depth)
			j++;
		end[i] = j;
	}
	/* The painter: top[p] is the last window in pre-order with an opaque pixel at p. */
	for (int64_t p = 0; p < sw * sh; p++)
		top[p] = -1;
	for (size_t i = 0; i < n; i++) {
		const struct vis_window *w = win[i];
		if (w->look.input_only || !oracle_viewable(w))
			continue;
		int64_t b[4];
		on_screen(w, sw, sh, b);
		for (int64_t y = b[1]; y < b[3]; y++)
			for (int64_t x = b[0]; x < b[2]; x++)
				if (oracle_opaque_of(w, x, y) && oracle_inside_chain(w, x, y))
					top[y * sw + x] = (long)i;
	}
	for (size_t i = 0; i < n; i++) {
		const struct vis_window *w = win[i];
		if (w->look.input_only || !oracle_viewable(w)) {
			states[i] = VIS_WTREE_STATE_NONE;
			continue;
		}
		long all = 0, seen = 0;
		int64_t b[4];
		on_screen(w, sw, sh, b);
		for (int64_t y = b[1]; y < b[3]; y++)
			for (int64_t x = b[0]; x < b[2]; x++) {
				if (!oracle_pixel_of(w, x, y))
					continue;
				all++;
				if (oracle_inside_chain(w, x, y) && top[y * sw + x] < (long)end[i])
					seen++;
			}
		/* Pixels off the screen are never seen: such a window is never unobscured. */
		bool off = pixels_off_screen(w);
		states[i] = all == 0 && !off ? 2 : seen == all && !off ? 0 : seen ? 1 : 2;
	}
	free(win);
	free(end);
	free(top);
	return (long)n;
}
