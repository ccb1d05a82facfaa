/*
 * The region method, as X.Org, wlroots and weston compute visibility: walk the stack from the
 * top down, keeping the union of the windows above as a pixman region, and classify each window
 * by how its on-screen box meets that union; a see-through window is classified but not added.
 * It is the baseline the sweeps are measured against, so it stays the straightforward method,
 * done carefully.
 */
#include <errno.h>
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
 * The top-down walk. boxes, when not NULL, holds every window's clipped box (in rank
 * coordinates); otherwise the boxes are clipped on the fly, their edges being small enough.
 * Returns 1 once the work (see vis_region_compute_within()) passes budget.
 */
static int walk(const struct vis_stack *stack, const pixman_box32_t *boxes, uint8_t *states,
		uint64_t budget)
{
	/*
	 * The union lives in two regions used in turn, each union written into the other one:
	 * pixman gives an operation whose destination is also its source a freshly allocated box
	 * array every time, which for a large union costs more than the union itself, while a
	 * separate destination keeps its array from one window to the next.
	 */
	pixman_region32_t regions[2], *above = &regions[0], *spare = &regions[1];
	uint64_t work = 0;
	int ret = 0;

	pixman_region32_init(above);
	pixman_region32_init(spare);
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

int vis_region_compute(const struct vis_stack *stack, uint8_t *states)
{
	/* No walk does 2^64 box steps, so the budget is never exceeded. */
	return vis_region_compute_within(stack, states, UINT64_MAX);
}

/*
 * The work counted is, for each window with pixels on the screen, one plus the number of boxes
 * of the union above it, once for the containment test and once more for the union when there
 * is one: both scan the union's boxes, so the count bounds the time up to a constant.
 */
int vis_region_compute_within(const struct vis_stack *stack, uint8_t *states, uint64_t budget)
{
	pixman_box32_t *boxes;
	bool far = false;
	int ret;

	for (size_t i = 0; i < stack->n && !far; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		far = !vis_box_empty(b) && box_too_far(b);
	}
	if (!far)
		return walk(stack, NULL, states, budget);

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
		ret = walk(stack, boxes, states, budget);
	free(boxes);
	return ret;
}
