/* Unit tests of the scene format (parse, format) and of the scene generators. */
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gen.h"
#include "scene.h"

/* An assert that survives NDEBUG builds and says where it failed. */
#define CHECK(cond)                                                                       \
	do {                                                                              \
		if (!(cond)) {                                                            \
			fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, \
				#cond);                                                   \
			exit(1);                                                          \
		}                                                                         \
	} while (0)

static int checks_run;

/* Parses a NUL-terminated text expecting success; the caller finishes the scene. */
static void parse_ok(struct vis_scene *scene, const char *text, size_t len)
{
	struct vis_scene_error err;

	vis_scene_init(scene);
	if (vis_scene_parse(scene, text, len, &err) != 0) {
		fprintf(stderr, "unexpected parse error at line %zu: %s\n", err.line, err.reason);
		exit(1);
	}
	checks_run++;
}

/* Parses text expecting a failure on the given line whose reason is exactly `reason`. */
static void parse_bad_len(const char *text, size_t len, size_t line, const char *reason)
{
	struct vis_scene scene;
	struct vis_scene_error err;

	vis_scene_init(&scene);
	if (vis_scene_parse(&scene, text, len, &err) == 0) {
		fprintf(stderr, "parse of %s unexpectedly succeeded\n", text);
		exit(1);
	}
	if (err.line != line || strcmp(err.reason, reason) != 0) {
		fprintf(stderr, "input:\n%s\nexpected line %zu '%s'\n     got line %zu '%s'\n", text,
			line, reason, err.line, err.reason);
		exit(1);
	}
	/* A failed parse leaves nothing behind to leak or to misuse. */
	CHECK(scene.n == 0 && scene.ids == NULL && scene.rects == NULL && !scene.has_screen);
	checks_run++;
}

/* parse_bad_len for NUL-terminated text. */
static void parse_bad(const char *text, size_t line, const char *reason)
{
	parse_bad_len(text, strlen(text), line, reason);
}

/* Well-formed inputs, including every lexical allowance the format makes. */
static void test_parse_good(void)
{
	struct vis_scene s;

	parse_ok(&s, "", 0);
	CHECK(s.n == 0 && !s.has_screen);
	vis_scene_finish(&s);

	const char *t = "# a comment\n"
			"\n"
			"   \t  \n"
			"screen 1920 1080   # trailing comment\r\n"
			"\twindow\t7  -5 -6\t10 20\r\n"
			"window 0 -2147483648 2147483647 2147483647 1#glued comment\n"
			"window 4294967295 -0 007 1 2147483647";
	parse_ok(&s, t, strlen(t));
	CHECK(s.has_screen && s.screen_w == 1920 && s.screen_h == 1080);
	CHECK(s.n == 3);
	CHECK(s.ids[0] == 7 && s.rects[0].x == -5 && s.rects[0].y == -6 && s.rects[0].w == 10 &&
	      s.rects[0].h == 20);
	CHECK(s.ids[1] == 0 && s.rects[1].x == INT32_MIN && s.rects[1].y == INT32_MAX &&
	      s.rects[1].w == INT32_MAX && s.rects[1].h == 1);
	CHECK(s.ids[2] == UINT32_MAX && s.rects[2].x == 0 && s.rects[2].y == 7 &&
	      s.rects[2].h == INT32_MAX);
	struct vis_stack st = vis_scene_stack(&s);
	CHECK(st.n == 3 && st.rects == s.rects && st.has_screen && st.screen_w == 1920);
	vis_scene_finish(&s);

	/* Only comments and a lone CR line: still an empty scene. */
	parse_ok(&s, "#x\r\n\r\n# y", 9);
	CHECK(s.n == 0);
	vis_scene_finish(&s);
}

/* Every way a record can be wrong, with the line blamed and the exact wording. */
static void test_parse_bad(void)
{
	parse_bad("foo 1 2\n", 1, "unknown record 'foo'");
	parse_bad("\n# c\nWindow 1 0 0 1 1\n", 3, "unknown record 'Window'");
	parse_bad("window 1 0 0 1\n", 1, "window: expected 5 fields (ID X Y W H), got 4");
	parse_bad("window\n", 1, "window: expected 5 fields (ID X Y W H), got 0");
	parse_bad("window 1 0 0 1 1 1\n", 1, "window: expected 5 fields (ID X Y W H), got 6");
	parse_bad("window 1 0 0 1 1 1 1 1 1 1\n", 1,
		  "window: expected 5 fields (ID X Y W H), got 10");
	parse_bad("window 1 12a 0 1 1\n", 1, "window: X '12a' is not a number");
	parse_bad("window 1 0 +5 1 1\n", 1, "window: Y '+5' is not a number");
	parse_bad("window 0x1 0 0 1 1\n", 1, "window: ID '0x1' is not a number");
	parse_bad("window 1 - 0 1 1\n", 1, "window: X '-' is not a number");
	parse_bad("window 1 0 0 1 1.5\n", 1, "window: H '1.5' is not a number");
	parse_bad("window 1 0 0 1 1,\n", 1, "window: H '1,' is not a number");
	parse_bad("window 1 0 0 --1 1\n", 1, "window: W '--1' is not a number");
	parse_bad("window 1 0 0 0 1\n", 1, "window: W 0 out of range 1..2147483647");
	parse_bad("window 1 0 0 1 -1\n", 1, "window: H -1 out of range 1..2147483647");
	parse_bad("window 1 0 0 2147483648 1\n", 1,
		  "window: W 2147483648 out of range 1..2147483647");
	parse_bad("window 1 2147483648 0 1 1\n", 1,
		  "window: X 2147483648 out of range -2147483648..2147483647");
	parse_bad("window 1 0 -2147483649 1 1\n", 1,
		  "window: Y -2147483649 out of range -2147483648..2147483647");
	parse_bad("window 4294967296 0 0 1 1\n", 1,
		  "window: ID 4294967296 out of range 0..4294967295");
	parse_bad("window -1 0 0 1 1\n", 1, "window: ID -1 out of range 0..4294967295");
	parse_bad("window 1 99999999999999999999999 0 1 1\n", 1,
		  "window: X 99999999999999999999999 out of range -2147483648..2147483647");
	parse_bad("window 1 -18446744073709551616 0 1 1\n", 1,
		  "window: X -18446744073709551616 out of range -2147483648..2147483647");
	/* Long junk is shortened so the reason always fits. */
	parse_bad("window 1 0 0 1 abcdefghijklmnopqrstuvwxyz0123456789\n", 1,
		  "window: H 'abcdefghijklmnopqrstuvwx...' is not a number");
	parse_bad("window 1 0 0 1 1\n\nwindow 2 0 0 1 1\nwindow 1 5 5 1 1\n", 4,
		  "duplicate window ID 1 (first on line 1)");
	parse_bad("window 7 0 0 1 1\nwindow 8 0 0 1 1\nwindow 7 0 0 1 1\n", 3,
		  "duplicate window ID 7 (first on line 1)");
	/* Of several duplicates, the one met first when reading is reported. */
	parse_bad("window 9 0 0 1 1\nwindow 3 0 0 1 1\nwindow 3 0 0 1 1\nwindow 9 0 0 1 1\n"
		  "window 3 0 0 1 1\n",
		  3, "duplicate window ID 3 (first on line 2)");
	/* A duplicate before a syntax error is the first error; after one, the syntax error is. */
	parse_bad("window 5 0 0 1 1\nwindow 5 0 0 1 1\nbogus\n", 2,
		  "duplicate window ID 5 (first on line 1)");
	parse_bad("window 5 0 0 1 1\nbogus\nwindow 5 0 0 1 1\n", 2, "unknown record 'bogus'");
	parse_bad("screen 10 10\nscreen 10 10\n", 2, "screen given twice (first on line 1)");
	parse_bad("window 1 0 0 1 1\nscreen 10 10\n", 2, "screen after a window");
	parse_bad("screen 10\n", 1, "screen: expected 2 fields (W H), got 1");
	parse_bad("screen 10 0\n", 1, "screen: H 0 out of range 1..2147483647");
	parse_bad("screen -10 10\n", 1, "screen: W -10 out of range 1..2147483647");
	parse_bad("screen 10 x\n", 1, "screen: H 'x' is not a number");
	parse_bad_len("window 1 0 0 1 1\nwin\0dow 2 0 0 1 1\n", 34, 2, "NUL byte in input");
	/* A CR is only a line ending at the end of a line. */
	parse_bad("window 1 0\r0 1 1\n", 1, "window: expected 5 fields (ID X Y W H), got 4");
	parse_bad("window 1 0 0 1 1\r\nwindow 2 0 0 1 1 x\r\n", 2,
		  "window: expected 5 fields (ID X Y W H), got 6");
}

/* Whether two scenes hold the same screen and windows. */
static bool scenes_equal(const struct vis_scene *a, const struct vis_scene *b)
{
	if (a->has_screen != b->has_screen || a->n != b->n)
		return false;
	if (a->has_screen && (a->screen_w != b->screen_w || a->screen_h != b->screen_h))
		return false;
	for (size_t i = 0; i < a->n; i++)
		if (a->ids[i] != b->ids[i] || memcmp(&a->rects[i], &b->rects[i], sizeof(a->rects[i])))
			return false;
	return true;
}

/* Generates a scene, failing the test on error. */
static void gen(struct vis_scene *s, enum vis_gen_kind kind, size_t n, uint64_t seed, int32_t w,
		int32_t h)
{
	vis_scene_init(s);
	if (vis_gen(s, kind, n, seed, w, h) != 0) {
		fprintf(stderr, "vis_gen(%s, %zu, %" PRIu64 ") failed: %s\n", vis_gen_kind_name(kind),
			n, seed, strerror(errno));
		exit(1);
	}
}

/* Formats a scene, failing the test on error. */
static char *format(const struct vis_scene *s, size_t *len)
{
	char *text;

	CHECK(vis_scene_format(s, &text, len) == 0);
	CHECK(strlen(text) == *len);
	return text;
}

/* The look records: what they accept, every way they can be wrong, and their text form. */
static void test_look_records(void)
{
	struct vis_scene s;
	const char *t = "window 1 0 0 10 10\n"
			"border 3\n"
			"shape -3,-3,16,2 0,0,1,1 0,0,1,1\n"
			"opaque 0,0,10,10\n"
			"window 2 5 5 1 1\n"
			"input-only\n"
			"window 3 0 0 4 4\n"
			"shape\n"
			"opaque none\n"
			"window 4 0 0 4 4\n"
			"opaque all\n";
	parse_ok(&s, t, strlen(t));
	CHECK(s.n == 4 && s.looks != NULL);
	CHECK(s.looks[0].border == 3 && s.looks[0].shaped && s.looks[0].n_shape == 3 &&
	      s.looks[0].shape[0].x == -3 && s.looks[0].shape[0].w == 16 &&
	      s.looks[0].opaque == VIS_OPAQUE_RECTS && s.looks[0].n_opaque == 1);
	CHECK(s.looks[1].input_only && vis_look_plain(&s.looks[3]));
	CHECK(s.looks[2].shaped && s.looks[2].n_shape == 0 && s.looks[2].opaque == VIS_OPAQUE_NONE);
	char *out;
	size_t len;
	CHECK(vis_scene_format(&s, &out, &len) == 0);
	const char *want = "window 1 0 0 10 10\n"
			   "border 3\n"
			   "shape -3,-3,16,2 0,0,1,1 0,0,1,1\n"
			   "opaque 0,0,10,10\n"
			   "window 2 5 5 1 1\n"
			   "input-only\n"
			   "window 3 0 0 4 4\n"
			   "shape\n"
			   "opaque none\n"
			   "window 4 0 0 4 4\n";
	CHECK(len == strlen(want) && strcmp(out, want) == 0);
	free(out);
	vis_scene_finish(&s);

	parse_bad("border 1\n", 1, "border before any window (it applies to the window above it)");
	parse_bad("window 1 0 0 1 1\nborder 1\nborder 2\n", 3,
		  "border given twice for window 1 (first on line 2)");
	parse_bad("window 1 0 0 1 1\nborder -1\n", 2, "border: B -1 out of range 0..2147483647");
	parse_bad("window 1 0 0 1 1\nborder\n", 2, "border: expected 1 field (B), got 0");
	parse_bad("window 1 0 0 2147483646 1\nborder 1\n", 2,
		  "border: window 1: border box wider or taller than 2147483647");
	parse_bad("window 1 0 0 1 1\nshape 0,0,1\n", 2, "shape: rectangle 1 '0,0,1' is not X,Y,W,H");
	parse_bad("window 1 0 0 1 1\nshape 0,0,1,1 0,0,1,1,\n", 2,
		  "shape: rectangle 2 '0,0,1,1,' is not X,Y,W,H");
	parse_bad("window 1 0 0 1 1\nshape 0,0,0,1\n", 2,
		  "shape rectangle 1: W 0 out of range 1..2147483647");
	parse_bad("window 1 0 0 1 1\nopaque 0,x,1,1\n", 2, "opaque rectangle 1: Y 'x' is not a number");
	parse_bad("window 1 0 0 1 1\nopaque\n", 2, "opaque: expected none, all or rectangles X,Y,W,H");
	parse_bad("window 1 0 0 1 1\nopaque none none\n", 2,
		  "opaque: rectangle 1 'none' is not X,Y,W,H");
	parse_bad("window 1 0 0 1 1\ninput-only\nborder 1\n", 3,
		  "border: window 1: an input-only window has no border, shape or opaque region");
	parse_bad("window 1 0 0 1 1\nshape\ninput-only\n", 3,
		  "input-only: window 1: an input-only window has no border, shape or opaque region");
	parse_bad("window 1 0 0 1 1\ninput-only x\n", 2, "input-only: expected no fields, got 1");
	parse_bad("window 1 2147483000 0 1000 1\nshape 0,0,1,1\n", 2,
		  "shape: window 1: a shaped window must end within the 32-bit plane (at 2147483648)");
	/* The same box without a shape is fine: a plain window may end past it. */
	t = "window 1 2147483000 0 1000 1\nborder 1\n";
	parse_ok(&s, t, strlen(t));
	vis_scene_finish(&s);
}

/* Format then parse gives back the same scene, and formatting that gives the same text. */
static void test_round_trip(void)
{
	struct vis_scene a, b;
	size_t len, len2;

	vis_scene_init(&a);
	char *text = format(&a, &len);
	CHECK(len == 0);
	free(text);

	for (int k = 0; k < VIS_GEN_KIND_COUNT; k++) {
		gen(&a, (enum vis_gen_kind)k, 3001, 42, 0, 0);
		text = format(&a, &len);
		parse_ok(&b, text, len);
		CHECK(scenes_equal(&a, &b));
		char *text2 = format(&b, &len2);
		CHECK(len == len2 && memcmp(text, text2, len) == 0);
		free(text);
		free(text2);
		vis_scene_finish(&a);
		vis_scene_finish(&b);
	}

	/* Extreme values survive the trip. */
	vis_scene_init(&a);
	a.has_screen = true;
	a.screen_w = INT32_MAX;
	a.screen_h = 1;
	CHECK(vis_scene_push(&a, UINT32_MAX,
			     (struct vis_rect){ INT32_MIN, INT32_MAX, 1, INT32_MAX }) == 0);
	CHECK(vis_scene_push(&a, 0, (struct vis_rect){ -1, 0, INT32_MAX, 3 }) == 0);
	text = format(&a, &len);
	CHECK(strcmp(text, "screen 2147483647 1\n"
			   "window 4294967295 -2147483648 2147483647 1 2147483647\n"
			   "window 0 -1 0 2147483647 3\n") == 0);
	parse_ok(&b, text, len);
	CHECK(scenes_equal(&a, &b));
	free(text);
	vis_scene_finish(&a);
	vis_scene_finish(&b);
	vis_scene_finish(&a); /* finishing twice is harmless */
}

/* Checks what every generated scene promises: n windows, IDs 1..n bottom-to-top, sides ≥ 1. */
static void check_basic(const struct vis_scene *s, size_t n)
{
	CHECK(s->n == n);
	for (size_t i = 0; i < n; i++) {
		CHECK(s->ids[i] == i + 1);
		CHECK(s->rects[i].w >= 1 && s->rects[i].h >= 1);
	}
	if (s->has_screen)
		CHECK(s->screen_w >= 1 && s->screen_h >= 1);
}

/* Whether rectangle r lies wholly inside the scene's screen. */
static bool on_screen(const struct vis_scene *s, struct vis_rect r)
{
	struct vis_box screen = { 0, 0, s->screen_w, s->screen_h };
	return vis_box_contains(screen, vis_rect_box(r));
}

/* Whether two rectangles share a pixel. */
static bool overlap(struct vis_rect a, struct vis_rect b)
{
	return !vis_box_empty(vis_box_intersect(vis_rect_box(a), vis_rect_box(b)));
}

/* Desktop-like scenes: the promised shares of maximized, partly and wholly off-screen windows. */
static void test_gen_random(void)
{
	struct vis_scene s;
	size_t maxed = 0, partly = 0, off = 0, negative = 0;

	gen(&s, VIS_GEN_RANDOM, 20000, 1, 0, 0);
	check_basic(&s, 20000);
	CHECK(s.has_screen && s.screen_w == VIS_GEN_SCREEN_W && s.screen_h == VIS_GEN_SCREEN_H);
	struct vis_box screen = { 0, 0, s.screen_w, s.screen_h };
	for (size_t i = 0; i < s.n; i++) {
		struct vis_rect r = s.rects[i];
		struct vis_box b = vis_rect_box(r);
		if (r.x == 0 && r.y == 0 && r.w == s.screen_w && r.h == s.screen_h)
			maxed++;
		else if (vis_box_empty(vis_box_intersect(b, screen)))
			off++;
		else if (!vis_box_contains(screen, b))
			partly++;
		if (r.x < 0 || r.y < 0)
			negative++;
	}
	/* Expected 2%, 1% and 5% of 20000; the bounds are loose so only a broken generator fails. */
	CHECK(maxed > 200 && maxed < 700);
	CHECK(off > 100 && off < 400);
	CHECK(partly > 600 && partly < 1400);
	CHECK(negative > 0);
	vis_scene_finish(&s);

	/* A tiny screen still gives valid windows. */
	gen(&s, VIS_GEN_RANDOM, 500, 3, 1, 2);
	check_basic(&s, 500);
	CHECK(s.screen_w == 1 && s.screen_h == 2);
	vis_scene_finish(&s);
}

/* Uniform rectangles stay in their ranges and have a screen only when one is asked for. */
static void test_gen_uniform(void)
{
	struct vis_scene s;

	gen(&s, VIS_GEN_UNIFORM, 5000, 9, 0, 0);
	check_basic(&s, 5000);
	CHECK(!s.has_screen);
	for (size_t i = 0; i < s.n; i++) {
		struct vis_rect r = s.rects[i];
		CHECK(r.x >= 0 && r.x < 1000000 && r.y >= 0 && r.y < 1000000);
		CHECK(r.w <= 100000 && r.h <= 100000);
	}
	vis_scene_finish(&s);
	gen(&s, VIS_GEN_UNIFORM, 10, 9, 500000, 400000);
	CHECK(s.has_screen && s.screen_w == 500000 && s.screen_h == 400000);
	vis_scene_finish(&s);
}

/* The grid: n/2 full-height vertical bars under full-width horizontal bars, all on-screen. */
static void test_gen_grid(void)
{
	static const size_t sizes[] = { 1, 2, 3, 10, 11, 1000 };

	for (size_t t = 0; t < sizeof(sizes) / sizeof(sizes[0]); t++) {
		struct vis_scene s;
		size_t n = sizes[t], nv = n / 2;

		gen(&s, VIS_GEN_GRID, n, 5, 0, 0);
		check_basic(&s, n);
		CHECK(s.has_screen);
		for (size_t i = 0; i < n; i++) {
			struct vis_rect r = s.rects[i];
			CHECK(on_screen(&s, r));
			if (i < nv)
				CHECK(r.w == 1 && r.y == 0 && r.h == s.screen_h);
			else
				CHECK(r.h == 1 && r.x == 0 && r.w == s.screen_w);
		}
		/* Every horizontal bar crosses every vertical one. */
		for (size_t i = 0; i < nv; i++)
			for (size_t j = nv; j < n; j++)
				CHECK(overlap(s.rects[i], s.rects[j]));
		vis_scene_finish(&s);
	}
}

/* Cascades: one window size, on-screen, mostly diagonal steps from the window below. */
static void test_gen_cascade(void)
{
	struct vis_scene s;

	gen(&s, VIS_GEN_CASCADE, 3000, 11, 0, 0);
	check_basic(&s, 3000);
	size_t steps = 0;
	for (size_t i = 0; i < s.n; i++) {
		CHECK(on_screen(&s, s.rects[i]));
		CHECK(s.rects[i].w == s.rects[0].w && s.rects[i].h == s.rects[0].h);
		if (i > 0 && s.rects[i].x > s.rects[i - 1].x && s.rects[i].y > s.rects[i - 1].y &&
		    s.rects[i].x - s.rects[i - 1].x == s.rects[i].y - s.rects[i - 1].y)
			steps++;
	}
	CHECK(steps > s.n / 2);
	vis_scene_finish(&s);
}

/* The tiles are a prefix of the stack that covers the screen exactly, without overlap. */
static void test_gen_tiles(void)
{
	static const size_t sizes[] = { 1, 2, 3, 9, 2000 };

	for (size_t t = 0; t < sizeof(sizes) / sizeof(sizes[0]); t++) {
		struct vis_scene s;
		size_t n = sizes[t];
		uint64_t area = 0, screen_area;
		size_t ntiles = 0;

		gen(&s, VIS_GEN_TILES, n, 13, 0, 0);
		check_basic(&s, n);
		CHECK(s.has_screen);
		screen_area = (uint64_t)s.screen_w * (uint64_t)s.screen_h;
		while (ntiles < s.n && area < screen_area) {
			area += (uint64_t)s.rects[ntiles].w * (uint64_t)s.rects[ntiles].h;
			ntiles++;
		}
		CHECK(area == screen_area);
		CHECK(ntiles >= 1 && ntiles <= (n + 1) / 2 && ntiles >= n / 4);
		for (size_t i = 0; i < ntiles; i++) {
			CHECK(on_screen(&s, s.rects[i]));
			for (size_t j = i + 1; j < ntiles; j++)
				CHECK(!overlap(s.rects[i], s.rects[j]));
		}
		for (size_t i = ntiles; i < s.n; i++)
			CHECK(on_screen(&s, s.rects[i]));
		vis_scene_finish(&s);
	}

	/* More tiles wanted than the screen has pixels: cells stay at least 1 px. */
	struct vis_scene s;
	gen(&s, VIS_GEN_TILES, 100, 1, 3, 2);
	check_basic(&s, 100);
	vis_scene_finish(&s);
}

/* A few large windows on top, small ones under them, some of those peeking out. */
static void test_gen_nested(void)
{
	struct vis_scene s;
	size_t n = 5000, nbig = 5, inside = 0, outside = 0;

	gen(&s, VIS_GEN_NESTED, n, 17, 0, 0);
	check_basic(&s, n);
	for (size_t i = n - nbig; i < n; i++) {
		CHECK(on_screen(&s, s.rects[i]));
		CHECK(s.rects[i].w >= s.screen_w * 2 / 5 - 1 && s.rects[i].h >= s.screen_h * 2 / 5 - 1);
	}
	for (size_t i = 0; i < n - nbig; i++) {
		CHECK(s.rects[i].w <= 200 && s.rects[i].h <= 200);
		bool in = false;
		for (size_t b = n - nbig; b < n && !in; b++)
			in = vis_box_contains(vis_rect_box(s.rects[b]), vis_rect_box(s.rects[i]));
		if (in)
			inside++;
		else
			outside++;
	}
	CHECK(inside > n / 2 && outside > 0);
	vis_scene_finish(&s);

	gen(&s, VIS_GEN_NESTED, 1, 17, 0, 0);
	check_basic(&s, 1);
	vis_scene_finish(&s);
}

/* Same arguments, same text; another seed, another scene; every kind copes with small n. */
static void test_gen_common(void)
{
	static const size_t sizes[] = { 0, 1, 2, 3, 7, 1001 };

	for (int k = 0; k < VIS_GEN_KIND_COUNT; k++) {
		enum vis_gen_kind kind = (enum vis_gen_kind)k, back;
		CHECK(vis_gen_kind_from_name(vis_gen_kind_name(kind), &back) == 0 && back == kind);

		for (size_t t = 0; t < sizeof(sizes) / sizeof(sizes[0]); t++) {
			struct vis_scene a, b;
			size_t la, lb;
			gen(&a, kind, sizes[t], 123, 0, 0);
			gen(&b, kind, sizes[t], 123, 0, 0);
			check_basic(&a, sizes[t]);
			char *ta = format(&a, &la), *tb = format(&b, &lb);
			CHECK(la == lb && memcmp(ta, tb, la) == 0);
			free(ta);
			free(tb);
			vis_scene_finish(&a);
			vis_scene_finish(&b);
		}
		if (kind == VIS_GEN_GRID)
			continue; /* the grid has nothing random about it */
		struct vis_scene a, b;
		gen(&a, kind, 200, 1, 0, 0);
		gen(&b, kind, 200, 2, 0, 0);
		CHECK(!scenes_equal(&a, &b));
		vis_scene_finish(&a);
		vis_scene_finish(&b);
	}

	enum vis_gen_kind kind;
	CHECK(vis_gen_kind_from_name("bogus", &kind) == -1);
	struct vis_scene s;
	vis_scene_init(&s);
	errno = 0;
	CHECK(vis_gen(&s, VIS_GEN_RANDOM, 10, 1, -1, 0) == -1 && errno == EINVAL && s.n == 0);
	CHECK(vis_gen(&s, VIS_GEN_RANDOM, 10, 1, 100, -5) == -1 && errno == EINVAL && s.n == 0);
}

/* A million windows, to see the parser stays linear; reports the time but does not judge it. */
static void test_parse_large(void)
{
	struct vis_scene a, b;
	size_t len;
	struct timespec t0, t1;

	gen(&a, VIS_GEN_RANDOM, 1000000, 99, 0, 0);
	char *text = format(&a, &len);
	clock_gettime(CLOCK_MONOTONIC, &t0);
	parse_ok(&b, text, len);
	clock_gettime(CLOCK_MONOTONIC, &t1);
	CHECK(scenes_equal(&a, &b));
	printf("parsed 10^6 windows (%zu bytes) in %.1f ms\n", len,
	       (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6);

	/* A duplicate at the very end of a large scene is still found and blamed correctly. */
	vis_scene_finish(&b);
	char *dup = malloc(len + 64);
	CHECK(dup != NULL);
	memcpy(dup, text, len);
	int extra = snprintf(dup + len, 64, "window 500000 1 1 1 1\n");
	struct vis_scene_error err;
	vis_scene_init(&b);
	CHECK(vis_scene_parse(&b, dup, len + (size_t)extra, &err) == -1);
	CHECK(err.line == 1000002); /* the screen line, then 10^6 windows */
	CHECK(strcmp(err.reason, "duplicate window ID 500000 (first on line 500001)") == 0);
	free(dup);
	free(text);
	vis_scene_finish(&a);
}

/* Runs every check; any failure exits 1 with the file and line. */
int main(void)
{
	test_parse_good();
	test_parse_bad();
	test_look_records();
	test_round_trip();
	test_gen_random();
	test_gen_uniform();
	test_gen_grid();
	test_gen_cascade();
	test_gen_tiles();
	test_gen_nested();
	test_gen_common();
	test_parse_large();
	printf("scene: all checks passed (%d parses)\n", checks_run);
	return 0;
}
