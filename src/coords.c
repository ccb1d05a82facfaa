#include <stdlib.h>

#include "coords.h"

/* Orders int64 values for qsort and bsearch. */
static int cmp_i64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
	return (x > y) - (x < y);
}

size_t vis_coords_unique(int64_t *values, size_t n)
{
	size_t k = 0;

	qsort(values, n, sizeof *values, cmp_i64);
	for (size_t i = 0; i < n; i++) {
		if (k == 0 || values[k - 1] != values[i])
			values[k++] = values[i];
	}
	return k;
}

size_t vis_coords_rank(const int64_t *values, size_t k, int64_t v)
{
	const int64_t *p = bsearch(&v, values, k, sizeof *values, cmp_i64);
	return (size_t)(p - values);
}
