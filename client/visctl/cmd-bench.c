/* visctl bench: every engine timed on generated scenes of growing size, against a qsort floor. */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "scene.h"
#include "visctl.h"

static const size_t default_sizes[] = {
	1000, 2000, 10000, 100000, 200000, 400000, 1000000,
};

/* Brute is left out: it is the tests' oracle, O(n³), and would only be skipped past n = 10^3. */
static const enum vis_engine default_engines[] = {
	VIS_ENGINE_AUTO, VIS_ENGINE_GMV, VIS_ENGINE_GMV_HEAP, VIS_ENGINE_REGION,
};

/* Seconds on the monotonic clock, which NTP slewing cannot bend. */
static double now_s(void)
{
	struct timespec ts;

	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* Formats a time in ms with about three significant figures, so columns stay narrow. */
static const char *fmt_ms(char *buf, size_t len, double ms)
{
	snprintf(buf, len, ms < 10 ? "%.3f" : ms < 10000 ? "%.1f" : "%.0f", ms);
	return buf;
}

/* Parses a whole unsigned decimal number; strtoull alone would accept "-1" and "12abc". */
static int parse_u64(const char *s, uint64_t *out)
{
	char *end;

	if (*s < '0' || *s > '9')
		return -1;
	errno = 0;
	unsigned long long v = strtoull(s, &end, 10);
	if (errno != 0 || *end != '\0')
		return -1;
	*out = v;
	return 0;
}

/* Orders sizes for qsort. */
static int cmp_size(const void *a, const void *b)
{
	size_t x = *(const size_t *)a, y = *(const size_t *)b;

	return (x > y) - (x < y);
}

/* Orders coordinates: the plain comparison the reference qsort is meant to measure. */
static int cmp_i64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;

	return (x > y) - (x < y);
}

/* Parses a comma-separated list of names or numbers into the bench; returns -1 after a message. */
static int parse_list(struct bench *b, int which, const char *arg)
{
	char *copy = strdup(arg), *save = NULL, *tok;

	if (copy == NULL) {
		fprintf(stderr, "visctl bench: out of memory\n");
		return -1;
	}
	if (which == 'k')
		b->nkinds = 0;
	else if (which == 'e')
		b->nengines = 0;
	else
		b->nsizes = 0;
	for (tok = strtok_r(copy, ",", &save); tok != NULL; tok = strtok_r(NULL, ",", &save)) {
		enum vis_gen_kind kind;
		enum vis_engine engine;
		uint64_t n;

		if (which == 'k' && vis_gen_kind_from_name(tok, &kind) == 0) {
			for (size_t i = 0; i < b->nkinds; i++)
				if (b->kinds[i] == kind)
					goto dup;
			b->kinds[b->nkinds++] = kind;
		} else if (which == 'e' && vis_engine_from_name(tok, &engine) == 0) {
			for (size_t i = 0; i < b->nengines; i++)
				if (b->engines[i] == engine)
					goto dup;
			b->engines[b->nengines++] = engine;
		} else if (which == 's' && parse_u64(tok, &n) == 0 && n >= 1 &&
			   n <= SIZE_MAX / 64) {
			if (b->nsizes == MAX_SIZES) {
				fprintf(stderr, "visctl bench: at most %d sizes\n", MAX_SIZES);
				goto fail;
			}
			b->sizes[b->nsizes++] = (size_t)n;
		} else {
			fprintf(stderr, "visctl bench: %s '%s'\n",
				which == 'k' ? "unknown kind" : which == 'e' ? "unknown engine" :
				"bad size", tok);
			goto fail;
		}
		continue;
dup:
		fprintf(stderr, "visctl bench: '%s' given twice\n", tok);
		goto fail;
	}
	if ((which == 'k' && b->nkinds == 0) || (which == 'e' && b->nengines == 0) ||
	    (which == 's' && b->nsizes == 0)) {
		fprintf(stderr, "visctl bench: empty list '%s'\n", arg);
		goto fail;
	}
	free(copy);
	return 0;
fail:
	free(copy);
	return -1;
}

/* Prints the usage text, for --help and after a bad option. */
static void usage(FILE *f)
{
	fprintf(f,
		"usage: visctl bench [--kinds K,...] [--engines E,...] [--sizes N,...]\n"
		"                    [--max-n N] [--reps R] [--seed S] [--limit SECONDS]\n"
		"                    [--svg FILE] [--csv FILE] [--quick]\n"
		"       visctl bench --family COUNT [--min-n N] [--max-n N] [--engines E,...]\n"
		"                    [--seed S] [--csv FILE] [--quick]\n"
		"Times vis_compute per engine on generated scenes (minimum over repetitions;\n"
		"by default at least 3, until 0.2 s is spent on a cell) against qsort of the 4n\n"
		"coordinates. Defaults: all kinds; engines auto,gmv,gmv-heap,region;\n"
		"sizes 1000,2000,10000,100000,200000,400000,1000000; seed 1; limit 60 s.\n"
		"--quick: sizes up to 10000 and 0.02 s per cell, a smoke run.\n"
		"--family: COUNT scenes drawn at random from a family with continuous parameters\n"
		"(window sizes, aspect, placement, steps, alignment, bars, screen or none; n from\n"
		"--min-n, default 100, to --max-n, default 100000), each engine's time against the\n"
		"fastest's on the same scene: median, p95, worst, and the worst scene's parameters;\n"
		"at least 3 runs and 0.01 s an engine (--quick: 3 runs); an engine past 32 times the\n"
		"fastest (and 2 s) is stopped and counted as slower than that.\n");
}

/*
 * Whether a cell has had enough repetitions: a fixed count, or enough time for a stable minimum
 * and at least three, so that even the largest cells are timed warm twice, as qsort is (on its
 * buffer allocated once): the first run of a size also faults in the memory the engines keep for
 * reuse, and one warm run on a shared machine is one draw of its noise.
 */
static bool reps_done(const struct bench *b, unsigned reps, double total_s, double last_s)
{
	if (last_s > b->limit_s)
		return true;
	if (b->reps != 0)
		return reps >= b->reps;
	return reps >= 3 && (total_s >= b->target_s || reps >= 100000);
}

/* Times one engine on a stack, leaving its states in states; returns -1 with errno on failure. */
static int time_engine(const struct bench *b, enum vis_engine engine,
		       const struct vis_stack *stack, uint8_t *states, double *ms,
		       unsigned *reps)
{
	double best = INFINITY, total = 0, t;

	*reps = 0;
	do {
		double t0 = now_s();

		if (vis_compute(engine, stack, states) < 0)
			return -1;
		t = now_s() - t0;
		total += t;
		(*reps)++;
		if (t < best)
			best = t;
	} while (!reps_done(b, *reps, total, t));
	*ms = best * 1e3;
	return 0;
}

/* Times qsort of count coordinates, each rep on a fresh copy so it never sorts sorted data. */
static void time_qsort(const struct bench *b, const int64_t *coords, int64_t *work,
		       size_t count, double *ms, unsigned *reps)
{
	double best = INFINITY, total = 0, t;

	*reps = 0;
	do {
		memcpy(work, coords, count * sizeof(*work));
		double t0 = now_s();

		qsort(work, count, sizeof(*work), cmp_i64);
		t = now_s() - t0;
		total += t;
		(*reps)++;
		if (t < best)
			best = t;
	} while (!reps_done(b, *reps, total, t));
	*ms = best * 1e3;
}

/*
 * Predicts column c's time at size s from its earlier sizes on the same kind, so a cell that
 * would run past the limit is never started. The growth exponent is the one observed between the
 * last two sizes, clamped to [1, 3]: no engine is sublinear or worse than cubic, and small-n
 * timing noise can suggest either. The region method, once past 1 s, is held to at least 2:
 * its box count grows as Θ(n²) on bad scenes, and being slow means it is on that curve.
 * Returns 0 when there is no earlier size to extrapolate from.
 */
static double predict_ms(const struct bench *b, size_t k, size_t s, size_t c)
{
	size_t last = SIZE_MAX, prev = SIZE_MAX;

	for (size_t i = 0; i < s; i++) {
		if (cell_at(b, k, i, c)->status == CELL_RAN) {
			prev = last;
			last = i;
		}
	}
	if (last == SIZE_MAX)
		return 0;
	double t1 = cell_at(b, k, last, c)->ms, n1 = (double)b->sizes[last];
	double e = 1;
	if (prev != SIZE_MAX) {
		double t0 = cell_at(b, k, prev, c)->ms, n0 = (double)b->sizes[prev];

		if (t0 > 0 && t1 > 0)
			e = log(t1 / t0) / log(n1 / n0);
	}
	if (c < b->nengines && b->engines[c] == VIS_ENGINE_REGION && t1 > 1000 && e < 2)
		e = 2;
	e = e < 1 ? 1 : e > 3 ? 3 : e;
	return t1 * pow((double)b->sizes[s] / n1, e);
}

/* Prints the first window two engines disagree on, the one failure a benchmark must not hide. */
static void report_mismatch(const struct bench *b, size_t k, size_t n, enum vis_engine ref,
			    const uint8_t *want, enum vis_engine engine, const uint8_t *got)
{
	size_t i = 0;

	while (i < n && want[i] == got[i])
		i++;
	fprintf(stderr, "visctl bench: engines disagree on %s n=%zu seed %llu: window %zu "
		"(id %zu) is %s under %s but %s under %s\n",
		vis_gen_kind_name(b->kinds[k]), n, (unsigned long long)b->seed, i, i + 1,
		vis_state_name((enum vis_state)want[i]), vis_engine_name(ref),
		vis_state_name((enum vis_state)got[i]), vis_engine_name(engine));
}

/* Measures every column at size s of kind k; returns 0, or -1 after printing why. */
static int bench_size(struct bench *b, size_t k, size_t s)
{
	const char *kind = vis_gen_kind_name(b->kinds[k]);
	size_t n = b->sizes[s], have_ref = SIZE_MAX;
	struct vis_scene scene;
	uint8_t *states = NULL, *ref = NULL;
	int64_t *coords = NULL, *work = NULL;
	char buf[32];
	unsigned reps;
	int ret = -1;

	vis_scene_init(&scene);
	if (vis_gen(&scene, b->kinds[k], n, b->seed, 0, 0) < 0) {
		fprintf(stderr, "visctl bench: generating %s n=%zu: %s\n", kind, n,
			strerror(errno));
		goto out;
	}
	struct vis_stack stack = vis_scene_stack(&scene);
	/* n ≤ SIZE_MAX / 64 was checked when parsing, so 4n coordinates cannot overflow. */
	states = malloc(n);
	ref = malloc(n);
	coords = malloc(4 * n * sizeof(*coords));
	work = malloc(4 * n * sizeof(*work));
	if (states == NULL || ref == NULL || coords == NULL || work == NULL) {
		fprintf(stderr, "visctl bench: %s n=%zu: out of memory\n", kind, n);
		goto out;
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_box box = vis_rect_box(stack.rects[i]);

		coords[4 * i] = box.x1;
		coords[4 * i + 1] = box.y1;
		coords[4 * i + 2] = box.x2;
		coords[4 * i + 3] = box.y2;
	}
	struct cell *q = cell_at(b, k, s, b->nengines);
	time_qsort(b, coords, work, 4 * n, &q->ms, &reps);
	q->status = CELL_RAN;
	fprintf(stderr, "bench: %s n=%zu qsort %s ms (%u rep%s)\n", kind, n,
		fmt_ms(buf, sizeof(buf), q->ms), reps, reps == 1 ? "" : "s");
	/* 64 bytes a window the engines need not compete with (64 MB at n = 10^6). */
	free(work);
	free(coords);
	work = coords = NULL;

	for (size_t c = 0; c < b->nengines; c++) {
		enum vis_engine engine = b->engines[c];
		struct cell *cell = cell_at(b, k, s, c);
		const struct cell *before = s > 0 ? cell_at(b, k, s - 1, c) : NULL;
		double predicted = predict_ms(b, k, s, c);

		/* Once skipped, an engine stays skipped: larger scenes only take longer. */
		if (before != NULL && before->status != CELL_RAN)
			cell->status = before->status;
		else if (before != NULL && before->ms > b->limit_s * 1e3)
			cell->status = CELL_STOPPED;
		else if (predicted > b->limit_s * 1e3)
			cell->status = CELL_PREDICTED;
		if (cell->status == CELL_PREDICTED) {
			fprintf(stderr, "bench: %s n=%zu %s skipped (predicted %.3g s > %g s)\n",
				kind, n, vis_engine_name(engine), predicted / 1e3, b->limit_s);
			continue;
		} else if (cell->status != CELL_PENDING) {
			fprintf(stderr, "bench: %s n=%zu %s skipped (a smaller size took > %g s)\n",
				kind, n, vis_engine_name(engine), b->limit_s);
			continue;
		}
		if (time_engine(b, engine, &stack, states, &cell->ms, &reps) < 0) {
			fprintf(stderr, "visctl bench: %s on %s n=%zu: %s\n",
				vis_engine_name(engine), kind, n, strerror(errno));
			goto out;
		}
		cell->status = CELL_RAN;
		fprintf(stderr, "bench: %s n=%zu %s %s ms (%u rep%s)\n", kind, n,
			vis_engine_name(engine), fmt_ms(buf, sizeof(buf), cell->ms), reps,
			reps == 1 ? "" : "s");
		if (have_ref == SIZE_MAX) {
			memcpy(ref, states, n);
			have_ref = c;
		} else if (memcmp(ref, states, n) != 0) {
			report_mismatch(b, k, n, b->engines[have_ref], ref, engine, states);
			goto out;
		}
	}
	ret = 0;
out:
	free(work);
	free(coords);
	free(ref);
	free(states);
	vis_scene_finish(&scene);
	return ret;
}

/* Prints a ratio as a fixed-width figure followed by ×, or a dash when it cannot be formed. */
static void print_ratio(double num, double den, int width)
{
	if (num > 0 && den > 0) {
		double r = num / den;

		if (r < 0.001)
			printf(" %*s×", width - 1, "<0.001");
		else
			printf(" %*.*f×", width - 1, r < 0.1 ? 3 : r < 10 ? 2 : r < 100 ? 1 : 0, r);
	} else {
		printf(" %*s", width, "-");
	}
}

/* Prints the table of kind k to stdout: a row per size, a column group per engine. */
static void print_table(const struct bench *b, size_t k)
{
	size_t region = SIZE_MAX;
	char buf[48];

	for (size_t c = 0; c < b->nengines; c++)
		if (b->engines[c] == VIS_ENGINE_REGION)
			region = c;
	printf("\n%s (seed %llu; /qsort = engine / qsort, speed-up = region / engine)\n%9s %11s",
	       vis_gen_kind_name(b->kinds[k]), (unsigned long long)b->seed, "n", "qsort ms");
	for (size_t c = 0; c < b->nengines; c++) {
		snprintf(buf, sizeof(buf), "%s ms", vis_engine_name(b->engines[c]));
		printf(" | %11s %8s %9s", buf, "/qsort", "speed-up");
	}
	printf("\n");
	for (size_t s = 0; s < b->nsizes; s++) {
		const struct cell *q = cell_at(b, k, s, b->nengines);
		const struct cell *r = region == SIZE_MAX ? NULL : cell_at(b, k, s, region);
		double region_ms = r != NULL && r->status == CELL_RAN ? r->ms : 0;

		if (q->status != CELL_RAN)
			break;
		printf("%9zu %11s", b->sizes[s], fmt_ms(buf, sizeof(buf), q->ms));
		for (size_t c = 0; c < b->nengines; c++) {
			const struct cell *cell = cell_at(b, k, s, c);

			printf(" |");
			if (cell->status == CELL_RAN) {
				printf(" %11s", fmt_ms(buf, sizeof(buf), cell->ms));
				print_ratio(cell->ms, q->ms, 8);
				print_ratio(region_ms, cell->ms, 9);
			} else {
				snprintf(buf, sizeof(buf), "skipped (%s > %g s)",
					 cell->status == CELL_PREDICTED ? "predicted" : "earlier",
					 b->limit_s);
				/* No padding after the last column: no trailing blanks. */
				printf(" %-*s", c + 1 < b->nengines ? 30 : 0, buf);
			}
		}
		printf("\n");
	}
	fflush(stdout);
}

/* Writes the measured cells as kind,n,engine,ms rows; skipped cells have no row. */
static int write_csv(const struct bench *b, FILE *f)
{
	fprintf(f, "kind,n,engine,ms\n");
	for (size_t k = 0; k < b->nkinds; k++)
		for (size_t s = 0; s < b->nsizes; s++)
			for (size_t c = 0; c <= b->nengines; c++) {
				const struct cell *cell = cell_at(b, k, s, c);

				if (cell->status != CELL_RAN)
					continue;
				fprintf(f, "%s,%zu,%s,%.6f\n", vis_gen_kind_name(b->kinds[k]),
					b->sizes[s], c == b->nengines ? "qsort" :
					vis_engine_name(b->engines[c]), cell->ms);
			}
	return ferror(f) ? -1 : 0;
}

/* Closes an output file; a failed write of buffered data (a full disk) shows up only here. */
static int close_output(FILE *f, const char *path, bool wrote)
{
	if (fclose(f) != 0 && wrote) {
		fprintf(stderr, "visctl bench: writing %s: %s\n", path, strerror(errno));
		return -1;
	}
	return 0;
}

/* Parses the options into b; returns 0, 1 after --help, or 2 after printing what is wrong. */
static int parse_options(struct bench *b, int argc, char **argv, const char **svg,
			 const char **csv, uint64_t *family, uint64_t *min_n, uint64_t *family_max_n)
{
	static const struct option longopts[] = {
		{ "kinds", required_argument, NULL, 'k' },
		{ "engines", required_argument, NULL, 'e' },
		{ "sizes", required_argument, NULL, 's' },
		{ "max-n", required_argument, NULL, 'm' },
		{ "reps", required_argument, NULL, 'r' },
		{ "seed", required_argument, NULL, 'S' },
		{ "limit", required_argument, NULL, 'l' },
		{ "svg", required_argument, NULL, 'g' },
		{ "csv", required_argument, NULL, 'c' },
		{ "quick", no_argument, NULL, 'q' },
		{ "family", required_argument, NULL, 'F' },
		{ "min-n", required_argument, NULL, 'M' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	uint64_t max_n = SIZE_MAX, v;
	bool sizes_given = false, quick = false;
	char *end;
	int opt;

	/* visctl may have run getopt already; 0 makes glibc start afresh on this argv. */
	optind = 0;
	opterr = 0;
	while ((opt = getopt_long(argc, argv, "h", longopts, NULL)) != -1) {
		switch (opt) {
		case 'k':
		case 'e':
		case 's':
			if (parse_list(b, opt, optarg) < 0)
				return 2;
			sizes_given |= opt == 's';
			break;
		case 'm':
		case 'r':
		case 'S':
		case 'F':
		case 'M':
			if (parse_u64(optarg, &v) < 0 || (opt == 'r' && (v < 1 || v > 1000000)) ||
			    ((opt == 'F' || opt == 'M') && (v < 1 || v > 10000000))) {
				fprintf(stderr, "visctl bench: bad number '%s'\n", optarg);
				return 2;
			}
			if (opt == 'F')
				*family = v;
			else if (opt == 'M')
				*min_n = v;
			else if (opt == 'm')
				max_n = *family_max_n = v;
			else if (opt == 'r')
				b->reps = (unsigned)v;
			else
				b->seed = v;
			break;
		case 'l':
			b->limit_s = strtod(optarg, &end);
			if (*end != '\0' || !(b->limit_s > 0 && b->limit_s < 1e6)) {
				fprintf(stderr, "visctl bench: bad limit '%s'\n", optarg);
				return 2;
			}
			break;
		case 'g':
			*svg = optarg;
			break;
		case 'c':
			*csv = optarg;
			break;
		case 'q':
			quick = true;
			break;
		case 'h':
			usage(stdout);
			return 1;
		default:
			fprintf(stderr, "visctl bench: bad option or missing value: '%s'\n",
				argv[optind - 1]);
			usage(stderr);
			return 2;
		}
	}
	if (optind < argc) {
		fprintf(stderr, "visctl bench: unexpected argument '%s'\n", argv[optind]);
		return 2;
	}
	if (*family) {
		b->target_s = quick ? 0 : 0.01;
		if (*min_n > *family_max_n) {
			fprintf(stderr, "visctl bench: --min-n %llu is over --max-n %llu\n",
				(unsigned long long)*min_n, (unsigned long long)*family_max_n);
			return 2;
		}
		return 0;
	}
	if (quick) {
		b->target_s = 0.02;
		if (!sizes_given && max_n > 10000)
			max_n = 10000;
	}
	/* Ascending, unique sizes: the skip prediction extrapolates from the smaller ones. */
	qsort(b->sizes, b->nsizes, sizeof(b->sizes[0]), cmp_size);
	size_t m = 0;
	for (size_t i = 0; i < b->nsizes; i++)
		if (b->sizes[i] <= max_n && (m == 0 || b->sizes[m - 1] != b->sizes[i]))
			b->sizes[m++] = b->sizes[i];
	b->nsizes = m;
	if (m == 0) {
		fprintf(stderr, "visctl bench: no size left under --max-n %llu\n",
			(unsigned long long)max_n);
		return 2;
	}
	return 0;
}

/* visctl bench: see usage(). Returns 0, 1 on a runtime error or engine mismatch, 2 on bad usage. */
int cmd_bench(int argc, char **argv)
{
	struct bench b = { .target_s = 0.2, .limit_s = 60, .seed = 1 };
	const char *svg_path = NULL, *csv_path = NULL;
	FILE *svg = NULL, *csv = NULL;
	int ret = VISCTL_EXIT_FAILURE;

	for (size_t i = 0; i < VIS_GEN_KIND_COUNT; i++)
		b.kinds[b.nkinds++] = (enum vis_gen_kind)i;
	for (size_t i = 0; i < sizeof(default_engines) / sizeof(default_engines[0]); i++)
		b.engines[b.nengines++] = default_engines[i];
	for (size_t i = 0; i < sizeof(default_sizes) / sizeof(default_sizes[0]); i++)
		b.sizes[b.nsizes++] = default_sizes[i];
	uint64_t family = 0, min_n = 100, family_max_n = 100000;
	int r = parse_options(&b, argc, argv, &svg_path, &csv_path, &family, &min_n, &family_max_n);
	if (r != 0)
		return r == 1 ? VISCTL_EXIT_OK : VISCTL_EXIT_USAGE;
	if (family && svg_path) {
		fprintf(stderr, "visctl bench: --svg plots the kinds, not --family\n");
		return VISCTL_EXIT_USAGE;
	}

	/* Open the outputs now: a bad path should fail before an hour of measuring, not after. */
	if ((svg_path != NULL && (svg = fopen(svg_path, "w")) == NULL) ||
	    (csv_path != NULL && (csv = fopen(csv_path, "w")) == NULL)) {
		fprintf(stderr, "visctl bench: %s: %s\n", svg != NULL || svg_path == NULL ?
			csv_path : svg_path, strerror(errno));
		goto out;
	}
	b.cells = calloc(b.nkinds * b.nsizes * (b.nengines + 1), sizeof(*b.cells));
	if (b.cells == NULL) {
		fprintf(stderr, "visctl bench: out of memory\n");
		goto out;
	}
	machine_describe(&b.machine);
	printf("visctl bench: %s, %ld CPUs, %s\n", b.machine.cpu, b.machine.ncpu,
	       b.machine.date);
#ifdef NDEBUG
	printf("build: release; ");
#else
	printf("build: assertions on (figures include self-checks; use a release build); ");
#endif
	if (family)
		printf("%s\n", b.target_s > 0 ? "fastest of at least 3 runs and 0.01 s an engine"
					      : "fastest of 3 runs an engine");
	else if (b.reps != 0)
		printf("seed %llu; minimum of %u reps per cell; skip limit %g s\n",
		       (unsigned long long)b.seed, b.reps, b.limit_s);
	else
		printf("seed %llu; minimum of at least 3 reps, until %g s per cell; skip limit %g s\n",
		       (unsigned long long)b.seed, b.target_s, b.limit_s);
	if (!family)
		printf("ms: fastest run of vis_compute\n"
		       "/qsort: engine time / qsort time (lower is better)\n"
		       "speed-up: region time / engine time (higher is better; > 1 beats region)\n");
	fflush(stdout);
	if (family) {
		if (bench_family(&b, family, (size_t)min_n, (size_t)family_max_n, csv) == 0)
			ret = VISCTL_EXIT_OK;
		if (csv && ferror(csv)) {
			fprintf(stderr, "visctl bench: writing %s failed\n", csv_path);
			ret = VISCTL_EXIT_FAILURE;
		}
		goto out;
	}

	for (size_t k = 0; k < b.nkinds; k++) {
		for (size_t s = 0; s < b.nsizes; s++)
			if (bench_size(&b, k, s) < 0)
				goto out;
		print_table(&b, k);
	}
	ret = VISCTL_EXIT_OK;
	if ((csv != NULL && write_csv(&b, csv) < 0) || (svg != NULL && bench_svg_write(&b, svg) < 0)) {
		fprintf(stderr, "visctl bench: writing %s failed\n",
			csv != NULL && ferror(csv) ? csv_path : svg_path);
		ret = VISCTL_EXIT_FAILURE;
	}
out:
	if (csv != NULL && close_output(csv, csv_path, ret == VISCTL_EXIT_OK) < 0)
		ret = VISCTL_EXIT_FAILURE;
	if (svg != NULL && close_output(svg, svg_path, ret == VISCTL_EXIT_OK) < 0)
		ret = VISCTL_EXIT_FAILURE;
	free(b.cells);
	return ret;
}
