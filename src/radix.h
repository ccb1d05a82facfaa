/* A stable radix sort, for the sorts on the hot paths (event schedules, IDs). */
#ifndef VIS_RADIX_H
#define VIS_RADIX_H

#include <stddef.h>
#include <stdint.h>

/*
 * Sorts the pairs (key[i], val[i]) by key, keeping equal keys in their order, 11 bits a pass and
 * skipping passes in which every key has the same digit. Returns 0, or -1 (ENOMEM).
 * O(n · b / 11) for keys of b significant bits.
 */
int vis_radix_sort(uint64_t *key, uint32_t *val, size_t n);

#endif
