/*
 * A log-linear histogram of durations in nanoseconds, in the manner of HdrHistogram: values below
 * 256 have a bucket each, then every power of two is split into 128 buckets, so a percentile read
 * back is the top of its bucket, at most 1/128 (0.8%) above the true value, and never above the
 * largest value recorded. Fixed size (17 KiB), no allocation: recording is O(1), reading O(buckets).
 */
#ifndef VISCTL_HISTOGRAM_H
#define VISCTL_HISTOGRAM_H

#include <stdint.h>

#define HISTOGRAM_SUB_BITS 7
/* Values past 2^40 ns (18 minutes) are counted as 2^40 - 1. */
#define HISTOGRAM_MAX_BITS 40
#define HISTOGRAM_BUCKETS \
	((2u << HISTOGRAM_SUB_BITS) + (HISTOGRAM_MAX_BITS - HISTOGRAM_SUB_BITS - 1) * \
	 (1u << HISTOGRAM_SUB_BITS))

/* Invariant: n is the sum of counts; sum and max are those of the values recorded. */
struct histogram {
	uint64_t n, sum, max;
	uint32_t counts[HISTOGRAM_BUCKETS];
};

/* Empties the histogram. */
void histogram_init(struct histogram *h);

/* Counts one value. */
void histogram_record(struct histogram *h, uint64_t ns);

/* Adds every value of from into h. */
void histogram_add(struct histogram *h, const struct histogram *from);

/* The value at percentile p (0 < p ≤ 100): the smallest v with at least p% of values ≤ v. 0 when
 * empty. */
uint64_t histogram_percentile(const struct histogram *h, double p);

/* The mean, 0 when empty. */
double histogram_mean(const struct histogram *h);

#endif
