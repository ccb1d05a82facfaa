/*
 * libvis's tallies: the states of a small tree's windows, kept by walks (libvis-walk.c) around
 * each change.
 *
 * A window's state follows from two counts, its own pixels (total) and those of them it sees
 * (seen): none seen, fully obscured; all, unobscured; else partially obscured. A change alters
 * what windows see only inside the boxes its window's subtree takes before and after it
 * (vis_wtree_compute_damaged()'s argument), so a walk over their hull before the change takes
 * every window's seen pixels there off its tally and one after it adds those seen then: the
 * tallies stay exact at the cost of two walks over the change's box, which on a desktop of a
 * thousand windows costs less than the live engine's bookkeeping, and grows with the windows
 * there, not the tree. An update then gives the windows the walks met their states from their
 * tallies, and, after a change of the order, numbers the viewable windows' keys and positions
 * again (the queries read them). Past LIBVIS_TALLY_WINDOWS × 2 windows, the core takes over.
 */
#include <string.h>

#include "libvis-private.h"
#include "wtree-live.h"

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
		/* Past a change of the order, the update numbers the windows again. */
		tree->tally_restacked |= restacks;
		tree->tally_restacks = restacks;
		if (vis_wtree_viewable(win->core))
			d = vis_wtree_box(win->core);
		if (shows_after)
			d = vis_box_hull(d, after);
		d = vis_box_intersect(d, tree->core.root.clip);
		if (!vis_box_empty(d) && libvis_walk(tree, d, -1, NULL, NULL) < 0)
			tree->tally_broken = true;
	}
	tree->tally_box = d;
	tree->kept_ok = false;
}

/*
 * Whether a change of w's place or size alone takes the moved window's way: a top-level window
 * whose pixels are its clip (opaque, or opaque in places: no shape), with no viewable child.
 */
static bool moves_alone(const struct vis_window *w)
{
	if (w->parent->parent || !w->mapped || w->look.input_only ||
	    libvis_pixels_of(w) == LIBVIS_PIECES)
		return false;
	for (const struct vis_window *c = w->top; c; c = c->below)
		if (c->mapped)
			return false;
	return true;
}

/*
 * A window that moves alone (moves_alone()) changes what the windows below it see only where it
 * was opaque and is not (they gain it) and where it is opaque and was not (they lose it), and
 * nothing of what the windows above it see: one walk down to it before the change, over the hull
 * d of its boxes, keeps what they leave of d (tree->above) and lists their part of its repaint
 * set; after it, the moved window's own count comes from that, and one walk below it, over what
 * the windows above leave less what it hides both before and after, lists the rest of the set
 * and counts what each window shows where the window was opaque (what it gains) and where it is
 * now (what it loses, which is not listed). A drag costs one walk over d above the window and one
 * below, where any other change costs two walks over its box.
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
	if (libvis_walk(tree, d, 0, &tree->kept, w) < 0) {
		tree->tally_broken = true;
		return;
	}
	/* What is left is kept: the walks after the change start from copies of it. */
	struct vis_bands t = tree->above;
	tree->above = k->left;
	k->left = t;
	tree->moved = w;
	tree->moved_seen = 0;
	tree->n_opaque_was = 0;
	if (!tree->above.n) /* covered above: end_move() has nothing to do */
		return;
	const pixman_box32_t *op;
	long n = libvis_opaque_boxes(tree, w, &op);
	if (n < 0 || libvis_reserve(&tree->opaque_was, &tree->cap_opaque_was, (size_t)n,
				    sizeof *tree->opaque_was) < 0) {
		tree->tally_broken = true;
		return;
	}
	if (n)
		memcpy(tree->opaque_was, op, (size_t)n * sizeof *op);
	tree->n_opaque_was = (size_t)n;
	tree->moved_seen =
		vis_box_empty(w->clip) ? 0 : vis_bands_area_in(&tree->above, pbox(w->clip));
}

/* The rest of a window's move alone (libvis_tally_begin_move()) over d. 0, or -1. */
static int end_move(struct vis_tree *tree, struct vis_window *w, struct vis_box d)
{
	struct libvis_walk *k = &tree->walk;
	struct vis_win *win = w->data;
	vis_wtree_place(w);
	/* The windows above cover d: nothing below changes, nor its own count (none). */
	if (!tree->above.n) {
		tree->kept_ok = true;
		tree->kept_box = d;
		return 0;
	}
	/* Its part of the repaint set, which is what it sees now, and the windows' below it. */
	if (vis_bands_copy(&k->left, &tree->above) < 0)
		return -1;
	k->out = &tree->kept;
	uint64_t now = 0;
	if (!vis_box_empty(w->clip) && libvis_draw_box(tree, w, w->clip, &now) < 0)
		return -1;
	win->seen += now - tree->moved_seen;
	if ((now || tree->moved_seen) && libvis_touch(tree, w) < 0)
		return -1;
	const pixman_box32_t *op;
	long m = libvis_opaque_boxes(tree, w, &op);
	if (m < 0 || libvis_reserve(&tree->opaque_is, &tree->cap_opaque_is, (size_t)m,
				    sizeof *tree->opaque_is) < 0)
		return -1;
	if (m)
		memcpy(tree->opaque_is, op, (size_t)m * sizeof *op);
	tree->n_opaque_is = (size_t)m;
	/* The windows below, in one walk over what is left less what it hides both before and
	 * after: where it was opaque they gain what they show, where it is they lose it (and
	 * list nothing there). */
	for (size_t i = 0; i < tree->n_opaque_is; i++)
		for (size_t j = 0; j < tree->n_opaque_was; j++) {
			pixman_box32_t both = vis_pbox_and(tree->opaque_is[i], tree->opaque_was[j]);
			if (both.x1 < both.x2 && both.y1 < both.y2 &&
			    vis_bands_subtract(&k->left, &k->scratch, both) < 0)
				return -1;
		}
	k->within = true;
	k->in = tree->opaque_was;
	k->n_in = tree->n_opaque_was;
	k->less = tree->opaque_is;
	k->n_less = tree->n_opaque_is;
	if (libvis_walk_left(tree, w->below, NULL, 1, &tree->kept) < 0)
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
	bool restacks = tree->tally_restacks;
	tree->tally_restacks = false;
	if (win) {
		if (count_total(win) < 0) {
			tree->tally_broken = true;
			return;
		}
		if (vis_wtree_viewable(win->core))
			place_subtree(win->core);
		/* Its subtree may have come into view or left it: each one's state is due. */
		for (struct vis_window *v = win->core; restacks && v;
		     v = vis_wtree_next_within(v, win->core))
			if (libvis_touch(tree, v) < 0) {
				tree->tally_broken = true;
				return;
			}
	}
	/* What each window shows in d now is the repaint set of any damage inside it, until the
	 * next change: a frame's damage is mostly that of its changes. */
	if (vis_box_empty(d))
		return;
	if (libvis_walk(tree, d, 1, &tree->kept, NULL) < 0) {
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
 * Numbers the viewable windows' keys and positions again, in pre-order (key 0 for the others),
 * as a recompute through the core leaves them. 0, or -1 with ENOMEM (nothing changed then). O(n).
 */
static int renumber(struct vis_tree *tree)
{
	struct vis_wtree *core = &tree->core;
	struct vis_window *root = &core->root;
	if (libvis_reserve(&core->order, &core->cap_order, core->count, sizeof *core->order) < 0)
		return -1;
	uint64_t step = WTREE_KEY_SPAN / ((uint64_t)core->count + 1), key = WTREE_KEY_BASE;
	size_t n = 0;
	for (struct vis_window *w = root->bottom; w;) {
		/* Pre-order: the parent's key is set before its children's. */
		if (w->mapped && (w->parent == root || w->parent->key)) {
			w->key = key += step;
			w->pos = n;
			core->order[n++] = w;
		} else {
			w->key = 0;
		}
		if (w->bottom) {
			w = w->bottom;
			continue;
		}
		while (!w->above && w->parent != root)
			w = w->parent;
		w = w->above;
	}
	core->n_order = n;
	return 0;
}

/* Empties the list of touched windows. */
static void untouch(struct vis_tree *tree)
{
	for (size_t i = 0; i < tree->n_touched; i++)
		((struct vis_win *)tree->touched[i]->data)->touched_slot = 0;
	tree->n_touched = 0;
}

void libvis_tally_forget(struct vis_tree *tree, struct vis_win *win)
{
	if (!win->touched_slot)
		return;
	size_t at = win->touched_slot - 1;
	tree->touched[at] = tree->touched[--tree->n_touched];
	if (at < tree->n_touched)
		((struct vis_win *)tree->touched[at]->data)->touched_slot = (uint32_t)(at + 1);
	win->touched_slot = 0;
}

int libvis_tally_update(struct vis_tree *tree, struct vis_window *const **changed, size_t *n)
{
	if (tree->tally_restacked && renumber(tree) < 0)
		return -1;
	/* Viewable windows have keys now; the states change where the walks went. */
	for (size_t i = 0; i < tree->n_touched; i++) {
		struct vis_window *w = tree->touched[i];
		w->old_state = w->state;
		w->state = w->key ? state_of(w) : VIS_WTREE_STATE_NONE;
	}
	*changed = tree->touched;
	*n = tree->n_touched;
	untouch(tree);
	tree->tally_restacked = false;
	return 0;
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
	tree->kept_ok = false;
	bool ok = libvis_walk(tree, core->root.clip, 1, NULL, NULL) == 0 && renumber(tree) == 0;
	untouch(tree); /* the states are the core's */
	if (!ok)
		return -1;
	/* From now on the changes go without the core's notes. */
	vis_wtree_drop_live(core);
	tree->tally = true;
	tree->tally_broken = tree->tally_restacked = tree->tally_restacks = false;
	return 0;
}

void libvis_tally_stop(struct vis_tree *tree)
{
	tree->kept_ok = false;
	untouch(tree);
	/* The core recomputes everything at its next update (vis_wtree_drop_live()). */
	tree->tally = false;
	tree->tally_broken = false;
}
