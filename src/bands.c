/* Banded regions for the walks that take boxes off a damaged area (bands.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "bands.h"

void vis_bands_init(struct vis_bands *r)
{
	*r = (struct vis_bands){ 0 };
}

void vis_bands_finish(struct vis_bands *r)
{
	free(r->boxes);
	*r = (struct vis_bands){ 0 };
}

/* Room for n boxes. 0, or -1 with ENOMEM. */
static int reserve(struct vis_bands *r, size_t n)
{
	if (n <= r->cap)
		return 0;
	size_t want = r->cap ? r->cap : 16;
	while (want < n)
		want *= 2;
	pixman_box32_t *more = want > SIZE_MAX / sizeof *more ? NULL
							      : realloc(r->boxes, want * sizeof *more);
	if (!more) {
		errno = ENOMEM;
		return -1;
	}
	r->boxes = more;
	r->cap = want;
	return 0;
}

int vis_bands_set_box(struct vis_bands *r, pixman_box32_t b)
{
	r->n = 0;
	r->ext = (pixman_box32_t){ 0 };
	if (b.x1 >= b.x2 || b.y1 >= b.y2)
		return 0;
	if (reserve(r, 1) < 0)
		return -1;
	r->boxes[0] = r->ext = b;
	r->n = 1;
	return 0;
}

int vis_bands_copy(struct vis_bands *dst, const struct vis_bands *src)
{
	dst->n = 0;
	dst->ext = (pixman_box32_t){ 0 };
	if (reserve(dst, src->n) < 0)
		return -1;
	if (src->n)
		memcpy(dst->boxes, src->boxes, src->n * sizeof *src->boxes);
	dst->n = src->n;
	dst->ext = src->ext;
	return 0;
}

/*
 * The region being written: boxes [last, n) are the band written last, [start, n) the one being
 * written, which band_end() closes, merging it into the last one when they touch with the same x
 * edges (pixman's coalescing: without it, every box taken off would leave three bands).
 */
struct out {
	struct vis_bands *r;
	size_t last;
};

static void band_end(struct out *o, size_t start)
{
	struct vis_bands *r = o->r;
	if (start == r->n)
		return;
	pixman_box32_t *p = r->boxes + o->last, *q = r->boxes + start;
	size_t m = r->n - start;
	if (o->last < start && start - o->last == m && p->y2 == q->y1) {
		size_t i = 0;
		while (i < m && p[i].x1 == q[i].x1 && p[i].x2 == q[i].x2)
			i++;
		if (i == m) {
			for (i = 0; i < m; i++)
				p[i].y2 = q->y2;
			r->n = start;
			return;
		}
	}
	o->last = start;
}

/* Writes one box of a band. */
static void put(struct vis_bands *r, int32_t x1, int32_t y1, int32_t x2, int32_t y2)
{
	r->boxes[r->n++] = (pixman_box32_t){ x1, y1, x2, y2 };
}

/* Writes the band of the m boxes from, between y1 and y2. */
static void put_band(struct out *o, const pixman_box32_t *from, size_t m, int32_t y1, int32_t y2)
{
	size_t start = o->r->n;
	for (size_t i = 0; i < m; i++)
		put(o->r, from[i].x1, y1, from[i].x2, y2);
	band_end(o, start);
}

/* Writes the band of the m boxes from less the columns x1 … x2, between y1 and y2, and, if p is
 * not NULL, their part in those columns to p. */
static void put_band_less(struct out *o, struct out *p, const pixman_box32_t *from, size_t m,
			  int32_t y1, int32_t y2, int32_t x1, int32_t x2)
{
	size_t start = o->r->n, pstart = p ? p->r->n : 0;
	for (size_t i = 0; i < m; i++) {
		const pixman_box32_t *f = &from[i];
		if (f->x2 <= x1 || f->x1 >= x2) {
			put(o->r, f->x1, y1, f->x2, y2);
			continue;
		}
		if (f->x1 < x1)
			put(o->r, f->x1, y1, x1, y2);
		if (f->x2 > x2)
			put(o->r, x2, y1, f->x2, y2);
		if (p)
			put(p->r, f->x1 > x1 ? f->x1 : x1, y1, f->x2 < x2 ? f->x2 : x2, y2);
	}
	band_end(o, start);
	if (p)
		band_end(p, pstart);
}

/* The index of the first box below row y (whose y2 passes it), or n: y2 grows box by box. */
static size_t first_below(const struct vis_bands *r, int32_t y)
{
	size_t lo = 0, hi = r->n;
	while (lo < hi) {
		size_t mid = lo + (hi - lo) / 2;
		if (r->boxes[mid].y2 <= y)
			lo = mid + 1;
		else
			hi = mid;
	}
	return lo;
}

/* The index of the first box of the band holding box i. */
static size_t band_start(const struct vis_bands *r, size_t i)
{
	while (i > 0 && r->boxes[i - 1].y1 == r->boxes[i].y1)
		i--;
	return i;
}

/* The index of the band after the one starting at i. */
static size_t band_after(const struct vis_bands *r, size_t i)
{
	size_t j = i;
	while (j < r->n && r->boxes[j].y1 == r->boxes[i].y1)
		j++;
	return j;
}

/* Sets the extents' columns, from the first and the last box of each band. */
static void columns(struct vis_bands *r)
{
	r->ext.x1 = INT32_MAX;
	r->ext.x2 = INT32_MIN;
	for (size_t i = 0, j; i < r->n; i = j) {
		j = band_after(r, i);
		if (r->boxes[i].x1 < r->ext.x1)
			r->ext.x1 = r->boxes[i].x1;
		if (r->boxes[j - 1].x2 > r->ext.x2)
			r->ext.x2 = r->boxes[j - 1].x2;
	}
}

/* Whether b covers a's extents (b meets a). */
static bool covers(pixman_box32_t b, const struct vis_bands *a)
{
	return b.x1 <= a->ext.x1 && b.y1 <= a->ext.y1 && a->ext.x2 <= b.x2 && a->ext.y2 <= b.y2;
}

/* vis_bands_subtract() of a region of one box, which b meets and does not cover: at most three
 * bands, the middle one of at most two boxes. 0, or -1. */
static int box_less(struct vis_bands *r, pixman_box32_t b)
{
	if (reserve(r, 4) < 0)
		return -1;
	pixman_box32_t a = r->boxes[0];
	int32_t y1 = a.y1 > b.y1 ? a.y1 : b.y1, y2 = a.y2 < b.y2 ? a.y2 : b.y2;
	r->n = 0;
	if (a.y1 < b.y1)
		put(r, a.x1, a.y1, a.x2, b.y1);
	if (a.x1 < b.x1)
		put(r, a.x1, y1, b.x1, y2);
	if (b.x2 < a.x2)
		put(r, b.x2, y1, a.x2, y2);
	if (b.y2 < a.y2)
		put(r, a.x1, b.y2, a.x2, a.y2);
	/* The rows above and below keep all columns, the middle ones lose some: the extents are
	 * a's but where b takes whole rows or columns. */
	r->ext = (pixman_box32_t){ r->boxes[0].x1, r->boxes[0].y1, r->boxes[0].x2,
				   r->boxes[r->n - 1].y2 };
	for (size_t i = 1; i < r->n; i++) {
		r->ext.x1 = r->boxes[i].x1 < r->ext.x1 ? r->boxes[i].x1 : r->ext.x1;
		r->ext.x2 = r->boxes[i].x2 > r->ext.x2 ? r->boxes[i].x2 : r->ext.x2;
	}
	return 0;
}

/* Regions of up to this many boxes are written again whole, not spliced. */
#define SMALL 24

/*
 * vis_bands_subtract() of a region of several boxes that b meets and does not cover; when p is
 * not NULL (a small region only), the bands of r ∩ b are written to it too. 0, or -1.
 */
static int subtract(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b,
		    struct out *p)
{
	/*
	 * Only the bands b's rows meet change, and the one above and the one below them, which
	 * may coalesce with what they become: those are written to scratch, and spliced into r
	 * between the bands above and below, which stay in place. A small region is written to
	 * scratch whole, which costs less than finding where to splice.
	 */
	size_t from = 0, to = r->n;
	bool small = r->n <= SMALL;
	if (!small) {
		from = first_below(r, b.y1);
		if (from > 0) /* the band above them */
			from = band_start(r, from - 1);
		to = from;
		while (to < r->n && r->boxes[to].y1 < b.y2)
			to = band_after(r, to);
		if (to < r->n)
			to = band_after(r, to); /* and the band below them */
	}
	/* A band meeting b becomes at most three: the parts above and below b, unchanged, and
	 * the one beside it, whose boxes but one (which b splits) stay one each. */
	size_t m = to - from;
	if (reserve(scratch, 4 * m) < 0 || (!small && reserve(r, r->n + 3 * m) < 0))
		return -1;
	struct out o = { scratch, 0 };
	scratch->n = 0;
	size_t start = from;
	if (small) {
		/* The bands above b's rows stay as they are, coalesced: copied at once. */
		while (start < to && r->boxes[start].y2 <= b.y1)
			start++;
		if (start) {
			memcpy(scratch->boxes, r->boxes, start * sizeof *r->boxes);
			scratch->n = start;
			o.last = band_start(scratch, start - 1);
		}
	}
	for (size_t i = start, j; i < to; i = j) {
		const pixman_box32_t *f = &r->boxes[i];
		int32_t y1 = f->y1, y2 = f->y2;
		bool meets = false;
		for (j = i; j < to && r->boxes[j].y1 == y1; j++)
			meets |= r->boxes[j].x1 < b.x2 && b.x1 < r->boxes[j].x2;
		size_t k = j - i;
		if (!meets || y2 <= b.y1 || y1 >= b.y2) {
			put_band(&o, f, k, y1, y2);
			if (small && y1 >= b.y2 && j < to) {
				/* Below b's rows, only the first band can coalesce: the rest as is. */
				memcpy(scratch->boxes + scratch->n, r->boxes + j,
				       (to - j) * sizeof *r->boxes);
				scratch->n += to - j;
				break;
			}
			continue;
		}
		if (y1 < b.y1)
			put_band(&o, f, k, y1, b.y1);
		put_band_less(&o, p, f, k, y1 > b.y1 ? y1 : b.y1, y2 < b.y2 ? y2 : b.y2, b.x1, b.x2);
		if (y2 > b.y2)
			put_band(&o, f, k, b.y2, y2);
	}
	if (small) {
		/* All of it was written again: the boxes change places with scratch's. */
		pixman_box32_t *boxes = r->boxes;
		size_t cap = r->cap;
		r->boxes = scratch->boxes;
		r->cap = scratch->cap;
		r->n = scratch->n;
		scratch->boxes = boxes;
		scratch->cap = cap;
	} else {
		memmove(r->boxes + from + scratch->n, r->boxes + to,
			(r->n - to) * sizeof *r->boxes);
		if (scratch->n)
			memcpy(r->boxes + from, scratch->boxes, scratch->n * sizeof *r->boxes);
		r->n = r->n - m + scratch->n;
	}
	/* The extents: the first and last bands' rows; the columns stay unless b took pixels of
	 * the first or the last column (a box holding one keeps it, as b leaves it alone). */
	if (!r->n) {
		r->ext = (pixman_box32_t){ 0 };
		return 0;
	}
	r->ext.y1 = r->boxes[0].y1;
	r->ext.y2 = r->boxes[r->n - 1].y2;
	if (b.x1 > r->ext.x1 && b.x2 < r->ext.x2)
		return 0;
	columns(r);
	return 0;
}

int vis_bands_subtract(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b)
{
	if (!vis_bands_meet(r, b))
		return 0;
	if (covers(b, r)) {
		r->n = 0; /* b covers it all: the common end of a walk */
		r->ext = (pixman_box32_t){ 0 };
		return 0;
	}
	if (r->n == 1)
		return box_less(r, b);
	return subtract(r, scratch, b, NULL);
}

long vis_bands_take(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b,
		    pixman_box32_t *out)
{
	if (!vis_bands_meet(r, b))
		return 0;
	size_t n = r->n;
	if (covers(b, r)) {
		memcpy(out, r->boxes, n * sizeof *out);
		r->n = 0;
		r->ext = (pixman_box32_t){ 0 };
		return (long)n;
	}
	if (n == 1) {
		out[0] = vis_pbox_and(r->boxes[0], b);
		return box_less(r, b) < 0 ? -1 : 1;
	}
	/* Meeting the extents and none of the boxes, b leaves r as it is: found for less than a
	 * rewrite costs. */
	size_t i = first_below(r, b.y1);
	while (i < n && r->boxes[i].y1 < b.y2 && (r->boxes[i].x2 <= b.x1 || b.x2 <= r->boxes[i].x1))
		i++;
	if (i == n || r->boxes[i].y1 >= b.y2)
		return 0;
	if (n > SMALL) {
		n = vis_bands_clip(r, b, out);
		return subtract(r, scratch, b, NULL) < 0 ? -1 : (long)n;
	}
	struct vis_bands parts = { out, 0, n, { 0 } };
	struct out p = { &parts, 0 };
	return subtract(r, scratch, b, &p) < 0 ? -1 : (long)parts.n;
}

/* Writes the band of src starting at box i, cut to b's columns, between rows y1 and y2, less the
 * columns of hole if not NULL; returns the index of the band after it. */
static size_t put_band_cut(struct out *o, const struct vis_bands *src, size_t i, int32_t y1,
			   int32_t y2, pixman_box32_t b, const pixman_box32_t *hole)
{
	size_t start = o->r->n;
	for (int32_t band = src->boxes[i].y1; i < src->n && src->boxes[i].y1 == band; i++) {
		int32_t x1 = src->boxes[i].x1 > b.x1 ? src->boxes[i].x1 : b.x1;
		int32_t x2 = src->boxes[i].x2 < b.x2 ? src->boxes[i].x2 : b.x2;
		if (x1 >= x2)
			continue;
		if (!hole || x2 <= hole->x1 || x1 >= hole->x2) {
			put(o->r, x1, y1, x2, y2);
			continue;
		}
		if (x1 < hole->x1)
			put(o->r, x1, y1, hole->x1, y2);
		if (x2 > hole->x2)
			put(o->r, hole->x2, y1, x2, y2);
	}
	band_end(o, start);
	return i;
}

/*
 * Writes src ∩ b less the box hole (inside b, or NULL) to dst's boxes, which have room for
 * src->n (3 src->n with a hole: a band across its rows becomes three), b meeting src, and sets
 * its extents if ext.
 */
static void clip_into(struct vis_bands *dst, const struct vis_bands *src, pixman_box32_t b,
		      const pixman_box32_t *hole, bool ext)
{
	struct out o = { dst, 0 };
	dst->n = 0;
	for (size_t i = first_below(src, b.y1); i < src->n && src->boxes[i].y1 < b.y2;) {
		int32_t y1 = src->boxes[i].y1 > b.y1 ? src->boxes[i].y1 : b.y1;
		int32_t y2 = src->boxes[i].y2 < b.y2 ? src->boxes[i].y2 : b.y2;
		if (!hole || y2 <= hole->y1 || y1 >= hole->y2) {
			i = put_band_cut(&o, src, i, y1, y2, b, NULL);
			continue;
		}
		if (y1 < hole->y1)
			put_band_cut(&o, src, i, y1, hole->y1, b, NULL);
		size_t next = put_band_cut(&o, src, i, y1 > hole->y1 ? y1 : hole->y1,
					   y2 < hole->y2 ? y2 : hole->y2, b, hole);
		if (y2 > hole->y2)
			put_band_cut(&o, src, i, hole->y2, y2, b, NULL);
		i = next;
	}
	dst->ext = (pixman_box32_t){ 0 };
	if (ext && dst->n) {
		dst->ext.y1 = dst->boxes[0].y1;
		dst->ext.y2 = dst->boxes[dst->n - 1].y2;
		columns(dst);
	}
}

int vis_bands_intersect(struct vis_bands *dst, const struct vis_bands *src, pixman_box32_t b)
{
	dst->n = 0;
	dst->ext = (pixman_box32_t){ 0 };
	if (!vis_bands_meet(src, b))
		return 0;
	/* A box, or a region b covers, is cut without a pass over its bands. */
	if (src->n == 1)
		return vis_bands_set_box(dst, vis_pbox_and(src->boxes[0], b));
	if (covers(b, src))
		return vis_bands_copy(dst, src);
	if (reserve(dst, src->n) < 0)
		return -1;
	clip_into(dst, src, b, NULL, true);
	return 0;
}

int vis_bands_intersect_less(struct vis_bands *dst, const struct vis_bands *src, pixman_box32_t b,
			     pixman_box32_t h)
{
	pixman_box32_t hole = vis_pbox_and(h, b);
	if (hole.x1 >= hole.x2 || hole.y1 >= hole.y2)
		return vis_bands_intersect(dst, src, b);
	dst->n = 0;
	dst->ext = (pixman_box32_t){ 0 };
	if (!vis_bands_meet(src, b))
		return 0;
	if (reserve(dst, 3 * src->n) < 0)
		return -1;
	clip_into(dst, src, b, &hole, true);
	return 0;
}

uint64_t vis_bands_area_in(const struct vis_bands *r, pixman_box32_t b)
{
	if (!vis_bands_meet(r, b))
		return 0;
	if (r->n == 1)
		return vis_pbox_area(vis_pbox_and(r->boxes[0], b));
	uint64_t a = 0;
	for (size_t i = first_below(r, b.y1); i < r->n; i++) {
		const pixman_box32_t *f = &r->boxes[i];
		if (f->y1 >= b.y2)
			break;
		int64_t x1 = f->x1 > b.x1 ? f->x1 : b.x1, x2 = f->x2 < b.x2 ? f->x2 : b.x2;
		int64_t y1 = f->y1 > b.y1 ? f->y1 : b.y1, y2 = f->y2 < b.y2 ? f->y2 : b.y2;
		if (x1 < x2 && y1 < y2)
			a += (uint64_t)(x2 - x1) * (uint64_t)(y2 - y1);
	}
	return a;
}

size_t vis_bands_clip(const struct vis_bands *r, pixman_box32_t b, pixman_box32_t *out)
{
	if (!vis_bands_meet(r, b))
		return 0;
	if (r->n == 1) {
		out[0] = vis_pbox_and(r->boxes[0], b);
		return 1;
	}
	if (covers(b, r)) {
		memcpy(out, r->boxes, r->n * sizeof *out);
		return r->n;
	}
	struct vis_bands view = { out, 0, r->n, { 0 } };
	clip_into(&view, r, b, NULL, false);
	return view.n;
}
