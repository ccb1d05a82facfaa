/*
 * The visible parts of a scene's windows, for `visctl compute --svg`: the stack walked top-down
 * with pixman regions, each window's pixels minus the union of the opaque pixels above, as X.Org
 * keeps its clip lists. Cheap on desktops; capped, since the parts can be Θ(n²).
 */
#include <errno.h>
#include <pixman.h>

#include "coords.h"
#include "stack-svg.h"

/*
 * Limits of stack_svg_find_parts(): box operations of the walk (a few ns each) and visible parts
 * kept (about 40 bytes of SVG each). A desktop needs a few per window; the grid needs n²/4.
 */
#define PARTS_WORK_LIMIT ((uint64_t)1 << 25)
#define PARTS_LIMIT ((size_t)1 << 20)

/* Forgets every visible part, saying why. */
static void drop_parts(struct stack_svg *p, const char *why)
{
	for (size_t i = 0; i < p->n; i++)
		p->windows[i].n_parts = 0;
	p->n_parts = 0;
	p->has_parts = false;
	stack_svg_note(p, "Visible parts not drawn: %s.", why);
}

int stack_svg_find_parts(struct stack_svg *p, const struct vis_stack *stack,
			 const uint32_t *window_of)
{
	pixman_region32_t regions[2], *above = &regions[0], *spare = &regions[1], own, visible,
		window_visible, opaque;
	struct vis_coords co;
	uint64_t work = 0;
	int ret = 0;

	/* Ranks go up to 2n and must stay well inside pixman's int32 arithmetic. */
	if (stack->n > (size_t)1 << 29) {
		drop_parts(p, "too many windows");
		return 0;
	}
	if (vis_coords_init(&co, stack) < 0)
		return -1;
	pixman_region32_init(above);
	pixman_region32_init(spare);
	pixman_region32_init(&visible);
	pixman_region32_init(&window_visible);
	pixman_region32_init(&opaque);
	/*
	 * A window's rectangles are consecutive: each is seen where no opaque rectangle of a higher
	 * window lies, so the window's own opaque ones join the union only after all of its own.
	 */
	for (size_t k = stack->n; k-- > 0;) {
		size_t i = window_of ? window_of[k] : k;
		struct vis_box b = vis_stack_clip(stack, k);
		if (!vis_box_empty(b)) {
			int32_t x1 = (int32_t)vis_coords_rank_x(&co, b.x1);
			int32_t y1 = (int32_t)vis_coords_rank_y(&co, b.y1);
			int32_t x2 = (int32_t)vis_coords_rank_x(&co, b.x2);
			int32_t y2 = (int32_t)vis_coords_rank_y(&co, b.y2);
			unsigned w = (unsigned)(x2 - x1), h = (unsigned)(y2 - y1);

			/* The subtraction and the unions each read the union's boxes. */
			work += 3 * (uint64_t)pixman_region32_n_rects(above) + 1;
			if (work > PARTS_WORK_LIMIT || p->n_parts > PARTS_LIMIT) {
				drop_parts(p, "the visible region is too fragmented to draw");
				goto out;
			}
			pixman_region32_init_rect(&own, x1, y1, w, h);
			bool ok = pixman_region32_subtract(&visible, &own, above) &&
				  pixman_region32_union(&window_visible, &window_visible, &visible) &&
				  (!vis_stack_opaque(stack, k) ||
				   pixman_region32_union_rect(&opaque, &opaque, x1, y1, w, h));
			pixman_region32_fini(&own);
			if (!ok) {
				errno = ENOMEM;
				ret = -1;
				goto out;
			}
		}
		if (k > 0 && (window_of ? window_of[k - 1] : k - 1) == i)
			continue; /* more of the same window below */

		if (!pixman_region32_union(spare, above, &opaque)) {
			errno = ENOMEM;
			ret = -1;
			goto out;
		}
		pixman_region32_t *t = above;
		above = spare;
		spare = t;
		int n;
		const pixman_box32_t *r = pixman_region32_rectangles(&window_visible, &n);
		struct vis_box *out = n ? stack_svg_parts(p, i, (size_t)n) : NULL;
		if (n && out == NULL) {
			ret = -1;
			goto out;
		}
		for (int j = 0; j < n; j++)
			out[j] = (struct vis_box){ co.x[r[j].x1], co.y[r[j].y1], co.x[r[j].x2],
						   co.y[r[j].y2] };
		pixman_region32_clear(&window_visible);
		pixman_region32_clear(&opaque);
	}
out:
	pixman_region32_fini(above);
	pixman_region32_fini(spare);
	pixman_region32_fini(&visible);
	pixman_region32_fini(&window_visible);
	pixman_region32_fini(&opaque);
	vis_coords_finish(&co);
	return ret;
}
