/*
 * Cutting windows with a look into disjoint rectangles. A window's pixels are a region: its shape
 * clipped to its border box; the opaque ones are that region intersected with its opaque region.
 * The region algebra is pixman's, run on the ranks of the rectangles' edges within the border
 * box: pixman computes in int and must not meet edges near the 32-bit limits, and ranks keep every
 * union, intersection and difference (the map is strictly increasing on the edges involved).
 */
#include <assert.h>
#include <errno.h>
#include <pixman.h>
#include <stdlib.h>
#include <string.h>

#include "look.h"

bool vis_look_plain(const struct vis_look *look)
{
	return look->border == 0 && !look->input_only && !look->shaped &&
	       look->opaque == VIS_OPAQUE_ALL;
}

bool vis_look_cuts_inside(const struct vis_look *look)
{
	return look->shaped || look->opaque == VIS_OPAQUE_RECTS;
}

const char *vis_look_check(struct vis_rect rect, const struct vis_look *look)
{
	if (look->border < 0)
		return "negative border";
	if (look->input_only && (look->border != 0 || look->shaped ||
				 look->opaque != VIS_OPAQUE_ALL))
		return "an input-only window has no border, shape or opaque region";
	if (look->opaque > VIS_OPAQUE_RECTS)
		return "unknown opaque mode";
	if ((int64_t)rect.w + 2 * (int64_t)look->border > INT32_MAX ||
	    (int64_t)rect.h + 2 * (int64_t)look->border > INT32_MAX)
		return "border box wider or taller than 2147483647";
	if (vis_look_cuts_inside(look) &&
	    ((int64_t)rect.x + rect.w + 2 * (int64_t)look->border > (int64_t)INT32_MAX + 1 ||
	     (int64_t)rect.y + rect.h + 2 * (int64_t)look->border > (int64_t)INT32_MAX + 1))
		return "a shaped window must end within the 32-bit plane (at 2147483648)";
	return NULL;
}

/* Grows the piece arrays for at least one more piece. */
static int pieces_grow(struct vis_pieces *p)
{
	size_t cap = p->cap ? 2 * p->cap : 64;
	if (cap > UINT32_MAX || cap > SIZE_MAX / sizeof(struct vis_rect)) {
		errno = EOVERFLOW;
		return -1;
	}
	struct vis_rect *rects = realloc(p->rects, cap * sizeof(*rects));
	if (rects == NULL)
		return -1;
	p->rects = rects;
	uint8_t *st = realloc(p->see_through, cap);
	if (st == NULL)
		return -1;
	p->see_through = st;
	uint32_t *window = realloc(p->window, cap * sizeof(*window));
	if (window == NULL)
		return -1;
	p->window = window;
	p->cap = cap;
	return 0;
}

static int push(struct vis_pieces *p, struct vis_rect r, bool see_through, size_t window)
{
	if (p->stack.n == p->cap && pieces_grow(p) < 0)
		return -1;
	p->rects[p->stack.n] = r;
	p->see_through[p->stack.n] = see_through;
	p->window[p->stack.n] = (uint32_t)window;
	p->stack.n++;
	return 0;
}

/* Adds a box relative to (ox, oy) as one piece. */
static int push_region_box(struct vis_pieces *p, struct vis_box r, int64_t ox, int64_t oy,
			   bool see_through, uint32_t window)
{
	int64_t x1 = ox + r.x1, y1 = oy + r.y1;
	if (x1 < INT32_MIN || y1 < INT32_MIN || x1 > INT32_MAX || y1 > INT32_MAX ||
	    r.x2 - r.x1 > INT32_MAX || r.y2 - r.y1 > INT32_MAX) {
		errno = EOVERFLOW;
		return -1;
	}
	return push(p, (struct vis_rect){ (int32_t)x1, (int32_t)y1, (int32_t)(r.x2 - r.x1),
					  (int32_t)(r.y2 - r.y1) }, see_through, window);
}

/*
 * The edges of one window's boxes (border-box coordinates, clipped, non-empty), sorted and unique,
 * for the rank map.
 */
struct edges {
	int64_t *x, *y;
	size_t nx, ny;
};

static int cmp64(const void *a, const void *b)
{
	int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
	return (x > y) - (x < y);
}

/*
 * Sorts v and drops repeats, returning how many are left. A look's edges are few (a rounded corner
 * has a few dozen), where qsort's calls through a comparator cost most of the cutting: insertion
 * sort for those.
 */
static size_t unique(int64_t *v, size_t n)
{
	if (n <= 64) {
		for (size_t i = 1; i < n; i++) {
			int64_t x = v[i];
			size_t j = i;
			for (; j > 0 && v[j - 1] > x; j--)
				v[j] = v[j - 1];
			v[j] = x;
		}
	} else {
		qsort(v, n, sizeof(*v), cmp64);
	}
	size_t k = 0;
	for (size_t i = 0; i < n; i++) {
		if (k == 0 || v[k - 1] != v[i])
			v[k++] = v[i];
	}
	return k;
}

static int32_t rank(const int64_t *v, size_t n, int64_t x)
{
	size_t lo = 0, hi = n;
	while (hi - lo > 1) {
		size_t mid = lo + (hi - lo) / 2;
		if (v[mid] <= x)
			lo = mid;
		else
			hi = mid;
	}
	return (int32_t)lo;
}

/* A rectangle in window coordinates as a box in border-box coordinates, clipped to limit. */
static struct vis_box to_box(struct vis_rect r, int32_t border, struct vis_box limit)
{
	struct vis_box b = vis_rect_box(r);
	b.x1 += border;
	b.x2 += border;
	b.y1 += border;
	b.y2 += border;
	return vis_box_intersect(b, limit);
}

/*
 * Builds a pixman region on the ranks from the boxes box_of(k) gives for k < n (border-box
 * coordinates, clipped; empty ones skipped): a look's rectangles, or the boxes that clip it.
 */
static int ranked_region(pixman_region32_t *reg, size_t n,
			 struct vis_box (*box_of)(const void *src, size_t k, const void *arg),
			 const void *src, const void *arg, const struct edges *e)
{
	pixman_box32_t *boxes = malloc((n ? n : 1) * sizeof(*boxes));
	size_t k = 0;
	if (boxes == NULL) {
		errno = ENOMEM;
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_box b = box_of(src, i, arg);
		if (vis_box_empty(b))
			continue;
		boxes[k++] = (pixman_box32_t){ rank(e->x, e->nx, b.x1), rank(e->y, e->ny, b.y1),
					       rank(e->x, e->nx, b.x2), rank(e->y, e->ny, b.y2) };
	}
	bool ok = pixman_region32_init_rects(reg, boxes, (int)k);
	free(boxes);
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

/* Where a look's rectangles go: in the border box of a window with this border, within limit. */
struct rect_frame {
	int32_t border;
	struct vis_box limit;
};

static struct vis_box rect_box_of(const void *src, size_t k, const void *arg)
{
	const struct rect_frame *f = arg;
	return to_box(((const struct vis_rect *)src)[k], f->border, f->limit);
}

/* Builds a pixman region (rank space) from the boxes of rects clipped to limit. */
static int region_of(pixman_region32_t *reg, const struct vis_rect *rects, size_t n,
		     int32_t border, struct vis_box limit, const struct edges *e)
{
	struct rect_frame f = { border, limit };
	return ranked_region(reg, n, rect_box_of, rects, &f, e);
}

/* Adds a region's boxes (rank space, relative to the border box at ox, oy) as pieces. */
static int push_region(struct vis_pieces *p, pixman_region32_t *reg, const struct edges *e,
		       int64_t ox, int64_t oy, bool see_through, uint32_t window)
{
	int n;
	const pixman_box32_t *b = pixman_region32_rectangles(reg, &n);
	for (int k = 0; k < n; k++) {
		int64_t x1 = ox + e->x[b[k].x1], x2 = ox + e->x[b[k].x2];
		int64_t y1 = oy + e->y[b[k].y1], y2 = oy + e->y[b[k].y2];
		if (x1 < INT32_MIN || y1 < INT32_MIN || x1 > INT32_MAX || y1 > INT32_MAX ||
		    x2 - x1 > INT32_MAX || y2 - y1 > INT32_MAX) {
			errno = EOVERFLOW;
			return -1;
		}
		struct vis_rect r = { (int32_t)x1, (int32_t)y1, (int32_t)(x2 - x1), (int32_t)(y2 - y1) };
		if (push(p, r, see_through, window) < 0)
			return -1;
	}
	return 0;
}

/* Adds the edges of a box (non-empty) to the rank map's lists. */
static void add_edges(struct edges *e, struct vis_box b)
{
	e->x[e->nx++] = b.x1;
	e->x[e->nx++] = b.x2;
	e->y[e->ny++] = b.y1;
	e->y[e->ny++] = b.y2;
}

int vis_pieces_add(struct vis_pieces *p, const struct vis_look *look, struct vis_box abs,
		   struct vis_box clip, uint32_t window)
{
	return vis_pieces_add_within(p, look, abs, clip, NULL, 0, window);
}

/* Where boxes that clip a window go: relative to its border box at abs, within limit. */
struct box_frame {
	struct vis_box abs, limit;
};

/* An absolute box in border-box coordinates, clipped to limit. */
static struct vis_box relative(struct vis_box b, const struct box_frame *f)
{
	return vis_box_intersect((struct vis_box){ b.x1 - f->abs.x1, b.y1 - f->abs.y1,
						   b.x2 - f->abs.x1, b.y2 - f->abs.y1 },
				 f->limit);
}

static struct vis_box within_box_of(const void *src, size_t k, const void *arg)
{
	return relative(((const struct vis_box *)src)[k], arg);
}

int vis_pieces_add_within(struct vis_pieces *p, const struct vis_look *look, struct vis_box abs,
			  struct vis_box clip, const struct vis_box *within, size_t n_within,
			  uint32_t window)
{
	static const struct vis_look plain = { 0 };
	if (look == NULL)
		look = &plain;
	if (look->input_only || vis_box_empty(abs))
		return 0;
	/* Border-box coordinates: the box is [0, W) × [0, H), the clip's part of it is limit. */
	struct vis_box bb = { 0, 0, abs.x2 - abs.x1, abs.y2 - abs.y1 };
	struct vis_box limit = vis_box_intersect(
		(struct vis_box){ clip.x1 - abs.x1, clip.y1 - abs.y1, clip.x2 - abs.x1,
				  clip.y2 - abs.y1 }, bb);
	if (!vis_look_cuts_inside(look) && within == NULL) {
		/* The border box, or what the clip leaves of it: one piece. */
		if (!vis_box_empty(limit) &&
		    push_region_box(p, limit, abs.x1, abs.y1, look->opaque == VIS_OPAQUE_NONE,
				    window) < 0)
			return -1;
		return !vis_box_contains(limit, bb);
	}
	int32_t b = look->border;
	struct vis_rect whole = { -b, -b, (int32_t)bb.x2, (int32_t)bb.y2 };
	const struct vis_rect *shape = look->shaped ? look->shape : &whole;
	size_t ns = look->shaped ? look->n_shape : 1;
	size_t no = look->opaque == VIS_OPAQUE_RECTS ? look->n_opaque : 0;
	struct edges e = { 0 };
	pixman_region32_t s, in, o, t;
	int ret = -1;

	if (within == NULL)
		n_within = 0;
	if (ns + no > SIZE_MAX / 4 / sizeof(int64_t) - 2 ||
	    n_within > SIZE_MAX / 4 / sizeof(int64_t) - 2) {
		errno = EOVERFLOW;
		return -1;
	}
	e.x = malloc((2 * (ns + no + n_within) + 2) * sizeof(int64_t));
	e.y = malloc((2 * (ns + no + n_within) + 2) * sizeof(int64_t));
	if (e.x == NULL || e.y == NULL) {
		free(e.x);
		free(e.y);
		errno = ENOMEM;
		return -1;
	}
	for (size_t k = 0; k < ns + no; k++) {
		struct vis_box r = to_box(k < ns ? shape[k] : look->opaque_rects[k - ns], b, bb);
		if (!vis_box_empty(r))
			add_edges(&e, r);
	}
	if (!vis_box_empty(limit))
		add_edges(&e, limit);
	struct box_frame frame = { abs, limit };
	for (size_t k = 0; k < n_within; k++) {
		struct vis_box r = relative(within[k], &frame);
		if (!vis_box_empty(r))
			add_edges(&e, r);
	}
	e.nx = unique(e.x, e.nx);
	e.ny = unique(e.y, e.ny);

	pixman_region32_init(&in);
	pixman_region32_init(&o);
	pixman_region32_init(&t);
	if (region_of(&s, shape, ns, b, bb, &e) < 0)
		goto out;
	/* The shape inside the clip; the clip cut the window if that is less than the shape. */
	if (!vis_box_empty(limit)) {
		pixman_box32_t lb = { rank(e.x, e.nx, limit.x1), rank(e.y, e.ny, limit.y1),
				      rank(e.x, e.nx, limit.x2), rank(e.y, e.ny, limit.y2) };
		pixman_region32_fini(&in);
		pixman_region32_init_with_extents(&in, &lb);
		if (!pixman_region32_intersect(&in, &in, &s)) {
			errno = ENOMEM;
			goto out_s;
		}
		/* And inside the region that clips it further (a shaped ancestor's). */
		if (within != NULL) {
			pixman_region32_t w;
			if (ranked_region(&w, n_within, within_box_of, within, &frame, &e) < 0)
				goto out_s;
			bool ok = pixman_region32_intersect(&in, &in, &w);
			pixman_region32_fini(&w);
			if (!ok) {
				errno = ENOMEM;
				goto out_s;
			}
		}
	}
	/* Empty regions may differ in their extents: compare only a shape with pixels. */
	bool was_cut = pixman_region32_not_empty(&s) && !pixman_region32_equal(&in, &s);
	switch (look->opaque) {
	case VIS_OPAQUE_ALL:
		if (push_region(p, &in, &e, abs.x1, abs.y1, false, window) < 0)
			goto out_s;
		break;
	case VIS_OPAQUE_NONE:
		if (push_region(p, &in, &e, abs.x1, abs.y1, true, window) < 0)
			goto out_s;
		break;
	default:
		pixman_region32_fini(&o);
		if (region_of(&o, look->opaque_rects, no, b, bb, &e) < 0) {
			pixman_region32_init(&o);
			goto out_s;
		}
		if (!pixman_region32_intersect(&o, &o, &in) || !pixman_region32_subtract(&t, &in, &o)) {
			errno = ENOMEM;
			goto out_s;
		}
		if (push_region(p, &o, &e, abs.x1, abs.y1, false, window) < 0 ||
		    push_region(p, &t, &e, abs.x1, abs.y1, true, window) < 0)
			goto out_s;
	}
	ret = was_cut;
out_s:
	pixman_region32_fini(&s);
out:
	pixman_region32_fini(&in);
	pixman_region32_fini(&o);
	pixman_region32_fini(&t);
	free(e.x);
	free(e.y);
	return ret;
}

int vis_look_cut_fill(struct vis_look_cut *cut, const struct vis_look *look, int32_t width,
		      int32_t height)
{
	/* The pieces of the window with its border box at the origin, unclipped: vis_pieces_add()
	 * puts the opaque ones first. The border box's sides fit in 31 bits, and so do the pieces. */
	struct vis_box bb = { 0, 0, (int64_t)width + 2 * (int64_t)look->border,
			      (int64_t)height + 2 * (int64_t)look->border };
	struct vis_pieces tmp = { 0 };
	vis_look_cut_finish(cut);
	int rc = vis_pieces_add(&tmp, look, bb, bb, 0);
	uint32_t opaque = 0;
	while (rc >= 0 && opaque < tmp.stack.n && !tmp.see_through[opaque])
		opaque++;
	free(tmp.see_through);
	free(tmp.window);
	cut->rects = tmp.rects;
	if (rc < 0)
		return -1;
	cut->n = (uint32_t)tmp.stack.n;
	cut->n_opaque = opaque;
#ifndef NDEBUG
	/* Each run banded (look.h): bands in order, a band's rectangles sharing top and bottom. */
	for (uint32_t k = 1; k < cut->n; k++) {
		struct vis_rect a = cut->rects[k - 1], b = cut->rects[k];
		assert(k == opaque || (a.y == b.y && a.h == b.h && a.x + a.w <= b.x) ||
		       a.y + a.h <= b.y);
	}
#endif
	cut->border = look->border;
	cut->width = width;
	cut->height = height;
	return 0;
}

void vis_look_cut_finish(struct vis_look_cut *cut)
{
	free(cut->rects);
	*cut = (struct vis_look_cut){ 0 };
}

int vis_pieces_add_cut(struct vis_pieces *p, const struct vis_look_cut *cut, struct vis_box abs,
		       struct vis_box clip, uint32_t window)
{
	bool was_cut = false;
	for (uint32_t k = 0; k < cut->n; k++) {
		struct vis_rect r = cut->rects[k];
		struct vis_box whole = { abs.x1 + r.x, abs.y1 + r.y, abs.x1 + r.x + r.w,
					 abs.y1 + r.y + r.h };
		struct vis_box b = vis_box_intersect(whole, clip);
		if (vis_box_empty(b)) {
			was_cut = true;
			continue;
		}
		was_cut |= !vis_box_equal(b, whole);
		if (push_region_box(p, (struct vis_box){ 0, 0, b.x2 - b.x1, b.y2 - b.y1 }, b.x1,
				    b.y1, k >= cut->n_opaque, window) < 0)
			return -1;
	}
	return was_cut;
}

int vis_look_translucent(const struct vis_look *look, int32_t width, int32_t height)
{
	if (look->input_only)
		return 0;
	if (!vis_look_cuts_inside(look))
		return look->opaque == VIS_OPAQUE_NONE; /* its whole border box, of one mode */
	struct vis_look_cut cut = { 0 };
	if (vis_look_cut_fill(&cut, look, width, height) < 0)
		return -1;
	int rc = vis_look_cut_translucent(&cut);
	vis_look_cut_finish(&cut);
	return rc;
}

int vis_pieces_init(struct vis_pieces *p, const struct vis_stack *windows)
{
	memset(p, 0, sizeof(*p));
	p->stack.has_screen = windows->has_screen;
	p->stack.screen_w = windows->screen_w;
	p->stack.screen_h = windows->screen_h;
	if (windows->n > UINT32_MAX) {
		errno = EOVERFLOW;
		return -1;
	}
	for (size_t i = 0; i < windows->n; i++) {
		struct vis_rect r = windows->rects[i];
		const struct vis_look *look = windows->looks ? &windows->looks[i] : NULL;
		int rc;

		if (look == NULL || vis_look_plain(look)) {
			rc = push(p, r, !vis_stack_opaque(windows, i), i);
		} else if (vis_look_check(r, look) != NULL) {
			errno = EINVAL;
			rc = -1;
		} else {
			/* Unclipped: the engines clip to the screen themselves. */
			struct vis_box bb = vis_rect_box(r);
			bb.x2 += 2 * (int64_t)look->border;
			bb.y2 += 2 * (int64_t)look->border;
			rc = vis_pieces_add(p, look, bb, bb, (uint32_t)i);
		}
		if (rc < 0) {
			vis_pieces_finish(p);
			return -1;
		}
	}
	p->stack.rects = p->rects;
	p->stack.see_through = p->see_through;
	return 0;
}

void vis_pieces_reset(struct vis_pieces *p)
{
	p->stack.n = 0;
}

void vis_pieces_finish(struct vis_pieces *p)
{
	free(p->rects);
	free(p->see_through);
	free(p->window);
	memset(p, 0, sizeof(*p));
}

void vis_pieces_join(const struct vis_pieces *p, const struct vis_stack *windows,
		     const uint8_t *piece_states, uint8_t *states)
{
	/* Bits of the states met: a window with none met has no pixels. */
	for (size_t i = 0; i < windows->n; i++)
		states[i] = 0;
	for (size_t k = 0; k < p->stack.n; k++)
		states[p->window[k]] |= (uint8_t)(1u << piece_states[k]);
	for (size_t i = 0; i < windows->n; i++) {
		uint8_t met = states[i];
		if (windows->looks != NULL && windows->looks[i].input_only)
			states[i] = VIS_NO_STATE;
		else if (met == 0 || met == 1u << VIS_FULLY_OBSCURED)
			states[i] = VIS_FULLY_OBSCURED;
		else if (met == 1u << VIS_UNOBSCURED)
			states[i] = VIS_UNOBSCURED;
		else
			states[i] = VIS_PARTIALLY_OBSCURED;
	}
}
