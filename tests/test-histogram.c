/*
 * visctl stress's latency histogram: exact below 256 ns, within 1/128 above the true value
 * beyond, never above the maximum; percentiles by rank; merging.
 */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <stdio.h>

#include "histogram.h"
#include "rng.h"

static struct histogram h, g;

int main(void)
{
	histogram_init(&h);
	assert(histogram_percentile(&h, 50) == 0 && histogram_mean(&h) == 0);

	/* 1 … 100: the p-th percentile is p itself; small values are exact. */
	for (uint64_t v = 1; v <= 100; v++)
		histogram_record(&h, v);
	assert(histogram_percentile(&h, 50) == 50);
	assert(histogram_percentile(&h, 99) == 99);
	assert(histogram_percentile(&h, 99.9) == 100 && histogram_percentile(&h, 100) == 100);
	assert(histogram_percentile(&h, 0.1) == 1);
	assert(histogram_mean(&h) == 50.5 && h.max == 100 && h.n == 100);

	/* Every value, alone, reads back within 1/128 above itself and never above the maximum. */
	struct vis_rng rng = { 1 };
	for (int i = 0; i < 200000; i++) {
		uint64_t v = vis_rng_next(&rng) >> (24 + vis_rng_below(&rng, 40));
		histogram_init(&g);
		histogram_record(&g, v);
		histogram_record(&g, (UINT64_C(1) << 40) - 1);
		uint64_t got = histogram_percentile(&g, 50);
		assert(got >= v && (double)(got - v) <= (double)v / 128);
	}

	/* A value past the range counts as its end. */
	histogram_init(&g);
	histogram_record(&g, UINT64_MAX);
	assert(g.max == (UINT64_C(1) << 40) - 1);

	/* 10,000 values 1 µs and one of 1 s: p99.99 is still 1 µs, the maximum 1 s. */
	histogram_init(&g);
	for (int i = 0; i < 10000; i++)
		histogram_record(&g, 1000);
	histogram_record(&g, 1000000000);
	uint64_t p = histogram_percentile(&g, 99.99);
	assert(p >= 1000 && p <= 1000 + 1000 / 128);
	assert(histogram_percentile(&g, 100) == 1000000000);

	/* Merging adds counts, sums and the maximum. */
	histogram_add(&h, &g);
	assert(h.n == 10101 && h.max == 1000000000 && h.sum == 5050 + 10000 * 1000 + 1000000000);
	printf("histogram: every check passed\n");
	return 0;
}
