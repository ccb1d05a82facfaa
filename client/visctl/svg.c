/* visctl's SVG helpers: documents and plots are written by hand, to need no library. */
#include <math.h>
#include <string.h>

#include "svg.h"

void svg_begin(FILE *f, double width, double height)
{
	fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
		"<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
		"viewBox=\"0 0 %.0f %.0f\" "
		"font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\">\n"
		"<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
		width, height, width, height);
}

void svg_text(FILE *f, const char *s)
{
	for (; *s != '\0'; s++) {
		if (*s == '&')
			fputs("&amp;", f);
		else if (*s == '<')
			fputs("&lt;", f);
		else if (*s == '>')
			fputs("&gt;", f);
		else if (*s == '"')
			fputs("&quot;", f);
		else
			fputc(*s, f);
	}
}

void svg_line(FILE *f, double x1, double y1, double x2, double y2, const char *stroke)
{
	fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\"/>\n",
		x1, y1, x2, y2, stroke);
}

/* Counts read faster on a small axis as 1k, 10k, 1M than as 10^3. */
const char *svg_decade_count(char *buf, size_t len, int d)
{
	static const char *const suffix[] = { "", "k", "M", "G" };

	if (d < 0 || d > 11)
		snprintf(buf, len, "1e%d", d);
	else
		snprintf(buf, len, "%.0f%s", pow(10, d % 3), suffix[d / 3]);
	return buf;
}

/* A decade of milliseconds in the unit that keeps it a small round number. */
const char *svg_decade_ms(char *buf, size_t len, int d)
{
	static const char *const unit[] = { "ns", "µs", "ms", "s" };

	if (d < -6 || d > 5)
		snprintf(buf, len, "1e%d ms", d);
	else
		snprintf(buf, len, "%.0f %s", pow(10, (d + 6) % 3), unit[(d + 6) / 3]);
	return buf;
}

void svg_decades(double lo, double hi, int r[2])
{
	r[0] = (int)floor(log10(lo));
	r[1] = (int)ceil(log10(hi));
	if (r[1] == r[0])
		r[1]++;
}

double svg_axes_x(const struct svg_axes *a, double v)
{
	return a->x0 + (log10(v) - a->xr[0]) / (a->xr[1] - a->xr[0]) * (a->x1 - a->x0);
}

double svg_axes_y(const struct svg_axes *a, double v)
{
	return a->y0 - (log10(v) - a->yr[0]) / (a->yr[1] - a->yr[0]) * (a->y0 - a->y1);
}

void svg_axes_draw(FILE *f, const struct svg_axes *a, svg_decade_fn xlabel, svg_decade_fn ylabel,
		   const char *xtitle, const char *ytitle, double ytitle_x)
{
	char buf[32];

	for (int d = a->xr[0]; d <= a->xr[1]; d++) {
		for (int m = d < a->xr[1] ? 9 : 1; m >= 1; m--) {
			double x = svg_axes_x(a, m * pow(10, d));

			svg_line(f, x, a->y0, x, a->y1, m == 1 ? "#c8c8c8" : "#eeeeee");
		}
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" "
			"text-anchor=\"middle\">%s</text>\n", svg_axes_x(a, pow(10, d)), a->y0 + 15,
			xlabel(buf, sizeof(buf), d));
	}
	for (int d = a->yr[0]; d <= a->yr[1]; d++) {
		for (int m = d < a->yr[1] ? 9 : 1; m >= 1; m--) {
			double y = svg_axes_y(a, m * pow(10, d));

			svg_line(f, a->x0, y, a->x1, y, m == 1 ? "#c8c8c8" : "#eeeeee");
		}
		fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"11\" "
			"text-anchor=\"end\">%s</text>\n", a->x0 - 6, svg_axes_y(a, pow(10, d)) + 4,
			ylabel(buf, sizeof(buf), d));
	}
	fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
		"stroke=\"#555555\"/>\n", a->x0, a->y1, a->x1 - a->x0, a->y0 - a->y1);
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" text-anchor=\"middle\">",
		(a->x0 + a->x1) / 2, a->y0 + 34);
	svg_text(f, xtitle);
	fprintf(f, "</text>\n<text transform=\"translate(%.1f %.1f) rotate(-90)\" "
		"font-size=\"12\" text-anchor=\"middle\">", ytitle_x, (a->y0 + a->y1) / 2);
	svg_text(f, ytitle);
	fprintf(f, "</text>\n");
}

void svg_marker(FILE *f, double x, double y, const char *colour)
{
	fprintf(f, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.2\" fill=\"%s\" stroke=\"white\" "
		"stroke-width=\"0.8\"/>\n", x, y, colour);
}

double svg_legend(FILE *f, double x, double y, const char *colour, const char *dash,
		  const char *name)
{
	fprintf(f, "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"%s\" "
		"stroke-width=\"2\"", x, y, x + 30, y, colour);
	if (dash != NULL)
		fprintf(f, " stroke-dasharray=\"%s\"", dash);
	fprintf(f, "/>\n<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3.2\" fill=\"%s\"/>\n"
		"<text x=\"%.1f\" y=\"%.1f\" font-size=\"13\">", x + 15, y, colour, x + 38, y + 4.5);
	svg_text(f, name);
	fprintf(f, "</text>\n");
	return x + 60 + 7.5 * (double)strlen(name);
}
