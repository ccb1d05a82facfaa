/*
 * libvis's updates: where the tree changed, the live recompute, and what it did, as a compositor
 * needs it: the windows whose state changed and, for those whose exposures are tracked, the pixels
 * they newly show.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "libvis-private.h"

int libvis_grow(void *arr, size_t *cap, size_t count, size_t size)
{
	size_t want = *cap ? *cap : 16;
	while (want < count)
		want = want > SIZE_MAX / 2 ? count : 2 * want;
	if (want > SIZE_MAX / size) {
		errno = EOVERFLOW;
		return -1;
	}
	/* The array pointer is read and written as bytes: it may point to any type. */
	void *old, *more;
	memcpy(&old, arr, sizeof old);
	if (!(more = realloc(old, want * size))) {
		errno = ENOMEM;
		return -1;
	}
	memcpy(arr, &more, sizeof more);
	*cap = want;
	return 0;
}

int libvis_append_rects(pixman_region32_t *region, int64_t dx, int64_t dy,
			struct vis_rect32 **arr, size_t *n, size_t *cap)
{
	int k;
	const pixman_box32_t *b = pixman_region32_rectangles(region, &k);
	if (libvis_reserve(arr, cap, *n + (size_t)k, sizeof **arr) < 0)
		return -1;
	struct vis_rect32 *out = *arr + *n;
	/* The callers' regions lie in the window's border box, whose sides fit in 31 bits: its
	 * window coordinates fit in 32. */
	for (int i = 0; i < k; i++)
		out[i] = (struct vis_rect32){ (int32_t)(b[i].x1 - dx), (int32_t)(b[i].y1 - dy),
					      (uint32_t)(b[i].x2 - b[i].x1),
					      (uint32_t)(b[i].y2 - b[i].y1) };
	*n += (size_t)k;
	return 0;
}

/* A box in pixman's 32-bit coordinates: clamped, as the screen lies well inside them. */
static pixman_box32_t clamp_box(struct vis_box b)
{
	const int64_t lo = INT32_MIN, hi = INT32_MAX;
	return (pixman_box32_t){ (int32_t)(b.x1 < lo ? lo : b.x1 > hi ? hi : b.x1),
				 (int32_t)(b.y1 < lo ? lo : b.y1 > hi ? hi : b.y1),
				 (int32_t)(b.x2 < lo ? lo : b.x2 > hi ? hi : b.x2),
				 (int32_t)(b.y2 < lo ? lo : b.y2 > hi ? hi : b.y2) };
}

void libvis_damage(struct vis_tree *tree, struct vis_win *win)
{
	tree->dirty = true;
	if (!tree->tally) /* the tallies' walks keep the states without notes */
		vis_wtree_note(&tree->core, win->core);
	/* Only exposures read the damage, and only of windows tracked before the change (one
	 * tracked since starts from nothing). */
	if (tree->damage_all || !tree->n_tracked)
		return;
	if (tree->n_damage == LIBVIS_DAMAGE_BOXES) {
		tree->damage_all = true;
		return;
	}
	/* Children are clipped by their parent: its box covers the subtree. */
	tree->damage[tree->n_damage++] = clamp_box(vis_wtree_box(win->core));
}

void libvis_untrack(struct vis_win *win)
{
	if (!win->tracked)
		return;
	struct vis_tree *tree = win->tree;
	size_t at = win->tracked_slot - 1;
	tree->tracked[at] = tree->tracked[--tree->n_tracked];
	if (at < tree->n_tracked)
		tree->tracked[at]->tracked_slot = (uint32_t)(at + 1);
	win->tracked_slot = 0;
	win->tracked = win->known = false;
	pixman_region32_clear(&win->region);
}

VIS_EXPORT int vis_win_track_exposure(struct vis_win *win, int on)
{
	if (!win) {
		errno = EINVAL;
		return -1;
	}
	if (!on) {
		libvis_untrack(win);
		return 0;
	}
	if (win->tracked)
		return 0;
	struct vis_tree *tree = win->tree;
	if (libvis_reserve(&tree->tracked, &tree->cap_tracked, tree->n_tracked + 1,
			   sizeof *tree->tracked) < 0)
		return -1;
	/* What it shows now is known only while the tree is as the last update left it. */
	pixman_region32_clear(&win->region);
	if (!tree->dirty && vis_wtree_visible_region(&tree->core, win->core, &win->region) < 0) {
		pixman_region32_clear(&win->region);
		errno = ENOMEM;
		return -1;
	}
	win->known = !tree->dirty;
	tree->tracked[tree->n_tracked++] = win;
	win->tracked_slot = (uint32_t)tree->n_tracked;
	win->tracked = true;
	return 0;
}

/*
 * The union of the damage boxes, built on first use in an update (only exposure tracking needs
 * it); NULL for everywhere: too many changes, or no memory for the region.
 */
struct damage {
	bool built, ok;
	pixman_region32_t region;
};

static pixman_region32_t *damage_region(struct vis_tree *tree, struct damage *d)
{
	if (!d->built) {
		d->built = true;
		if (!tree->damage_all)
			d->ok = pixman_region32_init_rects(&d->region, tree->damage,
							   (int)tree->n_damage);
	}
	return d->ok ? &d->region : NULL;
}

/*
 * Whether w's visible region may have changed at the update: a pixel that it gained or lost lies
 * in its new clip box and in the box of some change (its own, an ancestor's, or that of a window
 * that covered or uncovered it), or else its state changed. damage: the union of the changes'
 * boxes, or NULL for everywhere.
 */
static bool maybe_exposed(pixman_region32_t *damage, const struct vis_window *w, bool changed)
{
	if (!damage || changed)
		return true;
	if (vis_box_empty(w->clip))
		return false;
	pixman_box32_t b = clamp_box(w->clip);
	return pixman_region32_contains_rectangle(damage, &b) != PIXMAN_REGION_OUT;
}

/*
 * The newly exposed pixels of a tracked window, appended to the tree's rectangles: what it shows
 * now less what it showed. Their count; without memory, none, and the window's baseline is
 * forgotten (the next update reports all it shows).
 */
static uint32_t expose(struct vis_tree *tree, struct vis_win *win)
{
	struct vis_window *w = win->core;
	size_t before = tree->n_rects;
	if (vis_wtree_visible_region(&tree->core, w, &tree->now) < 0 ||
	    !pixman_region32_subtract(&tree->exposed, &tree->now, &win->region) ||
	    !pixman_region32_copy(&win->region, &tree->now) ||
	    libvis_append_rects(&tree->exposed, 0, 0, &tree->rects, &tree->n_rects,
				&tree->cap_rects) < 0) {
		pixman_region32_clear(&win->region);
		win->known = false;
		tree->n_rects = before;
		return 0;
	}
	win->known = true;
	return (uint32_t)(tree->n_rects - before);
}

/* Lists what the update did to one window, if anything; listed: its state change counts. */
static void look_at(struct vis_tree *tree, struct vis_win *win, bool listed, struct damage *d)
{
	const struct vis_window *w = win->core;
	bool changed = listed && w->state != w->old_state;
	uint32_t n_exposed = 0;
	if (win->tracked && (!win->known || maybe_exposed(damage_region(tree, d), w, changed)))
		n_exposed = expose(tree, win);
	if (!changed && !n_exposed)
		return;
	/* Room for every window was made before the recompute. */
	tree->changes[tree->n_changes++] = (struct vis_change){
		.win = win,
		.data = win->data,
		.state = w->state,
		.previous = changed ? w->old_state : w->state,
		.n_exposed = n_exposed,
	};
}

/* Orders windows by stacking (keys grow with it; 0 for those not viewable), then address. */
static int by_stacking(const void *a, const void *b)
{
	const struct vis_window *x = (*(struct vis_win *const *)a)->core;
	const struct vis_window *y = (*(struct vis_win *const *)b)->core;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return x < y ? -1 : x > y;
}

/* Sorts windows by stacking: a frame's few by insertion, the rest by qsort(). */
static void sort_by_stacking(struct vis_win **list, size_t m)
{
	if (m > 16) {
		qsort(list, m, sizeof *list, by_stacking);
		return;
	}
	for (size_t i = 1; i < m; i++) {
		struct vis_win *w = list[i];
		size_t j = i;
		for (; j > 0 && by_stacking(&list[j - 1], &w) > 0; j--)
			list[j] = list[j - 1];
		list[j] = w;
	}
}

VIS_EXPORT int vis_tree_update(struct vis_tree *tree, const struct vis_change **changes, size_t *n)
{
	if (!tree || !changes || !n) {
		errno = EINVAL;
		return -1;
	}
	tree->n_changes = tree->n_rects = 0;
	*changes = tree->changes;
	*n = 0;
	if (!tree->dirty)
		return 0;
	/* Room for every window, in the list and the changes, before the states move: past the
	 * recompute nothing may fail but an exposure, which only forgets its baseline. */
	size_t most = tree->core.count + tree->n_tracked + 1;
	if (libvis_reserve(&tree->list, &tree->cap_list, most, sizeof *tree->list) < 0 ||
	    libvis_reserve(&tree->changes, &tree->cap_changes, most, sizeof *tree->changes) < 0)
		return -1;
	/* From the tallies while the tree stays small and they are whole; else through the core,
	 * which recomputes everything once they are left. */
	if (tree->tally && (tree->tally_broken || tree->core.count > 2 * tree->tally_max))
		libvis_tally_stop(tree);
	struct vis_window *const *changed;
	size_t k, m = 0;
	int tallied = tree->tally ? libvis_tally_update(tree, &changed, &k) : -1;
	if (tree->tally && tallied < 0)
		libvis_tally_stop(tree);
	if (tallied < 0 && vis_wtree_update(&tree->core) < 0)
		return -1;
	tree->dirty = false;
	tree->serial++;
	struct damage d = { 0 };
	if ((tallied == 0 || (tallied < 0 && vis_wtree_changes(&tree->core, &changed, &k))) &&
	    libvis_reserve(&tree->list, &tree->cap_list, k + tree->n_tracked,
			   sizeof *tree->list) == 0) {
		/*
		 * A live recompute or the tallies list the windows they may have changed (no more
		 * than there are);
		 * the others keep their states and regions, but for tracked windows, whose regions
		 * count their own descendants as hiding them (X's clip list): maybe_exposed() tells,
		 * before the sort, so that a desktop of tracked windows is not sorted at each update
		 * for the few a change touched.
		 */
		for (size_t i = 0; i < k; i++) {
			struct vis_win *win = changed[i]->data;
			win->listed = tree->serial;
			tree->list[m++] = win;
		}
		for (size_t i = 0; i < tree->n_tracked; i++) {
			struct vis_win *win = tree->tracked[i];
			if (win->listed != tree->serial &&
			    (!win->known || maybe_exposed(damage_region(tree, &d), win->core, false)))
				tree->list[m++] = win;
		}
		/* In stacking order, those no longer viewable first, each once. */
		sort_by_stacking(tree->list, m);
		for (size_t i = 0; i < m; i++)
			look_at(tree, tree->list[i], tree->list[i]->listed == tree->serial, &d);
	} else {
		/*
		 * Any window may have changed: the recompute went through the tree, which moved
		 * every state to old_state. Pre-order is stacking order, so two walks list those no
		 * longer viewable (key 0), then the others, with no sort: sorting every window cost
		 * a desktop of 1,000 more than the recompute itself. With no window tracked, only
		 * a change of state lists one: its handle is not read for the others.
		 */
		bool any_tracked = tree->n_tracked > 0;
		for (int pass = 0; pass < 2; pass++)
			for (struct vis_window *w = tree->core.root.bottom; w; w = vis_wtree_next(w))
				if ((w->key == 0) == (pass == 0) &&
				    (any_tracked || w->state != w->old_state))
					look_at(tree, w->data, true, &d);
	}
	/* The rectangles are in place: point each change at its own. */
	size_t at = 0;
	for (size_t i = 0; i < tree->n_changes; i++) {
		struct vis_change *c = &tree->changes[i];
		c->exposed = c->n_exposed ? tree->rects + at : NULL;
		at += c->n_exposed;
	}
	if (d.ok)
		pixman_region32_fini(&d.region);
	tree->n_damage = 0;
	tree->damage_all = false;
	/* Taken up when small; without memory, the core goes on. */
	if (!tree->tally && tree->core.count <= tree->tally_max)
		(void)libvis_tally_start(tree);
	*changes = tree->changes;
	*n = tree->n_changes;
	return 0;
}
