/* bench-wtree's plot (--svg): the cost of one recompute against n, drawn with visctl's helpers. */
#include <math.h>
#include <stdbool.h>

#include "bench-wtree.h"
#include "machine.h"
#include "svg.h"

/* A colour per changed window, a dash per engine: live solid, what the daemon ran before dashed. */
static const char *const who_colours[WHO_COUNT] = { "#1f77b4", "#ff7f0e" };
static const char *const who_names[WHO_COUNT] = { "any window", "the top window" };
static const char *const engine_dashes[ENGINE_COUNT] = { "2 3", "7 4", NULL };
static const char *const engine_names[ENGINE_COUNT] = {
	"full (vis_wtree_compute)", "damaged (before)", "live (vis_wtree_update, after)",
};

/* Page geometry, in pixels: one panel per kind, three to a row. */
#define PW 400   /* panel width */
#define PH 300   /* panel height */
#define ML 66    /* plot area inset: left (time labels) */
#define MR 18    /* right */
#define MT 32    /* top (panel title) */
#define MB 48    /* bottom (n labels and axis title) */
#define PAD 20   /* page margin */
#define TOP 78   /* title band */
#define ROW 24   /* a legend row */

/* The plotted value, in ms: a recompute that read 0.0 µs sits on the axis's floor of 0.1 µs. */
static double plotted(double us)
{
	return fmax(us, 0.1) / 1e3;
}

/* Draws one series of kind's panel: the band up to the p99 when band, else the line and markers. */
static void series(FILE *f, const struct wtree_plot *p, const struct svg_axes *ax,
		   enum vis_gen_kind kind, enum who who, enum engine engine, bool band)
{
	const char *colour = who_colours[who];
	size_t first = p->count, last = 0;

	for (size_t i = 0; i < p->count; i++) {
		const struct wtree_result *r = &p->results[i];

		if (r->kind == kind && r->who == who && r->engine == engine) {
			first = first < i ? first : i;
			last = i;
		}
	}
	if (first == p->count)
		return;
	/* The results of a kind ran in the order of --sizes: the band goes out by median, back by p99. */
	if (band)
		fprintf(f, "<polygon fill=\"%s\" fill-opacity=\"0.12\" stroke=\"none\" points=\"",
			colour);
	else
		fprintf(f, "<polyline fill=\"none\" stroke=\"%s\" stroke-width=\"2\"%s%s%s points=\"",
			colour, engine_dashes[engine] ? " stroke-dasharray=\"" : "",
			engine_dashes[engine] ? engine_dashes[engine] : "",
			engine_dashes[engine] ? "\"" : "");
	for (size_t k = 0; k < (band ? 2 : 1); k++)
		for (size_t j = first; j <= last; j++) {
			const struct wtree_result *r = &p->results[k == 0 ? j : first + last - j];

			if (r->kind == kind && r->who == who && r->engine == engine)
				fprintf(f, "%.1f,%.1f ", svg_axes_x(ax, (double)r->n),
					svg_axes_y(ax, plotted(k == 0 ? r->median_us : r->p99_us)));
		}
	fprintf(f, "\"/>\n");
	for (size_t j = first; !band && j <= last; j++) {
		const struct wtree_result *r = &p->results[j];

		if (r->kind == kind && r->who == who && r->engine == engine)
			svg_marker(f, svg_axes_x(ax, (double)r->n), svg_axes_y(ax, plotted(r->median_us)),
				   colour);
	}
}

/*
 * Draws kind's panel at (px, py): grid, the band of the live recompute of any window (one band:
 * more overlap into mud), then the lines, live last so that it is on top.
 */
static void panel(FILE *f, const struct wtree_plot *p, enum vis_gen_kind kind, double px,
		  double py, const int xr[2], const int yr[2])
{
	const struct svg_axes ax = {
		.x0 = px + ML, .x1 = px + PW - MR, .y0 = py + PH - MB, .y1 = py + MT,
		.xr = { xr[0], xr[1] }, .yr = { yr[0], yr[1] },
	};

	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"15\" font-weight=\"bold\" "
		"text-anchor=\"middle\">%s</text>\n", (ax.x0 + ax.x1) / 2, py + 20,
		vis_gen_kind_name(kind));
	svg_axes_draw(f, &ax, svg_decade_count, svg_decade_ms, "n (windows)",
		      "one recompute (median)", px + 14);
	series(f, p, &ax, kind, ANY, LIVE, true);
	for (int e = 0; e < ENGINE_COUNT; e++)
		for (int w = 0; w < WHO_COUNT; w++)
			series(f, p, &ax, kind, (enum who)w, (enum engine)e, false);
}

int bench_wtree_svg_write(FILE *f, const struct wtree_plot *p)
{
	enum vis_gen_kind kinds[VIS_GEN_KIND_COUNT];
	bool ran[WHO_COUNT][ENGINE_COUNT] = { { false } };
	size_t nkinds = 0;
	double lo_n = INFINITY, hi_n = 0, lo_us = INFINITY, hi_us = 0;
	int xr[2], yr[2];

	for (size_t i = 0; i < p->count; i++) {
		const struct wtree_result *r = &p->results[i];
		size_t k = 0;

		while (k < nkinds && kinds[k] != r->kind)
			k++;
		if (k == nkinds)
			kinds[nkinds++] = r->kind;
		ran[r->who][r->engine] = true;
		lo_n = fmin(lo_n, (double)r->n);
		hi_n = fmax(hi_n, (double)r->n);
		lo_us = fmin(lo_us, r->median_us);
		hi_us = fmax(hi_us, r->p99_us);
	}
	if (nkinds == 0)
		lo_n = hi_n = lo_us = hi_us = 1;
	svg_decades(lo_n, hi_n, xr);
	svg_decades(plotted(lo_us), plotted(hi_us), yr);

	/* Three panels wide even for fewer kinds: the title and the legend need the room. */
	size_t cols = 3, rows = nkinds ? (nkinds + cols - 1) / cols : 1;
	double ly = TOP + (double)rows * PH + 26;
	struct machine m;

	machine_describe(&m);
	svg_begin(f, 2 * PAD + (double)cols * PW, ly + (WHO_COUNT + 1) * ROW + 40);
	fprintf(f, "<text x=\"%d\" y=\"34\" font-size=\"20\" font-weight=\"bold\">bench-wtree: one "
		"recompute after one %s against window count (log-log)</text>\n"
		"<text x=\"%d\" y=\"58\" font-size=\"13\" fill=\"#333333\">", PAD, p->op, PAD);
	svg_text(f, m.cpu);
	fprintf(f, ", %ld CPUs · %s · seed %llu · median of %zu changes", m.ncpu, m.date,
		(unsigned long long)p->seed, p->moves);
	if (p->note) {
		fprintf(f, " · ");
		svg_text(f, p->note);
	}
	fprintf(f, "</text>\n");
	for (size_t k = 0; k < nkinds; k++)
		panel(f, p, kinds[k], PAD + (double)(k % cols) * PW, TOP + (double)(k / cols) * PH,
		      xr, yr);

	/* A legend row per changed window, live first: the engines that ran. */
	for (int w = 0; w < WHO_COUNT; w++) {
		double lx = PAD + ML;

		for (int e = ENGINE_COUNT - 1; e >= 0; e--) {
			char name[96];

			if (!ran[w][e])
				continue;
			snprintf(name, sizeof(name), "%s, %s", who_names[w], engine_names[e]);
			lx = svg_legend(f, lx, ly, who_colours[w], engine_dashes[e], name);
		}
		ly += lx > PAD + ML ? ROW : 0;
	}
	if (ran[ANY][LIVE]) {
		fprintf(f, "<rect x=\"%d\" y=\"%.1f\" width=\"30\" height=\"12\" fill=\"%s\" "
			"fill-opacity=\"0.12\"/>\n<text x=\"%d\" y=\"%.1f\" font-size=\"13\">"
			"shaded: any window, live, from the median to the 99th percentile</text>\n",
			PAD + ML, ly - 6, who_colours[ANY], PAD + ML + 38, ly + 4.5);
		ly += ROW;
	}
	fprintf(f, "<text x=\"%d\" y=\"%.1f\" font-size=\"12\" fill=\"#555555\">One change of one "
		"window, then one recompute timed alone (bench-wtree.c says how). Below 2,048 "
		"windows vis_wtree_update recomputes as the damaged one does.</text>\n</svg>\n",
		PAD + ML, ly + 6);
	return ferror(f) ? -1 : 0;
}
