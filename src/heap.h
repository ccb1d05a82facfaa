/* Binary max-heaps of window numbers in caller-provided storage, for the per-node heaps. */
#ifndef VIS_HEAP_H
#define VIS_HEAP_H

#include <stdint.h>

/* Adds x to the max-heap a[0 … *len). The caller guarantees room. O(log len). */
static inline void vis_heap_push(uint32_t *a, uint32_t *len, uint32_t x)
{
	uint32_t i = (*len)++;
	while (i > 0) {
		uint32_t p = (i - 1) / 2;
		if (a[p] >= x)
			break;
		a[i] = a[p];
		i = p;
	}
	a[i] = x;
}

/* Moves x down from the hole at i of the max-heap a[0 … n) to its place. O(log n). */
static inline void vis_heap_sift(uint32_t *a, uint32_t n, uint32_t i, uint32_t x)
{
	for (;;) {
		uint32_t c = 2 * i + 1;
		if (c >= n)
			break;
		/*
		 * Which child is larger is a coin toss the branch predictor loses; as arithmetic
		 * it costs nothing. a[n] may be read: it is the old last element, still there.
		 */
		c += (c + 1 < n) & (a[c + 1] > a[c]);
		if (a[c] <= x)
			break;
		a[i] = a[c];
		i = c;
	}
	a[i] = x;
}

/* Removes the largest element of the non-empty max-heap a[0 … *len). O(log len). */
static inline void vis_heap_pop(uint32_t *a, uint32_t *len)
{
	uint32_t n = --(*len);
	if (n > 0)
		vis_heap_sift(a, n, 0, a[n]);
}

/* Puts a[0 … len) in heap order (Floyd). O(len). */
static inline void vis_heap_build(uint32_t *a, uint32_t len)
{
	for (uint32_t i = len / 2; i-- > 0;)
		vis_heap_sift(a, len, i, a[i]);
}

#endif
