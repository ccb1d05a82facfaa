/* visctl bench's plot: a self-contained SVG, written by hand to need no library. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bench.h"
#include "svg.h"

/* One colour per engine, indexed by enum vis_engine, so a plot reads the same across runs. */
static const char *const engine_colours[VIS_ENGINE_COUNT] = {
	[VIS_ENGINE_AUTO] = "#1f77b4",
	[VIS_ENGINE_GMV] = "#d62728",
	[VIS_ENGINE_GMV_HEAP] = "#2ca02c",
	[VIS_ENGINE_REGION] = "#ff7f0e",
	[VIS_ENGINE_BRUTE] = "#9467bd",
};

/* Panel geometry of the SVG plot, in pixels: one panel per kind, three to a row. */
#define SVG_PW 400  /* panel width */
#define SVG_PH 300  /* panel height */
#define SVG_ML 66   /* plot area inset: left (time labels) */
#define SVG_MR 18   /* right */
#define SVG_MT 32   /* top (panel title) */
#define SVG_MB 48   /* bottom (n labels and axis title) */
#define SVG_PAD 20  /* page margin */
#define SVG_TOP 78  /* title band */
#define SVG_FOOT 78 /* legend band */

/* Labels a decade of n: 1k, 10k, 1M, … reads faster on a small axis than 10^3. */
static const char *decade_n(char *buf, size_t len, int d)
{
	static const char *const suffix[] = { "", "k", "M", "G" };

	if (d < 0 || d > 11)
		snprintf(buf, len, "1e%d", d);
	else
		snprintf(buf, len, "%.0f%s", pow(10, d % 3), suffix[d / 3]);
	return buf;
}

/* Labels a decade of milliseconds in the unit that keeps it a small round number. */
static const char *decade_ms(char *buf, size_t len, int d)
{
	static const char *const unit[] = { "µs", "ms", "s" };

	if (d < -3 || d > 5)
		snprintf(buf, len, "1e%d ms", d);
	else
		snprintf(buf, len, "%.0f %s", pow(10, (d + 3) % 3), unit[(d + 3) / 3]);
	return buf;
}

/* Draws a grid line of a panel. */
static void svg_line(FILE *f, double x1, double y1, double x2, double y2, const char *stroke)
{
	fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n",
		x1, y1, x2, y2, stroke);
}

/* Draws one kind's panel: decade grid, labels, then a polyline with markers per column. */
static void svg_panel(const struct bench *b, FILE *f, size_t k, double px, double py,
		      const int xr[2], const int yr[2])
{
	double x0 = px + SVG_ML, x1 = px + SVG_PW - SVG_MR;
	double y0 = py + SVG_PH - SVG_MB, y1 = py + SVG_MT;
	char buf[32];

#define SX(n) (x0 + (log10(n) - xr[0]) / (xr[1] - xr[0]) * (x1 - x0))
#define SY(ms) (y0 - (log10(ms) - yr[0]) / (yr[1] - yr[0]) * (y0 - y1))
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"15\" font-weight=\"bold\" "
		"text-anchor=\"middle\">%s</text>\n", (x0 + x1) / 2, py + 20,
		vis_gen_kind_name(b->kinds[k]));
	/* Faint lines at 2…9 × each decade, stronger ones and a label at the decade itself. */
	for (int d = xr[0]; d <= xr[1]; d++) {
		for (int m = d < xr[1] ? 9 : 1; m >= 1; m--) {
			double x = SX(m * pow(10, d));

			svg_line(f, x, y0, x, y1, m == 1 ? "#c8c8c8" : "#eeeeee");
		}
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" "
			"text-anchor=\"middle\">%s</text>\n", SX(pow(10, d)), y0 + 15,
			decade_n(buf, sizeof(buf), d));
	}
	for (int d = yr[0]; d <= yr[1]; d++) {
		for (int m = d < yr[1] ? 9 : 1; m >= 1; m--) {
			double y = SY(m * pow(10, d));

			svg_line(f, x0, y, x1, y, m == 1 ? "#c8c8c8" : "#eeeeee");
		}
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" "
			"text-anchor=\"end\">%s</text>\n", x0 - 6, SY(pow(10, d)) + 4,
			decade_ms(buf, sizeof(buf), d));
	}
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
		"stroke=\"#555555\"/>\n", x0, y1, x1 - x0, y0 - y1);
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\">"
		"n (windows)</text>\n", (x0 + x1) / 2, y0 + 34);
	fprintf(f, "<text transform=\"translate(%.1f %.1f) rotate(-90)\" font-size=\"12\" "
		"text-anchor=\"middle\">time</text>\n", px + 14, (y0 + y1) / 2);

	/*
	 * A × along the bottom where an engine's skipping began, so a short line reads as skipped;
	 * the bottom right is where data never is (big scenes are slow).
	 */
	for (size_t c = 0; c < b->nengines; c++) {
		for (size_t s = 0; s < b->nsizes; s++) {
			enum cell_status st = cell_at(b, k, s, c)->status;

			if (st != CELL_PREDICTED && st != CELL_STOPPED)
				continue;
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"16\" "
				"font-weight=\"bold\" fill=\"%s\" "
				"text-anchor=\"middle\">×</text>\n",
				SX((double)b->sizes[s]), y0 - 6 - 13 * (double)c,
				engine_colours[b->engines[c]]);
			break;
		}
	}

	/* qsort first, so the engines' lines are drawn over the reference. */
	for (size_t i = 0; i <= b->nengines; i++) {
		size_t c = i == 0 ? b->nengines : i - 1;
		const char *colour = c == b->nengines ? "#444444" : engine_colours[b->engines[c]];

		fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\"%s points=\"",
			colour, c == b->nengines ? " stroke-dasharray=\"6 4\"" : "");
		for (size_t s = 0; s < b->nsizes; s++) {
			const struct cell *cell = cell_at(b, k, s, c);

			if (cell->status == CELL_RAN && cell->ms > 0)
				fprintf(f, "%.1f,%.1f ", SX((double)b->sizes[s]), SY(cell->ms));
		}
		fprintf(f, "\"/>\n");
		for (size_t s = 0; s < b->nsizes; s++) {
			const struct cell *cell = cell_at(b, k, s, c);

			if (cell->status == CELL_RAN && cell->ms > 0)
				fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.2\" fill=\"%s\" "
					"stroke=\"white\" stroke-width=\"0.8\"/>\n",
					SX((double)b->sizes[s]), SY(cell->ms), colour);
		}
	}
#undef SX
#undef SY
}

/*
 * Writes the log-log plot of time against n, one panel per kind. All panels share both axes, so
 * kinds compare at a glance; the ranges are whole decades around the data.
 */
int bench_svg_write(const struct bench *b, FILE *f)
{
	size_t cols = b->nkinds < 3 ? b->nkinds : 3, rows = (b->nkinds + cols - 1) / cols;
	double lo_ms = INFINITY, hi_ms = 0;
	int xr[2], yr[2];
	double w = 2 * SVG_PAD + (double)cols * SVG_PW;
	double h = SVG_TOP + (double)rows * SVG_PH + SVG_FOOT;

	for (size_t k = 0; k < b->nkinds; k++)
		for (size_t s = 0; s < b->nsizes; s++)
			for (size_t c = 0; c <= b->nengines; c++) {
				const struct cell *cell = cell_at(b, k, s, c);

				if (cell->status == CELL_RAN && cell->ms > 0) {
					lo_ms = cell->ms < lo_ms ? cell->ms : lo_ms;
					hi_ms = cell->ms > hi_ms ? cell->ms : hi_ms;
				}
			}
	if (hi_ms == 0)
		lo_ms = hi_ms = 1;
	xr[0] = (int)floor(log10((double)b->sizes[0]));
	xr[1] = (int)ceil(log10((double)b->sizes[b->nsizes - 1]));
	yr[0] = (int)floor(log10(lo_ms));
	yr[1] = (int)ceil(log10(hi_ms));
	if (xr[1] == xr[0])
		xr[1]++;
	if (yr[1] == yr[0])
		yr[1]++;

	svg_begin(f, w, h);
	fprintf(f, "<text x=\"%d\" y=\"34\" font-size=\"20\" font-weight=\"bold\">"
		"visctl bench: vis_compute time against window count (log-log)</text>\n"
		"<text x=\"%d\" y=\"58\" font-size=\"13\" fill=\"#333333\">", SVG_PAD, SVG_PAD);
	svg_text(f, b->cpu);
	fprintf(f, ", %ld CPUs · %s · seed %llu · minimum over repetitions</text>\n", b->ncpu,
		b->date, (unsigned long long)b->seed);
	for (size_t k = 0; k < b->nkinds; k++)
		svg_panel(b, f, k, SVG_PAD + (double)(k % cols) * SVG_PW,
			  SVG_TOP + (double)(k / cols) * SVG_PH, xr, yr);

	/* The legend: a sample line and marker per engine, then the dashed qsort reference. */
	double lx = SVG_PAD + SVG_ML, ly = SVG_TOP + (double)rows * SVG_PH + 26;
	for (size_t i = 0; i <= b->nengines; i++) {
		bool is_q = i == b->nengines;
		const char *name = is_q ? "qsort of 4n coordinates (lower bound)" :
			vis_engine_name(b->engines[i]);
		const char *colour = is_q ? "#444444" : engine_colours[b->engines[i]];

		fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
			"stroke-width=\"2\"%s/>\n<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.2\" "
			"fill=\"%s\"/>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"13\">%s</text>\n",
			lx, ly, lx + 30, ly, colour, is_q ? " stroke-dasharray=\"6 4\"" : "",
			lx + 15, ly, colour, lx + 38, ly + 4.5, name);
		lx += 60 + 7.5 * (double)strlen(name);
	}
	fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"12\" fill=\"#555555\">A line that ends "
		"early: from the size marked × at the bottom on, the engine was skipped "
		"(predicted or measured over %g s).</text>\n"
		"</svg>\n", SVG_PAD + SVG_ML, ly + 28, b->limit_s);
	return ferror(f) ? -1 : 0;
}
