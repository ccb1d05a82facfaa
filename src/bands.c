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
 * Closes the band o[start … n) of a region being written, whose band before starts at *last:
 * merges it into that one when they touch with the same columns (pixman's coalescing: without
 * it, every box taken off would leave three bands). Returns where the next band starts.
 */
static inline size_t close_band(pixman_box32_t *o, size_t *last, size_t start, size_t n)
{
	size_t m = n - start, l = *last;
	if (!m)
		return n;
	if (l < start && start - l == m && o[l].y2 == o[start].y1) {
		size_t i = 0;
		while (i < m && o[l + i].x1 == o[start + i].x1 && o[l + i].x2 == o[start + i].x2)
			i++;
		if (i == m) {
			for (i = 0; i < m; i++)
				o[l + i].y2 = o[start].y2;
			return start;
		}
	}
	*last = start;
	return n;
}

/* Copies the band in[i … j) to o[n …], between rows y1 and y2; returns where it ends. */
static inline size_t copy_rows(pixman_box32_t *o, size_t n, const pixman_box32_t *in, size_t i,
			       size_t j, int32_t y1, int32_t y2)
{
	for (; i < j; i++)
		o[n++] = (pixman_box32_t){ in[i].x1, y1, in[i].x2, y2 };
	return n;
}

/* copy_rows(), the band closed (close_band()); returns where the next band starts. */
static inline size_t copy_band(pixman_box32_t *o, size_t *last, size_t n, const pixman_box32_t *in,
			       size_t i, size_t j, int32_t y1, int32_t y2)
{
	return close_band(o, last, n, copy_rows(o, n, in, i, j, y1, y2));
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

/* Sets the extents of the boxes r holds. */
static void extents(struct vis_bands *r)
{
	r->ext = (pixman_box32_t){ 0 };
	if (!r->n)
		return;
	r->ext.y1 = r->boxes[0].y1;
	r->ext.y2 = r->boxes[r->n - 1].y2;
	columns(r);
}

/* Whether b covers a's extents (b meets a). */
static bool covers(pixman_box32_t b, const struct vis_bands *a)
{
	return b.x1 <= a->ext.x1 && b.y1 <= a->ext.y1 && a->ext.x2 <= b.x2 && a->ext.y2 <= b.y2;
}

/* Writes one box after r's. */
static void put(struct vis_bands *r, int32_t x1, int32_t y1, int32_t x2, int32_t y2)
{
	r->boxes[r->n++] = (pixman_box32_t){ x1, y1, x2, y2 };
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

/* The first box of in[0 … n) b takes pixels from, or n. */
static size_t first_taken(const pixman_box32_t *in, size_t n, pixman_box32_t b)
{
	size_t i = 0;
	while (i < n && in[i].y1 < b.y2 &&
	       (in[i].y2 <= b.y1 || in[i].x2 <= b.x1 || b.x2 <= in[i].x1))
		i++;
	return i < n && in[i].y1 < b.y2 ? i : n;
}

/*
 * Writes the banded boxes in[0 … n) less b to o (room for 4 n: a band b takes from becomes at
 * most three, the rows beside b one box more), b taking pixels from box i; when parts is not
 * NULL (room for n), the bands of in ∩ b are written to it too, *n_parts of them. Returns how
 * many boxes o has.
 *
 * Only the bands b takes from change, each into at most three: the rows above b and below it
 * keep the band's columns, which differ from those of the rows beside b (which lost some) and,
 * by the invariant, from the band above: only the rows beside b, the bands b's rows meet without
 * taking from, and the first band below can coalesce with what is written before them.
 */
static size_t write_less(const pixman_box32_t *in, size_t n, size_t i, pixman_box32_t b,
			 pixman_box32_t *o, pixman_box32_t *parts, size_t *n_parts)
{
	size_t k = 0, last = 0, q = 0, qlast = 0;
	while (i > 0 && in[i - 1].y1 == in[i].y1)
		i--;
	for (; k < i; k++) {
		if (in[k].y1 != in[last].y1)
			last = k;
		o[k] = in[k];
	}
	while (i < n && in[i].y1 < b.y2) {
		int32_t y1 = in[i].y1, y2 = in[i].y2;
		size_t i0 = i, j = i;
		bool meets = false;
		for (; j < n && in[j].y1 == y1; j++)
			meets |= in[j].x1 < b.x2 && b.x1 < in[j].x2;
		if (!meets) {
			k = copy_band(o, &last, k, in, i, j, y1, y2);
			i = j;
			continue;
		}
		if (y1 < b.y1) {
			last = k;
			k = copy_rows(o, k, in, i, j, y1, b.y1);
		}
		int32_t m1 = y1 > b.y1 ? y1 : b.y1, m2 = y2 < b.y2 ? y2 : b.y2;
		size_t start = k, qstart = q;
		for (; i < j; i++) {
			int32_t x1 = in[i].x1, x2 = in[i].x2;
			if (x2 <= b.x1 || x1 >= b.x2) {
				o[k++] = (pixman_box32_t){ x1, m1, x2, m2 };
				continue;
			}
			if (x1 < b.x1)
				o[k++] = (pixman_box32_t){ x1, m1, b.x1, m2 };
			if (x2 > b.x2)
				o[k++] = (pixman_box32_t){ b.x2, m1, x2, m2 };
			if (parts)
				parts[q++] = (pixman_box32_t){ x1 > b.x1 ? x1 : b.x1, m1,
							       x2 < b.x2 ? x2 : b.x2, m2 };
		}
		k = close_band(o, &last, start, k);
		if (parts)
			q = close_band(parts, &qlast, qstart, q);
		if (y2 > b.y2) {
			last = k;
			k = copy_rows(o, k, in, i0, j, b.y2, y2);
		}
	}
	if (i < n) {
		size_t j = i;
		while (j < n && in[j].y1 == in[i].y1)
			j++;
		k = copy_band(o, &last, k, in, i, j, in[i].y1, in[i].y2);
		for (; j < n; j++)
			o[k++] = in[j];
	}
	if (n_parts)
		*n_parts = q;
	return k;
}

/* Sets r's extents after b was taken off it: the first and last bands' rows; the columns stay
 * unless b took pixels of the first or the last column (a box holding one keeps it, as b leaves
 * it alone). */
static void extents_less(struct vis_bands *r, pixman_box32_t b)
{
	if (!r->n) {
		r->ext = (pixman_box32_t){ 0 };
		return;
	}
	r->ext.y1 = r->boxes[0].y1;
	r->ext.y2 = r->boxes[r->n - 1].y2;
	if (b.x1 <= r->ext.x1 || b.x2 >= r->ext.x2)
		columns(r);
}

/*
 * Takes b off r, which has several boxes and whose extents b meets without covering them,
 * through scratch; when parts is not NULL (room for r->n), writes the bands of r ∩ b there too,
 * *n_parts of them. Only the bands b's rows meet change, and the band above and the band below
 * them, which may coalesce with what they become: write_less() writes those to scratch. A small
 * region is written whole and its boxes change places with scratch's, which costs less than
 * finding where to splice; a larger one gets them spliced in between the bands above and below,
 * which stay in place. 0 (nothing written when b takes no pixel), or -1 with ENOMEM (r is then
 * unchanged).
 */
static int less(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b,
		pixman_box32_t *parts, size_t *n_parts)
{
	bool small = r->n <= SMALL;
	size_t from = 0, to = r->n;
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
	size_t m = to - from, i = first_taken(r->boxes + from, m, b);
	if (i == m)
		return 0;
	if (reserve(scratch, 4 * m) < 0 || (!small && reserve(r, r->n + 3 * m) < 0))
		return -1;
	size_t k = write_less(r->boxes + from, m, i, b, scratch->boxes, parts, n_parts);
	if (small) {
		pixman_box32_t *boxes = r->boxes;
		size_t cap = r->cap;
		r->boxes = scratch->boxes;
		r->cap = scratch->cap;
		scratch->boxes = boxes;
		scratch->cap = cap;
		r->n = k;
	} else {
		memmove(r->boxes + from + k, r->boxes + to, (r->n - to) * sizeof *r->boxes);
		memcpy(r->boxes + from, scratch->boxes, k * sizeof *r->boxes);
		r->n = r->n - m + k;
	}
	extents_less(r, b);
	return 0;
}

int vis_bands_subtract(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b)
{
	return vis_bands_take(r, scratch, b, NULL) < 0 ? -1 : 0;
}

long vis_bands_take(struct vis_bands *r, struct vis_bands *scratch, pixman_box32_t b,
		    pixman_box32_t *out)
{
	if (!vis_bands_meet(r, b))
		return 0;
	size_t n = r->n, parts = 0;
	if (covers(b, r)) {
		if (out)
			memcpy(out, r->boxes, n * sizeof *out);
		r->n = 0; /* the common end of a walk */
		r->ext = (pixman_box32_t){ 0 };
		return (long)n;
	}
	if (n == 1) {
		if (out)
			out[0] = vis_pbox_and(r->boxes[0], b);
		return box_less(r, b) < 0 ? -1 : 1;
	}
	return less(r, scratch, b, out, &parts) < 0 ? -1 : (long)parts;
}

int vis_bands_set_less(struct vis_bands *r, const pixman_box32_t *b, size_t n, pixman_box32_t h)
{
	r->n = 0;
	r->ext = (pixman_box32_t){ 0 };
	if (reserve(r, 4 * n) < 0)
		return -1;
	size_t i = h.x1 < h.x2 && h.y1 < h.y2 ? first_taken(b, n, h) : n;
	if (i < n) {
		r->n = write_less(b, n, i, h, r->boxes, NULL, NULL);
	} else if (n) {
		memcpy(r->boxes, b, n * sizeof *b);
		r->n = n;
	}
	extents(r);
	return 0;
}

/* Writes the boxes of src ∩ b to o, banded and coalesced (at most src->n), b meeting src;
 * returns how many. */
static size_t clip_into(pixman_box32_t *o, const struct vis_bands *src, pixman_box32_t b)
{
	size_t k = 0, last = 0;
	for (size_t i = first_below(src, b.y1); i < src->n && src->boxes[i].y1 < b.y2;) {
		int32_t y1 = src->boxes[i].y1 > b.y1 ? src->boxes[i].y1 : b.y1;
		int32_t y2 = src->boxes[i].y2 < b.y2 ? src->boxes[i].y2 : b.y2;
		size_t start = k;
		for (int32_t band = src->boxes[i].y1; i < src->n && src->boxes[i].y1 == band; i++) {
			int32_t x1 = src->boxes[i].x1 > b.x1 ? src->boxes[i].x1 : b.x1;
			int32_t x2 = src->boxes[i].x2 < b.x2 ? src->boxes[i].x2 : b.x2;
			if (x1 < x2)
				o[k++] = (pixman_box32_t){ x1, y1, x2, y2 };
		}
		k = close_band(o, &last, start, k);
	}
	return k;
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
	dst->n = clip_into(dst->boxes, src, b);
	extents(dst);
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
	return clip_into(out, r, b);
}
