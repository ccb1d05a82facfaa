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

/* Draws one kind's panel: decade grid, labels, then a polyline with markers per column. */
static void svg_panel(const struct bench *b, FILE *f, size_t k, double px, double py,
		      const int xr[2], const int yr[2])
{
	const struct svg_axes ax = {
		.x0 = px + SVG_ML, .x1 = px + SVG_PW - SVG_MR,
		.y0 = py + SVG_PH - SVG_MB, .y1 = py + SVG_MT,
		.xr = { xr[0], xr[1] }, .yr = { yr[0], yr[1] },
	};
	double y0 = ax.y0;

#define SX(n) svg_axes_x(&ax, n)
#define SY(ms) svg_axes_y(&ax, ms)
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"15\" font-weight=\"bold\" "
		"text-anchor=\"middle\">%s</text>\n", (ax.x0 + ax.x1) / 2, py + 20,
		vis_gen_kind_name(b->kinds[k]));
	svg_axes_draw(f, &ax, svg_decade_count, svg_decade_ms, "n (windows)", "time", px + 14);

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
				svg_marker(f, SX((double)b->sizes[s]), SY(cell->ms), colour);
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
	svg_decades((double)b->sizes[0], (double)b->sizes[b->nsizes - 1], xr);
	svg_decades(lo_ms, hi_ms, yr);

	svg_begin(f, w, h);
	fprintf(f, "<text x=\"%d\" y=\"34\" font-size=\"20\" font-weight=\"bold\">"
		"visctl bench: vis_compute time against window count (log-log)</text>\n"
		"<text x=\"%d\" y=\"58\" font-size=\"13\" fill=\"#333333\">", SVG_PAD, SVG_PAD);
	svg_text(f, b->machine.cpu);
	fprintf(f, ", %ld CPUs · %s · seed %llu · minimum over repetitions</text>\n", b->machine.ncpu,
		b->machine.date, (unsigned long long)b->seed);
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

		lx = svg_legend(f, lx, ly, colour, is_q ? "6 4" : NULL, name);
	}
	fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"12\" fill=\"#555555\">A line that ends "
		"early: from the size marked × at the bottom on, the engine was skipped "
		"(predicted or measured over %g s).</text>\n"
		"</svg>\n", SVG_PAD + SVG_ML, ly + 28, b->limit_s);
	return ferror(f) ? -1 : 0;
}
