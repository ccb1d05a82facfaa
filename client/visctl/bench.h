/* visctl bench's results, shared by the measuring (cmd-bench.c) and the plot (bench-svg.c). */
#ifndef VISCTL_BENCH_H
#define VISCTL_BENCH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "engine.h"
#include "gen.h"
#include "machine.h"

#define MAX_SIZES 64

/* What became of one (kind, size, column) measurement; the column past the engines is qsort. */
enum cell_status {
	CELL_PENDING,   /* not reached */
	CELL_RAN,       /* ms holds the minimum over the repetitions */
	CELL_PREDICTED, /* skipped: extrapolation says it would run past the limit */
	CELL_STOPPED,   /* skipped: a smaller size already ran past the limit */
};

struct cell {
	enum cell_status status;
	double ms;
};

/*
 * The run's settings and results. sizes are ascending and unique, which the extrapolation
 * relies on; cells holds nkinds × nsizes × (nengines + 1) entries, qsort last in each row.
 */
struct bench {
	enum vis_gen_kind kinds[VIS_GEN_KIND_COUNT];
	size_t nkinds;
	enum vis_engine engines[VIS_ENGINE_COUNT];
	size_t nengines;
	size_t sizes[MAX_SIZES];
	size_t nsizes;
	unsigned reps;    /* 0: adaptive */
	double target_s;  /* adaptive: repeat until this much time is spent on a cell */
	double limit_s;   /* a cell predicted or measured past this is skipped at larger sizes */
	uint64_t seed;
	struct machine machine;
	struct cell *cells;
};

/* The cell of kind k, size s and column c. */
static inline struct cell *cell_at(const struct bench *b, size_t k, size_t s, size_t c)
{
	return &b->cells[(k * b->nsizes + s) * (b->nengines + 1) + c];
}

/*
 * Times b's engines on count scenes drawn from the scene family (family.h) with b's seed, n
 * log-uniform in [min_n, max_n], and prints each engine's time / the fastest's: median, p95,
 * worst and the worst scene. csv, unless NULL, gets a row a scene. 0, or -1 after a message.
 */
int bench_family(const struct bench *b, uint64_t count, size_t min_n, size_t max_n, FILE *csv);

/* Writes the log-log plot of time against n, one panel per kind. Returns 0, or -1 on error. */
int bench_svg_write(const struct bench *b, FILE *f);

#endif
