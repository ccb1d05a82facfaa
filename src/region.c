/*
 * The region method, as X.Org, wlroots and weston compute visibility: walk the stack from the
 * top down, keeping the union of the windows above as a pixman region, and classify each window
 * by how its on-screen box meets that union; a see-through window is classified but not added.
 * It is the baseline the sweeps are measured against, so it stays the straightforward method,
 * done carefully.
 */
#include <errno.h>
#include <math.h>
#include <pixman.h>
#include <stdlib.h>

#include "coords.h"
#include "engine.h"

/*
 * pixman boxes have int32 edges, and pixman computes with them (widths, band heights) in int,
 * so edges must stay well inside the int32 range. Scenes whose edges do not are run on ranks.
 */
#define COORD_LIMIT ((int64_t)1 << 30)

/* Whether a clipped box has an edge pixman cannot be trusted with. */
static bool box_too_far(struct vis_box b)
{
	return b.x1 < -COORD_LIMIT || b.x2 > COORD_LIMIT ||
	       b.y1 < -COORD_LIMIT || b.y2 > COORD_LIMIT;
}

/*
 * Fills boxes[i] with window i's clipped box in rank coordinates: each distinct x edge (and each
 * distinct y edge) replaced by its rank. The map is strictly increasing, so every box keeps its
 * emptiness and every pair of boxes the same containment and overlap, which leaves every state
 * unchanged. Empty boxes are stored as all-zero. Returns 0, or -1 with errno set.
 */
static int compress(const struct vis_stack *stack, pixman_box32_t *boxes)
{
	struct vis_coords co;

	/* Ranks go up to 2n - 1 and must stay within pixman's comfortable range. */
	if (stack->n > (size_t)(COORD_LIMIT / 2)) {
		errno = EOVERFLOW;
		return -1;
	}
	if (vis_coords_init(&co, stack) < 0)
		return -1;
	for (size_t i = 0; i < stack->n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		pixman_box32_t *r = &boxes[i];
		if (vis_box_empty(b)) {
			r->x1 = r->y1 = r->x2 = r->y2 = 0;
			continue;
		}
		r->x1 = (int32_t)vis_coords_rank_x(&co, b.x1);
		r->x2 = (int32_t)vis_coords_rank_x(&co, b.x2);
		r->y1 = (int32_t)vis_coords_rank_y(&co, b.y1);
		r->y2 = (int32_t)vis_coords_rank_y(&co, b.y2);
	}
	vis_coords_finish(&co);
	return 0;
}

/* ⌊log2 x⌋ + 1 for x > 0, 0 for 0. */
static uint64_t ilog2(uint64_t x)
{
	uint64_t r = 0;
	while (x) {
		x >>= 1;
		r++;
	}
	return r;
}


/*
 * The forecast of the walk's remaining work, made at checkpoints: whenever the windows walked or
 * the work done have doubled since the last one. Over the last half of the windows walked (from
 * the latest checkpoint at or before k / 2) it measures the share f of the windows that were added
 * to the union rather than found inside it, how fast the union's box count r grew (rho boxes a
 * window), and how fast the part of the union's extents that the union leaves uncovered, q, shrank
 * (as e^-λk). New boxes and additions both come from windows that land on the uncovered part, so
 * both are damped by e^-λt, t windows on: each window costs its test, 1 + log2 r, and is added at
 * the rate f e^-λt, at the cost of the union's r + rho (1 - e^-λt) / λ boxes then. So a union that
 * keeps growing (the grid, a cascade's first round: λ = 0) is extrapolated quadratically, one that
 * has stopped growing linearly, and one that is closing the uncovered part (uniform) is summed to
 * where it closes. It is rough (measured: 0.3–0.8 times the rest on uniform at the first forecast,
 * far above it on a cascade's first round, far below it on the grid, whose growth itself grows),
 * but it need only fall on the right side of the rival, which on the benchmark's scenes it does
 * by a factor of 1.4 or more (uniform n = 10^4, near the crossover, is the closest at 0.71 of the
 * price; the tables are in docs/ENGINES.md); a miss costs at most the work to the next
 * checkpoint, one doubling.
 */
#define FORECAST_MAX 130 /* checkpoints: k and the work double at most 64 times each */

/*
 * A forecast that the rival is cheaper is acted on alone when the windows it was measured on are
 * evidently this many windows or more, else only when the next one agrees (forecast_exceeds()).
 */
#define WINDOWS_TO_TRUST 16

/*
 * A forecast that the rival is cheaper is acted on while the work done is early
 * (VIS_RIVAL_EARLY, engine.h), or once it has reached 1/LEAD of the rival: a forecast that is
 * wrong then costs at most 1 + LEAD times the region method's time, one that is right 1 + 1/LEAD
 * times the rival's (a ski rental with advice; auto.c).
 */
#define LEAD 2

/*
 * A forecast is acted on only when the windows left are at most this many times those its rates
 * were measured on: a cascade's first few dozen windows, all added, would speak for a million.
 */
#define EXTRAPOLATION_MAX 2048

/*
 * A forecast speaks for the next HORIZON times the windows it was measured on at most, and the
 * hand-over is taken when the work it forecasts for them alone exceeds the rival's: a sure sign.
 */
#define HORIZON 8

struct checkpoint {
	size_t k;        /* windows walked */
	size_t added;    /* windows added to the union among them */
	double r;        /* the union's boxes */
	double q, ql;    /* the uncovered share of the union's extents, of the landing area */
	double area;     /* the union's area */
	double laid;     /* the areas of the windows added, summed */
};

struct forecast {
	const struct vis_stack *stack;
	struct vis_rival rival; /* the other method's cost, in units of work */
	const pixman_box32_t *boxes; /* the walk's boxes, if it has its own */
	pixman_box32_t area;    /* where windows can land (landing_area()), once count > 0 */
	size_t k_next;          /* the next checkpoint: windows walked, */
	uint64_t work_next;     /* or work done */
	size_t count, base;     /* checkpoints so far; the latest at or before half the current k */
	bool sharpened;         /* the rival's sharpen() called: from then on at every checkpoint */
	bool measured;          /* what it returned is a measurement, not an estimate */
	unsigned agreed;        /* forecasts allowed to act, in a row, that the rival is cheaper */
	struct checkpoint at[FORECAST_MAX];
};

/*
 * The area windows can land on, in the walk's coordinates: the screen, or without one the hull of
 * every window, made at the first forecast (O(n)). A union's own extents would not do: a
 * cascade's grow with it, so the part of them it leaves uncovered never shrinks however much of
 * the area it has covered, and its first round, every window added, looks like the grid.
 */
static pixman_box32_t landing_area(const struct vis_stack *stack, const pixman_box32_t *boxes)
{
	pixman_box32_t h = { INT32_MAX, INT32_MAX, INT32_MIN, INT32_MIN };

	if (stack->has_screen && boxes == NULL)
		return (pixman_box32_t){ 0, 0, (int32_t)stack->screen_w, (int32_t)stack->screen_h };
	for (size_t i = 0; i < stack->n; i++) {
		pixman_box32_t b;
		if (boxes != NULL) {
			b = boxes[i];
		} else {
			struct vis_box c = vis_stack_clip(stack, i);
			b = (pixman_box32_t){ (int32_t)c.x1, (int32_t)c.y1, (int32_t)c.x2,
					      (int32_t)c.y2 };
		}
		if (b.x1 >= b.x2 || b.y1 >= b.y2)
			continue;
		h.x1 = b.x1 < h.x1 ? b.x1 : h.x1;
		h.y1 = b.y1 < h.y1 ? b.y1 : h.y1;
		h.x2 = b.x2 > h.x2 ? b.x2 : h.x2;
		h.y2 = b.y2 > h.y2 ? b.y2 : h.y2;
	}
	return h;
}

/* A box's area. */
static double box_area(const pixman_box32_t *b)
{
	return (double)((int64_t)b->x2 - b->x1) * (double)((int64_t)b->y2 - b->y1);
}

/* The part of box e that the union, of the given area inside it, does not cover: in [0, 1]. */
static double uncovered(double area, const pixman_box32_t *e)
{
	double hull = box_area(e);

	if (hull <= 0)
		return 1;
	return area >= hull ? 0 : 1 - area / hull;
}

/* The union's area. O(r). */
static double union_area(pixman_region32_t *above)
{
	int nb;
	const pixman_box32_t *b = pixman_region32_rectangles(above, &nb);
	double area = 0;

	for (int i = 0; i < nb; i++)
		area += box_area(&b[i]);
	return area;
}

/* Σ e^-at over the m windows to come, as an integral: (1 - e^-am) / a, m when a = 0. */
static double damped(double a, double m)
{
	if (isinf(a))
		return 0;
	return a * m < 1e-9 ? m : -expm1(-a * m) / a;
}

/*
 * The rest of the walk, forecast at checkpoint now from the rates over the windows since b (see
 * above), m windows being left.
 */
static double rest_of_walk(const struct checkpoint *b, const struct checkpoint *now, double m)
{
	double dk = (double)(now->k - b->k);
	double share = (double)(now->added - b->added) / dk;
	double rho = now->r > b->r ? (now->r - b->r) / dk : 0;
	double lambda, grown;

	if (now->q <= 0 || now->ql <= 0 || share <= 0)
		lambda = INFINITY;
	else if (now->q < b->q)
		lambda = log(b->q / now->q) / dk;
	else
		lambda = 0;
	/*
	 * A union also closes when the windows added bring it little new area, (1 - nu) of their
	 * own: they are landing on it (a cascade's overlapping windows), and once it covers the
	 * area windows land on, it holds the later ones. Its extents cannot show that, growing with
	 * it (a cascade's first round, all added, would look like the grid), so the closing is
	 * measured on the landing area, weighted by 1 - nu: windows that lay new ground (the
	 * grid's bars) keep it from counting at all.
	 */
	double laid = now->laid - b->laid;
	double nu = laid > 0 ? (now->area - b->area) / laid : 1;
	nu = nu < 0 ? 0 : nu > 1 ? 1 : nu;
	if (!isinf(lambda) && now->ql < b->ql && (1 - nu) * log(b->ql / now->ql) / dk > lambda)
		lambda = (1 - nu) * log(b->ql / now->ql) / dk;
	/*
	 * The share added is itself a measure of coverage: had windows been landing on the union
	 * at rate λ since the top, it would be e^-λk. A union that holds most windows already (a
	 * desktop's, q's changes being noise there) stops growing.
	 */
	if (share < 1 && -log(share) / (double)now->k > lambda)
		lambda = -log(share) / (double)now->k;
	/* Σ e^-λt (1 - e^-λt) / λ = (D(λ) - D(2λ)) / λ, which tends to m² / 2 with λ. */
	if (isinf(lambda))
		grown = 0;
	else if (lambda * m < 1e-6)
		grown = m * m / 2;
	else
		grown = (damped(lambda, m) - damped(2 * lambda, m)) / lambda;
	return m * (1 + (double)ilog2((uint64_t)now->r)) +
	       share * (now->r * damped(lambda, m) + rho * grown);
}

/*
 * Whether at least WINDOWS_TO_TRUST of the windows walked from the (n - 1 - from)th down to the
 * (n - 1 - to)th overlap the window with pixels walked just before them. O(to - from), counted
 * only when a forecast asks, so that the walk itself pays nothing for it.
 */
static bool many_windows(const struct vis_stack *stack, size_t from, size_t to)
{
	struct vis_box last = { 0, 0, 0, 0 }; /* empty: meets nothing */
	size_t overlaps = 0;

	for (size_t i = stack->n - from; i-- > stack->n - to && overlaps < WINDOWS_TO_TRUST;) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		if (!vis_box_empty(vis_box_intersect(b, last)))
			overlaps++;
		last = b;
	}
	return overlaps >= WINDOWS_TO_TRUST;
}

/* The work at which the walk gives up whatever the forecast: the rival measured, twice it
 * estimated (hand_over()). */
static uint64_t cap_of(const struct forecast *f)
{
	uint64_t units = f->rival.units;
	if (f->measured)
		return units;
	return units > (UINT64_MAX - 1) / 2 ? UINT64_MAX : 2 * units + 1;
}

/*
 * Whether to hand over at a checkpoint, the rival's units as they stand (forecast_exceeds()).
 * A measured rival is a ski rental's price: the cap is the rival, and a forecast is acted on early
 * or from 1/LEAD of it. An estimate may be wrong either way, so the cap is twice it, and a
 * forecast is acted on only where it has the walk passing that cap anyway (a hand-over then
 * costs less than one at the cap): an agreed one at any time, a lone one only early.
 */
static bool hand_over(const struct forecast *f, const struct checkpoint *b, size_t k, double rest,
		      bool actionable, uint64_t work)
{
	uint64_t units = f->rival.units;
	bool early = work <= units / VIS_RIVAL_EARLY;

	if (work >= cap_of(f))
		return true;
	if (!actionable || rest <= (double)units)
		return false;
	if (f->measured && !early && work < units / LEAD)
		return false;
	if (!f->measured && (double)work + rest <= (double)cap_of(f))
		return false;
	return f->agreed >= 2 || (early && many_windows(f->stack, b->k, k)) ||
	       (f->measured && many_windows(f->stack, b->k, k));
}

/*
 * A checkpoint after k of n windows, added of them added to the union (laid their areas summed),
 * work units in all: returns whether to hand over to the rival, and sets the next checkpoint.
 * The walk gives up once its work reaches the rival's (the cap: a forecast can be wrong, and this
 * bounds what trusting it can cost), or once it has reached 1/LEAD of it and the rest is forecast
 * to cost more than the rival. Such a forecast is trusted alone when at least WINDOWS_TO_TRUST of
 * the windows it measured overlap the window walked before them (a window's pieces, a shaped
 * window's rows, are disjoint, so each such overlap begins another window); otherwise the next
 * forecast must agree: the windows since the last checkpoint can be a single window's pieces, all
 * added, which look like the grid's bars, and a late forecast can be a union's passing jump in
 * boxes. A rival that can be sharpened is sharpened from the first checkpoint where the work, or
 * a forecast that may be acted on, passes its floor, and at every one after; and before any
 * hand-over, which is then decided again on what it says.
 */
static bool forecast_exceeds(struct forecast *f, pixman_region32_t *above, size_t k, size_t n,
			     size_t added, double laid, uint64_t work)
{
	struct checkpoint now = {
		.k = k,
		.added = added,
		.r = (double)pixman_region32_n_rects(above),
		.area = union_area(above),
		.laid = laid,
	};
	const struct checkpoint *b = NULL;
	double rest = 0;
	bool over, actionable = false;

	if (f->count == 0)
		f->area = landing_area(f->stack, f->boxes);
	now.q = uncovered(now.area, pixman_region32_extents(above));
	now.ql = uncovered(now.area, &f->area);
	while (f->base + 1 < f->count && f->at[f->base + 1].k <= k / 2)
		f->base++;
	if (f->count > 0 && f->at[f->base].k <= k / 2) {
		b = &f->at[f->base];
		double h = (double)HORIZON * (double)k;
		rest = rest_of_walk(b, &now, (double)(n - k) < h ? (double)(n - k) : h);
		actionable = (double)(n - k) <= EXTRAPOLATION_MAX * (double)(k - b->k);
	}
	if (f->rival.sharpen != NULL &&
	    (f->sharpened || work >= f->rival.floor || (actionable && rest > (double)f->rival.floor))) {
		f->rival.units = f->rival.sharpen(f->stack, f->rival.data, work, false, &f->measured);
		f->sharpened = true;
	}
	if (actionable)
		f->agreed = rest > (double)f->rival.units ? f->agreed + 1 : 0;
	over = hand_over(f, b, k, rest, actionable, work);
	if (over && f->rival.sharpen != NULL) {
		f->rival.units = f->rival.sharpen(f->stack, f->rival.data, work, true, &f->measured);
		f->sharpened = true;
		over = hand_over(f, b, k, rest, actionable, work);
	}
	if (f->count < FORECAST_MAX)
		f->at[f->count++] = now;

	uint64_t cap = cap_of(f), lead = f->rival.units / LEAD;
	f->k_next = 2 * k;
	f->work_next = work < cap / 2 ? 2 * work : cap;
	if (work < lead && f->work_next > lead)
		f->work_next = lead;
	if (f->rival.sharpen != NULL && !f->sharpened && work < f->rival.floor &&
	    f->work_next > f->rival.floor)
		f->work_next = f->rival.floor;
	return over;
}

/*
 * The top-down walk. boxes, when not NULL, holds every window's clipped box (in rank
 * coordinates); otherwise the boxes are clipped on the fly, their edges being small enough.
 * Returns 1 once the work (see vis_region_compute_within()) passes budget.
 */
static int walk(const struct vis_stack *stack, const pixman_box32_t *boxes, uint8_t *states,
		uint64_t budget, struct forecast *f)
{
	/*
	 * The union lives in two regions used in turn, each union written into the other one:
	 * pixman gives an operation whose destination is also its source a freshly allocated box
	 * array every time, which for a large union costs more than the union itself, while a
	 * separate destination keeps its array from one window to the next.
	 */
	pixman_region32_t regions[2], *above = &regions[0], *spare = &regions[1];
	uint64_t work = 0;
	size_t added = 0;
	double laid = 0;
	int ret = 0;

	pixman_region32_init(above);
	pixman_region32_init(spare);
	if (f != NULL)
		f->boxes = boxes;
	for (size_t i = stack->n; i-- > 0;) {
		pixman_box32_t box;

		if (boxes != NULL) {
			box = boxes[i];
		} else {
			struct vis_box b = vis_stack_clip(stack, i);
			box.x1 = (int32_t)b.x1;
			box.y1 = (int32_t)b.y1;
			box.x2 = (int32_t)b.x2;
			box.y2 = (int32_t)b.y2;
		}
		if (f != NULL && (stack->n - 1 - i >= f->k_next || work >= f->work_next) &&
		    forecast_exceeds(f, above, stack->n - 1 - i, stack->n, added, laid, work)) {
			ret = 1;
			break;
		}
		if (box.x1 >= box.x2 || box.y1 >= box.y2) {
			states[i] = VIS_FULLY_OBSCURED;
			continue;
		}
		/*
		 * The test binary-searches the union's bands, then reads the boxes beside the
		 * window; a union reads every box. Count both so, since a window under a union
		 * that holds it costs little and the unions are what grow quadratic.
		 */
		uint64_t boxes_above = (uint64_t)pixman_region32_n_rects(above);
		work += 1 + ilog2(boxes_above);
		if (work > budget) {
			ret = 1;
			break;
		}
		switch (pixman_region32_contains_rectangle(above, &box)) {
		case PIXMAN_REGION_IN:
			/* The union already holds the box: nothing to add. */
			states[i] = VIS_FULLY_OBSCURED;
			continue;
		case PIXMAN_REGION_OUT:
			states[i] = vis_stack_on_screen(stack, i) ? VIS_UNOBSCURED
								  : VIS_PARTIALLY_OBSCURED;
			break;
		case PIXMAN_REGION_PART:
		default:
			states[i] = VIS_PARTIALLY_OBSCURED;
			break;
		}
		if (!vis_stack_opaque(stack, i))
			continue; /* it hides nothing: the union above stays */
		work += boxes_above;
		added++;
		laid += box_area(&box);
		/* union_rect builds its one-box operand on the stack: no allocation for it. */
		if (!pixman_region32_union_rect(spare, above, box.x1, box.y1,
						(unsigned)(box.x2 - box.x1),
						(unsigned)(box.y2 - box.y1))) {
			errno = ENOMEM;
			ret = -1;
			break;
		}
		pixman_region32_t *t = above;
		above = spare;
		spare = t;
	}
	pixman_region32_fini(above);
	pixman_region32_fini(spare);
	return ret;
}

/* The walk on the window's own edges, or on their ranks where pixman could not take them. */
static int run(const struct vis_stack *stack, uint8_t *states, uint64_t budget, struct forecast *f)
{
	pixman_box32_t *boxes;
	bool far = false;
	int ret;

	for (size_t i = 0; i < stack->n && !far; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		far = !vis_box_empty(b) && box_too_far(b);
	}
	if (!far)
		return walk(stack, NULL, states, budget, f);

	/*
	 * Some edge lies beyond ±2^30: run on the ranks of the edges instead, which pixman handles
	 * safely and which give the same states (see compress()).
	 */
	if (stack->n > SIZE_MAX / sizeof *boxes) {
		errno = EOVERFLOW;
		return -1;
	}
	boxes = malloc(stack->n * sizeof *boxes);
	if (boxes == NULL) {
		errno = ENOMEM;
		return -1;
	}
	ret = compress(stack, boxes);
	if (ret == 0)
		ret = walk(stack, boxes, states, budget, f);
	free(boxes);
	return ret;
}

int vis_region_compute(const struct vis_stack *stack, uint8_t *states)
{
	/* No walk does 2^64 box steps, so the budget is never exceeded. */
	return run(stack, states, UINT64_MAX, NULL);
}

/*
 * The work counted is, for each window with pixels on the screen, one plus the number of boxes
 * of the union above it, once for the containment test and once more for the union when there
 * is one: both scan the union's boxes, so the count bounds the time up to a constant.
 */
int vis_region_compute_within(const struct vis_stack *stack, uint8_t *states, uint64_t budget)
{
	return run(stack, states, budget, NULL);
}

/*
 * The first checkpoint comes after 16 windows or 2,048 units of work, the first forecast once the
 * windows walked have doubled since: fewer windows are too few to measure rates from. On small
 * stacks the sweep costs 40,000-70,000 units (n = 10^3), so a hand-over must come within a few
 * thousand units to cost it little; on large ones EXTRAPOLATION_MAX holds the forecasts back.
 */
int vis_region_compute_against(const struct vis_stack *stack, uint8_t *states,
			       const struct vis_rival *rival)
{
	struct forecast f = { .stack = stack, .rival = *rival, .k_next = 16, .work_next = 2048 };

	return run(stack, states, UINT64_MAX, &f);
}
