/*
 * `visctl plot-service`: the service benchmark's plot (tools/service-bench.sh). It reads the CSV
 * the benchmark writes (a `run` column, then visctl stress --csv's fields) and draws the latency
 * percentiles of the closed-loop runs against the window count, log-log, one panel per number of
 * subscribers.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "svg.h"
#include "visctl.h"

#define MAX_POINTS 256
#define MAX_COLUMNS 64
#define NPCT 3

/* The CSV columns read, by name; the latencies are in µs. */
enum column { COL_RUN, COL_WINDOWS, COL_CLIENTS, COL_P50, COL_P99, COL_P999, NCOLS };
static const char *const column_names[NCOLS] = { "run", "windows", "clients", "p50_us", "p99_us",
						 "p999_us" };

/* The percentiles drawn: colour and dash differ, so that the lines read in grey too. */
static const char *const pct_names[NPCT] = { "p50", "p99", "p99.9" };
static const char *const pct_colours[NPCT] = { "#1f77b4", "#ff7f0e", "#d62728" };
static const char *const pct_dashes[NPCT] = { NULL, "7 4", "2 3" };

/* One closed-loop run: its cell and its latencies. */
struct point {
	double windows, clients;
	double us[NPCT];
};

/* Panel geometry, in pixels: one panel per subscriber count, side by side. */
#define PW 380   /* panel width */
#define PH 320   /* panel height */
#define ML 66    /* plot area inset: left (latency labels) */
#define MR 18    /* right */
#define MT 32    /* top (panel title) */
#define MB 48    /* bottom (window labels and axis title) */
#define PAD 20   /* page margin */
#define TOP 78   /* title band */
#define FOOT 70  /* legend band */

/* Prints a usage line to f. */
static void usage(FILE *f)
{
	fprintf(f, "usage: visctl plot-service [--note TEXT] CSV SVG\n"
		   "  Draws the latency percentiles (p50, p99, p99.9) of the service benchmark's\n"
		   "  closed-loop runs (rows whose run is \"latency\") against windows, log-log, one\n"
		   "  panel per subscriber count. CSV: as tools/service-bench.sh writes it; TEXT goes\n"
		   "  under the title (the machine, the date).\n");
}

/* Splits line (modified) at commas into at most max fields. Returns how many, or -1 if more. */
static int split(char *line, char **fields, int max)
{
	int n = 0;

	for (char *p = line;; p++) {
		if (n == max)
			return -1;
		fields[n++] = p;
		p = strchr(p, ',');
		if (p == NULL)
			return n;
		*p = '\0';
	}
}

/* Parses a number filling the whole field, positive (or 0 when zero_ok). 0, or -1. */
static int parse_number(const char *s, bool zero_ok, double *out)
{
	char *end;

	errno = 0;
	*out = strtod(s, &end);
	return *s != '\0' && *end == '\0' && errno == 0 && (*out > 0 || (zero_ok && *out == 0)) ?
		0 : -1;
}

/* Orders points by subscribers, then windows. */
static int point_cmp(const void *a, const void *b)
{
	const struct point *p = a, *q = b;

	if (p->clients != q->clients)
		return p->clients < q->clients ? -1 : 1;
	return p->windows < q->windows ? -1 : p->windows > q->windows;
}

/*
 * Reads the closed-loop rows of the CSV in data (modified). Returns how many points, or -1 after
 * printing why on stderr.
 */
static int read_points(const char *path, char *data, struct point *pts)
{
	int col[NCOLS], n = 0, lineno = 0;
	char *fields[MAX_COLUMNS], *save = NULL;

	for (char *line = strtok_r(data, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
		int nf = split(line, fields, MAX_COLUMNS);

		if (++lineno == 1) {
			for (int c = 0; c < NCOLS; c++) {
				col[c] = -1;
				for (int i = 0; i < nf; i++)
					if (strcmp(fields[i], column_names[c]) == 0)
						col[c] = i;
				if (col[c] < 0) {
					fprintf(stderr, "visctl plot-service: %s: no column '%s'\n",
						path, column_names[c]);
					return -1;
				}
			}
			continue;
		}
		if (nf < 0 || nf <= col[COL_RUN] || strcmp(fields[col[COL_RUN]], "latency") != 0)
			continue;
		struct point p;
		bool ok = n < MAX_POINTS;
		for (int c = COL_WINDOWS; ok && c < NCOLS; c++) {
			double *v = c == COL_WINDOWS ? &p.windows : c == COL_CLIENTS ? &p.clients :
				    &p.us[c - COL_P50];
			ok = col[c] < nf && parse_number(fields[col[c]], c == COL_CLIENTS, v) == 0;
		}
		if (!ok) {
			fprintf(stderr, "visctl plot-service: %s:%d: %s\n", path, lineno,
				n == MAX_POINTS ? "too many rows" : "bad windows, clients or latency");
			return -1;
		}
		pts[n++] = p;
	}
	if (n == 0)
		fprintf(stderr, "visctl plot-service: %s: no closed-loop (\"latency\") rows\n", path);
	return n > 0 ? n : -1;
}

/* Draws the panel of the points of one subscriber count: grid, then a line per percentile. */
static void panel(FILE *f, const struct point *pts, int n, double px, const int xr[2],
		  const int yr[2])
{
	const struct svg_axes ax = {
		.x0 = px + ML, .x1 = px + PW - MR, .y0 = TOP + PH - MB, .y1 = TOP + MT,
		.xr = { xr[0], xr[1] }, .yr = { yr[0], yr[1] },
	};

	fprintf(f, "<text x=\"%.1f\" y=\"%d\" font-size=\"15\" font-weight=\"bold\" "
		"text-anchor=\"middle\">%.0f subscriber%s</text>\n", (ax.x0 + ax.x1) / 2, TOP + 20,
		pts[0].clients, pts[0].clients == 1 ? "" : "s");
	svg_axes_draw(f, &ax, svg_decade_count, svg_decade_ms, "windows",
		      "change → last notice", px + 14);
	for (int k = 0; k < NPCT; k++) {
		fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\"", pct_colours[k]);
		if (pct_dashes[k] != NULL)
			fprintf(f, " stroke-dasharray=\"%s\"", pct_dashes[k]);
		fprintf(f, " points=\"");
		for (int i = 0; i < n; i++)
			fprintf(f, "%.1f,%.1f ", svg_axes_x(&ax, pts[i].windows),
				svg_axes_y(&ax, pts[i].us[k] / 1e3));
		fprintf(f, "\"/>\n");
		for (int i = 0; i < n; i++)
			svg_marker(f, svg_axes_x(&ax, pts[i].windows),
				   svg_axes_y(&ax, pts[i].us[k] / 1e3), pct_colours[k]);
	}
}

/* Writes the plot of the n points (sorted by point_cmp()). Returns 0, or -1 on error. */
static int write_svg(FILE *f, const struct point *pts, int n, const char *note)
{
	double lo_w = pts[0].windows, hi_w = lo_w, lo_ms = pts[0].us[0] / 1e3, hi_ms = lo_ms;
	int xr[2], yr[2], npanels = 1;

	for (int i = 0; i < n; i++) {
		lo_w = pts[i].windows < lo_w ? pts[i].windows : lo_w;
		hi_w = pts[i].windows > hi_w ? pts[i].windows : hi_w;
		for (int k = 0; k < NPCT; k++) {
			lo_ms = pts[i].us[k] / 1e3 < lo_ms ? pts[i].us[k] / 1e3 : lo_ms;
			hi_ms = pts[i].us[k] / 1e3 > hi_ms ? pts[i].us[k] / 1e3 : hi_ms;
		}
		npanels += i > 0 && pts[i].clients != pts[i - 1].clients;
	}
	svg_decades(lo_w, hi_w, xr);
	svg_decades(lo_ms, hi_ms, yr);

	svg_begin(f, 2 * PAD + npanels * PW, TOP + PH + FOOT);
	fprintf(f, "<text x=\"%d\" y=\"34\" font-size=\"20\" font-weight=\"bold\">visctl stress: "
		"change → last notice latency against windows (closed loop, log-log)</text>\n"
		"<text x=\"%d\" y=\"58\" font-size=\"13\" fill=\"#333333\">", PAD, PAD);
	svg_text(f, note);
	fprintf(f, "</text>\n");
	for (int i = 0, p = 0; i < n; p++) {
		int j = i;

		while (j < n && pts[j].clients == pts[i].clients)
			j++;
		panel(f, pts + i, j - i, PAD + (double)p * PW, xr, yr);
		i = j;
	}
	double lx = PAD + ML, ly = TOP + PH + 24;
	for (int k = 0; k < NPCT; k++)
		lx = svg_legend(f, lx, ly, pct_colours[k], pct_dashes[k], pct_names[k]);
	fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"12\" fill=\"#555555\">One operation at "
		"a time; latency from its start to the arrival of the last notice it causes at any "
		"subscriber (see visctl stress).</text>\n</svg>\n", PAD + ML, ly + 28);
	return ferror(f) ? -1 : 0;
}

int cmd_plot_service(int argc, char **argv)
{
	const char *note = "";
	int i = 1;

	if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
		usage(stdout);
		return VISCTL_EXIT_OK;
	}
	if (argc > 2 && strcmp(argv[1], "--note") == 0) {
		note = argv[2];
		i = 3;
	}
	if (argc - i != 2) {
		usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	const char *csv = argv[i], *out = argv[i + 1];
	struct point *pts = malloc(MAX_POINTS * sizeof(*pts));
	char *data = NULL;
	size_t len;
	int n = -1, ret = VISCTL_EXIT_USAGE;

	if (pts == NULL) {
		fprintf(stderr, "visctl plot-service: %s\n", strerror(ENOMEM));
		return VISCTL_EXIT_FAILURE;
	}
	if (visctl_read_all(csv, &data, &len) < 0)
		fprintf(stderr, "visctl plot-service: %s: cannot read: %s\n", csv, strerror(errno));
	else if (memchr(data, '\0', len) != NULL)
		fprintf(stderr, "visctl plot-service: %s: not text\n", csv);
	else {
		char *text = realloc(data, len + 1);
		if (text != NULL) {
			data = text;
			data[len] = '\0';
			n = read_points(csv, data, pts);
		} else {
			fprintf(stderr, "visctl plot-service: %s\n", strerror(ENOMEM));
			ret = VISCTL_EXIT_FAILURE;
		}
	}
	if (n > 0) {
		FILE *f = fopen(out, "w");

		qsort(pts, (size_t)n, sizeof(*pts), point_cmp);
		ret = VISCTL_EXIT_FAILURE;
		if (f == NULL)
			fprintf(stderr, "visctl plot-service: %s: cannot write: %s\n", out,
				strerror(errno));
		else if ((write_svg(f, pts, n, note) < 0) | (fclose(f) != 0))
			fprintf(stderr, "visctl plot-service: %s: write error\n", out);
		else
			ret = VISCTL_EXIT_OK;
	}
	free(data);
	free(pts);
	return ret;
}
