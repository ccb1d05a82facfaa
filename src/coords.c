#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "coords.h"

/* Orders int64 values for qsort and bsearch. */
static int cmp_i64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
	return (x > y) - (x < y);
}

/* Sorts values[0 … n) and drops duplicates; returns how many distinct values remain. */
static size_t sort_unique(int64_t *values, size_t n)
{
	size_t k = 0;

	qsort(values, n, sizeof *values, cmp_i64);
	for (size_t i = 0; i < n; i++) {
		if (k == 0 || values[k - 1] != values[i])
			values[k++] = values[i];
	}
	return k;
}

int vis_coords_init(struct vis_coords *coords, const struct vis_stack *stack)
{
	size_t n = stack->n;

	memset(coords, 0, sizeof(*coords));
	if (n > SIZE_MAX / (2 * sizeof(int64_t)) - 1) {
		errno = EOVERFLOW;
		return -1;
	}
	coords->x = malloc((2 * n + 1) * sizeof(int64_t));
	coords->y = malloc((2 * n + 1) * sizeof(int64_t));
	if (coords->x == NULL || coords->y == NULL) {
		vis_coords_finish(coords);
		errno = ENOMEM;
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		coords->x[coords->nx++] = b.x1;
		coords->x[coords->nx++] = b.x2;
		coords->y[coords->ny++] = b.y1;
		coords->y[coords->ny++] = b.y2;
	}
	coords->nx = sort_unique(coords->x, coords->nx);
	coords->ny = sort_unique(coords->y, coords->ny);
	return 0;
}

void vis_coords_finish(struct vis_coords *coords)
{
	free(coords->x);
	free(coords->y);
	memset(coords, 0, sizeof(*coords));
}

/* The index of v among the k distinct sorted values. */
static size_t rank(const int64_t *values, size_t k, int64_t v)
{
	const int64_t *p = bsearch(&v, values, k, sizeof *values, cmp_i64);
	return (size_t)(p - values);
}

size_t vis_coords_rank_x(const struct vis_coords *coords, int64_t v)
{
	return rank(coords->x, coords->nx, v);
}

size_t vis_coords_rank_y(const struct vis_coords *coords, int64_t v)
{
	return rank(coords->y, coords->ny, v);
}
