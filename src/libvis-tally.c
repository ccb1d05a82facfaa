/*
 * libvis's walks over a damaged area, and the tallies a small tree's states come from.
 *
 * A walk goes from the top window down over the windows whose clips meet what is left of the
 * area, taking each one's opaque pixels off it: what was left where a window was reached is
 * what it shows there (the repaint set), and, left as it was before the window's descendants
 * (which hide nothing of it, X's rule), what it sees there (the tallies).
 *
 * Tallies: a window's state follows from two counts, its own pixels (total) and those of them it
 * sees (seen): none seen, fully obscured; all, unobscured; else partially obscured. A change
 * alters what windows see only inside the boxes its window's subtree takes before and after it
 * (vis_wtree_compute_damaged()'s argument), so a walk over their hull before the change takes
 * every window's seen pixels there off its tally and one after it adds those seen then: the tallies
 * stay exact at the cost of two walks over the change's box, which on a small desktop is less
 * than the live engine's bookkeeping, and grows with the windows there, not the tree. An update
 * is then one pass over the windows, their states from their tallies, and the positions and keys
 * the queries read. Past LIBVIS_TALLY_WINDOWS × 2 windows, the core takes over again.
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

/* What a window's pixels are, for a walk: its clip, all opaque (a plain window, or one with a
 * border alone); its clip, opaque where its cut's opaque pieces are (a see-through look without a
 * shape); or its pieces (a shape of its own or of an ancestor, which clips it). */
enum pixels { CLIP, CLIP_SEE_THROUGH, PIECES };

static enum pixels pixels_of(const struct vis_window *w)
{
	for (const struct vis_window *a = w->parent; a->parent; a = a->parent)
		if (a->look.shaped)
			return PIECES;
	if (w->look.shaped)
		return PIECES;
	return w->look.opaque == VIS_OPAQUE_ALL ? CLIP : CLIP_SEE_THROUGH;
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

/* Lists w as touched by the walks since the last update, once. 0, or -1. */
static int touch(struct vis_tree *tree, const struct vis_window *w)
{
	struct vis_win *win = w->data;
	if (win->touched != tree->serial + 1 && !tree->tally_restacked) {
		if (libvis_reserve(&tree->touched, &tree->cap_touched, tree->n_touched + 1,
				   sizeof *tree->touched) < 0)
			return -1;
		tree->touched[tree->n_touched++] = (struct vis_window *)w;
		win->touched = tree->serial + 1;
	}
	return 0;
}

/* Adds seen pixels of w to its tally (or takes them off). 0, or -1. */
static int count(struct vis_tree *tree, const struct vis_window *w, uint64_t seen)
{
	struct vis_win *win = w->data;
	win->seen += (uint64_t)(int64_t)tree->walk.sign * seen;
	return seen ? touch(tree, w) : 0;
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
 * Lists w in the walk's set with its pixels, the disjoint boxes px[0 … n), in what is left, if
 * any: the boxes it shows (0 when none), or -1.
 */
static long draw(struct vis_tree *tree, const struct vis_window *w, const pixman_box32_t *px,
		 size_t n)
{
	struct libvis_walk *k = &tree->walk;
	struct libvis_set *set = k->out;
	int64_t x = w->box.x1 + w->look.border, y = w->box.y1 + w->look.border;
	size_t at = set->n_rects, parts = 0;
	if (libvis_reserve(&tree->parts, &tree->cap_parts, n * k->left.n + 1,
			   sizeof *tree->parts) < 0)
		return -1;
	for (size_t i = 0; i < n; i++)
		parts += vis_bands_clip(&k->left, px[i], tree->parts + parts);
	if (!parts)
		return 0;
	/* One box's part is banded; several boxes' parts are once pixman joins them. */
	if (n == 1) {
		if (append_boxes(set, tree->parts, parts, x, y) < 0)
			return -1;
	} else {
		pixman_region32_fini(&tree->part);
		if (!pixman_region32_init_rects(&tree->part, tree->parts, (int)parts) ||
		    libvis_append_rects(&tree->part, x, y, &set->rects, &set->n_rects,
					&set->cap_rects) < 0) {
			errno = ENOMEM;
			return -1;
		}
	}
	if (libvis_reserve(&set->wins, &set->cap, set->n + 1, sizeof *set->wins) < 0)
		return -1;
	struct vis_win *win = w->data;
	set->wins[set->n++] = (struct vis_repaint){ .win = win, .x = x, .y = y,
						    .n_rects = (uint32_t)(set->n_rects - at) };
	return (long)parts;
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

/*
 * A walk's visit of a viewable window with pixels: its tally (mine: what was left where it
 * began), its part of the set being listed (what is left now), then its opaque pixels off what
 * is left. 0, or -1.
 */
static int visit(struct vis_tree *tree, const struct vis_window *w, const struct vis_bands *mine)
{
	struct libvis_walk *k = &tree->walk;
	enum pixels kind = pixels_of(w);
	const pixman_box32_t *e = &mine->ext;
	struct vis_box c = vis_box_intersect(w->clip,
					     (struct vis_box){ e->x1, e->y1, e->x2, e->y2 });
	/* Its pixels px[0 … n), its opaque ones op[0 … n_opaque). */
	size_t n = 1, n_opaque = 1;
	const pixman_box32_t *px, *op;
	if (kind == PIECES) {
		long m = pieces_of(tree, w, c, &n_opaque);
		if (m < 0)
			return -1;
		n = (size_t)m;
		px = op = tree->boxes;
	} else {
		long m = kind == CLIP ? 1 : opaque_cut(tree, w, c);
		if (m < 0 || libvis_reserve(&tree->boxes, &tree->cap_boxes, 1,
					    sizeof *tree->boxes) < 0)
			return -1;
		tree->boxes[0] = pbox(w->clip);
		px = tree->boxes;
		op = kind == CLIP ? tree->boxes : tree->boxes + 1;
		n_opaque = (size_t)m;
	}
	/* What is left lies in mine: a clip that meets nothing of either takes nothing off. */
	bool meets = kind != CLIP;
	if (k->sign) {
		/* Pieces are disjoint: their counts add up. */
		uint64_t seen = 0;
		for (size_t i = 0; i < n; i++)
			seen += vis_bands_area_in(mine, px[i]);
		if (count(tree, w, seen) < 0)
			return -1;
		meets |= seen != 0;
	}
	if (k->out) {
		long parts = draw(tree, w, px, n);
		if (parts < 0)
			return -1;
		meets = parts > 0 || kind != CLIP;
	}
	return meets ? take_off(k, op, n_opaque) : 0;
}

static int walk_window(struct vis_tree *tree, const struct vis_window *w, size_t level);

/* Walks c and the siblings below it, while something is left. 0, or -1. */
static int walk_from(struct vis_tree *tree, const struct vis_window *c, size_t level)
{
	for (; c && c != tree->walk.stop && tree->walk.left.n; c = c->below)
		if (c->mapped && meets_left(&tree->walk, c->clip) &&
		    walk_window(tree, c, level) < 0)
			return -1;
	return 0;
}

/* Walks a viewable window: its descendants above it first. 0, or -1. */
static int walk_window(struct vis_tree *tree, const struct vis_window *w, size_t level)
{
	struct libvis_walk *k = &tree->walk;
	const struct vis_window *c = w->top;
	while (c && !(c->mapped && meets_left(k, c->clip)))
		c = c->below;
	bool counts = !w->look.input_only, saved = false;
	if (c) {
		/* A tally counts what was left before the descendants took their part. */
		saved = k->sign && counts;
		if (saved) {
			size_t cap = k->cap_saves;
			if (libvis_reserve(&k->saves, &k->cap_saves, level + 1, sizeof *k->saves) < 0)
				return -1;
			for (size_t i = cap; i < k->cap_saves; i++)
				vis_bands_init(&k->saves[i]);
			if (vis_bands_copy(&k->saves[level], &k->left) < 0)
				return -1;
		}
		if (walk_from(tree, c, level + saved) < 0)
			return -1;
	}
	return counts ? visit(tree, w, saved ? &k->saves[level] : &k->left) : 0;
}

/* Walks what k->left holds, from the top-level window start down to stop (not walked; NULL:
 * all), with sign, listing into out. 0, or -1. */
static int walk_left(struct vis_tree *tree, const struct vis_window *start,
		     const struct vis_window *stop, int sign, struct libvis_set *out)
{
	struct libvis_walk *k = &tree->walk;
	k->sign = sign;
	k->out = out;
	k->stop = stop;
	return walk_from(tree, start, 0);
}

/* libvis_walk() stopping at the top-level window stop (NULL: none). */
static int walk_to(struct vis_tree *tree, struct vis_box d, int sign, struct libvis_set *out,
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
	return walk_left(tree, tree->core.root.top, stop, sign, out);
}

int libvis_walk(struct vis_tree *tree, struct vis_box d, int sign, struct libvis_set *out)
{
	return walk_to(tree, d, sign, out, NULL);
}

void libvis_tally_below(struct vis_tree *tree, size_t windows)
{
	tree->tally_max = windows;
	if (tree->tally && windows == 0)
		libvis_tally_stop(tree);
}

/* A window's own pixels: its border box's, or its look's pieces' (none when input-only). 0, or
 * -1 with ENOMEM (the look cut for its size). */
static int count_total(struct vis_win *win)
{
	const struct vis_window *w = win->core;
	uint64_t t = 0;
	if (w->look.input_only) {
		win->total = 0;
		return 0;
	}
	if (!w->cut) {
		win->total = (uint64_t)(w->width + 2 * (int64_t)w->look.border) *
			     (uint64_t)(w->height + 2 * (int64_t)w->look.border);
		return 0;
	}
	const struct vis_look_cut *cut = vis_wtree_cut(w);
	if (!cut)
		return -1;
	for (uint32_t i = 0; i < cut->n; i++)
		t += (uint64_t)cut->rects[i].w * (uint64_t)cut->rects[i].h;
	win->total = t;
	return 0;
}

/* Puts a viewable window's subtree where it is now (its viewable windows' boxes). O(subtree). */
static void place_subtree(struct vis_window *top)
{
	for (struct vis_window *v = top; v;) {
		if (!v->mapped) {
			/* Its subtree is not viewable: past it. */
			struct vis_window *s = v;
			while (s != top && !s->above)
				s = s->parent;
			v = s == top ? NULL : s->above;
			continue;
		}
		vis_wtree_place(v);
		v = vis_wtree_next_within(v, top);
	}
}

void libvis_tally_begin(struct vis_tree *tree, struct vis_win *win, struct vis_box after,
			bool shows_after, bool restacks)
{
	struct vis_box d = { 0, 0, 0, 0 };
	if (tree->tally && !tree->tally_broken) {
		/* Past a change of the order, the update goes over every window. */
		tree->tally_restacked |= restacks;
		if (vis_wtree_viewable(win->core))
			d = vis_wtree_box(win->core);
		if (shows_after)
			d = vis_box_hull(d, after);
		d = vis_box_intersect(d, tree->core.root.clip);
		if (!vis_box_empty(d) && libvis_walk(tree, d, -1, NULL) < 0)
			tree->tally_broken = true;
	}
	tree->tally_box = d;
	tree->kept_ok = false;
}

/*
 * Whether a change of w's place or size alone takes the moved window's way: a top-level window
 * whose pixels are its clip, all opaque, with no viewable child.
 */
static bool moves_alone(const struct vis_window *w)
{
	if (w->parent->parent || !w->mapped || w->look.input_only || pixels_of(w) != CLIP)
		return false;
	for (const struct vis_window *c = w->top; c; c = c->below)
		if (c->mapped)
			return false;
	return true;
}

/*
 * A window that moves alone (moves_alone()) changes what the windows below it see only where it
 * was and is not (they gain it) and where it is and was not (they lose it), and nothing of what
 * the windows above it see: one walk down to it before the change, over the hull d of its boxes,
 * keeps what they leave of d (tree->above) and lists their part of its repaint set; after it,
 * the moved window's own count comes from that, the windows below list the rest of the set, and
 * two walks over those two strips alone correct their tallies. A drag costs one walk over d and
 * the strips, where any other change costs two walks over its box.
 */
void libvis_tally_begin_move(struct vis_tree *tree, struct vis_win *win, struct vis_box after)
{
	struct vis_window *w = win->core;
	if (!tree->tally || tree->tally_broken || !moves_alone(w)) {
		libvis_tally_begin(tree, win, after, vis_wtree_viewable(w), false);
		return;
	}
	struct vis_box d = vis_box_intersect(vis_box_hull(w->box, after), tree->core.root.clip);
	tree->kept_ok = false;
	tree->tally_box = d;
	if (vis_box_empty(d))
		return;
	struct libvis_walk *k = &tree->walk;
	if (walk_to(tree, d, 0, &tree->kept, w) < 0 || vis_bands_copy(&tree->above, &k->left) < 0) {
		tree->tally_broken = true;
		return;
	}
	tree->moved = w;
	tree->moved_from = w->clip;
	tree->moved_seen =
		vis_box_empty(w->clip) ? 0 : vis_bands_area_in(&tree->above, pbox(w->clip));
}

/* The rest of a window's move alone (libvis_tally_begin_move()) over d. 0, or -1. */
static int end_move(struct vis_tree *tree, struct vis_window *w, struct vis_box d)
{
	struct libvis_walk *k = &tree->walk;
	struct vis_win *win = w->data;
	vis_wtree_place(w);
	pixman_box32_t a = pbox(tree->moved_from), b = pbox(w->clip);
	bool was = !vis_box_empty(tree->moved_from), is = !vis_box_empty(w->clip);
	uint64_t now = is ? vis_bands_area_in(&tree->above, b) : 0;
	win->seen += now - tree->moved_seen;
	if ((now || tree->moved_seen) && touch(tree, w) < 0)
		return -1;
	/* Its part of the repaint set, and the windows' below it. */
	if (vis_bands_copy(&k->left, &tree->above) < 0)
		return -1;
	k->out = &tree->kept;
	if (is && (draw(tree, w, &b, 1) < 0 || vis_bands_subtract(&k->left, &k->scratch, b) < 0))
		return -1;
	if (walk_left(tree, w->below, NULL, 0, &tree->kept) < 0)
		return -1;
	/* The windows below gain what it left, and lose what it took. */
	if (was && (vis_bands_intersect(&k->left, &tree->above, a) < 0 ||
		    (is && vis_bands_subtract(&k->left, &k->scratch, b) < 0) ||
		    walk_left(tree, w->below, NULL, 1, NULL) < 0))
		return -1;
	if (is && (vis_bands_intersect(&k->left, &tree->above, b) < 0 ||
		   (was && vis_bands_subtract(&k->left, &k->scratch, a) < 0) ||
		   walk_left(tree, w->below, NULL, -1, NULL) < 0))
		return -1;
	tree->kept_ok = true;
	tree->kept_box = d;
	return 0;
}

void libvis_tally_end(struct vis_tree *tree, struct vis_win *win)
{
	struct vis_box d = tree->tally_box;
	struct vis_window *moved = tree->moved;
	tree->tally_box = (struct vis_box){ 0, 0, 0, 0 };
	tree->moved = NULL;
	if (!tree->tally || tree->tally_broken)
		return;
	if (moved) {
		if (count_total(win) < 0 || end_move(tree, moved, d) < 0)
			tree->tally_broken = true;
		return;
	}
	if (win) {
		if (count_total(win) < 0) {
			tree->tally_broken = true;
			return;
		}
		if (vis_wtree_viewable(win->core))
			place_subtree(win->core);
	}
	/* What each window shows in d now is the repaint set of any damage inside it, until the
	 * next change: a frame's damage is mostly that of its changes. */
	if (vis_box_empty(d))
		return;
	if (libvis_walk(tree, d, 1, &tree->kept) < 0) {
		tree->tally_broken = true;
		return;
	}
	tree->kept_ok = true;
	tree->kept_box = d;
}

/* A window's state from its tally. */
static uint8_t state_of(const struct vis_window *w)
{
	const struct vis_win *win = w->data;
	if (w->look.input_only)
		return VIS_WTREE_STATE_NONE;
	if (win->seen == 0)
		return VIS_FULLY_OBSCURED;
	return win->seen == win->total ? VIS_UNOBSCURED : VIS_PARTIALLY_OBSCURED;
}

/*
 * The pass of an update: the viewable windows in pre-order with their positions and keys (the
 * queries read them, as after a recompute through the tree), and with states, each window's
 * moved to old_state first, as a recompute does. 0, or -1 with ENOMEM (nothing changed then).
 */
static int pass(struct vis_tree *tree, bool states)
{
	struct vis_wtree *core = &tree->core;
	if (libvis_reserve(&core->order, &core->cap_order, core->count, sizeof *core->order) < 0)
		return -1;
	size_t n = 0;
	for (struct vis_window *w = core->root.bottom; w; w = vis_wtree_next(w)) {
		/* Pre-order: the parent's key is set before its children's. */
		bool viewable = w->mapped && (!w->parent->parent || w->parent->key);
		if (states) {
			w->old_state = w->state;
			w->state = viewable ? state_of(w) : VIS_WTREE_STATE_NONE;
		}
		if (!viewable) {
			w->key = 0;
			continue;
		}
		w->key = wtree_key_of(n, core->count);
		w->pos = n;
		core->order[n++] = w;
	}
	core->n_order = n;
	return 0;
}

int libvis_tally_update(struct vis_tree *tree, struct vis_window *const **changed, size_t *n)
{
	bool all = tree->tally_restacked;
	if (all && pass(tree, true) < 0)
		return -1;
	/* Else the order and the boxes stand; states change where the walks went. */
	for (size_t i = 0; !all && i < tree->n_touched; i++) {
		struct vis_window *w = tree->touched[i];
		w->old_state = w->state;
		w->state = state_of(w);
	}
	*changed = tree->touched;
	*n = all ? 0 : tree->n_touched;
	tree->n_touched = 0;
	tree->tally_restacked = false;
	return all;
}

int libvis_tally_start(struct vis_tree *tree)
{
	struct vis_wtree *core = &tree->core;
	for (struct vis_window *w = core->root.bottom; w; w = vis_wtree_next(w)) {
		struct vis_win *win = w->data;
		win->seen = 0;
		if (count_total(win) < 0)
			return -1;
	}
	/* Every window the walk meets is listed as touched unless restacked says all are. */
	tree->tally_restacked = true;
	tree->kept_ok = false;
	if (libvis_walk(tree, core->root.clip, 1, NULL) < 0 || pass(tree, false) < 0)
		return -1;
	/* From now on the changes go without the core's notes. */
	vis_wtree_drop_live(core);
	tree->tally = true;
	tree->tally_broken = tree->tally_restacked = false;
	tree->n_touched = 0;
	return 0;
}

void libvis_tally_stop(struct vis_tree *tree)
{
	tree->kept_ok = false;
	/* The core recomputes everything at its next update (vis_wtree_drop_live()). */
	tree->tally = false;
	tree->tally_broken = false;
}
