/* What visctl's SVG writers share: the document's start, text escaping, log-log axes. */
#ifndef VISCTL_SVG_H
#define VISCTL_SVG_H

#include <stddef.h>
#include <stdio.h>

/*
 * Starts a standalone SVG document of width × height user units (one per CSS pixel), with a white
 * background; the caller writes the content and "</svg>\n".
 */
void svg_begin(FILE *f, double width, double height);

/* Writes s as XML text or attribute content: &, <, > and " escaped. */
void svg_text(FILE *f, const char *s);

/* Draws a one-pixel line. */
void svg_line(FILE *f, double x1, double y1, double x2, double y2, const char *stroke);

/*
 * A log-log plot area in pixels: x0 < x1 left to right, y0 > y1 bottom to top. xr and yr are the
 * whole decades shown (10^xr[0] … 10^xr[1]), xr[0] < xr[1] and yr[0] < yr[1].
 */
struct svg_axes {
	double x0, y0, x1, y1;
	int xr[2], yr[2];
};

/* Labels decade d of an axis into buf: "1k", "100 µs", …. */
typedef const char *(*svg_decade_fn)(char *buf, size_t len, int d);

/* Decade labels of counts (1, 10, 100, 1k, …) and of milliseconds (1 ns … 100 s). */
const char *svg_decade_count(char *buf, size_t len, int d);
const char *svg_decade_ms(char *buf, size_t len, int d);

/* Sets r to the whole decades around [lo, hi] (lo, hi > 0), at least one decade wide. */
void svg_decades(double lo, double hi, int r[2]);

/* The pixel of value v on the x, or the y, axis. */
double svg_axes_x(const struct svg_axes *a, double v);
double svg_axes_y(const struct svg_axes *a, double v);

/*
 * Draws the decade grid (faint lines at 2…9 × each decade), its labels, the frame, the x axis's
 * title under it and the y axis's title rotated at ytitle_x.
 */
void svg_axes_draw(FILE *f, const struct svg_axes *a, svg_decade_fn xlabel, svg_decade_fn ylabel,
		   const char *xtitle, const char *ytitle, double ytitle_x);

/* Draws a polyline point and marker: a circle of colour with a white rim. */
void svg_marker(FILE *f, double x, double y, const char *colour);

/*
 * Draws a legend entry at (x, y): a sample line (dashed when dash is not NULL: its
 * stroke-dasharray) with a marker, and name. Returns the x of the next entry.
 */
double svg_legend(FILE *f, double x, double y, const char *colour, const char *dash,
		  const char *name);

#endif
