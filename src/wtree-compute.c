/* The window tree's states, visible regions and repaint sets, computed with the core's engines. */
#include <errno.h>
#include <pixman.h>
#include <stdlib.h>

#include "engine.h"
#include "wtree.h"

/* The pre-order successor of w among viewable windows: unmapped subtrees are skipped. */
static struct vis_window *next_viewable(struct vis_window *w)
{
	if (w->mapped && w->bottom)
		return w->bottom;
	for (; w->parent; w = w->parent)
		if (w->above)
			return w->above;
	return NULL;
}

/* Lists the viewable windows in pre-order, with their absolute and clipped boxes. */
static int flatten(struct vis_wtree *tree)
{
	tree->n_order = 0;
	if (tree->cap_order < tree->count) {
		struct vis_window **order = realloc(tree->order, tree->count * sizeof *order);
		if (!order)
			return -1;
		tree->order = order;
		tree->cap_order = tree->count;
	}
	for (struct vis_window *w = tree->root.bottom; w; w = next_viewable(w)) {
		if (!w->mapped)
			continue;
		const struct vis_window *p = w->parent;
		w->box = (struct vis_box){ p->box.x1 + w->x, p->box.y1 + w->y, 0, 0 };
		w->box.x2 = w->box.x1 + w->width;
		w->box.y2 = w->box.y1 + w->height;
		w->clip = vis_box_intersect(w->box, p->clip);
		w->pos = tree->n_order;
		tree->order[tree->n_order++] = w;
	}
	return 0;
}

/* Whether a viewable window has a viewable child with pixels that can be seen. */
static bool covers_children(const struct vis_window *w)
{
	for (const struct vis_window *c = w->bottom; c; c = c->above)
		if (c->mapped && !vis_box_empty(c->clip))
			return true;
	return false;
}

static struct vis_rect box_rect(struct vis_box b)
{
	return (struct vis_rect){ (int32_t)b.x1, (int32_t)b.y1, (int32_t)(b.x2 - b.x1),
				  (int32_t)(b.y2 - b.y1) };
}

/*
 * Runs the default engine over the viewable windows with pixels to show and depth ≤ max_depth
 * (0: any), each clipped to its box and to within; writes each one's state to state_of[pos].
 */
static int sweep(const struct vis_wtree *tree, uint32_t max_depth, struct vis_box within,
		 struct vis_rect *rects, size_t *index, uint8_t *states, uint8_t *state_of)
{
	size_t n = 0;
	for (size_t i = 0; i < tree->n_order; i++) {
		const struct vis_window *w = tree->order[i];
		state_of[i] = VIS_FULLY_OBSCURED;
		if (!w)
			continue;
		struct vis_box c = vis_box_intersect(w->clip, within);
		if (vis_box_empty(c) || (max_depth && w->depth > max_depth))
			continue;
		rects[n] = box_rect(c);
		index[n++] = i;
	}
	struct vis_stack stack = { rects, n, false, 0, 0 };
	if (vis_compute(VIS_ENGINE_AUTO, &stack, states) < 0)
		return -1;
	for (size_t k = 0; k < n; k++)
		state_of[index[k]] = states[k];
	return 0;
}

int vis_wtree_compute(struct vis_wtree *tree)
{
	if (flatten(tree) < 0)
		return -1;
	size_t n = tree->n_order;
	struct vis_rect *rects = malloc((n ? n : 1) * sizeof *rects);
	size_t *index = malloc((n ? n : 1) * sizeof *index);
	uint8_t *states = malloc(n ? n : 1), *all = malloc(n ? n : 1), *level = malloc(n ? n : 1);
	bool *parent = malloc((n ? n : 1) * sizeof *parent);
	int ret = -1;
	if (!rects || !index || !states || !all || !level || !parent)
		goto out;
	/* Everything lies inside the screen: clip to it, and nothing else clips. */
	struct vis_box screen = tree->root.clip;
	if (sweep(tree, 0, screen, rects, index, states, all) < 0)
		goto out;
	/* Windows with children: one sweep per depth, without the deeper windows. */
	uint32_t depth_done = 0;
	for (size_t i = 0; i < n; i++)
		parent[i] = covers_children(tree->order[i]);
	for (;;) {
		uint32_t next = 0;
		for (size_t i = 0; i < n; i++) {
			uint32_t d = tree->order[i]->depth;
			if (parent[i] && d > depth_done && (!next || d < next))
				next = d;
		}
		if (!next)
			break;
		if (sweep(tree, next, screen, rects, index, states, level) < 0)
			goto out;
		for (size_t i = 0; i < n; i++)
			if (parent[i] && tree->order[i]->depth == next)
				all[i] = level[i];
		depth_done = next;
	}

	/* Every window, viewable or not, moves its state to old_state: unviewable ones have none. */
	for (struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w)) {
		w->old_state = w->state;
		w->state = VIS_WTREE_STATE_NONE;
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_window *w = tree->order[i];
		uint8_t s = all[i];
		/* A window the clip cuts into is never unobscured, as X compares the whole window. */
		if (s == VIS_UNOBSCURED && !vis_box_contains(w->clip, w->box))
			s = VIS_PARTIALLY_OBSCURED;
		w->state = s;
	}
	ret = 0;
out:
	free(rects);
	free(index);
	free(states);
	free(all);
	free(level);
	free(parent);
	return ret;
}

int vis_wtree_visible_region(const struct vis_wtree *tree, const struct vis_window *window,
			     void *out)
{
	pixman_region32_t *region = out;
	struct vis_box clip = window->clip;
	pixman_region32_clear(region);
	if (window->state == VIS_WTREE_STATE_NONE || window->state == VIS_FULLY_OBSCURED ||
	    vis_box_empty(clip))
		return 0;
	/* In window coordinates, every box below lies in [0, width) × [0, height). */
	int64_t ox = window->box.x1, oy = window->box.y1;
	size_t cap = 16, n = 0;
	pixman_box32_t *boxes = malloc(cap * sizeof *boxes);
	if (!boxes)
		return -1;
	for (size_t i = window->pos + 1; i < tree->n_order; i++) {
		if (!tree->order[i])
			continue;
		struct vis_box c = vis_box_intersect(tree->order[i]->clip, clip);
		if (vis_box_empty(c))
			continue;
		if (n == cap) {
			pixman_box32_t *more = realloc(boxes, 2 * cap * sizeof *boxes);
			if (!more) {
				free(boxes);
				return -1;
			}
			boxes = more;
			cap *= 2;
		}
		boxes[n++] = (pixman_box32_t){ (int32_t)(c.x1 - ox), (int32_t)(c.y1 - oy),
					       (int32_t)(c.x2 - ox), (int32_t)(c.y2 - oy) };
	}
	pixman_region32_t above;
	int ok = pixman_region32_init_rects(&above, boxes, (int)n);
	free(boxes);
	pixman_box32_t own = { (int32_t)(clip.x1 - ox), (int32_t)(clip.y1 - oy),
			       (int32_t)(clip.x2 - ox), (int32_t)(clip.y2 - oy) };
	pixman_region32_reset(region, &own);
	ok = ok && pixman_region32_subtract(region, region, &above);
	pixman_region32_fini(&above);
	if (!ok) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

long vis_wtree_repaint(const struct vis_wtree *tree, struct vis_box damage,
		       struct vis_window **out)
{
	size_t n = tree->n_order;
	struct vis_rect *rects = malloc((n ? n : 1) * sizeof *rects);
	size_t *index = malloc((n ? n : 1) * sizeof *index);
	uint8_t *states = malloc(n ? n : 1), *state_of = malloc(n ? n : 1);
	long count = -1;
	if (rects && index && states && state_of &&
	    sweep(tree, 0, damage, rects, index, states, state_of) == 0) {
		count = 0;
		for (size_t i = 0; i < n; i++)
			if (state_of[i] != VIS_FULLY_OBSCURED)
				out[count++] = tree->order[i];
	}
	free(rects);
	free(index);
	free(states);
	free(state_of);
	return count;
}
