/*
 * The scene family: every parameter drawn from a range, so that the scenes cover what the fixed
 * generators of gen.c do not (window sizes from a few pixels to most of the screen, cascades of
 * any step, lattices with shared edges, bars that cross, clusters, no screen), and the draws come
 * from the splitmix64 stream in a fixed order, the same on every machine.
 */
#include <math.h>
#include <stdio.h>

#include "family.h"

static const char *const place_names[] = {
	[VIS_FAMILY_SCATTER] = "scatter",
	[VIS_FAMILY_CLUSTER] = "cluster",
	[VIS_FAMILY_CASCADE] = "cascade",
	[VIS_FAMILY_LATTICE] = "lattice",
};

/* A number in [0, 1). */
static double uniform(struct vis_rng *r)
{
	return (double)(vis_rng_next(r) >> 11) * 0x1p-53;
}

static double between(struct vis_rng *r, double lo, double hi)
{
	return lo + (hi - lo) * uniform(r);
}

/* A number in [lo, hi] whose logarithm is uniform: sizes and counts over orders of magnitude. */
static double log_between(struct vis_rng *r, double lo, double hi)
{
	return lo * pow(hi / lo, uniform(r));
}

/* A standard normal deviate (Box-Muller). */
static double normal(struct vis_rng *r)
{
	double u = uniform(r), v = uniform(r);
	return sqrt(-2 * log(1 - u)) * cos(2 * M_PI * v);
}

static int64_t clamp(double v, int64_t lo, int64_t hi)
{
	return v < (double)lo ? lo : v > (double)hi ? hi : (int64_t)v;
}

void vis_family_draw(struct vis_rng *r, size_t min_n, size_t max_n, struct vis_family *f)
{
	double lo = min_n ? (double)min_n : 1, hi = max_n > min_n ? (double)max_n : lo;
	f->n = (size_t)llround(log_between(r, lo, hi));
	f->screen = uniform(r) < 0.75;
	double side = f->screen ? log_between(r, 640, 7680) : log_between(r, 1e4, 1e6);
	f->w = (int32_t)side;
	f->h = (int32_t)clamp(side * between(r, 0.4, 1), 1, INT32_MAX);
	f->size = log_between(r, 0.004, 0.9);
	f->spread = pow(uniform(r), 2);
	f->aspect = log_between(r, 0.25, 4);
	f->thin = uniform(r) < 0.15 ? between(r, 0.1, 1) : 0;
	f->out = f->screen && uniform(r) < 0.5 ? between(r, 0, 0.3) : 0;
	double p = uniform(r);
	f->place = p < 0.35 ? VIS_FAMILY_SCATTER
		   : p < 0.55 ? VIS_FAMILY_CLUSTER
		   : p < 0.8  ? VIS_FAMILY_CASCADE
			      : VIS_FAMILY_LATTICE;
	f->clusters = 1 + (uint32_t)vis_rng_below(r, VIS_FAMILY_CLUSTERS_MAX);
	f->cluster_sigma = log_between(r, 0.01, 0.3);
	f->step_x = (int32_t)vis_rng_range(r, 1, 64) * (vis_rng_below(r, 4) ? 1 : -1);
	f->step_y = (int32_t)vis_rng_range(r, 0, 64);
	f->snap = uniform(r) < 0.3 ? (int32_t)1 << vis_rng_range(r, 1, 6) : 1;
}

/* Where the window i of side s starts along an axis of the area (length a): by the placement. */
static int64_t place(const struct vis_family *f, struct vis_rng *r, size_t i, int64_t a, int64_t s,
		     double centre, int32_t step, int64_t pitch)
{
	int64_t span = a - s > 0 ? a - s : 0;
	switch (f->place) {
	case VIS_FAMILY_CLUSTER:
		return clamp(centre * (double)a + normal(r) * f->cluster_sigma * (double)a -
				     (double)s / 2,
			     0, span);
	case VIS_FAMILY_CASCADE: {
		int64_t at = ((int64_t)i * step) % (span + 1);
		return at < 0 ? at + span + 1 : at;
	}
	case VIS_FAMILY_LATTICE:
		return (int64_t)vis_rng_below(r, (uint64_t)(a / pitch > 0 ? a / pitch : 1)) * pitch;
	default:
		return (int64_t)vis_rng_below(r, (uint64_t)span + 1);
	}
}

int vis_family_gen(struct vis_scene *scene, const struct vis_family *f, uint64_t seed)
{
	struct vis_rng r = { seed };
	int64_t w = f->w, h = f->h;
	scene->has_screen = f->screen;
	scene->screen_w = f->w;
	scene->screen_h = f->h;
	double mw = f->size * (double)w * sqrt(f->aspect), mh = f->size * (double)h / sqrt(f->aspect);
	int64_t pitch_x = clamp(mw, 1, w), pitch_y = clamp(mh, 1, h);
	double cx[VIS_FAMILY_CLUSTERS_MAX], cy[VIS_FAMILY_CLUSTERS_MAX];
	for (int k = 0; k < VIS_FAMILY_CLUSTERS_MAX; k++) {
		cx[k] = uniform(&r);
		cy[k] = uniform(&r);
	}
	for (size_t i = 0; i < f->n; i++) {
		int64_t ww = clamp(mw * exp(f->spread * normal(&r)), 1, w);
		int64_t wh = clamp(mh * exp(f->spread * normal(&r)), 1, h);
		if (f->place == VIS_FAMILY_LATTICE) {
			ww = pitch_x * (vis_rng_below(&r, 4) ? 1 : 2);
			wh = pitch_y * (vis_rng_below(&r, 4) ? 1 : 2);
		}
		if (uniform(&r) < f->thin) {
			/* A bar across or down, most of the area long. */
			bool across = vis_rng_below(&r, 2);
			int64_t t = vis_rng_range(&r, 1, 4);
			ww = across ? clamp((double)w * between(&r, 0.3, 1), 1, w) : t;
			wh = across ? t : clamp((double)h * between(&r, 0.3, 1), 1, h);
		}
		uint32_t k = (uint32_t)vis_rng_below(&r, f->clusters);
		int64_t x = place(f, &r, i, w, ww, cx[k], f->step_x, pitch_x);
		int64_t y = place(f, &r, i, h, wh, cy[k], f->step_y, pitch_y);
		if (uniform(&r) < f->out) {
			/* Partly outside, past a side at random. */
			switch (vis_rng_below(&r, 4)) {
			case 0: x = -(int64_t)((double)ww * between(&r, 0.1, 0.9)); break;
			case 1: x = w - (int64_t)((double)ww * between(&r, 0.1, 0.9)); break;
			case 2: y = -(int64_t)((double)wh * between(&r, 0.1, 0.9)); break;
			default: y = h - (int64_t)((double)wh * between(&r, 0.1, 0.9)); break;
			}
		}
		if (f->snap > 1) {
			/* Floors, not truncations: negative corners snap outwards too. */
			x = (x >= 0 ? x : x - f->snap + 1) / f->snap * f->snap;
			y = (y >= 0 ? y : y - f->snap + 1) / f->snap * f->snap;
			ww = ww / f->snap > 0 ? ww / f->snap * f->snap : f->snap;
			wh = wh / f->snap > 0 ? wh / f->snap * f->snap : f->snap;
		}
		struct vis_rect rect = { (int32_t)x, (int32_t)y, (int32_t)ww, (int32_t)wh };
		if (vis_scene_push(scene, (uint32_t)(i + 1), rect) < 0)
			return -1;
	}
	return 0;
}

int vis_family_describe(const struct vis_family *f, char *buf, size_t len)
{
	char where[64] = "";
	if (f->place == VIS_FAMILY_CLUSTER)
		snprintf(where, sizeof where, "(%u, sigma %.3f)", f->clusters, f->cluster_sigma);
	else if (f->place == VIS_FAMILY_CASCADE)
		snprintf(where, sizeof where, "(step %d,%d)", f->step_x, f->step_y);
	return snprintf(buf, len,
			"n=%zu %s=%dx%d size=%.3f spread=%.2f aspect=%.2f thin=%.2f out=%.2f "
			"place=%s%s snap=%d",
			f->n, f->screen ? "screen" : "area", f->w, f->h, f->size, f->spread, f->aspect,
			f->thin, f->out, place_names[f->place], where, f->snap);
}
