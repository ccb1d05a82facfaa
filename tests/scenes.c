/*
 * Nasty scenes. Each nasty kind is a screen choice plus a weighting of window "styles"; a style
 * pushes one window, or a few (a cover), chosen to make edges coincide: the engines' bugs live
 * where edges are equal, not where they are random.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"
#include "rng.h"
#include "scenes.h"

enum style {
	STYLE_LATTICE, /* edges on a coarse lattice */
	STYLE_DUP,     /* a copy of an earlier window */
	STYLE_COVER,   /* pieces covering an earlier window exactly, or all but one pixel */
	STYLE_TINY,    /* a 1×1 window at or beside an earlier window's corner */
	STYLE_EDGE,    /* placed against the screen's edges */
	STYLE_LIMIT,   /* edges near the int32 limits */
	STYLE_SNAP,    /* edges copied from earlier windows, ±1 */
	STYLE_SMALL,   /* small random window around the frame */
	STYLE_COUNT,
};

enum screen_choice {
	SCREEN_NONE,
	SCREEN_TINY,   /* 3×2 … 8×8 */
	SCREEN_MEDIUM, /* 16 … 96 */
	SCREEN_HUGE,   /* INT32_MAX × INT32_MAX or so */
	SCREEN_ANY,
};

struct nasty {
	const char *name;
	enum screen_choice screen;
	unsigned weight[STYLE_COUNT]; /* in the order of enum style */
};

static const struct nasty nasties[SCENES_KIND_COUNT - VIS_GEN_KIND_COUNT] = {
	/*                                       lat dup cov tiny edge lim snap small */
	{ "dup", SCREEN_ANY, { 3, 6, 0, 0, 0, 0, 1, 0 } },
	{ "abut", SCREEN_ANY, { 6, 0, 0, 0, 0, 0, 4, 0 } },
	{ "cover", SCREEN_ANY, { 3, 1, 5, 0, 0, 0, 2, 0 } },
	{ "tiny", SCREEN_ANY, { 2, 1, 0, 6, 0, 0, 1, 1 } },
	{ "edge", SCREEN_MEDIUM, { 1, 1, 2, 1, 6, 0, 2, 0 } },
	{ "limits", SCREEN_HUGE, { 0, 1, 1, 1, 0, 6, 2, 0 } },
	{ "tinyscreen", SCREEN_TINY, { 1, 1, 2, 2, 2, 0, 2, 4 } },
	{ "mix", SCREEN_ANY, { 2, 2, 3, 2, 2, 1, 3, 1 } },
	{ "looks", SCREEN_ANY, { 2, 2, 3, 2, 2, 1, 3, 1 } }, /* mix, then each window a look */
};

/* A scene under construction, and the frame its windows are drawn around. */
struct maker {
	struct vis_rng rng;
	struct vis_scene *scene;
	size_t n;         /* windows wanted */
	int64_t fw, fh;   /* the frame: the screen, or a virtual one without a screen */
	int64_t step;     /* the lattice step */
	bool far;         /* the frame is huge: lattice edges reach the int32 limits */
	bool failed;      /* vis_scene_push() ran out of memory */
};

const char *scenes_kind_name(unsigned kind)
{
	if (kind < VIS_GEN_KIND_COUNT)
		return vis_gen_kind_name((enum vis_gen_kind)kind);
	if (kind < SCENES_KIND_COUNT)
		return nasties[kind - VIS_GEN_KIND_COUNT].name;
	return "invalid";
}

int scenes_kind_from_name(const char *name, unsigned *kind)
{
	for (unsigned k = 0; k < SCENES_KIND_COUNT; k++) {
		if (strcmp(name, scenes_kind_name(k)) == 0) {
			*kind = k;
			return 0;
		}
	}
	return -1;
}

/* Pushes the box [x1, x2) × [y1, y2) when it is a valid window; returns whether it did. */
static bool push_box(struct maker *m, int64_t x1, int64_t y1, int64_t x2, int64_t y2)
{
	if (m->scene->n >= m->n)
		return false;
	if (x1 < INT32_MIN || x1 > INT32_MAX || y1 < INT32_MIN || y1 > INT32_MAX)
		return false;
	if (x2 - x1 < 1 || x2 - x1 > INT32_MAX || y2 - y1 < 1 || y2 - y1 > INT32_MAX)
		return false;
	struct vis_rect r = { (int32_t)x1, (int32_t)y1, (int32_t)(x2 - x1), (int32_t)(y2 - y1) };
	if (vis_scene_push(m->scene, (uint32_t)m->scene->n + 1, r) != 0) {
		m->failed = true;
		return false;
	}
	return true;
}

/* Pushes a box given as a vis_box. */
static bool push(struct maker *m, struct vis_box b)
{
	return push_box(m, b.x1, b.y1, b.x2, b.y2);
}

/* An earlier window's box, chosen at random; false when there is none. */
static bool pick(struct maker *m, struct vis_box *b)
{
	if (m->scene->n == 0)
		return false;
	*b = vis_rect_box(m->scene->rects[vis_rng_below(&m->rng, m->scene->n)]);
	return true;
}

/* A small offset, mostly zero: snapping keeps edges equal or one apart. */
static int64_t jitter(struct maker *m)
{
	static const int64_t d[] = { 0, 0, 0, 0, 1, -1 };
	return d[vis_rng_below(&m->rng, sizeof d / sizeof d[0])];
}

/* A window whose edges lie on the lattice around the frame. */
static void style_lattice(struct maker *m)
{
	int64_t kx = m->fw / m->step, ky = m->fh / m->step;
	int64_t x1 = vis_rng_range(&m->rng, -2, kx + 1), y1 = vis_rng_range(&m->rng, -2, ky + 1);
	int64_t x2 = x1 + vis_rng_range(&m->rng, 1, kx / 2 + 2);
	int64_t y2 = y1 + vis_rng_range(&m->rng, 1, ky / 2 + 2);
	int64_t base = m->far ? INT32_MAX - m->fw : 0;

	if (m->far && vis_rng_below(&m->rng, 2))
		base = INT32_MIN;
	push_box(m, base + x1 * m->step, base + y1 * m->step, base + x2 * m->step,
		 base + y2 * m->step);
}

/* A small random window in or around the frame. */
static void style_small(struct maker *m)
{
	int64_t x1 = vis_rng_range(&m->rng, -3, m->fw + 2);
	int64_t y1 = vis_rng_range(&m->rng, -3, m->fh + 2);
	int64_t w = vis_rng_range(&m->rng, 1, m->fw + 4);
	int64_t h = vis_rng_range(&m->rng, 1, m->fh + 4);
	push_box(m, x1, y1, x1 + w, y1 + h);
}

/* A copy of an earlier window, sometimes several copies in a row. */
static void style_dup(struct maker *m)
{
	struct vis_box b;
	if (!pick(m, &b)) {
		style_lattice(m);
		return;
	}
	for (uint64_t k = vis_rng_range(&m->rng, 1, 3); k > 0; k--)
		push(m, b);
}

/* Pushes piece minus the pixel (px, py) when piece holds it, else piece itself. */
static void push_without(struct maker *m, struct vis_box p, int64_t px, int64_t py)
{
	if (px < p.x1 || px >= p.x2 || py < p.y1 || py >= p.y2) {
		push(m, p);
		return;
	}
	/* Four abutting pieces around the hole: more shared edges for the engines to get right. */
	push_box(m, p.x1, p.y1, px, p.y2);
	push_box(m, px + 1, p.y1, p.x2, p.y2);
	push_box(m, px, p.y1, px + 1, py);
	push_box(m, px, py + 1, px + 1, p.y2);
}

/* A point strictly inside (lo, hi), or lo when there is none. */
static int64_t split(struct maker *m, int64_t lo, int64_t hi)
{
	return hi - lo >= 2 ? vis_rng_range(&m->rng, lo + 1, hi - 1) : lo;
}

/*
 * Pieces that cover an earlier window (or its on-screen part) exactly: split in x, in y, 2×2 or
 * L-shaped, pushed in random order, some stretched outwards. Half the time one pixel is left free.
 */
static void style_cover(struct maker *m)
{
	struct vis_box t, p[4];
	size_t k;

	if (!pick(m, &t)) {
		style_lattice(m);
		return;
	}
	if (m->scene->has_screen && vis_rng_below(&m->rng, 2)) {
		struct vis_box s = { 0, 0, m->scene->screen_w, m->scene->screen_h };
		t = vis_box_intersect(t, s);
		if (vis_box_empty(t))
			return;
	}
	int64_t xm = split(m, t.x1, t.x2), ym = split(m, t.y1, t.y2);
	switch (vis_rng_below(&m->rng, 4)) {
	case 0: /* split in x */
		p[0] = (struct vis_box){ t.x1, t.y1, xm, t.y2 };
		p[1] = (struct vis_box){ xm, t.y1, t.x2, t.y2 };
		k = 2;
		break;
	case 1: /* split in y */
		p[0] = (struct vis_box){ t.x1, t.y1, t.x2, ym };
		p[1] = (struct vis_box){ t.x1, ym, t.x2, t.y2 };
		k = 2;
		break;
	case 2: /* 2×2 */
		p[0] = (struct vis_box){ t.x1, t.y1, xm, ym };
		p[1] = (struct vis_box){ xm, t.y1, t.x2, ym };
		p[2] = (struct vis_box){ t.x1, ym, xm, t.y2 };
		p[3] = (struct vis_box){ xm, ym, t.x2, t.y2 };
		k = 4;
		break;
	default: /* L-shaped: a tall left piece, the rest in two */
		p[0] = (struct vis_box){ t.x1, t.y1, xm, t.y2 };
		p[1] = (struct vis_box){ xm, t.y1, t.x2, ym };
		p[2] = (struct vis_box){ xm, ym, t.x2, t.y2 };
		k = 3;
		break;
	}
	/* Stretch some outer edges outwards: the cover stays exact inside t. */
	for (size_t i = 0; i < k; i++) {
		if (vis_rng_below(&m->rng, 4) == 0 && p[i].x1 == t.x1)
			p[i].x1 -= vis_rng_range(&m->rng, 1, 3);
		if (vis_rng_below(&m->rng, 4) == 0 && p[i].y2 == t.y2)
			p[i].y2 += vis_rng_range(&m->rng, 1, 3);
	}
	for (size_t i = k; i > 1; i--) {
		size_t j = vis_rng_below(&m->rng, i);
		struct vis_box tmp = p[i - 1];
		p[i - 1] = p[j];
		p[j] = tmp;
	}
	if (vis_rng_below(&m->rng, 2)) {
		int64_t px = vis_rng_range(&m->rng, t.x1, t.x2 - 1);
		int64_t py = vis_rng_range(&m->rng, t.y1, t.y2 - 1);
		for (size_t i = 0; i < k; i++)
			push_without(m, p[i], px, py);
	} else {
		for (size_t i = 0; i < k; i++)
			push(m, p[i]);
	}
}

/* A 1×1 window at, inside or just outside an earlier window's corner. */
static void style_tiny(struct maker *m)
{
	struct vis_box b;
	int64_t x, y;

	if (!pick(m, &b) || vis_rng_below(&m->rng, 4) == 0) {
		x = vis_rng_range(&m->rng, -1, m->fw);
		y = vis_rng_range(&m->rng, -1, m->fh);
	} else {
		/* One random draw a statement: argument and operand order is unspecified in C. */
		x = vis_rng_below(&m->rng, 2) ? b.x1 : b.x2 - 1;
		x += jitter(m);
		y = vis_rng_below(&m->rng, 2) ? b.y1 : b.y2 - 1;
		y += jitter(m);
	}
	push_box(m, x, y, x + 1, y + 1);
}

/* One edge placed against the frame [0, size): outside, touching, on it, or ending at it. */
static void edge_span(struct maker *m, int64_t size, int64_t *lo, int64_t *hi)
{
	int64_t len;

	switch (vis_rng_below(&m->rng, 4)) {
	case 0:
		len = size;
		break;
	case 1:
		len = 1;
		break;
	case 2:
		len = size + vis_rng_range(&m->rng, 1, 3);
		break;
	default:
		len = vis_rng_range(&m->rng, 1, size);
		break;
	}
	const int64_t starts[] = { 0, 0, -len, -len - 1, -len + 1, -1, 1,
				   size - len, size - len + 1, size - 1, size, size + 1 };
	*lo = starts[vis_rng_below(&m->rng, sizeof starts / sizeof starts[0])];
	*hi = *lo + len;
}

/* A window against the screen's edges: off it, touching it from outside, or ending at W/H. */
static void style_edge(struct maker *m)
{
	int64_t x1, x2, y1, y2;

	edge_span(m, m->fw, &x1, &x2);
	edge_span(m, m->fh, &y1, &y2);
	if (vis_rng_below(&m->rng, 8) == 0) {
		x1 = y1 = 0;
		x2 = m->fw;
		y2 = m->fh;
	}
	push_box(m, x1, y1, x2, y2);
}

/* One span with ends near the int32 limits. */
static void limit_span(struct maker *m, int64_t *lo, int64_t *hi)
{
	static const int64_t ends[] = {
		INT32_MIN, (int64_t)INT32_MIN + 1, (int64_t)INT32_MIN + 2, -(1ll << 30) - 1,
		-(1ll << 30), -1, 0, 1, 1ll << 30, (1ll << 30) + 1, (int64_t)INT32_MAX - 1,
		INT32_MAX, (int64_t)INT32_MAX + 1, (int64_t)INT32_MAX + 2, (1ll << 32) - 3,
		(1ll << 32) - 2,
	};
	const size_t k = sizeof ends / sizeof ends[0];

	for (int tries = 0; tries < 16; tries++) {
		*lo = ends[vis_rng_below(&m->rng, k)];
		switch (vis_rng_below(&m->rng, 4)) {
		case 0:
			*hi = *lo + INT32_MAX;
			break;
		case 1:
			*hi = *lo + vis_rng_range(&m->rng, 1, 3);
			break;
		default:
			*hi = ends[vis_rng_below(&m->rng, k)];
			break;
		}
		if (*lo <= INT32_MAX && *hi > *lo && *hi - *lo <= INT32_MAX)
			return;
	}
	*lo = INT32_MIN;
	*hi = 0;
}

/* A window with edges near the int32 limits. */
static void style_limit(struct maker *m)
{
	int64_t x1, x2, y1, y2;

	limit_span(m, &x1, &x2);
	if (vis_rng_below(&m->rng, 3) == 0) {
		y1 = vis_rng_range(&m->rng, -2, 2);
		y2 = y1 + vis_rng_range(&m->rng, 1, 3);
	} else {
		limit_span(m, &y1, &y2);
	}
	push_box(m, x1, y1, x2, y2);
}

/* A window whose edges are those of earlier windows, give or take one. */
static void style_snap(struct maker *m)
{
	struct vis_box a, b;

	if (!pick(m, &a) || !pick(m, &b)) {
		style_lattice(m);
		return;
	}
	int64_t xs[] = { a.x1, a.x2, b.x1, b.x2 }, ys[] = { a.y1, a.y2, b.y1, b.y2 };
	int64_t x1 = xs[vis_rng_below(&m->rng, 4)];
	x1 += jitter(m);
	int64_t x2 = xs[vis_rng_below(&m->rng, 4)];
	x2 += jitter(m);
	int64_t y1 = ys[vis_rng_below(&m->rng, 4)];
	y1 += jitter(m);
	int64_t y2 = ys[vis_rng_below(&m->rng, 4)];
	y2 += jitter(m);
	push_box(m, x1 < x2 ? x1 : x2, y1 < y2 ? y1 : y2, x1 < x2 ? x2 : x1, y1 < y2 ? y2 : y1);
}

static void (*const styles[STYLE_COUNT])(struct maker *) = {
	[STYLE_LATTICE] = style_lattice, [STYLE_DUP] = style_dup,   [STYLE_COVER] = style_cover,
	[STYLE_TINY] = style_tiny,       [STYLE_EDGE] = style_edge, [STYLE_LIMIT] = style_limit,
	[STYLE_SNAP] = style_snap,       [STYLE_SMALL] = style_small,
};

/* Chooses the screen (or the virtual frame without one) for a nasty scene. */
static void choose_screen(struct maker *m, enum screen_choice choice)
{
	struct vis_scene *s = m->scene;

	if (choice == SCREEN_ANY)
		choice = (enum screen_choice)vis_rng_below(&m->rng, SCREEN_ANY);
	s->has_screen = true;
	m->far = false;
	switch (choice) {
	case SCREEN_NONE:
		s->has_screen = false;
		m->fw = vis_rng_range(&m->rng, 8, 64);
		m->fh = vis_rng_range(&m->rng, 8, 64);
		break;
	case SCREEN_TINY:
		m->fw = vis_rng_range(&m->rng, 3, 8);
		m->fh = vis_rng_range(&m->rng, 2, 8);
		break;
	case SCREEN_MEDIUM:
		m->fw = vis_rng_range(&m->rng, 16, 96);
		m->fh = vis_rng_range(&m->rng, 16, 96);
		break;
	case SCREEN_HUGE:
	case SCREEN_ANY:
		/* Mostly no screen, as the limits matter most unclipped. */
		s->has_screen = vis_rng_below(&m->rng, 3) == 0;
		m->fw = INT32_MAX - vis_rng_below(&m->rng, 2);
		m->fh = INT32_MAX - vis_rng_below(&m->rng, 2);
		m->far = true;
		break;
	}
	s->screen_w = s->has_screen ? (int32_t)m->fw : 0;
	s->screen_h = s->has_screen ? (int32_t)m->fh : 0;
	m->step = m->far ? 1 << 20 : (m->fw > 16 ? m->fw / 8 : 1);
}

/* Fills the scene with a nasty kind's windows. */
static int make_nasty(struct maker *m, const struct nasty *k)
{
	unsigned total = 0;

	choose_screen(m, k->screen);
	for (int s = 0; s < STYLE_COUNT; s++)
		total += k->weight[s];
	while (m->scene->n < m->n) {
		size_t before = m->scene->n;
		unsigned w = (unsigned)vis_rng_below(&m->rng, total);
		int s = 0;

		while (w >= k->weight[s])
			w -= k->weight[s++];
		styles[s](m);
		/* A style may find nothing valid to push; a plain 1×1 window always is. */
		if (m->scene->n == before && vis_rng_below(&m->rng, 4) == 0)
			push_box(m, 0, 0, 1, 1);
		if (m->failed) {
			errno = ENOMEM;
			return -1;
		}
	}
	return 0;
}

/*
 * Rectangles cutting the box (x, y, w, h) into abutting pieces: halves in x or y, quarters, or
 * the whole; with hole, one pixel is left out of the last piece (by shrinking it), if it can be.
 */
static struct vis_rect *cut_box(struct maker *m, int64_t x, int64_t y, int64_t w, int64_t h,
				bool hole, uint32_t *n)
{
	struct vis_rect *r = malloc(4 * sizeof(*r));
	if (r == NULL)
		return NULL;
	int64_t hw = w / 2, hh = h / 2;
	switch (vis_rng_below(&m->rng, 4)) {
	case 0:
		r[0] = (struct vis_rect){ (int32_t)x, (int32_t)y, (int32_t)w, (int32_t)h };
		*n = 1;
		break;
	case 1:
		if (hw == 0)
			goto whole;
		r[0] = (struct vis_rect){ (int32_t)x, (int32_t)y, (int32_t)hw, (int32_t)h };
		r[1] = (struct vis_rect){ (int32_t)(x + hw), (int32_t)y, (int32_t)(w - hw), (int32_t)h };
		*n = 2;
		break;
	case 2:
		if (hh == 0)
			goto whole;
		r[0] = (struct vis_rect){ (int32_t)x, (int32_t)y, (int32_t)w, (int32_t)hh };
		r[1] = (struct vis_rect){ (int32_t)x, (int32_t)(y + hh), (int32_t)w, (int32_t)(h - hh) };
		*n = 2;
		break;
	default:
		if (hw == 0 || hh == 0)
			goto whole;
		r[0] = (struct vis_rect){ (int32_t)x, (int32_t)y, (int32_t)hw, (int32_t)hh };
		r[1] = (struct vis_rect){ (int32_t)(x + hw), (int32_t)y, (int32_t)(w - hw), (int32_t)hh };
		r[2] = (struct vis_rect){ (int32_t)x, (int32_t)(y + hh), (int32_t)hw, (int32_t)(h - hh) };
		r[3] = (struct vis_rect){ (int32_t)(x + hw), (int32_t)(y + hh), (int32_t)(w - hw),
					  (int32_t)(h - hh) };
		*n = 4;
		break;
	whole:
		r[0] = (struct vis_rect){ (int32_t)x, (int32_t)y, (int32_t)w, (int32_t)h };
		*n = 1;
	}
	if (hole && r[*n - 1].w > 1)
		r[*n - 1].w--;
	return r;
}

/*
 * Gives every window of a scene a look whose edges coincide with its own and others': borders
 * of 0–2, shapes that cut the border box into abutting pieces (or all but one pixel of it, or
 * nothing), opaque regions cut the same way, translucent and input-only windows.
 */
static int add_looks(struct maker *m)
{
	struct vis_scene *s = m->scene;
	for (size_t i = 0; i < s->n; i++) {
		struct vis_rect r = s->rects[i];
		struct vis_look look = { 0 };
		uint64_t roll = vis_rng_below(&m->rng, 16);
		if (roll == 0) {
			look.input_only = true;
		} else if (roll > 3) {
			look.border = (int32_t)vis_rng_below(&m->rng, 3);
			if (vis_look_check(r, &look) != NULL)
				look.border = 0;
			int64_t b = look.border, bw = r.w + 2 * b, bh = r.h + 2 * b;
			struct vis_look cut = look;
			cut.shaped = true;
			bool can_cut = vis_look_check(r, &cut) == NULL;
			uint64_t shape = vis_rng_below(&m->rng, 6);
			if (can_cut && shape >= 3) {
				look.shaped = true;
				look.shape = shape == 3 ? NULL
							: cut_box(m, -b, -b, bw, bh, shape == 4, &look.n_shape);
				if (shape != 3 && look.shape == NULL)
					return -1;
			}
			uint64_t opaque = vis_rng_below(&m->rng, 5);
			if (opaque == 1) {
				look.opaque = VIS_OPAQUE_NONE;
			} else if (opaque >= 3 && can_cut) {
				look.opaque = VIS_OPAQUE_RECTS;
				look.opaque_rects = cut_box(m, -b, -b, bw, bh, opaque == 4, &look.n_opaque);
				if (look.opaque_rects == NULL)
					return -1;
			}
		}
		if (vis_look_plain(&look))
			continue;
		struct vis_look *to = vis_scene_look(s, i);
		if (to == NULL) {
			free(look.shape);
			free(look.opaque_rects);
			return -1;
		}
		*to = look;
	}
	return 0;
}

int scenes_make(struct vis_scene *scene, unsigned kind, size_t n, uint64_t seed)
{
	struct maker m = { .rng = { seed }, .scene = scene, .n = n };

	if (kind >= SCENES_KIND_COUNT) {
		errno = EINVAL;
		return -1;
	}
	if (kind < VIS_GEN_KIND_COUNT) {
		/* Now and then a smaller screen than the default, for more clipping. */
		int32_t w = seed % 4 == 3 ? 640 : 0, h = seed % 4 == 3 ? 480 : 0;
		return vis_gen(scene, (enum vis_gen_kind)kind, n, seed, w, h);
	}
	const struct nasty *k = &nasties[kind - VIS_GEN_KIND_COUNT];
	if (make_nasty(&m, k) < 0)
		return -1;
	if (strcmp(k->name, "looks") == 0 && add_looks(&m) < 0) {
		vis_scene_finish(scene);
		errno = ENOMEM;
		return -1;
	}
	return 0;
}
