/*
 * Events in the last second (commits, frames), for viscompctl list: counted in ten buckets of
 * 100 ms, each reused once its tenth of a second is a second old. O(1) to count, O(10) to read;
 * the figure may include up to the last 100 ms before the second.
 */
#ifndef VISCOMP_RATE_H
#define VISCOMP_RATE_H

#include <stdint.h>

#define RATE_BUCKETS 10
#define RATE_BUCKET_MS 100

struct rate {
	uint64_t tick[RATE_BUCKETS]; /* the tenth of a second a bucket counts (ms / 100), 0: unused */
	uint32_t count[RATE_BUCKETS];
};

/* Counts one event at now_ms (monotonic milliseconds). */
static inline void rate_add(struct rate *rate, uint64_t now_ms)
{
	uint64_t tick = now_ms / RATE_BUCKET_MS + 1;
	unsigned slot = (unsigned)(tick % RATE_BUCKETS);
	if (rate->tick[slot] != tick) {
		rate->tick[slot] = tick;
		rate->count[slot] = 0;
	}
	rate->count[slot]++;
}

/* The events counted in the second up to now_ms. */
static inline uint32_t rate_get(const struct rate *rate, uint64_t now_ms)
{
	uint64_t tick = now_ms / RATE_BUCKET_MS + 1;
	uint32_t sum = 0;
	for (unsigned i = 0; i < RATE_BUCKETS; i++)
		if (rate->tick[i] + RATE_BUCKETS > tick)
			sum += rate->count[i];
	return sum;
}

#endif
