#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "radix.h"

#define RADIX_BITS 11
#define RADIX_SIZE (1u << RADIX_BITS)

int vis_radix_sort(uint64_t *key, uint32_t *val, size_t n)
{
	uint64_t max = 0;
	for (size_t i = 0; i < n; i++)
		max |= key[i];
	uint64_t *key2 = malloc(n * sizeof(*key2) + 1);
	uint32_t *val2 = malloc(n * sizeof(*val2) + 1);
	size_t *count = malloc(RADIX_SIZE * sizeof(*count));
	if (!key2 || !val2 || !count) {
		free(key2);
		free(val2);
		free(count);
		errno = ENOMEM;
		return -1;
	}
	uint64_t *src_k = key, *dst_k = key2;
	uint32_t *src_v = val, *dst_v = val2;
	for (unsigned shift = 0; shift < 64 && (max >> shift) != 0; shift += RADIX_BITS) {
		memset(count, 0, RADIX_SIZE * sizeof(*count));
		for (size_t i = 0; i < n; i++)
			count[(src_k[i] >> shift) & (RADIX_SIZE - 1)]++;
		if (count[(src_k[0] >> shift) & (RADIX_SIZE - 1)] == n)
			continue;
		size_t sum = 0;
		for (size_t d = 0; d < RADIX_SIZE; d++) {
			size_t c = count[d];
			count[d] = sum;
			sum += c;
		}
		for (size_t i = 0; i < n; i++) {
			size_t at = count[(src_k[i] >> shift) & (RADIX_SIZE - 1)]++;
			dst_k[at] = src_k[i];
			dst_v[at] = src_v[i];
		}
		uint64_t *tk = src_k;
		src_k = dst_k;
		dst_k = tk;
		uint32_t *tv = src_v;
		src_v = dst_v;
		dst_v = tv;
	}
	if (src_k != key) {
		memcpy(key, src_k, n * sizeof(*key));
		memcpy(val, src_v, n * sizeof(*val));
	}
	free(key2);
	free(val2);
	free(count);
	return 0;
}
