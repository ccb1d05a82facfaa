/* bench-wtree's changes, recomputes and results, shared with its plot (bench-wtree-svg.c). */
#ifndef BENCH_WTREE_H
#define BENCH_WTREE_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "gen.h"

/* Which windows change: any window, or the top one (a drag). */
enum who { ANY, TOP, WHO_COUNT };

/* The changes, and the recomputes. */
enum op { MOVE, RAISE, LOWER, UNMAP, MAP, OP_COUNT };
enum engine { FULL, DAMAGED, LIVE, ENGINE_COUNT };

/* One printed cell: the median and the 99th percentile (µs) of one recompute after one change. */
struct wtree_result {
	enum vis_gen_kind kind;
	size_t n;
	enum who who;
	enum engine engine;
	double median_us, p99_us;
};

/* What the plot draws: the results of one change, in the order they ran, and its title's facts. */
struct wtree_plot {
	const struct wtree_result *results;
	size_t count;
	const char *op;   /* the change, "move" … */
	size_t moves;
	uint64_t seed;
	const char *note; /* --note: after the machine and the date, or NULL */
};

/*
 * Writes the log-log plot of the median cost against n, one panel per kind, shaded up to the 99th
 * percentile. Returns 0, or -1 on a write error.
 */
int bench_wtree_svg_write(FILE *f, const struct wtree_plot *p);

#endif
