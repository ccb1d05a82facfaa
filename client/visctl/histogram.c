/* The latency histogram of visctl stress: log-linear buckets, as HdrHistogram lays them out. */
#include <math.h>
#include <string.h>

#include "histogram.h"

#define SUB (1u << HISTOGRAM_SUB_BITS)
#define LIMIT ((UINT64_C(1) << HISTOGRAM_MAX_BITS) - 1)

/* The bucket of a value: values below 2·SUB are their own bucket; above, each power of two
 * [2^k, 2^(k+1)) is cut into SUB buckets of width 2^(k - SUB_BITS). */
static uint32_t bucket_of(uint64_t v)
{
	if (v < 2 * SUB)
		return (uint32_t)v;
	unsigned msb = 63u - (unsigned)__builtin_clzll(v);
	unsigned shift = msb - HISTOGRAM_SUB_BITS;
	return 2 * SUB + (shift - 1) * SUB + (uint32_t)((v >> shift) - SUB);
}

/* The largest value that falls into bucket b. */
static uint64_t bucket_top(uint32_t b)
{
	if (b < 2 * SUB)
		return b;
	unsigned shift = (b - 2 * SUB) / SUB + 1;
	uint64_t mantissa = SUB + (b - 2 * SUB) % SUB;
	return ((mantissa + 1) << shift) - 1;
}

void histogram_init(struct histogram *h)
{
	memset(h, 0, sizeof(*h));
}

void histogram_record(struct histogram *h, uint64_t ns)
{
	if (ns > LIMIT)
		ns = LIMIT;
	h->counts[bucket_of(ns)]++;
	h->n++;
	h->sum += ns;
	if (ns > h->max)
		h->max = ns;
}

void histogram_add(struct histogram *h, const struct histogram *from)
{
	for (uint32_t b = 0; b < HISTOGRAM_BUCKETS; b++)
		h->counts[b] += from->counts[b];
	h->n += from->n;
	h->sum += from->sum;
	if (from->max > h->max)
		h->max = from->max;
}

uint64_t histogram_percentile(const struct histogram *h, double p)
{
	if (h->n == 0)
		return 0;
	/* The rank of the value asked for, 1-based; rounding up so that p99 of 100 values is the
	 * 99th and p100 the last. */
	double want = ceil(p / 100.0 * (double)h->n);
	uint64_t rank = want < 1 ? 1 : want > (double)h->n ? h->n : (uint64_t)want;
	uint64_t seen = 0;
	for (uint32_t b = 0; b < HISTOGRAM_BUCKETS; b++) {
		seen += h->counts[b];
		if (seen >= rank) {
			uint64_t top = bucket_top(b);
			return top < h->max ? top : h->max;
		}
	}
	return h->max;
}

double histogram_mean(const struct histogram *h)
{
	return h->n ? (double)h->sum / (double)h->n : 0;
}
