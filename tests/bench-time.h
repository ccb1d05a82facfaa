/* The benchmarks' clock and medians (bench-wtree.c, bench-libvis.c). */
#ifndef VIS_TESTS_BENCH_TIME_H
#define VIS_TESTS_BENCH_TIME_H

#include <time.h>

/* A monotonic time in microseconds, for differences. */
static inline double bench_now_us(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec * 1e6 + (double)ts.tv_nsec / 1e3;
}

/* qsort's order of doubles, to take medians and percentiles. */
static inline int bench_cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return x < y ? -1 : x > y;
}

#endif
