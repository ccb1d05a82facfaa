/*
 * visctl stress's model of the daemon's stack: the changes it draws, applied to a copy of the
 * stack as the daemon must apply them, and the states the core's engines compute from that copy,
 * which the daemon's must equal at the end. Every change is O(1); the states cost one vis_compute.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "stress.h"

static const char *const kind_names[STRESS_KINDS] = {
	[STRESS_MOVE] = "move",       [STRESS_RESIZE] = "resize", [STRESS_RAISE] = "raise",
	[STRESS_LOWER] = "lower",     [STRESS_RESTACK] = "restack", [STRESS_MAP] = "map",
	[STRESS_BATCH] = "batch",     [STRESS_BORDER] = "border", [STRESS_SHAPE] = "shape",
	[STRESS_OPAQUE] = "opaque",
};

const char *stress_kind_name(enum stress_kind kind)
{
	return (unsigned)kind < STRESS_KINDS ? kind_names[kind] : "?";
}

int stress_model_init(struct stress_model *m, const struct vis_rect *rects, uint32_t n,
		      int32_t screen_w, int32_t screen_h, uint64_t seed)
{
	memset(m, 0, sizeof(*m));
	vis_idmap_init(&m->by_id);
	m->w = calloc(n ? n : 1, sizeof(*m->w));
	m->unmapped = calloc(n ? n : 1, sizeof(*m->unmapped));
	if (!m->w || !m->unmapped) {
		stress_model_finish(m);
		errno = ENOMEM;
		return -1;
	}
	for (uint32_t i = 0; i < n; i++)
		m->w[i] = (struct stress_window){ .r = rects[i],
						  .below = i ? i - 1 : STRESS_NONE,
						  .above = i + 1 < n ? i + 1 : STRESS_NONE,
						  .unmapped_at = STRESS_NONE };
	m->n = n;
	m->bottom = n ? 0 : STRESS_NONE;
	m->top = n ? n - 1 : STRESS_NONE;
	m->screen_w = screen_w;
	m->screen_h = screen_h;
	/* Apart from the scene's stream, so that the same seed gives the same desktop whatever the
	 * mix. */
	m->rng.state = seed ^ 0x5bd1e9955bd1e995ull;
	return 0;
}

void stress_model_finish(struct stress_model *m)
{
	free(m->w);
	free(m->unmapped);
	vis_idmap_finish(&m->by_id);
	m->w = NULL;
	m->unmapped = NULL;
}

int stress_model_set_id(struct stress_model *m, uint32_t slot, uint32_t id)
{
	m->w[slot].id = id;
	return vis_idmap_put(&m->by_id, id, &m->w[slot]);
}

uint32_t stress_model_slot(const struct stress_model *m, uint32_t id)
{
	const struct stress_window *w = vis_idmap_get(&m->by_id, id);
	return w ? (uint32_t)(w - m->w) : STRESS_NONE;
}

/* A number in [lo, hi], or lo when the range is empty. */
static int64_t range(struct stress_model *m, int64_t lo, int64_t hi)
{
	return hi <= lo ? lo : vis_rng_range(&m->rng, lo, hi);
}

/* v held to [lo, hi] (lo wins if they cross). */
static int64_t clamp(int64_t v, int64_t lo, int64_t hi)
{
	return v > hi ? (hi > lo ? hi : lo) : v < lo ? lo : v;
}

/* Takes window k out of the stacking order. */
static void unlink_window(struct stress_model *m, uint32_t k)
{
	struct stress_window *w = &m->w[k];
	if (w->below != STRESS_NONE)
		m->w[w->below].above = w->above;
	else
		m->bottom = w->above;
	if (w->above != STRESS_NONE)
		m->w[w->above].below = w->below;
	else
		m->top = w->below;
	w->above = w->below = STRESS_NONE;
}

/* Puts window k (unlinked) just above window j; STRESS_NONE: at the bottom. */
static void link_above(struct stress_model *m, uint32_t k, uint32_t j)
{
	struct stress_window *w = &m->w[k];
	w->below = j;
	w->above = j == STRESS_NONE ? m->bottom : m->w[j].above;
	if (w->above != STRESS_NONE)
		m->w[w->above].below = k;
	else
		m->top = k;
	if (j != STRESS_NONE)
		m->w[j].above = k;
	else
		m->bottom = k;
}

/* Draws a new position: mostly a drag of up to 64 pixels, sometimes a jump anywhere on screen. */
static void draw_move(struct stress_model *m, const struct vis_rect *r, struct stress_change *c)
{
	int64_t sw = m->screen_w, sh = m->screen_h, x, y;
	if (vis_rng_below(&m->rng, 4)) {
		x = clamp(r->x + range(m, -64, 64), -(int64_t)r->w / 2, sw - r->w / 2);
		y = clamp(r->y + range(m, -64, 64), -(int64_t)r->h / 2, sh - r->h / 2);
	} else {
		x = sw >= r->w ? range(m, 0, sw - r->w) : range(m, sw - r->w, 0);
		y = sh >= r->h ? range(m, 0, sh - r->h) : range(m, sh - r->h, 0);
	}
	c->a = (int32_t)x;
	c->b = (int32_t)y;
}

/* Draws a new size: mostly a drag of a corner, sometimes a desktop-like size anew. */
static void draw_size(struct stress_model *m, const struct vis_rect *r, struct stress_change *c)
{
	int64_t sw = m->screen_w, sh = m->screen_h, w, h;
	if (vis_rng_below(&m->rng, 4)) {
		w = clamp(r->w + range(m, -64, 64), sw < 50 ? sw : 50, sw);
		h = clamp(r->h + range(m, -64, 64), sh < 40 ? sh : 40, sh);
	} else {
		w = clamp(range(m, 200, 1600), 1, sw);
		h = clamp(range(m, 150, 1200), 1, sh);
	}
	c->a = (int32_t)w;
	c->b = (int32_t)h;
}

/* Maps or unmaps: unmaps a mapped window, or maps an unmapped one back, keeping at most one
 * window in twenty (and at least one) unmapped, so the desktop stays a desktop. */
static void toggle_map(struct stress_model *m, struct stress_change *c)
{
	uint32_t most = m->n / 20 ? m->n / 20 : 1;
	if (m->n_unmapped && (m->n_unmapped >= most || vis_rng_below(&m->rng, 2))) {
		uint32_t i = (uint32_t)vis_rng_below(&m->rng, m->n_unmapped);
		c->slot = m->unmapped[i];
		c->flag = true;
		m->unmapped[i] = m->unmapped[--m->n_unmapped];
		m->w[m->unmapped[i]].unmapped_at = i;
		m->w[c->slot].unmapped_at = STRESS_NONE;
		return;
	}
	while (m->w[c->slot].unmapped_at != STRESS_NONE)
		c->slot = (uint32_t)vis_rng_below(&m->rng, m->n);
	c->flag = false;
	m->w[c->slot].unmapped_at = m->n_unmapped;
	m->unmapped[m->n_unmapped++] = c->slot;
}

/* Draws a shape for window r with border b: rounded corners, an L, none, or the box again. */
static void draw_shape(struct stress_model *m, const struct vis_rect *r, int32_t b,
		       struct stress_change *c)
{
	int32_t bw = r->w + 2 * b, bh = r->h + 2 * b;
	uint64_t roll = vis_rng_below(&m->rng, 8);
	c->mode = 1;
	if (roll < 3 && bw > 8 && bh > 8) {
		/* Corners cut in two steps, as a small radius comes out a row at a time. */
		c->rects[0] = (struct vis_rect){ -b + 3, -b, bw - 6, 1 };
		c->rects[1] = (struct vis_rect){ -b + 1, -b + 1, bw - 2, 2 };
		c->rects[2] = (struct vis_rect){ -b, -b + 3, bw, bh - 6 };
		c->rects[3] = (struct vis_rect){ -b + 1, -b + bh - 3, bw - 2, 2 };
		c->rects[4] = (struct vis_rect){ -b + 3, -b + bh - 1, bw - 6, 1 };
		c->n_rects = 5;
	} else if (roll < 6 && bw > 1 && bh > 1) {
		c->rects[0] = (struct vis_rect){ -b, -b, bw, bh / 2 };
		c->rects[1] = (struct vis_rect){ -b, -b + bh / 2, bw / 2, bh - bh / 2 };
		c->n_rects = 2;
	} else if (roll == 6) {
		c->n_rects = 0; /* no pixels at all */
	} else {
		c->mode = 0;
		c->n_rects = 0;
	}
}

/* Draws an opaque region for window r: all, none, or the inside of a shadow margin. */
static void draw_opaque(struct stress_model *m, const struct vis_rect *r, struct stress_change *c)
{
	uint64_t roll = vis_rng_below(&m->rng, 4);
	int32_t margin = (int32_t)range(m, 4, 32);
	c->n_rects = 0;
	if (roll == 0) {
		c->mode = VIS_OPAQUE_MODE_ALL;
	} else if (roll == 1 || r->w <= 2 * margin || r->h <= 2 * margin) {
		c->mode = VIS_OPAQUE_MODE_NONE;
	} else {
		c->mode = VIS_OPAQUE_MODE_RECTS;
		c->rects[0] = (struct vis_rect){ margin, margin, r->w - 2 * margin, r->h - 2 * margin };
		c->n_rects = 1;
	}
}

void stress_model_change(struct stress_model *m, enum stress_kind kind, struct stress_change *c)
{
	memset(c, 0, sizeof(*c));
	c->kind = kind;
	c->slot = (uint32_t)vis_rng_below(&m->rng, m->n);
	struct stress_window *w = &m->w[c->slot];
	switch (kind) {
	case STRESS_MOVE:
		draw_move(m, &w->r, c);
		w->r.x = c->a;
		w->r.y = c->b;
		break;
	case STRESS_RESIZE:
		draw_size(m, &w->r, c);
		w->r.w = c->a;
		w->r.h = c->b;
		break;
	case STRESS_RAISE:
		unlink_window(m, c->slot);
		link_above(m, c->slot, m->top);
		break;
	case STRESS_LOWER:
		unlink_window(m, c->slot);
		link_above(m, c->slot, STRESS_NONE);
		break;
	case STRESS_RESTACK:
		if (m->n < 2) {
			c->kind = STRESS_RAISE;
			break;
		}
		c->sibling = (uint32_t)vis_rng_below(&m->rng, m->n - 1);
		c->sibling += c->sibling >= c->slot;
		c->flag = vis_rng_below(&m->rng, 2);
		unlink_window(m, c->slot);
		link_above(m, c->slot, c->flag ? c->sibling : m->w[c->sibling].below);
		break;
	case STRESS_MAP:
	case STRESS_BATCH:
		c->kind = STRESS_MAP;
		toggle_map(m, c);
		break;
	case STRESS_BORDER:
		/* Within 31 bits: the inside is at most the screen's. */
		c->a = (int32_t)vis_rng_below(&m->rng, 4);
		w->look.border = c->a;
		break;
	case STRESS_SHAPE:
		draw_shape(m, &w->r, w->look.border, c);
		w->look.shaped = c->mode == 1;
		w->look.n_shape = c->n_rects;
		memcpy(w->shape, c->rects, c->n_rects * sizeof(*c->rects));
		break;
	case STRESS_OPAQUE:
		draw_opaque(m, &w->r, c);
		w->look.opaque = (uint8_t)c->mode;
		w->look.n_opaque = c->n_rects;
		memcpy(w->opaque, c->rects, c->n_rects * sizeof(*c->rects));
		break;
	}
}

enum stress_kind stress_model_kind(struct stress_model *m, const uint32_t *mix, bool no_batch)
{
	uint64_t total = 0;
	for (int k = 0; k < STRESS_KINDS; k++)
		total += no_batch && k == STRESS_BATCH ? 0 : mix[k];
	if (total == 0)
		return STRESS_MOVE;
	uint64_t x = vis_rng_below(&m->rng, total);
	for (int k = 0; k < STRESS_KINDS; k++) {
		uint64_t wk = no_batch && k == STRESS_BATCH ? 0 : mix[k];
		if (x < wk)
			return (enum stress_kind)k;
		x -= wk;
	}
	return STRESS_MOVE;
}

int stress_model_states(const struct stress_model *m, uint8_t *states)
{
	struct vis_rect *rects = malloc((m->n ? m->n : 1) * sizeof(*rects));
	struct vis_look *looks = malloc((m->n ? m->n : 1) * sizeof(*looks));
	uint32_t *slots = malloc((m->n ? m->n : 1) * sizeof(*slots));
	uint8_t *got = malloc(m->n ? m->n : 1);
	int ret = -1;
	bool any_look = false;
	if (!rects || !looks || !slots || !got)
		goto out;
	size_t n = 0;
	for (uint32_t k = m->bottom; k != STRESS_NONE; k = m->w[k].above) {
		states[k] = VIS_VISIBILITY_NONE;
		if (m->w[k].unmapped_at == STRESS_NONE) {
			rects[n] = m->w[k].r;
			looks[n] = m->w[k].look;
			looks[n].shape = (struct vis_rect *)m->w[k].shape;
			looks[n].opaque_rects = (struct vis_rect *)m->w[k].opaque;
			any_look |= !vis_look_plain(&looks[n]);
			slots[n++] = k;
		}
	}
	struct vis_stack stack = { rects, n, true, m->screen_w, m->screen_h, NULL,
				   any_look ? looks : NULL };
	if (vis_compute(VIS_ENGINE_AUTO, &stack, got) < 0)
		goto out;
	for (size_t i = 0; i < n; i++)
		states[slots[i]] = got[i];
	ret = 0;
out:
	free(rects);
	free(looks);
	free(slots);
	free(got);
	return ret;
}

uint64_t stress_model_compare_tree(const struct stress_model *m,
				   const struct vis_window_info *tree, size_t n, uint64_t limit)
{
	uint64_t bad = 0;
	if (n != m->n) {
		fprintf(stderr, "visctl stress: visd has %zu windows, the model %u\n", n, m->n);
		return 1;
	}
	size_t i = 0;
	for (uint32_t k = m->bottom; k != STRESS_NONE; k = m->w[k].above, i++) {
		const struct stress_window *w = &m->w[k];
		const struct vis_window_info *t = &tree[i];
		bool mapped = w->unmapped_at == STRESS_NONE;
		struct vis_look look = w->look;
		look.shape = (struct vis_rect *)w->shape;
		look.opaque_rects = (struct vis_rect *)w->opaque;
		if (t->window == w->id && t->parent == VIS_WINDOW_ROOT && t->x == w->r.x &&
		    t->y == w->r.y && t->width == (uint32_t)w->r.w && t->height == (uint32_t)w->r.h &&
		    t->border == (uint32_t)w->look.border &&
		    !!(t->flags & VIS_WINDOW_SHAPED) == w->look.shaped &&
		    !!(t->flags & VIS_WINDOW_TRANSLUCENT) == (vis_look_translucent(&look, w->r.w, w->r.h) > 0) &&
		    !!(t->flags & VIS_WINDOW_MAPPED) == mapped)
			continue;
		if (bad++ < limit)
			fprintf(stderr,
				"visctl stress: stack position %zu: visd has window %u at %d,%d,%u,%u "
				"%s, the model window %u at %d,%d,%d,%d %s\n",
				i, t->window, t->x, t->y, t->width, t->height,
				t->flags & VIS_WINDOW_MAPPED ? "mapped" : "unmapped", w->id, w->r.x,
				w->r.y, w->r.w, w->r.h, mapped ? "mapped" : "unmapped");
	}
	return bad;
}

void stress_model_corrupt(struct stress_model *m)
{
	if (m->n)
		m->w[m->top].r.x = m->screen_w;
}

void stress_model_record(FILE *f, const struct stress_change *c)
{
	uint32_t at = c->slot + 1;
	switch (c->kind) {
	case STRESS_MOVE:
		fprintf(f, "move @%u %d %d\n", at, c->a, c->b);
		break;
	case STRESS_RESIZE:
		fprintf(f, "resize @%u %d %d\n", at, c->a, c->b);
		break;
	case STRESS_RAISE:
		fprintf(f, "raise @%u\n", at);
		break;
	case STRESS_LOWER:
		fprintf(f, "lower @%u\n", at);
		break;
	case STRESS_RESTACK:
		fprintf(f, "stack @%u %s @%u\n", at, c->flag ? "above" : "below", c->sibling + 1);
		break;
	case STRESS_MAP:
	case STRESS_BATCH:
		fprintf(f, "%s @%u\n", c->flag ? "map" : "unmap", at);
		break;
	case STRESS_BORDER:
		fprintf(f, "border @%u %d\n", at, c->a);
		break;
	case STRESS_SHAPE:
	case STRESS_OPAQUE:
		fprintf(f, "%s @%u", c->kind == STRESS_SHAPE ? "shape" : "opaque", at);
		if (c->kind == STRESS_SHAPE && c->mode == 0)
			fprintf(f, " --box");
		if (c->kind == STRESS_OPAQUE && c->mode != VIS_OPAQUE_MODE_RECTS)
			fprintf(f, " %s", c->mode == VIS_OPAQUE_MODE_NONE ? "none" : "all");
		for (uint32_t i = 0; i < c->n_rects; i++)
			fprintf(f, " %d,%d,%d,%d", c->rects[i].x, c->rects[i].y, c->rects[i].w,
				c->rects[i].h);
		fputc('\n', f);
		break;
	}
}
