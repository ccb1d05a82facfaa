/*
 * Borders, shapes, opaque regions and input-only windows (look.h) on every engine, against a
 * pixel painter written straight from the model's definition: a window's pixels are its shape's
 * rectangles clipped to its border box, its opaque pixels those inside its opaque region; a pixel
 * is visible when it is on the screen and no opaque pixel of a higher window covers it.
 * Seeded random scenes on a small grid (so that every pixel can be painted), the same scenes moved
 * next to the 32-bit limits (states do not change under a move without a screen), and the cases
 * of docs/ENGINES.md's exactness list in bordered, shaped and translucent variants, read from scene text.
 * A failure prints the seed and the scene; rerun one with `test-look --seed S`.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "engine.h"
#include "rng.h"
#include "scene.h"

/* Whether pixel (px, py) is one of the window's pixels, and whether it is an opaque one. */
static void pixel_of(struct vis_rect r, const struct vis_look *look, int64_t px, int64_t py,
		     bool *mine, bool *opaque)
{
	int64_t b = look ? look->border : 0;
	struct vis_box bb = { r.x, r.y, (int64_t)r.x + r.w + 2 * b, (int64_t)r.y + r.h + 2 * b };
	int64_t wx = px - r.x - b, wy = py - r.y - b; /* window coordinates */
	*mine = *opaque = false;
	if (look && look->input_only)
		return;
	if (px < bb.x1 || px >= bb.x2 || py < bb.y1 || py >= bb.y2)
		return;
	if (look && look->shaped) {
		for (uint32_t k = 0; k < look->n_shape && !*mine; k++) {
			struct vis_box s = vis_rect_box(look->shape[k]);
			*mine = wx >= s.x1 && wx < s.x2 && wy >= s.y1 && wy < s.y2;
		}
	} else {
		*mine = true;
	}
	if (!*mine)
		return;
	if (look == NULL || look->opaque == VIS_OPAQUE_ALL) {
		*opaque = true;
	} else if (look->opaque == VIS_OPAQUE_RECTS) {
		for (uint32_t k = 0; k < look->n_opaque && !*opaque; k++) {
			struct vis_box s = vis_rect_box(look->opaque_rects[k]);
			*opaque = wx >= s.x1 && wx < s.x2 && wy >= s.y1 && wy < s.y2;
		}
	}
}

/* A window's border box. */
static struct vis_box border_box(struct vis_rect r, const struct vis_look *look)
{
	int64_t b = look ? look->border : 0;
	return (struct vis_box){ r.x, r.y, (int64_t)r.x + r.w + 2 * b, (int64_t)r.y + r.h + 2 * b };
}

/* The painter: states of a scene whose windows lie within a few thousand pixels of each other. */
static void paint(const struct vis_scene *s, uint8_t *states)
{
	struct vis_box all = { INT64_MAX, INT64_MAX, INT64_MIN, INT64_MIN };
	for (size_t i = 0; i < s->n; i++) {
		struct vis_box b = border_box(s->rects[i], s->looks ? &s->looks[i] : NULL);
		all = (struct vis_box){ b.x1 < all.x1 ? b.x1 : all.x1, b.y1 < all.y1 ? b.y1 : all.y1,
					b.x2 > all.x2 ? b.x2 : all.x2, b.y2 > all.y2 ? b.y2 : all.y2 };
	}
	int64_t gw = all.x2 - all.x1, gh = all.y2 - all.y1;
	if (s->n == 0 || gw > 4096 || gh > 4096) {
		fprintf(stderr, "test-look: a scene too large to paint\n");
		exit(2);
	}
	/* owner: the highest window with an opaque pixel there, or -1. */
	int32_t *owner = malloc((size_t)(gw * gh) * sizeof(*owner));
	if (owner == NULL)
		exit(2);
	for (int64_t k = 0; k < gw * gh; k++)
		owner[k] = -1;
	for (size_t i = 0; i < s->n; i++) {
		const struct vis_look *look = s->looks ? &s->looks[i] : NULL;
		struct vis_box b = border_box(s->rects[i], look);
		for (int64_t py = b.y1; py < b.y2; py++)
			for (int64_t px = b.x1; px < b.x2; px++) {
				bool mine, opaque;
				pixel_of(s->rects[i], look, px, py, &mine, &opaque);
				if (opaque)
					owner[(py - all.y1) * gw + (px - all.x1)] = (int32_t)i;
			}
	}
	for (size_t i = 0; i < s->n; i++) {
		const struct vis_look *look = s->looks ? &s->looks[i] : NULL;
		struct vis_box b = border_box(s->rects[i], look);
		size_t pixels = 0, seen = 0;
		bool off = false;
		if (look && look->input_only) {
			states[i] = VIS_NO_STATE;
			continue;
		}
		for (int64_t py = b.y1; py < b.y2; py++)
			for (int64_t px = b.x1; px < b.x2; px++) {
				bool mine, opaque;
				pixel_of(s->rects[i], look, px, py, &mine, &opaque);
				if (!mine)
					continue;
				pixels++;
				bool on = !s->has_screen || (px >= 0 && py >= 0 && px < s->screen_w &&
							     py < s->screen_h);
				off |= !on;
				if (on && owner[(py - all.y1) * gw + (px - all.x1)] <= (int32_t)i)
					seen++;
			}
		if (seen == 0)
			states[i] = VIS_FULLY_OBSCURED;
		else if (seen == pixels && !off)
			states[i] = VIS_UNOBSCURED;
		else
			states[i] = VIS_PARTIALLY_OBSCURED;
	}
	free(owner);
}

static struct vis_rect random_rect(struct vis_rng *rng, int lo, int hi, int maxw)
{
	return (struct vis_rect){ (int32_t)vis_rng_range(rng, lo, hi),
				  (int32_t)vis_rng_range(rng, lo, hi),
				  (int32_t)vis_rng_range(rng, 1, maxw),
				  (int32_t)vis_rng_range(rng, 1, maxw) };
}

/* Fills rects with k rectangles: random, abutting halves of one, or repeats of one. */
static struct vis_rect *random_rects(struct vis_rng *rng, uint32_t k, int32_t w, int32_t h)
{
	struct vis_rect *r = malloc((k ? k : 1) * sizeof(*r));
	if (r == NULL)
		exit(2);
	for (uint32_t j = 0; j < k; j++) {
		switch (vis_rng_below(rng, 4)) {
		case 0: /* abutting the previous one on its right */
			if (j > 0) {
				r[j] = r[j - 1];
				r[j].x += r[j - 1].w;
				break;
			}
			/* fall through */
		case 1: /* anywhere near the window, reaching past its border box too */
			r[j] = random_rect(rng, -6, w + 2, 14);
			break;
		case 2: /* the same again: a union counts it once */
			r[j] = j > 0 ? r[j - 1] : random_rect(rng, -3, w, 10);
			break;
		default: /* inside the inside */
			r[j] = (struct vis_rect){ (int32_t)vis_rng_range(rng, 0, w - 1),
						  (int32_t)vis_rng_range(rng, 0, h - 1), 1, 1 };
			r[j].w = (int32_t)vis_rng_range(rng, 1, w - r[j].x);
			r[j].h = (int32_t)vis_rng_range(rng, 1, h - r[j].y);
		}
	}
	return r;
}

/* A random scene of n windows, each of its pixels within [-GRID_ORIGIN, GRID - GRID_ORIGIN). */
static void random_scene(struct vis_rng *rng, struct vis_scene *s, size_t n)
{
	vis_scene_init(s);
	if (vis_rng_below(rng, 4) != 0) {
		s->has_screen = true;
		s->screen_w = (int32_t)vis_rng_range(rng, 1, 60);
		s->screen_h = (int32_t)vis_rng_range(rng, 1, 60);
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_rect r = random_rect(rng, -20, 50, 30);
		if (i > 0 && vis_rng_below(rng, 6) == 0)
			r = s->rects[vis_rng_below(rng, i)]; /* identical boxes */
		if (vis_scene_push(s, (uint32_t)i, r) < 0)
			exit(2);
		if (vis_rng_below(rng, 5) == 0)
			continue; /* plain */
		struct vis_look *look = vis_scene_look(s, i);
		if (look == NULL)
			exit(2);
		if (vis_rng_below(rng, 12) == 0) {
			look->input_only = true;
			continue;
		}
		if (vis_rng_below(rng, 2) == 0)
			look->border = (int32_t)vis_rng_range(rng, 0, 4);
		if (vis_rng_below(rng, 2) == 0) {
			look->shaped = true;
			look->n_shape = (uint32_t)vis_rng_range(rng, 0, 5);
			look->shape = random_rects(rng, look->n_shape, r.w, r.h);
		}
		switch (vis_rng_below(rng, 3)) {
		case 0:
			break;
		case 1:
			look->opaque = VIS_OPAQUE_NONE;
			break;
		default:
			look->opaque = VIS_OPAQUE_RECTS;
			look->n_opaque = (uint32_t)vis_rng_range(rng, 0, 4);
			look->opaque_rects = random_rects(rng, look->n_opaque, r.w, r.h);
		}
	}
}

static void print_scene(const struct vis_scene *s)
{
	char *text;
	size_t len;
	if (vis_scene_format(s, &text, &len) == 0) {
		fwrite(text, 1, len, stderr);
		free(text);
	}
}

/* Compares every engine's states on s with want; says which scene on a difference. */
static void compare(const struct vis_scene *s, const uint8_t *want, const char *what,
		    uint64_t seed)
{
	struct vis_stack st = vis_scene_stack(s);
	uint8_t *got = malloc(s->n + 1);
	if (got == NULL)
		exit(2);
	for (int e = 0; e < VIS_ENGINE_COUNT; e++) {
		if (vis_compute((enum vis_engine)e, &st, got) < 0) {
			fprintf(stderr, "%s, seed %" PRIu64 ": engine %s: %s\n", what, seed,
				vis_engine_name((enum vis_engine)e), strerror(errno));
			failures++;
			continue;
		}
		for (size_t i = 0; i < s->n; i++) {
			if (got[i] == want[i])
				continue;
			fprintf(stderr, "%s, seed %" PRIu64 ": engine %s: window %" PRIu32
				": %s, want %s; the scene:\n", what, seed,
				vis_engine_name((enum vis_engine)e), s->ids[i],
				vis_state_name((enum vis_state)got[i]),
				vis_state_name((enum vis_state)want[i]));
			print_scene(s);
			failures++;
			break;
		}
	}
	free(got);
}

/* The random scenes, against the painter, then moved next to the 32-bit limits. */
static void test_random(uint64_t seed, size_t count)
{
	for (size_t c = 0; c < count && failures == 0; c++) {
		struct vis_rng rng = { seed + c };
		struct vis_scene s;
		random_scene(&rng, &s, (size_t)vis_rng_range(&rng, 1, 14));
		uint8_t want[16];
		paint(&s, want);
		compare(&s, want, "random scene", seed + c);

		/* Moved to either end of the plane, without a screen: nothing changes. */
		s.has_screen = false;
		paint(&s, want);
		static const int64_t shifts[] = { (int64_t)INT32_MAX - 100, (int64_t)INT32_MIN + 30 };
		for (int k = 0; k < 2; k++) {
			for (size_t i = 0; i < s.n; i++)
				s.rects[i].x = (int32_t)(s.rects[i].x + shifts[k]);
			compare(&s, want, k ? "moved to INT32_MIN" : "moved to INT32_MAX", seed + c);
			for (size_t i = 0; i < s.n; i++)
				s.rects[i].x = (int32_t)(s.rects[i].x - shifts[k]);
		}
		vis_scene_finish(&s);
	}
}

/* A scene from text with the states wanted, in window order. */
static void check_text(const char *name, const char *text, const char *want)
{
	struct vis_scene s;
	struct vis_scene_error err;
	vis_scene_init(&s);
	if (vis_scene_parse(&s, text, strlen(text), &err) < 0) {
		fprintf(stderr, "%s: line %zu: %s\n", name, err.line, err.reason);
		failures++;
		return;
	}
	uint8_t states[32], painted[32];
	size_t n = 0;
	for (const char *w = want; *w; w++) {
		if (n < 32)
			states[n] = *w == 'U' ? VIS_UNOBSCURED : *w == 'P' ? VIS_PARTIALLY_OBSCURED
				  : *w == 'F' ? VIS_FULLY_OBSCURED : VIS_NO_STATE;
		n++;
	}
	CHECK(n == s.n);
	if (n != s.n) {
		vis_scene_finish(&s);
		return;
	}
	/* The wanted states are the painter's too, so the painter is checked as well. */
	paint(&s, painted);
	if (memcmp(states, painted, n) != 0) {
		fprintf(stderr, "%s: the painter disagrees with the wanted states\n", name);
		failures++;
	}
	compare(&s, states, name, 0);
	vis_scene_finish(&s);
}

/* docs/ENGINES.md's exactness cases and the model's own, in bordered, shaped and translucent variants. */
static void test_cases(void)
{
	/* A border is the window's own: it obscures, and is obscured. */
	check_text("border obscures", "window 1 0 0 10 10\nwindow 2 9 0 5 5\nborder 1\n", "PU");
	check_text("border box abuts", "window 1 0 0 10 10\nwindow 2 10 0 5 5\nborder 1\n", "UU");
	check_text("border abuts", "window 1 0 0 10 10\nwindow 2 10 0 5 5\n", "UU");
	check_text("border covered", "screen 100 100\nwindow 1 5 5 10 10\nborder 2\n"
		   "window 2 5 5 14 14\n", "FU");
	check_text("border box off screen", "screen 10 10\nwindow 1 0 0 9 9\nborder 1\n", "P");
	check_text("border box exactly the screen", "screen 10 10\nwindow 1 0 0 6 6\nborder 2\n",
		   "U");
	/* Covered exactly by abutting pieces: of two windows, of one shape, of one opaque region. */
	check_text("abutting windows over a border box",
		   "window 1 0 0 8 8\nborder 1\nwindow 2 0 0 5 10\nwindow 3 5 0 5 10\n", "FUU");
	check_text("abutting shape pieces", "window 1 0 0 10 10\n"
		   "window 2 0 0 10 10\nshape 0,0,5,10 5,0,5,5 5,5,5,5\n", "FU");
	check_text("a shape with a one-row piece", "window 1 0 0 10 10\n"
		   "window 2 0 0 10 10\nshape 0,0,5,10 5,0,5,5 5,5,5,4 5,9,5,1\n", "FU");
	check_text("a shape leaving one pixel free", "window 1 0 0 10 10\n"
		   "window 2 0 0 10 10\nshape 0,0,5,10 5,0,5,5 5,5,5,4\n", "PU");
	check_text("abutting opaque pieces", "window 1 0 0 10 10\n"
		   "window 2 0 0 10 10\nopaque 0,0,5,10 5,0,5,10\n", "FU");
	check_text("opaque pieces leaving a pixel", "window 1 0 0 10 10\n"
		   "window 2 0 0 10 10\nopaque 0,0,5,10 5,0,5,9\n", "PU");
	/* An empty shape has no pixels: fully obscured with nothing above, hiding nothing. */
	check_text("empty shape", "screen 100 100\nwindow 1 0 0 10 10\nwindow 2 0 0 10 10\nshape\n",
		   "UF");
	/* A shape reaching past the border box is clipped to it (X reports such a window partially
	 * obscured; visd follows the pixels). */
	check_text("shape past the border box", "screen 1000 1000\nwindow 4 400 100 50 50\n"
		   "shape 0,0,40,40 100,100,5,5\n", "U");
	check_text("shape into the border", "window 1 0 0 10 10\nwindow 2 10 0 5 5\nborder 3\n"
		   "shape -3,0,1,1\n", "UU");
	check_text("shape into the border, overlapping", "window 1 0 0 10 10\n"
		   "window 2 9 0 5 5\nborder 3\nshape -3,0,1,1\n", "PU");
	/* Translucency: a translucent window hides nothing, and is obscured as any other. */
	check_text("translucent above", "window 1 0 0 10 10\nwindow 2 0 0 10 10\nopaque none\n",
		   "UU");
	check_text("translucent below", "window 1 0 0 10 10\nopaque none\nwindow 2 0 0 10 10\n",
		   "FU");
	check_text("shadow margin", "window 1 0 0 10 10\nwindow 2 -4 -4 10 10\nborder 2\n"
		   "opaque 0,0,10,10\n", "PU");
	check_text("shadow margin only", "window 1 0 0 10 10\nwindow 2 8 0 10 10\n"
		   "opaque 2,0,8,10\n", "UU");
	check_text("translucent over an exact cover", "window 1 0 0 10 10\nwindow 2 0 0 5 10\n"
		   "window 3 5 0 5 10\nwindow 4 0 0 10 10\nopaque none\n", "FUUU");
	check_text("identical, translucent top", "window 1 0 0 10 10\nwindow 2 0 0 10 10\n"
		   "window 3 0 0 10 10\nopaque none\n", "FUU");
	/* Input-only windows: no pixels, no state, hide nothing. */
	check_text("input-only", "window 1 0 0 10 10\nwindow 2 0 0 10 10\ninput-only\n", "UN");
	check_text("1x1 under input-only", "window 1 3 3 1 1\nwindow 2 0 0 10 10\ninput-only\n"
		   "window 3 3 3 1 1\nshape 0,0,1,1\n", "FNU");
}

/*
 * vis_pieces_add_within() against the painter: the pieces are the window's pixels inside the clip
 * and the union of the within boxes, opaque where the look says, each pixel once; the window is
 * cut when any of its pixels is left out.
 */
static void test_within(uint64_t seed, size_t count)
{
	for (size_t c = 0; c < count && failures == 0; c++) {
		struct vis_rng rng = { seed + c };
		struct vis_scene s;
		random_scene(&rng, &s, 1);
		const struct vis_look *look = s.looks ? &s.looks[0] : NULL;
		struct vis_rect r = s.rects[0];
		struct vis_box bb = border_box(r, look);
		struct vis_box clip = { vis_rng_range(&rng, -25, 60), vis_rng_range(&rng, -25, 60), 0, 0 };
		clip.x2 = clip.x1 + vis_rng_range(&rng, 1, 90);
		clip.y2 = clip.y1 + vis_rng_range(&rng, 1, 90);
		struct vis_box within[3];
		size_t nw = (size_t)vis_rng_below(&rng, 4);
		for (size_t k = 0; k < nw; k++) {
			within[k].x1 = vis_rng_range(&rng, -25, 60);
			within[k].y1 = vis_rng_range(&rng, -25, 60);
			within[k].x2 = within[k].x1 + vis_rng_range(&rng, 1, 50);
			within[k].y2 = within[k].y1 + vis_rng_range(&rng, 1, 50);
		}
		struct vis_pieces p = { 0 };
		int cut = vis_pieces_add_within(&p, look, bb, clip, within, nw, 0);
		CHECK(cut >= 0);
		bool want_cut = false, bad = false;
		for (int64_t py = bb.y1; py < bb.y2 && !bad; py++)
			for (int64_t px = bb.x1; px < bb.x2 && !bad; px++) {
				bool mine, opaque, in = px >= clip.x1 && px < clip.x2 && py >= clip.y1 &&
							py < clip.y2, inw = false;
				pixel_of(r, look, px, py, &mine, &opaque);
				for (size_t k = 0; k < nw; k++)
					inw |= px >= within[k].x1 && px < within[k].x2 &&
					       py >= within[k].y1 && py < within[k].y2;
				in &= inw;
				want_cut |= mine && !in;
				int hits = 0, op = -1;
				for (size_t k = 0; k < p.stack.n; k++) {
					struct vis_box q = vis_rect_box(p.rects[k]);
					if (px >= q.x1 && px < q.x2 && py >= q.y1 && py < q.y2) {
						hits++;
						op = !p.see_through[k];
					}
				}
				if (hits != (mine && in) || (hits && op != opaque))
					bad = true;
			}
		if (bad || (cut == 1) != want_cut) {
			fprintf(stderr, "within, seed %" PRIu64 ": pieces or cut (%d) wrong; the window:\n",
				seed + c, cut);
			print_scene(&s);
			failures++;
		}
		vis_pieces_finish(&p);
		vis_scene_finish(&s);
	}
}

/* The translucent flag by the painter: whether some pixel of the window hides nothing. */
static bool painted_translucent(struct vis_rect r, const struct vis_look *look)
{
	struct vis_box bb = border_box(r, look);
	for (int64_t y = bb.y1; y < bb.y2; y++)
		for (int64_t x = bb.x1; x < bb.x2; x++) {
			bool mine, opaque;
			pixel_of(r, look, x, y, &mine, &opaque);
			if (mine && !opaque)
				return true;
		}
	return false;
}

/* One look whose flag is known, at the geometry w × h (its border is the look's). */
static void check_translucent(const char *what, struct vis_look look, int32_t w, int32_t h,
			      bool want)
{
	int got = vis_look_translucent(&look, w, h);
	if (got != want) {
		fprintf(stderr, "test-look: translucent: %s: got %d, wanted %d\n", what, got, want);
		failures++;
	}
}

/*
 * vis_look_translucent(): the cases of the rule, then random looks at random geometries against
 * the painter.
 */
static void test_translucent(uint64_t seed, size_t count)
{
	const struct vis_rect whole = { 0, 0, 10, 10 }, halves[2] = { { 0, 0, 5, 10 }, { 5, 0, 5, 10 } };
	const struct vis_rect overlap[2] = { { 0, 0, 7, 10 }, { 3, 0, 7, 10 } };
	const struct vis_rect but_one[2] = { { 0, 0, 10, 9 }, { 0, 9, 9, 1 } };
	const struct vis_rect framed = { -2, -2, 14, 14 };
	const struct vis_rect far = { INT32_MAX - 4, INT32_MAX - 4, INT32_MAX, INT32_MAX };
	struct vis_look l = { .opaque = VIS_OPAQUE_RECTS, .n_opaque = 1 };
	l.opaque_rects = (struct vis_rect *)&whole;
	check_translucent("opaque rectangle = inside", l, 10, 10, false);
	check_translucent("opaque rectangle < inside after a resize", l, 11, 10, true);
	check_translucent("opaque rectangle > inside after a resize", l, 9, 9, false);
	l.border = 1;
	check_translucent("border outside the opaque rectangle", l, 10, 10, true);
	l.opaque_rects = (struct vis_rect *)&framed;
	l.border = 2;
	check_translucent("opaque rectangle = border box", l, 10, 10, false);
	l.border = 3;
	check_translucent("a border grown past the opaque rectangle", l, 10, 10, true);
	l.border = 0;
	l.n_opaque = 2;
	l.opaque_rects = (struct vis_rect *)halves;
	check_translucent("abutting opaque rectangles", l, 10, 10, false);
	l.opaque_rects = (struct vis_rect *)overlap;
	check_translucent("overlapping opaque rectangles", l, 10, 10, false);
	l.opaque_rects = (struct vis_rect *)but_one;
	check_translucent("one pixel left free", l, 10, 10, true);
	check_translucent("the free pixel resized away", l, 10, 9, false);
	struct vis_look empty = { .shaped = true, .opaque = VIS_OPAQUE_NONE };
	check_translucent("no pixels, mode none", empty, 10, 10, false);
	empty.opaque = VIS_OPAQUE_RECTS;
	check_translucent("no pixels, opaque rectangles", empty, 10, 10, false);
	struct vis_look out = { .shaped = true, .n_shape = 1, .opaque = VIS_OPAQUE_NONE };
	out.shape = (struct vis_rect *)&far;
	check_translucent("a shape beyond the border box", out, 10, 10, false);
	check_translucent("a border box reaching the shape", out, INT32_MAX - 2, INT32_MAX - 2, true);
	struct vis_look shaped = { .shaped = true, .n_shape = 1, .opaque = VIS_OPAQUE_RECTS,
				   .n_opaque = 2, .border = 2 };
	shaped.shape = (struct vis_rect *)&framed;
	shaped.opaque_rects = (struct vis_rect *)halves;
	check_translucent("a shape reaching into the border", shaped, 10, 10, true);
	shaped.border = 0;
	check_translucent("the same shape, no border", shaped, 10, 10, false);
	check_translucent("mode none", (struct vis_look){ .opaque = VIS_OPAQUE_NONE }, 1, 1, true);
	check_translucent("mode all", (struct vis_look){ .border = 3 }, 1, 1, false);
	check_translucent("input-only", (struct vis_look){ .input_only = true }, 1, 1, false);

	for (size_t i = 0; i < count; i++) {
		struct vis_rng rng = { seed + i };
		struct vis_scene s;
		random_scene(&rng, &s, 4);
		for (size_t k = 0; k < s.n; k++) {
			struct vis_look look = s.looks ? s.looks[k] : (struct vis_look){ 0 };
			for (int g = 0; g < 4; g++) {
				struct vis_rect r = s.rects[k];
				if (g > 0) { /* resized, its border changed */
					r.w = (int32_t)vis_rng_range(&rng, 1, 40);
					r.h = (int32_t)vis_rng_range(&rng, 1, 40);
					if (!look.input_only)
						look.border = (int32_t)vis_rng_range(&rng, 0, 6);
				}
				bool want = painted_translucent(r, &look);
				if (vis_look_translucent(&look, r.w, r.h) != want) {
					fprintf(stderr, "test-look: seed %" PRIu64 ": window %zu at "
							"%dx%d border %d: translucent should be %d\n",
						seed + i, k, r.w, r.h, look.border, want);
					print_scene(&s);
					failures++;
				}
			}
		}
		vis_scene_finish(&s);
	}
}

int main(int argc, char **argv)
{
	uint64_t seed = 1;
	size_t count = 20000;
	bool one = false;
	for (int i = 1; i + 1 < argc; i += 2) {
		if (strcmp(argv[i], "--seed") == 0) {
			seed = strtoull(argv[i + 1], NULL, 10);
			one = true;
		} else if (strcmp(argv[i], "--count") == 0) {
			count = strtoull(argv[i + 1], NULL, 10);
		}
	}
	if (one && count == 20000)
		count = 1;
	test_cases();
	test_random(seed, count);
	test_within(seed, count / 4);
	test_translucent(seed, count / 4);
	if (failures) {
		fprintf(stderr, "test-look: %d failures\n", failures);
		return 1;
	}
	printf("test-look: %zu random scenes (and each moved to both 32-bit ends) and the cases "
	       "agree with the painter on every engine; %zu windows cut within a clip and boxes; "
	       "the translucent flag of %zu scenes' windows at 4 geometries each\n",
	       count, count / 4, count / 4);
	return 0;
}
