/*
 * libvis's walks over a damaged area: the repaint set, and the tallies a small tree's states come
 * from (libvis-tally.c).
 *
 * A walk goes from the top window down over the windows whose clips meet what is left of the
 * area, taking each one's opaque pixels off it: what was left where a window was reached is
 * what it shows there (the repaint set), and, left as it was before the window's descendants
 * (which hide nothing of it, X's rule), what it sees there (the tallies).
 */
#include <errno.h>
#include <stdlib.h>

#include "libvis-private.h"
#include "wtree-live.h"

/* Whether a clip (on the screen, maybe empty) meets what is left. */
static bool meets_left(const struct libvis_walk *k, struct vis_box c)
{
	return !vis_box_empty(c) && vis_bands_meet(&k->left, pbox(c));
}

enum libvis_pixels libvis_pixels_of(const struct vis_window *w)
{
	for (const struct vis_window *a = w->parent; a->parent; a = a->parent)
		if (a->look.shaped)
			return LIBVIS_PIECES;
	if (w->look.shaped)
		return LIBVIS_PIECES;
	return w->look.opaque == VIS_OPAQUE_ALL ? LIBVIS_CLIP : LIBVIS_CLIP_SEE_THROUGH;
}

/* w's pieces inside box c (tree->pieces), as pixman boxes in tree->boxes; their count, or -1. */
static long pieces_of(struct vis_tree *tree, const struct vis_window *w, struct vis_box c,
		      size_t *n_opaque)
{
	struct vis_pieces *p = &tree->pieces;
	vis_pieces_reset(p);
	if (vis_wtree_add_pieces(p, w, c, 0) < 0)
		return -1;
	size_t n = p->stack.n;
	if (libvis_reserve(&tree->boxes, &tree->cap_boxes, n + 1, sizeof *tree->boxes) < 0)
		return -1;
	*n_opaque = 0;
	while (*n_opaque < n && !p->see_through[*n_opaque])
		(*n_opaque)++;
	for (size_t i = 0; i < n; i++)
		tree->boxes[i] = pbox(vis_rect_box(p->rects[i]));
	return (long)n;
}

/* Takes boxes[0 … n) off what is left. 0, or -1. */
static int take_off(struct libvis_walk *k, const pixman_box32_t *boxes, size_t n)
{
	for (size_t i = 0; i < n; i++)
		if (vis_bands_subtract(&k->left, &k->scratch, boxes[i]) < 0)
			return -1;
	return 0;
}

int libvis_touch(struct vis_tree *tree, struct vis_window *w)
{
	struct vis_win *win = w->data;
	if (win->touched_slot)
		return 0;
	if (libvis_reserve(&tree->touched, &tree->cap_touched, tree->n_touched + 1,
			   sizeof *tree->touched) < 0)
		return -1;
	tree->touched[tree->n_touched++] = w;
	win->touched_slot = (uint32_t)tree->n_touched;
	return 0;
}

/* Adds seen pixels of w to its tally (or takes them off). 0, or -1. */
static int count(struct vis_tree *tree, const struct vis_window *w, uint64_t seen)
{
	struct vis_win *win = w->data;
	win->seen += (uint64_t)(int64_t)tree->walk.sign * seen;
	return seen ? libvis_touch(tree, (struct vis_window *)w) : 0;
}

/* Appends boxes[0 … n), moved by -x, -y, to a set's rectangles. 0, or -1. */
static int append_boxes(struct libvis_set *set, const pixman_box32_t *b, size_t n, int64_t x,
			int64_t y)
{
	if (libvis_reserve(&set->rects, &set->cap_rects, set->n_rects + n, sizeof *set->rects) < 0)
		return -1;
	struct vis_rect32 *out = set->rects + set->n_rects;
	/* They lie in the window's border box, whose sides fit in 31 bits. */
	for (size_t i = 0; i < n; i++)
		out[i] = (struct vis_rect32){ (int32_t)(b[i].x1 - x), (int32_t)(b[i].y1 - y),
					      (uint32_t)(b[i].x2 - b[i].x1),
					      (uint32_t)(b[i].y2 - b[i].y1) };
	set->n_rects += n;
	return 0;
}

/*
 * Lists w in the walk's set with the parts of its pixels, the disjoint boxes px[0 … n), found
 * left: tree->parts[0 … parts), banded when n is 1; in a walk within (k->within), less the
 * boxes of k->less, and not at all when nothing is left of them. 0, or -1.
 */
static int list(struct vis_tree *tree, const struct vis_window *w, size_t n, size_t parts)
{
	struct libvis_walk *k = &tree->walk;
	struct libvis_set *set = k->out;
	int64_t x = w->box.x1 + w->look.border, y = w->box.y1 + w->look.border;
	size_t at = set->n_rects;
	const pixman_box32_t *b = tree->parts;
	/* Not the pixels of k->less: is any in the parts' extents? */
	bool cut = false;
	if (k->within && k->n_less) {
		pixman_box32_t e = b[0];
		for (size_t i = 1; i < parts; i++) {
			e.x1 = b[i].x1 < e.x1 ? b[i].x1 : e.x1;
			e.y1 = b[i].y1 < e.y1 ? b[i].y1 : e.y1;
			e.x2 = b[i].x2 > e.x2 ? b[i].x2 : e.x2;
			e.y2 = b[i].y2 > e.y2 ? b[i].y2 : e.y2;
		}
		for (size_t j = 0; j < k->n_less && !cut; j++) {
			const pixman_box32_t *l = &k->less[j];
			if (l->x1 <= e.x1 && l->y1 <= e.y1 && e.x2 <= l->x2 && e.y2 <= l->y2)
				return 0; /* all of it: often where it only loses */
			cut = e.x1 < l->x2 && l->x1 < e.x2 && e.y1 < l->y2 && l->y1 < e.y2;
		}
	}
	/* One box's part is banded; several boxes' parts are once pixman joins them. */
	if (n == 1 && cut) {
		if (vis_bands_set_less(&k->listed, b, parts, k->less[0]) < 0)
			return -1;
		for (size_t j = 1; j < k->n_less; j++)
			if (vis_bands_subtract(&k->listed, &k->scratch, k->less[j]) < 0)
				return -1;
		if (!k->listed.n)
			return 0;
		if (append_boxes(set, k->listed.boxes, k->listed.n, x, y) < 0)
			return -1;
	} else if (n == 1) {
		if (append_boxes(set, b, parts, x, y) < 0)
			return -1;
	} else {
		pixman_region32_fini(&tree->part);
		if (!pixman_region32_init_rects(&tree->part, b, (int)parts))
			goto nomem;
		for (size_t j = 0; cut && j < k->n_less; j++) {
			pixman_region32_t less;
			pixman_region32_init_rects(&less, &k->less[j], 1);
			bool ok = pixman_region32_subtract(&tree->part, &tree->part, &less);
			pixman_region32_fini(&less);
			if (!ok)
				goto nomem;
		}
		if (!pixman_region32_not_empty(&tree->part))
			return 0;
		if (libvis_append_rects(&tree->part, x, y, &set->rects, &set->n_rects,
					&set->cap_rects) < 0)
			goto nomem;
	}
	if (libvis_reserve(&set->wins, &set->cap, set->n + 1, sizeof *set->wins) < 0)
		return -1;
	struct vis_win *win = w->data;
	set->wins[set->n++] = (struct vis_repaint){ .win = win, .x = x, .y = y,
						    .n_rects = (uint32_t)(set->n_rects - at) };
	return 0;
nomem:
	errno = ENOMEM;
	return -1;
}

/*
 * Lists w in the walk's set with its pixels, the disjoint boxes px[0 … n), in what is left, if
 * any: the boxes it shows (0 when none), or -1.
 */
static long draw(struct vis_tree *tree, const struct vis_window *w, const pixman_box32_t *px,
		 size_t n)
{
	struct libvis_walk *k = &tree->walk;
	size_t parts = 0;
	if (libvis_reserve(&tree->parts, &tree->cap_parts, n * k->left.n + 1,
			   sizeof *tree->parts) < 0)
		return -1;
	for (size_t i = 0; i < n; i++)
		parts += vis_bands_clip(&k->left, px[i], tree->parts + parts);
	return parts && list(tree, w, n, parts) < 0 ? -1 : (long)parts;
}

/*
 * Takes the box px off what is left, its part (tree->parts) listed in the walk's set if it has
 * one: the boxes of the part (0 when none), or -1.
 */
static long draw_take(struct vis_tree *tree, const struct vis_window *w, pixman_box32_t px)
{
	struct libvis_walk *k = &tree->walk;
	if (libvis_reserve(&tree->parts, &tree->cap_parts, k->left.n + 1, sizeof *tree->parts) < 0)
		return -1;
	long parts = vis_bands_take(&k->left, &k->scratch, px, tree->parts);
	return parts > 0 && k->out && list(tree, w, 1, (size_t)parts) < 0 ? -1 : parts;
}

/*
 * The opaque pieces of a see-through window without a shape inside box c, from its cut (none
 * without one: opaque nowhere), into tree->boxes[1 …]: their count, or -1.
 */
static long opaque_cut(struct vis_tree *tree, const struct vis_window *w, struct vis_box c)
{
	if (!w->cut)
		return 0;
	const struct vis_look_cut *cut = vis_wtree_cut(w);
	if (!cut || libvis_reserve(&tree->boxes, &tree->cap_boxes, (size_t)cut->n_opaque + 1,
				   sizeof *tree->boxes) < 0)
		return -1;
	size_t n = 0;
	for (uint32_t i = 0; i < cut->n_opaque; i++) {
		struct vis_rect r = cut->rects[i];
		struct vis_box b = vis_box_intersect(
			(struct vis_box){ w->box.x1 + r.x, w->box.y1 + r.y, w->box.x1 + r.x + r.w,
					  w->box.y1 + r.y + r.h },
			c);
		if (!vis_box_empty(b))
			tree->boxes[1 + n++] = pbox(b);
	}
	return (long)n;
}

long libvis_opaque_boxes(struct vis_tree *tree, const struct vis_window *w,
			 const pixman_box32_t **out)
{
	if (libvis_pixels_of(w) != LIBVIS_CLIP) {
		long n = opaque_cut(tree, w, w->clip);
		*out = tree->boxes + 1; /* where opaque_cut() writes, once it has grown them */
		return n;
	}
	if (vis_box_empty(w->clip))
		return 0;
	if (libvis_reserve(&tree->boxes, &tree->cap_boxes, 1, sizeof *tree->boxes) < 0)
		return -1;
	tree->boxes[0] = pbox(w->clip);
	*out = tree->boxes;
	return 1;
}

/* The pixels of box b inside the boxes in[0 … n): in mine, unless b is a part found left
 * (drawn). */
static uint64_t area_inside(const pixman_box32_t *in, size_t n, pixman_box32_t b, bool drawn,
			    const struct vis_bands *mine)
{
	uint64_t a = 0;
	for (size_t j = 0; j < n; j++) {
		pixman_box32_t x = vis_pbox_and(b, in[j]);
		if (x.x1 < x.x2 && x.y1 < x.y2)
			a += drawn ? vis_pbox_area(x) : vis_bands_area_in(mine, x);
	}
	return a;
}

/*
 * A walk's visit of a viewable window with pixels: its tally (mine: what was left where it
 * began), its part of the set being listed (what is left now), then its opaque pixels off what
 * is left. 0, or -1.
 */
static int visit(struct vis_tree *tree, const struct vis_window *w, const struct vis_bands *mine)
{
	struct libvis_walk *k = &tree->walk;
	enum libvis_pixels kind = libvis_pixels_of(w);
	const pixman_box32_t *e = &mine->ext;
	struct vis_box c = vis_box_intersect(w->clip,
					     (struct vis_box){ e->x1, e->y1, e->x2, e->y2 });
	/* Its pixels px[0 … n), its opaque ones op[0 … n_opaque). */
	size_t n = 1, n_opaque = 1;
	const pixman_box32_t *px, *op;
	if (kind == LIBVIS_PIECES) {
		long m = pieces_of(tree, w, c, &n_opaque);
		if (m < 0)
			return -1;
		n = (size_t)m;
		px = op = tree->boxes;
	} else {
		long m = kind == LIBVIS_CLIP ? 1 : opaque_cut(tree, w, c);
		if (m < 0 || libvis_reserve(&tree->boxes, &tree->cap_boxes, 1,
					    sizeof *tree->boxes) < 0)
			return -1;
		tree->boxes[0] = pbox(w->clip);
		px = tree->boxes;
		op = kind == LIBVIS_CLIP ? tree->boxes : tree->boxes + 1;
		n_opaque = (size_t)m;
	}
	/* What is left lies in mine: a clip that meets nothing of either takes nothing off. An
	 * opaque clip, what was left its tally's, is listed and taken off in one pass. */
	bool meets = kind != LIBVIS_CLIP, taken = kind == LIBVIS_CLIP && mine == &k->left;
	long parts = -1;
	if (taken ? (parts = draw_take(tree, w, px[0])) < 0
		  : k->out && (parts = draw(tree, w, px, n)) < 0)
		return -1;
	if (k->sign) {
		/* Pieces are disjoint: their counts add up. Without descendants that took their part
		 * (mine is what is left), what it sees is the parts it shows. */
		uint64_t seen = 0;
		bool drawn = parts >= 0 && mine == &k->left;
		size_t m = drawn ? (size_t)parts : n;
		const pixman_box32_t *b = drawn ? tree->parts : px;
		for (size_t i = 0; i < m; i++) {
			if (!k->within)
				seen += drawn ? vis_pbox_area(b[i]) : vis_bands_area_in(mine, b[i]);
			else
				seen += area_inside(k->in, k->n_in, b[i], drawn, mine) -
					area_inside(k->less, k->n_less, b[i], drawn, mine);
		}
		if (count(tree, w, seen) < 0)
			return -1;
		meets |= seen != 0;
	}
	if (k->out)
		meets = parts > 0 || kind != LIBVIS_CLIP;
	return meets && !taken ? take_off(k, op, n_opaque) : 0;
}

/*
 * A repaint walk, from the keys below from down, over what is left through the live engine's
 * grid of clips (a tree past tallies): the windows whose clips meet it, highest key first, which
 * is the walk's order (a window's descendants before it), without passing over the others one by
 * one. 0, or -1.
 */
static int walk_grid(struct vis_tree *tree, uint64_t from)
{
	struct libvis_walk *k = &tree->walk;
	struct vis_wtree_live *lv = tree->core.live;
	struct vis_zgrid_walk walk;
	pixman_box32_t *e = &k->left.ext;
	if (vis_zgrid_walk_init(&walk, &lv->grid, (struct vis_box){ e->x1, e->y1, e->x2, e->y2 },
				from, false) < 0)
		return -1;
	int rc = 0;
	uint64_t key;
	uint32_t slot;
	while (rc == 0 && k->left.n && vis_zgrid_walk_next(&walk, &key, &slot)) {
		const struct live_slot *sl = &lv->slots[slot];
		if (!vis_bands_meet(&k->left, sl->clip))
			continue;
		rc = visit(tree, sl->w, &k->left);
		if (k->left.n)
			vis_zgrid_walk_narrow(&walk, (struct vis_box){ e->x1, e->y1, e->x2, e->y2 });
	}
	vis_zgrid_walk_finish(&walk);
	return rc;
}

/* The first mapped child of w, from the top, whose clip meets what is left, or NULL. */
static const struct vis_window *first_child(const struct libvis_walk *k,
					    const struct vis_window *w)
{
	const struct vis_window *c = w->top;
	while (c && !(c->mapped && meets_left(k, c->clip)))
		c = c->below;
	return c;
}

/*
 * Walks c and the siblings below it, while something is left: each window meeting it after its
 * descendants above it, those from the top child down. Without recursion (a chain of nested
 * windows is as deep as the tree): the windows entered, whose children are walked, wait in
 * k->entered, with whether they kept what was left for their tally in k->saves. 0, or -1.
 */
static int walk_from(struct vis_tree *tree, const struct vis_window *c)
{
	struct libvis_walk *k = &tree->walk;
	/* A repaint of a large tree whose top windows leave the damage uncovered goes on by the
	 * grid, past the windows that miss it (a cascade's damage, which thousands cross). */
	bool grid = !k->sign && !k->stop && wtree_live_indexed(&tree->core);
	uint64_t from = UINT64_MAX;
	size_t depth = 0, level = 0, passed = 0;
	for (;;) {
		for (; c && c != k->stop && k->left.n; c = c->below) {
			if (!depth && grid && ++passed > k->grid_after)
				return walk_grid(tree, from);
			if (c->mapped && meets_left(k, c->clip))
				break;
		}
		const struct vis_window *w;
		const struct vis_bands *mine = &k->left;
		if (c && c != k->stop && k->left.n) {
			const struct vis_window *child = first_child(k, c);
			if (child) {
				/* A tally counts what was left before the descendants took their
				 * part. */
				bool saved = k->sign && !c->look.input_only;
				if (libvis_reserve(&k->entered, &k->cap_entered, depth + 1,
						   sizeof *k->entered) < 0)
					return -1;
				if (saved) {
					size_t cap = k->cap_saves;
					if (libvis_reserve(&k->saves, &k->cap_saves, level + 1,
							   sizeof *k->saves) < 0)
						return -1;
					for (size_t i = cap; i < k->cap_saves; i++)
						vis_bands_init(&k->saves[i]);
					if (vis_bands_copy(&k->saves[level], &k->left) < 0)
						return -1;
				}
				k->entered[depth++] = (struct libvis_entered){ c, saved };
				level += saved;
				c = child;
				continue;
			}
			w = c;
		} else {
			/* The siblings are done: their parent, entered, is next, or the walk ends. */
			if (!depth)
				return 0;
			struct libvis_entered e = k->entered[--depth];
			w = e.w;
			if (e.saved)
				mine = &k->saves[--level];
		}
		if (!w->look.input_only && visit(tree, w, mine) < 0)
			return -1;
		if (!depth)
			from = w->key;
		c = w->below;
	}
}

int libvis_walk_left(struct vis_tree *tree, const struct vis_window *start,
		     const struct vis_window *stop, int sign, struct libvis_set *out)
{
	struct libvis_walk *k = &tree->walk;
	k->sign = sign;
	k->out = out;
	k->stop = stop;
	int rc = walk_from(tree, start);
	k->within = false;
	return rc;
}

int libvis_walk(struct vis_tree *tree, struct vis_box d, int sign, struct libvis_set *out,
		const struct vis_window *stop)
{
	struct libvis_walk *k = &tree->walk;
	if (out)
		out->n = out->n_rects = 0;
	d = vis_box_intersect(d, tree->core.root.clip);
	if (vis_box_empty(d))
		return vis_bands_set_box(&k->left, (pixman_box32_t){ 0 });
	if (vis_bands_set_box(&k->left, pbox(d)) < 0)
		return -1;
	return libvis_walk_left(tree, tree->core.root.top, stop, sign, out);
}

int libvis_draw_box(struct vis_tree *tree, const struct vis_window *w, struct vis_box b,
		    uint64_t *pixels)
{
	pixman_box32_t px = pbox(b);
	long parts = draw(tree, w, &px, 1);
	if (parts < 0)
		return -1;
	*pixels = 0;
	for (long i = 0; i < parts; i++)
		*pixels += vis_pbox_area(tree->parts[i]);
	return 0;
}
