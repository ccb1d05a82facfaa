/*
 * visctl's pictures of a window stack. The scene is scaled so that the drawing fits in DRAW_W ×
 * DRAW_H units of the viewBox: any coordinates fit, and line widths and labels keep one size.
 * Everything is written in O(windows + visible parts).
 */
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "stack-svg.h"
#include "svg.h"

/* The canvas, in SVG user units: a title band, the drawing, the legend band. */
#define DRAW_W 1200.0
#define DRAW_H 720.0
#define MIN_W 680.0  /* the legend's width */
#define PAD 18.0     /* page margin, and the drawing's margin inside its clip */
#define TITLE_H 58.0 /* title and subtitle */
#define LEGEND_H 38.0 /* the legend line, down to the first note line's baseline */
#define NOTE_H 18.0

/* Label sizes: a label shrinks to fit its visible part, down to LABEL_MIN. */
#define LABEL_MAX 15.0
#define LABEL_MIN 8.0
#define HIDDEN_LABEL_MAX 12.0 /* labels of windows showing nothing, in a corner */
#define DIGIT_W 0.64          /* a digit's advance in DejaVu Sans, in em */

/* Colours by enum vis_state: distinguishable with the common colour-vision deficiencies. */
static const char *const state_colour[3] = { "#009e73", "#e69f00", "#d55e00" };
/* The fills: 30% of the colour over white, opaque (see write_window()). */
static const char *const state_tint[3] = { "#b3e2d5", "#f7e2b3", "#f2cfb3" };
static const char *const state_class[3] = { "u", "p", "f" };
static const char *const state_label[3] = { "unobscured", "partially-obscured",
					    "fully-obscured (outline only)" };

void stack_svg_init(struct stack_svg *p, const char *title)
{
	memset(p, 0, sizeof(*p));
	p->title = title;
	p->has_parts = true;
}

void stack_svg_finish(struct stack_svg *p)
{
	free(p->windows);
	free(p->parts);
	free(p->pixels);
	memset(p, 0, sizeof(*p));
}

/* Grows an array to hold at least want elements of size bytes. Returns 0, or -1 with errno set. */
static int grow(void **array, size_t *cap, size_t want, size_t size)
{
	if (want <= *cap)
		return 0;
	size_t c = *cap ? *cap : 64;
	while (c < want) {
		if (c > SIZE_MAX / 2 / size) {
			errno = EOVERFLOW;
			return -1;
		}
		c *= 2;
	}
	void *a = realloc(*array, c * size);
	if (a == NULL) {
		errno = ENOMEM;
		return -1;
	}
	*array = a;
	*cap = c;
	return 0;
}

int stack_svg_add(struct stack_svg *p, uint32_t id, uint32_t parent, struct vis_box box,
		  uint8_t state)
{
	if (grow((void **)&p->windows, &p->cap, p->n + 1, sizeof(*p->windows)) < 0)
		return -1;
	p->windows[p->n++] = (struct stack_svg_window){
		.id = id, .parent = parent, .state = state <= 2 ? state : 2, .box = box,
		.inside = box,
	};
	return 0;
}

int stack_svg_add_pixels(struct stack_svg *p, struct vis_box box, bool see_through)
{
	struct stack_svg_window *w = &p->windows[p->n - 1];
	if (grow((void **)&p->pixels, &p->cap_pixels, p->n_pixels + 1, sizeof(*p->pixels)) < 0)
		return -1;
	if (w->n_px == 0)
		w->first_px = p->n_pixels;
	w->n_px++;
	p->pixels[p->n_pixels++] = (struct stack_svg_pixels){ box, see_through };
	return 0;
}

struct vis_box *stack_svg_parts(struct stack_svg *p, size_t i, size_t n)
{
	if (n > SIZE_MAX - p->n_parts) {
		errno = EOVERFLOW;
		return NULL;
	}
	if (grow((void **)&p->parts, &p->cap_parts, p->n_parts + n, sizeof(*p->parts)) < 0)
		return NULL;
	p->windows[i].first = p->n_parts;
	p->windows[i].n_parts = n;
	p->n_parts += n;
	return p->parts + p->windows[i].first;
}

void stack_svg_note(struct stack_svg *p, const char *fmt, ...)
{
	size_t len = strlen(p->note);
	va_list ap;

	if (len > 0 && len + 1 < sizeof(p->note))
		p->note[len++] = ' ';
	va_start(ap, fmt);
	vsnprintf(p->note + len, sizeof(p->note) - len, fmt, ap);
	va_end(ap);
}

/*
 * Where the scene lands on the canvas: scene x maps to ox + (x − x0) · s. The area shown is the
 * screen, widened by at most a quarter of its size toward windows that stick out; without a
 * screen, the windows' bounding box.
 */
struct view {
	double x0, y0, x1, y1;
	double s, ox, oy;
	double w, h; /* the drawing's size on the canvas */
};

static double dmin(double a, double b)
{
	return a < b ? a : b;
}

static double dmax(double a, double b)
{
	return a > b ? a : b;
}

/* Picks the area shown and the scale. */
static struct view view_of(const struct stack_svg *p)
{
	struct vis_box bb = { 0, 0, 1, 1 };
	struct view v;

	for (size_t i = 0; i < p->n; i++) {
		struct vis_box b = p->windows[i].box;
		if (i == 0)
			bb = b;
		bb.x1 = b.x1 < bb.x1 ? b.x1 : bb.x1;
		bb.y1 = b.y1 < bb.y1 ? b.y1 : bb.y1;
		bb.x2 = b.x2 > bb.x2 ? b.x2 : bb.x2;
		bb.y2 = b.y2 > bb.y2 ? b.y2 : bb.y2;
	}
	if (p->has_screen) {
		double w = (double)p->screen_w, h = (double)p->screen_h;
		v.x0 = p->n ? dmax(dmin(0, (double)bb.x1), -w / 4) : 0;
		v.y0 = p->n ? dmax(dmin(0, (double)bb.y1), -h / 4) : 0;
		v.x1 = p->n ? dmin(dmax(w, (double)bb.x2), w * 1.25) : w;
		v.y1 = p->n ? dmin(dmax(h, (double)bb.y2), h * 1.25) : h;
	} else {
		v.x0 = (double)bb.x1;
		v.y0 = (double)bb.y1;
		v.x1 = (double)bb.x2;
		v.y1 = (double)bb.y2;
	}
	v.s = dmin(DRAW_W / (v.x1 - v.x0), DRAW_H / (v.y1 - v.y0));
	v.w = (v.x1 - v.x0) * v.s;
	v.h = (v.y1 - v.y0) * v.s;
	v.ox = PAD + (v.w < MIN_W ? (MIN_W - v.w) / 2 : 0);
	v.oy = TITLE_H + PAD;
	return v;
}

/* A box on the canvas; scene boxes are cut to the view first, so numbers stay small. */
struct cbox {
	double x1, y1, x2, y2;
};

/* Maps a scene box onto the canvas, cut to the view plus a margin; false when nothing is left. */
static bool to_canvas(const struct view *v, struct vis_box b, struct cbox *c)
{
	double m = PAD / v->s;
	double x1 = (double)b.x1 > v->x0 - m ? (double)b.x1 : v->x0 - m;
	double y1 = (double)b.y1 > v->y0 - m ? (double)b.y1 : v->y0 - m;
	double x2 = (double)b.x2 < v->x1 + m ? (double)b.x2 : v->x1 + m;
	double y2 = (double)b.y2 < v->y1 + m ? (double)b.y2 : v->y1 + m;

	if (x1 >= x2 || y1 >= y2)
		return false;
	c->x1 = v->ox + (x1 - v->x0) * v->s;
	c->y1 = v->oy + (y1 - v->y0) * v->s;
	c->x2 = v->ox + (x2 - v->x0) * v->s;
	c->y2 = v->oy + (y2 - v->y0) * v->s;
	return true;
}

/* The number of digits of an ID. */
static int digits(uint32_t id)
{
	int n = 1;
	while (id >= 10) {
		id /= 10;
		n++;
	}
	return n;
}

/*
 * A label: the ID centred on x (starting at x in a corner), baseline y, font size fs. A label
 * that fits its window's visible part overlaps no other that does; the others may.
 */
struct label {
	enum { LABEL_NONE, LABEL_FITS, LABEL_SPILLS, LABEL_CORNER } kind;
	double x, y, fs;
	struct cbox box; /* LABEL_CORNER: the window's outline */
};

/*
 * Where window w's label goes: centred in the visible part where it can be largest; without a
 * visible part, small in the top left corner of the outline (in the middle when the parts are
 * unknown).
 */
static struct label place_label(const struct stack_svg *p, const struct view *v,
				const struct stack_svg_window *w)
{
	double chars = digits(w->id) * DIGIT_W + 0.3, best = 0, area = 0;
	struct cbox at = { 0 }, c;
	struct label l = { .kind = LABEL_NONE };

	for (size_t j = w->first; j < w->first + w->n_parts; j++) {
		if (!to_canvas(v, p->parts[j], &c))
			continue;
		double cw = c.x2 - c.x1, ch = c.y2 - c.y1;
		double fs = ch * 0.8 < cw / chars ? ch * 0.8 : cw / chars;
		fs = fs < LABEL_MAX ? fs : LABEL_MAX;
		if (fs > best || (fs == best && cw * ch > area)) {
			best = fs;
			area = cw * ch;
			at = c;
		}
	}
	if (area > 0) {
		l.kind = best >= LABEL_MIN ? LABEL_FITS : LABEL_SPILLS;
		l.fs = best >= LABEL_MIN ? best : LABEL_MIN;
		l.x = (at.x1 + at.x2) / 2;
		l.y = (at.y1 + at.y2) / 2 + l.fs * 0.36;
	} else if (!to_canvas(v, w->box, &c)) {
		return l;
	} else if (p->has_parts || w->state == VIS_FULLY_OBSCURED) {
		l.kind = LABEL_CORNER;
		l.fs = (c.y2 - c.y1) * 0.8 < HIDDEN_LABEL_MAX ? (c.y2 - c.y1) * 0.8 : HIDDEN_LABEL_MAX;
		l.fs = l.fs > LABEL_MIN ? l.fs : LABEL_MIN;
		l.box = c;
		l.x = c.x1 + 3;
		l.y = c.y1 + l.fs + 1.5;
	} else {
		l.kind = LABEL_SPILLS;
		l.fs = LABEL_MIN;
		l.x = (c.x1 + c.x2) / 2;
		l.y = (c.y1 + c.y2) / 2 + l.fs * 0.36;
	}
	return l;
}

/* The canvas in cells of CELL × CELL units, marking those under a label, so labels never pile up. */
#define CELL 4.0
struct occupancy {
	uint8_t *cells;
	long cols, rows;
};

/*
 * Marks the cells under label l of window id, unless (without force) one of them is marked
 * already. Returns whether it marked them.
 */
static bool occupy(struct occupancy *o, const struct label *l, uint32_t id, bool force)
{
	double w = (digits(id) * DIGIT_W + 0.3) * l->fs;
	double x0 = l->kind == LABEL_CORNER ? l->x : l->x - w / 2, y0 = l->y - 0.8 * l->fs;
	long c0 = (long)(x0 / CELL), c1 = (long)((x0 + w) / CELL);
	long r0 = (long)(y0 / CELL), r1 = (long)((y0 + l->fs) / CELL);

	c0 = c0 < 0 ? 0 : c0;
	r0 = r0 < 0 ? 0 : r0;
	c1 = c1 < o->cols ? c1 : o->cols - 1;
	r1 = r1 < o->rows ? r1 : o->rows - 1;
	if (c0 > c1 || r0 > r1)
		return true;
	for (long r = r0; r <= r1 && !force; r++)
		for (long c = c0; c <= c1; c++)
			if (o->cells[r * o->cols + c])
				return false;
	for (long r = r0; r <= r1; r++)
		memset(o->cells + r * o->cols + c0, 1, (size_t)(c1 - c0 + 1));
	return true;
}

/*
 * Places every window's label: those that fit their visible part first, then the others from the
 * top of the stack down, each only where no label is yet. Returns the labels (labels[i] for
 * window i) and how many were left out, or NULL (ENOMEM).
 */
static struct label *plan_labels(const struct stack_svg *p, const struct view *v,
				 double width, double height, size_t *left_out)
{
	struct occupancy o = { NULL, (long)(width / CELL) + 1, (long)(height / CELL) + 1 };
	struct label *labels = malloc((p->n ? p->n : 1) * sizeof(*labels));

	*left_out = 0;
	o.cells = calloc((size_t)o.cols * (size_t)o.rows, 1);
	if (labels == NULL || o.cells == NULL) {
		free(labels);
		free(o.cells);
		errno = ENOMEM;
		return NULL;
	}
	for (size_t i = 0; i < p->n; i++) {
		labels[i] = place_label(p, v, &p->windows[i]);
		if (labels[i].kind == LABEL_FITS)
			occupy(&o, &labels[i], p->windows[i].id, true);
	}
	for (size_t i = p->n; i-- > 0;) {
		struct label *l = &labels[i];
		uint32_t id = p->windows[i].id;
		if (l->kind == LABEL_FITS || l->kind == LABEL_NONE || occupy(&o, l, id, false))
			continue;
		/* A corner label tries the other corners: top right, bottom left, bottom right. */
		bool placed = false;
		double w = digits(id) * DIGIT_W * l->fs;
		for (int k = 1; k < 4 && l->kind == LABEL_CORNER && !placed; k++) {
			l->x = k & 1 ? l->box.x2 - 3 - w : l->box.x1 + 3;
			l->y = k & 2 ? l->box.y2 - 4 : l->box.y1 + l->fs + 1.5;
			placed = occupy(&o, l, id, false);
		}
		if (!placed) {
			l->kind = LABEL_NONE;
			++*left_out;
		}
	}
	free(o.cells);
	return labels;
}

/* Writes the labels planned; those in corners are italic, for windows showing nothing. */
static void write_labels(const struct stack_svg *p, const struct label *labels, FILE *f)
{
	for (size_t i = 0; i < p->n; i++) {
		const struct label *l = &labels[i];
		if (l->kind != LABEL_NONE)
			fprintf(f, "<text class=\"l%s\" x=\"%.1f\" y=\"%.1f\" font-size=\"%.1f\">%"
				PRIu32 "</text>\n", l->kind == LABEL_CORNER ? " h" : "", l->x, l->y,
				l->fs, p->windows[i].id);
	}
}

/*
 * Writes one window: its visible parts as one filled path, then its outline. The fills are
 * opaque, so that a window's visible parts hide the edges of the windows under them and only the
 * edges one can see remain: drawn bottom to top, the picture is the stack as seen.
 */
/* Draws a window's see-through (or opaque) pixels as one path of class cls; returns how many. */
static int write_pixels(const struct stack_svg *p, const struct view *v,
			const struct stack_svg_window *w, bool see_through, const char *cls, FILE *f)
{
	int drawn = 0;
	for (size_t j = w->first_px; j < w->first_px + w->n_px; j++) {
		struct cbox r;
		if (p->pixels[j].see_through != see_through || !to_canvas(v, p->pixels[j].box, &r))
			continue;
		if (drawn++ == 0)
			fprintf(f, "<path class=\"%s\" d=\"", cls);
		fprintf(f, "M%.1f %.1fH%.1fV%.1fH%.1fZ", r.x1, r.y1, r.x2, r.y2, r.x1);
	}
	if (drawn)
		fputs("\"/>\n", f);
	return drawn;
}

static void write_window(const struct stack_svg *p, const struct view *v,
			 const struct stack_svg_window *w, bool tooltip, FILE *f)
{
	struct cbox c;
	const char *cls = state_class[w->state];

	if (!to_canvas(v, w->box, &c))
		return;
	if (tooltip) {
		fprintf(f, "<g><title>%" PRIu32, w->id);
		if (w->parent)
			fprintf(f, " (child of %" PRIu32 ")", w->parent);
		fprintf(f, ": %" PRId64 ",%" PRId64 " %" PRId64 "×%" PRId64 ", %s</title>\n",
			w->box.x1, w->box.y1, w->box.x2 - w->box.x1, w->box.y2 - w->box.y1,
			vis_state_name((enum vis_state)w->state));
	}
	/* A translucent window's visible parts are filled faintly: what they show through is seen. */
	bool see_through = w->translucent;
	for (size_t j = w->first_px; j < w->first_px + w->n_px; j++)
		see_through |= p->pixels[j].see_through;
	bool open = false;
	for (size_t j = w->first; j < w->first + w->n_parts; j++) {
		struct cbox r;
		if (!to_canvas(v, p->parts[j], &r))
			continue;
		if (!open)
			fprintf(f, "<path class=\"v%s%s\" d=\"", cls, see_through ? " t" : "");
		open = true;
		fprintf(f, "M%.1f %.1fH%.1fV%.1fH%.1fZ", r.x1, r.y1, r.x2, r.y2, r.x1);
	}
	if (open)
		fputs("\"/>\n", f);
	/* Translucent pixels hatched over their fill: seen, but hiding nothing. */
	if (w->state != VIS_FULLY_OBSCURED)
		write_pixels(p, v, w, true, "pt", f);
	/* A shaped window's outline is its pixels'; its border box is drawn faint. */
	if (w->n_px > 0 && write_pixels(p, v, w, true, cls, f) + write_pixels(p, v, w, false, cls, f))
		cls = "b";
	fprintf(f, "<rect class=\"%s\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\"/>\n",
		cls, c.x1, c.y1, c.x2 - c.x1, c.y2 - c.y1);
	struct cbox in;
	if (memcmp(&w->inside, &w->box, sizeof(w->box)) != 0 && to_canvas(v, w->inside, &in))
		fprintf(f, "<rect class=\"i\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
			"height=\"%.1f\"/>\n", in.x1, in.y1, in.x2 - in.x1, in.y2 - in.y1);
	if (tooltip)
		fputs("</g>\n", f);
}

/*
 * Past this many fully-obscured windows, their outlines and labels drawn over everything would
 * hide the windows one sees: they are drawn fainter.
 */
#define CROWD 30

/*
 * The style sheet: one class per state for outlines (u, p, f) and fills (vu, vp), then labels (l,
 * and h for those in a corner).
 */
static void write_style(FILE *f, bool crowded)
{
	fputs("<style>\n", f);
	for (int s = 0; s < 3; s++)
		fprintf(f, ".%s{fill:none;stroke:%s;stroke-width:1.5}\n.v%s{fill:%s;stroke:none}\n",
			state_class[s], state_colour[s], state_class[s], state_tint[s]);
	/* Translucent windows' fills and pixels (hatched), borders' insides, shaped border boxes. */
	fputs(".t{fill-opacity:0.45}\n"
	      ".pt{fill:url(#hatch);stroke:none}\n"
	      ".i{fill:none;stroke:#495057;stroke-width:0.6}\n"
	      ".b{fill:none;stroke:#868e96;stroke-width:0.6;stroke-dasharray:2 2}\n", f);
	fprintf(f, ".f{stroke-dasharray:5 3%s}\n"
		".l{fill:#212529;stroke:white;stroke-width:2.5;stroke-linejoin:round;"
		"paint-order:stroke;text-anchor:middle}\n"
		".h{text-anchor:start;font-style:italic%s}\n"
		"</style>\n",
		crowded ? ";stroke-width:0.8;stroke-opacity:0.6" : "", crowded ? ";fill:#6c757d" : "");
}

/* The legend: a sample window per state with the number of windows in it. */
static void write_legend(const struct stack_svg *p, double y, FILE *f)
{
	size_t count[3] = { 0 };
	double x = PAD;

	for (size_t i = 0; i < p->n; i++)
		count[p->windows[i].state]++;
	for (int s = 0; s < 3; s++) {
		if (s != VIS_FULLY_OBSCURED)
			fprintf(f, "<rect class=\"v%s\" x=\"%.1f\" y=\"%.1f\" width=\"28\" "
				"height=\"16\"/>\n", state_class[s], x, y);
		fprintf(f, "<rect class=\"%s\" x=\"%.1f\" y=\"%.1f\" width=\"28\" height=\"16\"/>\n"
			"<text x=\"%.1f\" y=\"%.1f\" font-size=\"13\">%s: %zu</text>\n",
			state_class[s], x, y, x + 36, y + 12.5, state_label[s], count[s]);
		x += 36 + 7.4 * (double)(strlen(state_label[s]) + 8);
	}
}

/* The most lines the note under the legend takes; what does not fit is cut. */
#define NOTE_LINES 6

/*
 * Writes text as lines of at most width units at font size 12, broken at spaces, from baseline
 * y on. Returns the number of lines; with f NULL, only counts them.
 */
static int write_wrapped(const char *text, double width, double y, FILE *f)
{
	size_t max = (size_t)(width / 6.6), len = strlen(text);
	int lines = 0;
	char line[sizeof(((struct stack_svg *)0)->note) + 512];

	for (size_t at = 0; at < len && lines < NOTE_LINES; lines++) {
		size_t n = len - at;
		if (n > max) {
			n = max;
			while (n > 1 && text[at + n] != ' ')
				n--;
			n = n > 1 ? n : max;
		}
		if (f) {
			memcpy(line, text + at, n < sizeof(line) ? n : sizeof(line) - 1);
			line[n < sizeof(line) ? n : sizeof(line) - 1] = '\0';
			fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" fill=\"#495057\">",
				PAD, y + lines * NOTE_H);
			svg_text(f, line);
			fputs("</text>\n", f);
		}
		at += n;
		while (text[at] == ' ')
			at++;
	}
	return lines;
}

/* Appends to a string of capacity len, cutting it short when full. */
static void append(char *buf, size_t len, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void append(char *buf, size_t len, const char *fmt, ...)
{
	size_t at = strlen(buf);
	va_list ap;

	va_start(ap, fmt);
	vsnprintf(buf + at, len - at, fmt, ap);
	va_end(ap);
}

/*
 * The note under the legend: how to read the picture, the caller's note, then what the drawing
 * leaves out, which it must say since every window is to be found in the picture: windows
 * outside the view (the first few), and labels.
 */
static void full_note(const struct stack_svg *p, const struct view *v, size_t left_out,
		      char *buf, size_t len)
{
	size_t outside = 0;
	struct cbox c;

	snprintf(buf, len, "Filled: the visible parts; outlined: the whole window; label: its ID, "
		 "in its largest visible part (tooltips say more).");
	bool borders = false, shaped = false, see_through = false, faint = false;
	for (size_t i = 0; i < p->n; i++) {
		const struct stack_svg_window *w = &p->windows[i];
		borders |= memcmp(&w->inside, &w->box, sizeof(w->box)) != 0;
		shaped |= w->n_px > 0;
		faint |= w->translucent;
	}
	for (size_t j = 0; j < p->n_pixels; j++)
		see_through |= p->pixels[j].see_through;
	if (shaped)
		append(buf, len, " A shaped or translucent window is outlined by its pixels, its border box dotted.");
	if (borders)
		append(buf, len, " A thin inner line: a border's inside.");
	if (see_through)
		append(buf, len, " Hatched, faintly filled: translucent pixels, which hide nothing.");
	else if (faint)
		append(buf, len, " Faintly filled: windows with translucent pixels, which hide nothing.");
	if (p->note[0])
		append(buf, len, " %s", p->note);
	for (size_t i = 0; i < p->n; i++) {
		if (to_canvas(v, p->windows[i].box, &c))
			continue;
		if (outside == 0)
			append(buf, len, " Outside the picture: ");
		if (outside < 12)
			append(buf, len, "%s%" PRIu32, outside ? ", " : "", p->windows[i].id);
		outside++;
	}
	if (outside > 12)
		append(buf, len, " and %zu more", outside - 12);
	if (outside)
		append(buf, len, ".");
	if (p->n > STACK_SVG_MAX_LABELS)
		append(buf, len, " More than %d windows: no labels or tooltips, and fully-obscured "
		       "windows are drawn in stacking order, under what covers them.",
		       STACK_SVG_MAX_LABELS);
	if (left_out)
		append(buf, len, " %zu label%s left out where %s would cover others.", left_out,
		       left_out == 1 ? "" : "s", left_out == 1 ? "it" : "they");
}

int stack_svg_write(const struct stack_svg *p, FILE *f)
{
	struct view v = view_of(p);
	double width = (v.w > MIN_W ? v.w : MIN_W) + 2 * PAD;
	double legend_y = v.oy + v.h + PAD + 6;
	struct label *labels = NULL;
	size_t left_out = 0;
	char note[sizeof(p->note) + 512];
	struct cbox c;

	if (p->n <= STACK_SVG_MAX_LABELS &&
	    (labels = plan_labels(p, &v, width, legend_y, &left_out)) == NULL)
		return -1;
	full_note(p, &v, left_out, note, sizeof(note));
	int lines = write_wrapped(note, width - 2 * PAD, 0, NULL);
	double height = legend_y + LEGEND_H + lines * NOTE_H + PAD;

	svg_begin(f, width, height);
	if (labels == NULL)
		fprintf(f, "<!-- %zu windows: no labels or tooltips past %d -->\n", p->n,
			STACK_SVG_MAX_LABELS);
	size_t hidden = 0;
	for (size_t i = 0; i < p->n; i++)
		hidden += p->windows[i].state == VIS_FULLY_OBSCURED;
	write_style(f, hidden > CROWD);
	fputs("<defs><pattern id=\"hatch\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" "
	      "patternTransform=\"rotate(45)\"><line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"6\" "
	      "stroke=\"#495057\" stroke-width=\"1.2\" stroke-opacity=\"0.6\"/></pattern></defs>\n", f);
	fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-size=\"17\" font-weight=\"bold\">", PAD,
		PAD + 13);
	svg_text(f, p->title);
	size_t children = 0;
	for (size_t i = 0; i < p->n; i++)
		children += p->windows[i].parent != 0;
	fprintf(f, "</text>\n<text x=\"%.1f\" y=\"%.1f\" font-size=\"12\" fill=\"#495057\">%zu "
		"window%s", PAD, PAD + 32, p->n, p->n == 1 ? "" : "s");
	if (children == 1)
		fputs(" (1 a child, drawn over its parent)", f);
	else if (children)
		fprintf(f, " (%zu of them children, drawn over their parents)", children);
	fputs(", bottom to top", f);
	if (p->has_screen)
		fprintf(f, " on a %" PRId64 "×%" PRId64 " screen", p->screen_w, p->screen_h);
	else
		fputs(" (no screen: their bounding box)", f);
	fprintf(f, 1 / v.s < 10 ? "; drawn at 1:%.2g</text>\n" : "; drawn at 1:%.0f</text>\n", 1 / v.s);

	/* The drawing, clipped to the view and its margin; the screen white, grey around it. */
	fprintf(f, "<clipPath id=\"view\"><rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" "
		"height=\"%.1f\"/></clipPath>\n<g clip-path=\"url(#view)\">\n"
		"<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>\n",
		v.ox - PAD, v.oy - PAD, v.w + 2 * PAD, v.h + 2 * PAD,
		v.ox - PAD, v.oy - PAD, v.w + 2 * PAD, v.h + 2 * PAD,
		p->has_screen ? "#e9ecef" : "#f8f9fa");
	bool screen = p->has_screen &&
		      to_canvas(&v, (struct vis_box){ 0, 0, p->screen_w, p->screen_h }, &c);
	if (screen)
		fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" "
			"fill=\"white\"/>\n", c.x1, c.y1, c.x2 - c.x1, c.y2 - c.y1);
	/*
	 * Fully-obscured windows have nothing to fill: their outlines go over everything, unless
	 * there are so many that they would hide it.
	 */
	bool on_top = p->has_parts && labels != NULL;
	for (size_t i = 0; i < p->n; i++)
		if (!on_top || p->windows[i].state != VIS_FULLY_OBSCURED)
			write_window(p, &v, &p->windows[i], labels != NULL, f);
	for (size_t i = 0; i < p->n && on_top; i++)
		if (p->windows[i].state == VIS_FULLY_OBSCURED)
			write_window(p, &v, &p->windows[i], labels != NULL, f);
	/* The screen's edge over the windows, which would hide it. */
	if (screen)
		fprintf(f, "<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"none\" "
			"stroke=\"#343a40\" stroke-width=\"1.5\"/>\n", c.x1, c.y1, c.x2 - c.x1,
			c.y2 - c.y1);
	if (labels)
		write_labels(p, labels, f);
	fputs("</g>\n", f);

	write_legend(p, legend_y, f);
	write_wrapped(note, width - 2 * PAD, legend_y + LEGEND_H, f);
	fputs("</svg>\n", f);
	free(labels);
	return ferror(f) ? -1 : 0;
}
