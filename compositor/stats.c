#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "control.h"
#include "stats.h"

uint64_t stats_now_ns(void)
{
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	return (uint64_t)now.tv_sec * 1000000000u + (uint64_t)now.tv_nsec;
}

void stats_add(struct stats_series *series, uint64_t ns)
{
	stats_add_latency(series, ns, 0);
}

void stats_add_latency(struct stats_series *series, uint64_t ns, uint32_t frames)
{
	series->ns[series->count % STATS_SAMPLES] = ns;
	series->frames[series->count % STATS_SAMPLES] = frames;
	series->count++;
}

void stats_mark_change(struct stats *stats, uint64_t ns)
{
	stats->change_ns = ns;
	stats->change_frames = stats->frames;
}

void stats_reset(struct stats *stats)
{
	stats->frame.count = stats->cover.count = stats->uncover.count = 0;
}

static int cmp_u64(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return (x > y) - (x < y);
}

/* One series' line: its samples sorted in a copy (the ring keeps its order); a latency's ends
 * with the most frames one took. */
static void report_series(const char *name, const struct stats_series *series, bool latency,
			  struct control_reply *reply)
{
	static uint64_t sorted[STATS_SAMPLES];
	size_t n = series->count < STATS_SAMPLES ? (size_t)series->count : STATS_SAMPLES;
	memcpy(sorted, series->ns, n * sizeof(*sorted));
	qsort(sorted, n, sizeof(*sorted), cmp_u64);
	double median = n ? (double)sorted[n / 2] / 1e3 : 0, p99 = n ? (double)sorted[n * 99 / 100] / 1e3 : 0;
	double max = n ? (double)sorted[n - 1] / 1e3 : 0;
	control_reply_printf(reply, "%s count=%llu median_us=%.1f p99_us=%.1f max_us=%.1f", name,
			     (unsigned long long)series->count, median, p99, max);
	if (latency) {
		uint32_t max_frames = 0;
		for (size_t i = 0; i < n; i++)
			if (series->frames[i] > max_frames)
				max_frames = series->frames[i];
		control_reply_printf(reply, " max_frames=%u", max_frames);
	}
	control_reply_printf(reply, "\n");
}

void stats_report(const struct stats *stats, struct control_reply *reply)
{
	report_series("frame", &stats->frame, false, reply);
	report_series("cover", &stats->cover, true, reply);
	report_series("uncover", &stats->uncover, true, reply);
}
