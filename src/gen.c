/*
 * Scene generators. Every random choice comes from the splitmix64 generator in rng.h, drawn in a
 * fixed order, so a (kind, n, seed, screen) tuple gives the same scene on every machine.
 * Coordinates are computed in 64 bits and only narrowed once known to fit, because a screen may be
 * as large as INT32_MAX on a side.
 */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gen.h"
#include "rng.h"

static const char *const kind_names[VIS_GEN_KIND_COUNT] = {
	[VIS_GEN_RANDOM] = "random",
	[VIS_GEN_UNIFORM] = "uniform",
	[VIS_GEN_GRID] = "grid",
	[VIS_GEN_CASCADE] = "cascade",
	[VIS_GEN_TILES] = "tiles",
	[VIS_GEN_NESTED] = "nested",
	[VIS_GEN_SHAPED] = "shaped",
	[VIS_GEN_TRANSLUCENT] = "translucent",
};

/* Names a kind as `visctl gen` spells it. */
const char *vis_gen_kind_name(enum vis_gen_kind kind)
{
	return (unsigned)kind < VIS_GEN_KIND_COUNT ? kind_names[kind] : "invalid";
}

/* Maps a command-line kind name back to the kind. */
int vis_gen_kind_from_name(const char *name, enum vis_gen_kind *kind)
{
	for (int i = 0; i < VIS_GEN_KIND_COUNT; i++) {
		if (strcmp(name, kind_names[i]) == 0) {
			*kind = (enum vis_gen_kind)i;
			return 0;
		}
	}
	return -1;
}

/* What every generator needs: the scene being filled, the screen size and the random stream. */
struct gen {
	struct vis_scene *scene;
	struct vis_rng rng;
	int64_t sw, sh;
};

/* Appends the next window, numbering IDs 1…n bottom-to-top as they are pushed. */
static int put(struct gen *g, int64_t x, int64_t y, int64_t w, int64_t h)
{
	struct vis_rect r = { (int32_t)x, (int32_t)y, (int32_t)w, (int32_t)h };
	return vis_scene_push(g->scene, (uint32_t)(g->scene->n + 1), r);
}

/* The smaller of two coordinates. */
static int64_t min64(int64_t a, int64_t b)
{
	return a < b ? a : b;
}

/* The larger of two coordinates. */
static int64_t max64(int64_t a, int64_t b)
{
	return a > b ? a : b;
}

/* A number in [lo, hi], or lo when the range is empty (tiny screens make some ranges so). */
static int64_t range(struct gen *g, int64_t lo, int64_t hi)
{
	return hi <= lo ? lo : vis_rng_range(&g->rng, lo, hi);
}

/*
 * Desktop-like windows: mostly 200…1600 × 150…1200 and on-screen; about 2% maximized, 5% partly
 * and 1% wholly off-screen (sometimes just touching the edge from outside), on every side.
 */
static int gen_random(struct gen *g, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		uint64_t roll = vis_rng_below(&g->rng, 1000);
		int64_t w = min64(range(g, 200, 1600), g->sw);
		int64_t h = min64(range(g, 150, 1200), g->sh);
		int64_t x = range(g, 0, g->sw - w);
		int64_t y = range(g, 0, g->sh - h);
		int side = (int)vis_rng_below(&g->rng, 4);

		if (roll < 20) {
			x = 0, y = 0, w = g->sw, h = g->sh;
		} else if (roll < 30) {
			/* Wholly off-screen; an offset of 0 only touches the edge, which must not count. */
			int64_t off = range(g, 0, 1000);
			switch (side) {
			case 0: x = -w - off; break;
			case 1: x = g->sw + min64(off, INT32_MAX - g->sw); break;
			case 2: y = -h - off; break;
			default: y = g->sh + min64(off, INT32_MAX - g->sh); break;
			}
		} else if (roll < 80) {
			/* Partly off-screen: at least one pixel column or row on each side of the edge. */
			switch (side) {
			case 0: x = -range(g, 1, max64(1, w - 1)); break;
			case 1: x = g->sw - w + range(g, 1, max64(1, w - 1)); break;
			case 2: y = -range(g, 1, max64(1, h - 1)); break;
			default: y = g->sh - h + range(g, 1, max64(1, h - 1)); break;
			}
			if (x > INT32_MAX)
				x = INT32_MAX;
			if (y > INT32_MAX)
				y = INT32_MAX;
		}
		if (put(g, x, y, w, h) < 0)
			return -1;
	}
	return 0;
}

/* Rectangles with no structure: corners uniform in [0, 10^6)², sides uniform in [1, 10^5]. */
static int gen_uniform(struct gen *g, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		int64_t x = range(g, 0, 999999);
		int64_t y = range(g, 0, 999999);
		int64_t w = range(g, 1, 100000);
		int64_t h = range(g, 1, 100000);
		if (put(g, x, y, w, h) < 0)
			return -1;
	}
	return 0;
}

/*
 * The paper's Figure 1, where the visible pieces number Θ(n²): n/2 vertical bars of width 1 at
 * x = 1, 3, 5, … spanning the full height, under n − n/2 horizontal bars of height 1 at
 * y = 1, 3, 5, … spanning the full width (the extra bar of an odd n is horizontal). Row 0 is free,
 * so every bar is visible. The screen is set to exactly the bounding box, whatever was asked, so
 * every crossing is on-screen.
 */
static int gen_grid(struct gen *g, size_t n)
{
	int64_t nv = (int64_t)(n / 2), nh = (int64_t)(n - n / 2);
	int64_t gw = 2 * nv + 1, gh = 2 * nh + 1;

	if (gw > INT32_MAX || gh > INT32_MAX) {
		errno = EINVAL;
		return -1;
	}
	g->scene->has_screen = true;
	g->scene->screen_w = (int32_t)gw;
	g->scene->screen_h = (int32_t)gh;
	for (int64_t i = 0; i < nv; i++)
		if (put(g, 2 * i + 1, 0, 1, gh) < 0)
			return -1;
	for (int64_t j = 0; j < nh; j++)
		if (put(g, 0, 2 * j + 1, gw, 1) < 0)
			return -1;
	return 0;
}

/*
 * A cascade: windows of one size (drawn from the seed, clamped to the screen), each k pixels right
 * of and below the one under it; when the next would run off the screen it wraps to the top-left,
 * shifted right a little each round so rounds do not stack exactly.
 */
static int gen_cascade(struct gen *g, size_t n)
{
	int64_t w = min64(range(g, 400, 1200), g->sw);
	int64_t h = min64(range(g, 300, 900), g->sh);
	int64_t k = range(g, 8, 40);
	int64_t steps = min64((g->sw - w) / k, (g->sh - h) / k) + 1;

	for (size_t i = 0; i < n; i++) {
		uint64_t j = i % (uint64_t)steps, round = i / (uint64_t)steps;
		int64_t x = (int64_t)((j * (uint64_t)k + round * 5) % (uint64_t)(g->sw - w + 1));
		int64_t y = (int64_t)(j * (uint64_t)k);
		if (put(g, x, y, w, h) < 0)
			return -1;
	}
	return 0;
}

/*
 * A tiled desktop: cols × rows tiles (about n/2, no more than the screen has pixels) that cover the
 * screen exactly and abut without overlapping, cell edges at c·W/cols; then popups of varied size,
 * on-screen, on top.
 */
static int gen_tiles(struct gen *g, size_t n)
{
	int64_t want = (int64_t)((n + 1) / 2);
	int64_t cols = 0, rows = 0;

	if (want > 0) {
		cols = (int64_t)llround(sqrt((double)want * (double)g->sw / (double)g->sh));
		cols = max64(1, min64(cols, min64(want, g->sw)));
		rows = max64(1, min64(want / cols, g->sh));
	}
	for (int64_t r = 0; r < rows; r++) {
		int64_t y1 = r * g->sh / rows, y2 = (r + 1) * g->sh / rows;
		for (int64_t c = 0; c < cols; c++) {
			int64_t x1 = c * g->sw / cols, x2 = (c + 1) * g->sw / cols;
			if (put(g, x1, y1, x2 - x1, y2 - y1) < 0)
				return -1;
		}
	}
	for (size_t i = (size_t)(cols * rows); i < n; i++) {
		int64_t w = min64(range(g, 50, 900), g->sw);
		int64_t h = min64(range(g, 30, 700), g->sh);
		if (put(g, range(g, 0, g->sw - w), range(g, 0, g->sh - h), w, h) < 0)
			return -1;
	}
	return 0;
}

/*
 * Many small windows under max(1, n/1000) large ones: 85% of the small ones lie wholly inside a
 * large window, 10% straddle one of its edges and 5% land anywhere, so some peek out.
 */
static int gen_nested(struct gen *g, size_t n)
{
	size_t nbig = n == 0 ? 0 : n / 1000 > 1 ? n / 1000 : 1;
	struct vis_rect *big = NULL;

	if (nbig > 0 && (big = calloc(nbig, sizeof(*big))) == NULL)
		return -1;
	for (size_t b = 0; b < nbig; b++) {
		int64_t w = max64(1, g->sw * range(g, 40, 90) / 100);
		int64_t h = max64(1, g->sh * range(g, 40, 90) / 100);
		big[b] = (struct vis_rect){ (int32_t)range(g, 0, g->sw - w),
					    (int32_t)range(g, 0, g->sh - h), (int32_t)w, (int32_t)h };
	}
	for (size_t i = 0; i < n - nbig; i++) {
		const struct vis_rect *b = &big[vis_rng_below(&g->rng, nbig)];
		uint64_t roll = vis_rng_below(&g->rng, 100);
		int64_t w = min64(range(g, 20, 200), g->sw);
		int64_t h = min64(range(g, 20, 200), g->sh);
		int64_t x, y;

		if (roll < 85) {
			w = min64(w, b->w), h = min64(h, b->h);
			x = range(g, b->x, b->x + b->w - w);
			y = range(g, b->y, b->y + b->h - h);
		} else if (roll < 95) {
			/* Centred on the big window's left or right edge, so it is cut in two. */
			x = (vis_rng_below(&g->rng, 2) ? b->x : (int64_t)b->x + b->w) - w / 2;
			y = range(g, b->y, (int64_t)b->y + b->h - 1);
		} else {
			x = range(g, 0, g->sw - w);
			y = range(g, 0, g->sh - h);
		}
		if (put(g, x, y, w, h) < 0) {
			free(big);
			return -1;
		}
	}
	for (size_t b = 0; b < nbig; b++) {
		if (put(g, big[b].x, big[b].y, big[b].w, big[b].h) < 0) {
			free(big);
			return -1;
		}
	}
	free(big);
	return 0;
}

/* Gives window i (inside w × h, border b) rounded corners of radius r: a rectangle a row. */
static int round_corners(struct vis_look *look, int64_t w, int64_t h, int64_t b, int64_t r)
{
	int64_t bw = w + 2 * b, bh = h + 2 * b;
	look->shape = malloc((size_t)(2 * r + 1) * sizeof(*look->shape));
	if (look->shape == NULL)
		return -1;
	look->shaped = true;
	look->n_shape = 0;
	for (int64_t y = 0; y < r; y++) {
		/* The row's inset: where the circle of radius r about (r, r) crosses the row's middle. */
		double dy = (double)r - (double)y - 0.5;
		int64_t inset = r - (int64_t)sqrt((double)(r * r) - dy * dy);
		look->shape[look->n_shape++] = (struct vis_rect){ (int32_t)(inset - b), (int32_t)(y - b),
								  (int32_t)(bw - 2 * inset), 1 };
		look->shape[look->n_shape++] = (struct vis_rect){
			(int32_t)(inset - b), (int32_t)(bh - 1 - y - b), (int32_t)(bw - 2 * inset), 1 };
	}
	look->shape[look->n_shape++] = (struct vis_rect){ (int32_t)-b, (int32_t)(r - b), (int32_t)bw,
							  (int32_t)(bh - 2 * r) };
	return 0;
}

/* random's windows with rounded corners, L shapes and borders. */
static int gen_shaped(struct gen *g, size_t n)
{
	if (gen_random(g, n) < 0)
		return -1;
	for (size_t i = 0; i < n; i++) {
		struct vis_rect *rect = &g->scene->rects[i];
		uint64_t roll = vis_rng_below(&g->rng, 10);
		int64_t b = vis_rng_below(&g->rng, 10) < 3 ? range(g, 1, 3) : 0;
		/* The border grows the box: keep it within 31 bits. */
		if ((int64_t)rect->w + 2 * b > INT32_MAX || (int64_t)rect->h + 2 * b > INT32_MAX)
			b = 0;
		struct vis_look *look = vis_scene_look(g->scene, i);
		if (look == NULL)
			return -1;
		look->border = (int32_t)b;
		int64_t w = rect->w, h = rect->h, bw = w + 2 * b, bh = h + 2 * b;
		if (vis_look_check(*rect, &(struct vis_look){ .border = (int32_t)b, .shaped = true }))
			continue; /* too near the plane's end for pieces: stays a plain box */
		if (roll < 4 && bw >= 17 && bh >= 17) {
			if (round_corners(look, w, h, b, range(g, 4, 8)) < 0)
				return -1;
		} else if (roll < 6 && bw >= 2 && bh >= 2) {
			look->shape = malloc(2 * sizeof(*look->shape));
			if (look->shape == NULL)
				return -1;
			look->shaped = true;
			look->n_shape = 2;
			look->shape[0] = (struct vis_rect){ (int32_t)-b, (int32_t)-b, (int32_t)bw,
							    (int32_t)(bh / 2) };
			look->shape[1] = (struct vis_rect){ (int32_t)-b, (int32_t)(bh / 2 - b),
							    (int32_t)(bw / 2), (int32_t)(bh - bh / 2) };
		}
	}
	return 0;
}

/* random's windows with client-side shadows, and a few wholly translucent ones. */
static int gen_translucent(struct gen *g, size_t n)
{
	if (gen_random(g, n) < 0)
		return -1;
	for (size_t i = 0; i < n; i++) {
		struct vis_rect *rect = &g->scene->rects[i];
		uint64_t roll = vis_rng_below(&g->rng, 60);
		int64_t m = range(g, 8, 40);
		if (roll >= 23)
			continue;
		struct vis_look *look = vis_scene_look(g->scene, i);
		if (look == NULL)
			return -1;
		if (roll < 3) {
			look->opaque = VIS_OPAQUE_NONE;
			continue;
		}
		/* The shadow: a margin of m around an opaque inside, when the window has room. */
		if (rect->w <= 2 * m || rect->h <= 2 * m)
			continue;
		struct vis_look shadow = { .opaque = VIS_OPAQUE_RECTS };
		if (vis_look_check(*rect, &shadow) != NULL)
			continue;
		look->opaque_rects = malloc(sizeof(*look->opaque_rects));
		if (look->opaque_rects == NULL)
			return -1;
		look->opaque = VIS_OPAQUE_RECTS;
		look->n_opaque = 1;
		look->opaque_rects[0] = (struct vis_rect){ (int32_t)m, (int32_t)m, (int32_t)(rect->w - 2 * m),
							   (int32_t)(rect->h - 2 * m) };
	}
	return 0;
}

/* Checks the arguments, sets up the screen and the random stream, and runs the kind's generator. */
int vis_gen(struct vis_scene *scene, enum vis_gen_kind kind, size_t n, uint64_t seed,
	    int32_t screen_w, int32_t screen_h)
{
	/* IDs run 1…n and must fit in 32 bits. */
	if (screen_w < 0 || screen_h < 0 || (uint64_t)n > UINT32_MAX ||
	    (unsigned)kind >= VIS_GEN_KIND_COUNT) {
		errno = EINVAL;
		return -1;
	}

	struct gen g = {
		.scene = scene,
		.rng = { seed },
		.sw = screen_w ? screen_w : VIS_GEN_SCREEN_W,
		.sh = screen_h ? screen_h : VIS_GEN_SCREEN_H,
	};
	/* uniform is unclipped unless a size was asked for; the others live on a screen. */
	if (kind != VIS_GEN_UNIFORM || screen_w != 0 || screen_h != 0) {
		scene->has_screen = true;
		scene->screen_w = (int32_t)g.sw;
		scene->screen_h = (int32_t)g.sh;
	}

	int ret = -1;
	switch (kind) {
	case VIS_GEN_RANDOM: ret = gen_random(&g, n); break;
	case VIS_GEN_UNIFORM: ret = gen_uniform(&g, n); break;
	case VIS_GEN_GRID: ret = gen_grid(&g, n); break;
	case VIS_GEN_CASCADE: ret = gen_cascade(&g, n); break;
	case VIS_GEN_TILES: ret = gen_tiles(&g, n); break;
	case VIS_GEN_NESTED: ret = gen_nested(&g, n); break;
	case VIS_GEN_SHAPED: ret = gen_shaped(&g, n); break;
	case VIS_GEN_TRANSLUCENT: ret = gen_translucent(&g, n); break;
	}
	if (ret < 0) {
		int e = errno;
		vis_scene_finish(scene);
		errno = e;
	}
	return ret;
}
