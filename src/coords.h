/* Sorted sets of distinct coordinates, for mapping edges to their ranks. */
#ifndef VIS_COORDS_H
#define VIS_COORDS_H

#include <stddef.h>
#include <stdint.h>

/* Sorts values[0 … n) and drops duplicates; returns how many distinct values remain. O(n log n). */
size_t vis_coords_unique(int64_t *values, size_t n);

/* The index of v among the k distinct sorted values; v must be one of them. O(log k). */
size_t vis_coords_rank(const int64_t *values, size_t k, int64_t v);

#endif
