/*
 * The live recompute: the states kept up to date from the changes noted, at the cost of the
 * windows a change can affect rather than of the tree (see vis_wtree_update() for the rule).
 */
#include <errno.h>
#include <pixman.h>
#include <stdlib.h>
#include <string.h>

#include "wtree-live.h"
#include "zgrid.h"

/*
 * The windows below which updates go through the tree, for libvis (visd sets its own, 2048, for
 * its tails: at 1,000 windows bench-wtree found the live update's 99th percentiles 2-20 times
 * the damaged recompute's). Measured on members of the scene family nobody tuned either for
 * (bench-libvis --family 40 --min-n 16 --max-n 256 --seed 11, two runs of each threshold), a
 * frame's median over the region method's was 3.1-3.6 going live from 2048, 2.3-2.6 from 32,
 * 2.2-2.5 from 64, 2.8-2.9 from 128; the 99th percentiles' medians 2.5-3.4 from 2048 and
 * 2.5-2.8 from 64. Below 64 the tree costs less (n 10-64: 3.5 through it, 4.1 live).
 */
#define LIVE_MIN_WINDOWS 64

/*
 * The work, per window, of making the seen regions exact when the structures are built: a unit
 * is a box of the union of the clips above, read once, 1.5–3.2 ns measured (bench-wtree's
 * scenes). A loose seen region costs later changes a walk over every window above it where it
 * is seen, thousands of steps in a cascade; the pass costs 0.3 s at 10^5 windows of cascade
 * and 0.8 s at 10^6 of uniform, and the bound stops unions that grow without end (the grid's)
 * at about 5 µs a window.
 */
#define SEEN_WORK 2048

/* Updates through the tree after one could not go live, before the structures are rebuilt. */
#define LIVE_COOLDOWN 64

/* Keys stay in [KEY_LOW, KEY_HIGH]; windows new at either end of the order are KEY_GAP apart. */
#define KEY_LOW ((uint64_t)1 << 40)
#define KEY_HIGH (UINT64_MAX - KEY_LOW)
#define KEY_GAP ((uint64_t)1 << 32)

/* Makes room for one more element in a growing array. 0, or -1 with ENOMEM. */
static int grow(void *array, size_t *cap, size_t n, size_t size)
{
	void **a = array;
	if (n < *cap)
		return 0;
	size_t c = *cap ? 2 * *cap : 16;
	void *b = c <= SIZE_MAX / size ? realloc(*a, c * size) : NULL;
	if (!b) {
		errno = ENOMEM;
		return -1;
	}
	*a = b;
	*cap = c;
	return 0;
}

/*
 * The candidates and changed windows an update has room for once the structures are built,
 * a share of the viewable windows: arrays grown in an update fault their new pages in there
 * (172 faults, 3.5 ms against 0.8 ms with the pages in, when a raise over a cascade of 10^5
 * first took 6,000 windows, on a 2-core VM), a cost better paid with the build's.
 */
#define WORK_SHARE 16

/* Grows an array to at least want elements, touching the new ones. Not being able to is not
 * an error: the array grows when it must. */
static void prefault(void *array, size_t *cap, size_t want, size_t size)
{
	void **a = array;
	if (*cap >= want || want > SIZE_MAX / size)
		return;
	unsigned char *b = realloc(*a, want * size);
	if (!b)
		return;
	memset(b + *cap * size, 0, (want - *cap) * size);
	*a = b;
	*cap = want;
}

/* The tree's live structures, made on first use; NULL without memory. */
static struct vis_wtree_live *live_of(struct vis_wtree *tree)
{
	if (!tree->live && (tree->live = calloc(1, sizeof *tree->live))) {
		tree->live->min_windows = LIVE_MIN_WINDOWS;
		tree->live->seen_boxes = SEEN_BOXES;
		tree->live->left_boxes = LEFT_BOXES;
		tree->live->give_up = SIZE_MAX;
	}
	return tree->live;
}

int vis_wtree_live_from(struct vis_wtree *tree, size_t windows)
{
	struct vis_wtree_live *lv = live_of(tree);
	if (!lv) {
		errno = ENOMEM;
		return -1;
	}
	lv->min_windows = windows;
	return 0;
}

void vis_wtree_live_destroy(struct vis_wtree_live *lv)
{
	if (!lv)
		return;
	if (lv->grid.cells)
		vis_zgrid_finish(&lv->grid);
	free(lv->slots);
	free(lv->free_slots);
	free(lv->seen);
	free(lv->free_seen);
	free(lv->pending);
	vis_sgrid_finish(&lv->seen_grid);
	free(lv->dirty);
	free(lv->changed);
	free(lv->exposures);
	free(lv->cands);
	free(lv->gains);
	free(lv->saved);
	free(lv);
}

/* Indexes w's clip under its key, in a slot of its own. 0, or -1 (ENOMEM: the grid must then be
 * rebuilt). */
static int index_window(struct vis_wtree_live *lv, struct vis_window *w)
{
	uint32_t slot;
	if (lv->n_free) {
		slot = lv->free_slots[--lv->n_free];
	} else {
		if (lv->n_slots == UINT32_MAX) {
			errno = ENOMEM;
			return -1;
		}
		size_t cap = lv->cap_slots;
		if (grow(&lv->slots, &cap, lv->n_slots, sizeof *lv->slots) < 0)
			return -1;
		/* Room to free every slot, so that freeing one cannot fail. */
		uint32_t *f = cap > lv->cap_slots ? realloc(lv->free_slots, cap * sizeof *f)
						  : lv->free_slots;
		if (!f) {
			errno = ENOMEM;
			return -1;
		}
		lv->free_slots = f;
		lv->cap_slots = cap;
		slot = (uint32_t)lv->n_slots++;
	}
	lv->slots[slot] = (struct live_slot){ pbox(w->clip), w, wtree_live_has_look(w) };
	w->live_look = lv->slots[slot].look;
	lv->n_looks += w->live_look;
	w->live_slot = slot;
	w->live_indexed = true;
	return vis_zgrid_insert(&lv->grid, w->clip, w->key, slot);
}

/* Takes an indexed window's clip out of the grid and frees its slot. */
static void unindex_window(struct vis_wtree_live *lv, struct vis_window *w)
{
	vis_zgrid_remove(&lv->grid, w->clip, w->key);
	lv->free_slots[lv->n_free++] = w->live_slot;
	w->live_indexed = false;
	w->live_looked = w->live_look;
	lv->n_looks -= w->live_look;
}

/* Removes slot (1-based) from a list of windows whose slot field is at offset off. */
#define REMOVE_SLOT(list, n, w, field)                                   \
	do {                                                              \
		size_t at_ = (w)->field - 1;                              \
		(list)[at_] = (list)[--(n)];                              \
		if (at_ < (n))                                            \
			(list)[at_]->field = (uint32_t)(at_ + 1);         \
		(w)->field = 0;                                           \
	} while (0)

/* Makes room in the seen list for more windows, and to free every entry. 0, or -1 (ENOMEM). */
static int seen_reserve(struct vis_wtree_live *lv, size_t more)
{
	size_t cap = lv->cap_seen;
	while (cap < lv->n_seen + more) {
		if (cap > UINT32_MAX / 2) {
			errno = ENOMEM;
			return -1;
		}
		cap = cap ? 2 * cap : 16;
	}
	if (cap == lv->cap_seen)
		return 0;
	struct seen_window *s = realloc(lv->seen, cap * sizeof *s);
	if (!s) {
		errno = ENOMEM;
		return -1;
	}
	lv->seen = s;
	uint32_t *f = realloc(lv->free_seen, cap * sizeof *f);
	if (f)
		lv->free_seen = f;
	uint32_t *p = f ? realloc(lv->pending, cap * sizeof *p) : NULL;
	if (!p) {
		errno = ENOMEM;
		return -1; /* the lists grew: cap_seen stays what all hold */
	}
	lv->pending = p;
	lv->cap_seen = cap;
	return 0;
}

/* Gives w an entry in the seen list, a free one first (room made). */
static void seen_add(struct vis_wtree_live *lv, struct vis_window *w)
{
	size_t at;
	if (lv->n_free_seen) {
		at = lv->free_seen[--lv->n_free_seen];
		lv->seen[at].stamp += 2;
	} else {
		at = lv->n_seen++;
		lv->seen[at].stamp = 0;
	}
	lv->seen[at].w = w;
	w->live_seen = (uint32_t)(at + 1);
}

static void seen_remove(struct vis_wtree_live *lv, struct vis_window *w)
{
	size_t at = w->live_seen - 1;
	lv->seen[at].w = NULL;
	lv->seen[at].stamp += 2;
	lv->free_seen[lv->n_free_seen++] = (uint32_t)at;
	w->live_seen = 0;
}

/* Whether a seen grid entry stands: its seen entry is in use and has not changed since. */
static bool seen_stands(const void *arg, uint32_t val, uint32_t stamp)
{
	const struct vis_wtree_live *lv = arg;
	return val < lv->n_seen && lv->seen[val].w && SEEN_STAMP(lv->seen[val].stamp) == stamp;
}

/* Puts a seen entry's boxes in the seen grid; without memory, the grid is no longer used. */
static void seen_index(struct vis_wtree_live *lv, size_t at)
{
	const struct seen_window *sw = &lv->seen[at];
	int n = sw->seen.n == SEEN_EXTENTS ? 1 : sw->seen.n;
	for (int i = 0; lv->seen_grid_ok && i < n; i++)
		lv->seen_grid_ok = vis_sgrid_insert(&lv->seen_grid, vbox(&sw->seen.boxes[i]),
						    (uint32_t)at, SEEN_STAMP(sw->stamp), seen_stands,
						    lv) == 0;
}

void wtree_live_seen_flush(struct vis_wtree_live *lv)
{
	for (size_t i = 0; i < lv->n_pending; i++) {
		size_t at = lv->pending[i];
		lv->seen[at].stamp &= ~SEEN_PENDING;
		if (lv->seen[at].w)
			seen_index(lv, at);
	}
	lv->n_pending = 0;
}

void wtree_live_seen_changed(struct vis_wtree_live *lv, size_t at)
{
	lv->seen[at].stamp += 2;
	if (!(lv->seen[at].stamp & SEEN_PENDING)) {
		lv->seen[at].stamp |= SEEN_PENDING;
		lv->pending[lv->n_pending++] = (uint32_t)at; /* at most one per entry: room */
	}
}

/* Whether two seen regions have the same boxes (or the same loose box; its edges aside). */
static bool same_boxes(const struct seen *a, const struct seen *b)
{
	if (a->n != b->n)
		return false;
	int n = a->n == SEEN_EXTENTS ? 1 : a->n;
	for (int i = 0; i < n; i++)
		if (a->boxes[i].x1 != b->boxes[i].x1 || a->boxes[i].y1 != b->boxes[i].y1 ||
		    a->boxes[i].x2 != b->boxes[i].x2 || a->boxes[i].y2 != b->boxes[i].y2)
			return false;
	return true;
}

/*
 * Sets w's seen region (w in the seen list), in the seen grid too; fresh tells that the entry
 * was just given (its boxes not in the grid yet).
 */
static void seen_set(struct vis_wtree_live *lv, struct vis_window *w, struct seen seen, bool fresh)
{
	struct seen *s = &lv->seen[w->live_seen - 1].seen;
	if (!fresh && same_boxes(s, &seen)) {
		s->edges = seen.edges;
		return; /* its entries in the grid stand */
	}
	*s = seen;
	wtree_live_seen_changed(lv, w->live_seen - 1);
}

void vis_wtree_note(struct vis_wtree *tree, struct vis_window *w)
{
	struct vis_wtree_live *lv = live_of(tree);
	if (!lv) {
		tree->stale = true; /* the change is not known: recompute everything */
		return;
	}
	if (lv->n_damage == LIVE_DAMAGE)
		lv->damage_all = true;
	else if (!lv->damage_all)
		lv->damage[lv->n_damage++] = vis_wtree_box(w);
	if (w->live_dirty)
		return;
	w->live_parent = w->parent;
	if (grow(&lv->dirty, &lv->cap_dirty, lv->n_dirty, sizeof *lv->dirty) < 0) {
		lv->damage_all = true;
		lv->valid = false;
		return;
	}
	lv->dirty[lv->n_dirty++] = w;
	w->live_dirty = (uint32_t)lv->n_dirty;
}

/* Keeps what a window saw as an exposure for the next update (w: NULL once destroyed). */
static void expose(struct vis_wtree_live *lv, uint64_t key, struct vis_window *w,
		   const struct seen *seen)
{
	if (grow(&lv->exposures, &lv->cap_exposures, lv->n_exposures, sizeof *lv->exposures) < 0) {
		lv->valid = false;
		return;
	}
	lv->exposures[lv->n_exposures++] = (struct exposure){ key, w, *seen };
}

void wtree_live_forget(struct vis_wtree *tree, struct vis_window *w)
{
	struct vis_wtree_live *lv = tree->live;
	if (!lv)
		return;
	if (w->live_dirty)
		REMOVE_SLOT(lv->dirty, lv->n_dirty, w, live_dirty);
	if (w->live_changed)
		REMOVE_SLOT(lv->changed, lv->n_changed, w, live_changed);
	if (!lv->valid)
		return;
	if (w->live_indexed)
		unindex_window(lv, w);
	if (w->live_seen) {
		expose(lv, w->key, NULL, &lv->seen[w->live_seen - 1].seen);
		seen_remove(lv, w);
	}
}

/*
 * Empties the changed list, first making each one's old state its state (reset) as a recompute
 * moves every state to old_state; a recompute through the tree has done so already.
 */
static void reset_changed(struct vis_wtree_live *lv, bool reset)
{
	for (size_t i = 0; i < lv->n_changed; i++) {
		if (reset)
			lv->changed[i]->old_state = lv->changed[i]->state;
		lv->changed[i]->live_changed = 0;
	}
	lv->n_changed = 0;
	lv->changed_all = lv->changed_lost = false;
}

/* Lists a window as changed; a full list is a flag that every window may have. */
static void list_changed(struct vis_wtree_live *lv, struct vis_window *w)
{
	if (w->live_changed)
		return;
	if (grow(&lv->changed, &lv->cap_changed, lv->n_changed, sizeof *lv->changed) < 0) {
		lv->changed_lost = lv->changed_all = true;
		return;
	}
	lv->changed[lv->n_changed++] = w;
	w->live_changed = (uint32_t)lv->n_changed;
}

/* Forgets the notes: the recompute that used them succeeded. */
static void clear_notes(struct vis_wtree_live *lv)
{
	for (size_t i = 0; i < lv->n_dirty; i++)
		lv->dirty[i]->live_dirty = 0;
	lv->n_dirty = 0;
	lv->n_damage = 0;
	lv->damage_all = false;
	lv->n_exposures = 0;
}

/*
 * After a recompute through the tree (wk its work), which moved every state to old_state:
 * lists the windows whose state changed, as any window may have.
 */
static void list_state_changes(struct vis_wtree *tree, struct vis_wtree_live *lv,
			       const struct vis_wtree_work *wk)
{
	reset_changed(lv, false);
	for (size_t i = 0; i < tree->n_order; i++)
		if (tree->order[i]->state != tree->order[i]->old_state)
			list_changed(lv, tree->order[i]);
	for (size_t i = 0; i < wk->n_hidden; i++)
		if (wk->hidden[i]->state != wk->hidden[i]->old_state)
			list_changed(lv, wk->hidden[i]);
	lv->changed_all = true;
}

void vis_wtree_drop_live(struct vis_wtree *tree)
{
	tree->stale = true;
	struct vis_wtree_live *lv = tree->live;
	if (!lv)
		return;
	clear_notes(lv);
	lv->valid = lv->keeping = false;
}

void wtree_live_invalidate(struct vis_wtree *tree)
{
	if (tree->live && !tree->live->keeping)
		tree->live->valid = false;
}

bool wtree_live_keeping(const struct vis_wtree *tree)
{
	return tree->live && tree->live->keeping;
}

/*
 * Keeps a box holding a window's seen region after a recompute through the tree whose damage
 * lies in the box damage (or none when it sees nothing): outside the damage its pixels are
 * covered as before, so what it sees now lies in what it saw and the damage, inside its clip.
 * 0, or -1 (ENOMEM).
 */
static int seen_after(struct vis_wtree_live *lv, struct vis_window *w, struct vis_box damage)
{
	bool sees = w->state == VIS_UNOBSCURED || w->state == VIS_PARTIALLY_OBSCURED;
	if (!sees) {
		if (w->live_seen)
			seen_remove(lv, w);
		return 0;
	}
	struct vis_box box = vis_box_intersect(damage, w->clip);
	bool fresh = !w->live_seen;
	if (!fresh) {
		const struct seen *old = &lv->seen[w->live_seen - 1].seen;
		int n = old->n == SEEN_EXTENTS ? 1 : old->n;
		for (int i = 0; i < n; i++)
			box = vis_box_hull(box, vbox(&old->boxes[i]));
	} else {
		if (seen_reserve(lv, 1) < 0)
			return -1;
		seen_add(lv, w);
	}
	box = vis_box_intersect(box, w->clip);
	seen_set(lv, w, (struct seen){ SEEN_EXTENTS, 0, { pbox(vis_box_empty(box) ? w->clip : box) } },
		 fresh);
	return 0;
}

void wtree_live_repair(struct vis_wtree *tree, const struct vis_wtree_work *wk)
{
	struct vis_wtree_live *lv = tree->live;
	struct vis_box damage = { 0, 0, 0, 0 };
	for (size_t i = 0; i < lv->n_damage && !lv->damage_all; i++)
		damage = vis_box_hull(damage, lv->damage[i]);
	if (lv->damage_all)
		damage = tree->root.clip;
	bool ok = true;
	for (size_t a = 0; a < wk->n_affected; a++)
		ok &= seen_after(lv, tree->order[wk->affected[a]], damage) == 0;
	for (size_t i = 0; i < wk->n_hidden; i++)
		ok &= seen_after(lv, wk->hidden[i], damage) == 0;
	list_state_changes(tree, lv, wk);
	if (!ok)
		lv->valid = false;
}

void wtree_live_computed(struct vis_wtree *tree, const struct vis_wtree_work *wk)
{
	struct vis_wtree_live *lv = live_of(tree);
	if (!lv)
		return;
	lv->valid = false;
	list_state_changes(tree, lv, wk);
}

/*
 * The cells along a side of the grid for n windows: about GRID_WINDOWS_PER_CELL windows a cell,
 * up to VIS_ZGRID_SIDE. A walk merges the cells its box meets, a heap step an entry: in a small
 * tree fine cells cost more steps than the entries they leave out (100 windows on 3840×2160, a
 * move 116,000 instructions in 16 × 16 cells, of which 40% the merge). Coarse cells cost a walk
 * that fragments, which goes on a cell at a time, more: at 16 windows a cell, bench-stall's chain
 * 64 deep over 1,000 windows took 23.7 s for its moves against 7.9 s in 16 × 16 cells; at 4, 7.9 s,
 * and a frame of random 100 / 300 windows in bench-libvis 10.6 / 9.0 µs against 13.4 / 11.1.
 */
#define GRID_WINDOWS_PER_CELL 4

static uint32_t grid_side(size_t n)
{
	uint32_t side = 1;
	while (side < VIS_ZGRID_SIDE && (size_t)side * side * GRID_WINDOWS_PER_CELL < n)
		side++;
	return side;
}

/*
 * Builds the live structures from a tree just computed through the order, unless a viewable
 * window lies under a shaped ancestor: the grid from the order, the seen list from the states
 * (the regions not known: their clips). 0, or -1 (ENOMEM, or such a window: the structures are
 * then not valid).
 */
static int rebuild(struct vis_wtree *tree, struct vis_wtree_live *lv)
{
	for (size_t i = 0; i < tree->n_order; i++)
		if (wtree_live_under_shape(tree->order[i]))
			return -1;
	if (lv->grid.cells)
		vis_zgrid_finish(&lv->grid);
	lv->n_seen = 0;
	lv->n_free_seen = 0;
	lv->n_pending = 0;
	lv->n_slots = 0;
	lv->n_looks = 0;
	lv->n_free = 0;
	for (struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w)) {
		w->live_seen = 0;
		w->live_indexed = false;
		w->live_leaf = true;
	}
	for (size_t i = 0; i < tree->n_order; i++)
		tree->order[i]->parent->live_leaf = false;
	lv->grid_windows = tree->n_order;
	if (vis_zgrid_init(&lv->grid, tree->root.clip, grid_side(tree->n_order)) < 0)
		return -1;
	for (size_t i = 0; i < tree->n_order; i++) {
		struct vis_window *w = tree->order[i];
		if (w->look.input_only || vis_box_empty(w->clip))
			continue;
		if (index_window(lv, w) < 0)
			return -1;
		if (w->state == VIS_FULLY_OBSCURED)
			continue;
		if (seen_reserve(lv, 1) < 0)
			return -1;
		seen_add(lv, w);
		lv->seen[w->live_seen - 1].seen =
			(struct seen){ SEEN_EXTENTS, 0, { pbox(w->clip) } };
	}
	if (wtree_live_seen_from_order(tree, lv, SEEN_WORK * tree->n_order + 4096) < 0)
		return -1;
	if (lv->seen_grid.cells)
		vis_sgrid_finish(&lv->seen_grid);
	lv->seen_grid_ok = vis_sgrid_init(&lv->seen_grid, tree->root.clip) == 0;
	for (size_t at = 0; at < lv->n_seen; at++)
		seen_index(lv, at);
	size_t room = tree->n_order / WORK_SHARE + 256;
	prefault(&lv->cands, &lv->cap_cands, room, sizeof *lv->cands);
	prefault(&lv->changed, &lv->cap_changed, room, sizeof *lv->changed);
	lv->valid = true;
	return 0;
}

/* The previous viewable window in pre-order, or NULL before the first. O(siblings + depth). */
static struct vis_window *prev_viewable(const struct vis_window *w)
{
	struct vis_window *s = w->below;
	while (s && !s->mapped)
		s = s->below;
	if (!s)
		return w->parent->parent ? w->parent : NULL;
	for (;;) {
		struct vis_window *c = s->top;
		while (c && !c->mapped)
			c = c->below;
		if (!c)
			return s;
		s = c;
	}
}

/*
 * Gives keys to the run of viewable windows without one that holds viewable d (its subtree's,
 * and those of changed subtrees next to it), in pre-order between the nearest keyed windows
 * before and after the run: each window is keyed once, however many changed subtrees lie side
 * by side (a batch creating windows). false when the keys there are used up: the order is then
 * numbered afresh by a recompute through the tree.
 */
static bool give_keys(const struct vis_wtree *tree, struct vis_window *d)
{
	if (d->key)
		return true; /* in a run keyed already */
	struct vis_window *first = d, *p = prev_viewable(d), *s = d;
	for (; p && !p->key; p = prev_viewable(p))
		first = p;
	size_t k = 0;
	for (s = first; s && !s->key; s = vis_wtree_next_viewable(tree, s))
		k++;
	uint64_t span = (uint64_t)(k + 1) * KEY_GAP;
	uint64_t lo = p ? p->key : 0, hi = s ? s->key : 0;
	if (!lo && !hi)
		lo = WTREE_KEY_BASE;
	if (!hi)
		hi = lo < KEY_HIGH - span ? lo + span : KEY_HIGH;
	if (!lo)
		lo = hi > KEY_LOW + span ? hi - span : KEY_LOW;
	if (hi <= lo || (hi - lo) / (k + 1) == 0)
		return false;
	uint64_t step = (hi - lo) / (k + 1), key = lo;
	for (struct vis_window *v = first; v != s; v = vis_wtree_next_viewable(tree, v))
		v->key = key += step;
	return true;
}

int wtree_live_gained(struct vis_wtree_live *lv, struct candidate *c, struct vis_box box)
{
	if (grow(&lv->gains, &lv->cap_gains, lv->n_gains, sizeof *lv->gains) < 0)
		return -1;
	lv->gains[lv->n_gains++] = (struct gained_box){ box, c->gained };
	c->gained = (uint32_t)lv->n_gains;
	return 0;
}

int wtree_live_take(struct vis_wtree_live *lv, struct vis_window *w, uint8_t state, bool gain)
{
	/* An indexed window has pixels: its look is not read (another cache line) for those. */
	if (!w->live_indexed && w->look.input_only)
		return 0;
	if (w->live_mark == lv->mark) {
		lv->cands[w->live_cand - 1].gain |= gain;
		return 0;
	}
	if (grow(&lv->cands, &lv->cap_cands, lv->n_cands, sizeof *lv->cands) < 0)
		return -1;
	w->live_mark = lv->mark;
	lv->cands[lv->n_cands++] = (struct candidate){ .w = w, .state = state, .gain = gain };
	w->live_cand = (uint32_t)lv->n_cands;
	return 0;
}

bool wtree_live_kept_parent(const struct vis_window *w)
{
	const struct vis_window *root = w;
	for (const struct vis_window *a = w; a->parent; a = a->parent)
		if (a->live_dirty)
			root = a;
	return root->live_parent == root->parent;
}

bool wtree_live_order_stale(const struct vis_wtree *tree)
{
	return tree->live && tree->live->valid && tree->n_order == 0 && tree->count > 0;
}

bool wtree_live_indexed(const struct vis_wtree *tree)
{
	return tree->live && tree->live->valid;
}

/* Whether some ancestor of w was noted too: its change takes w's in. */
static bool under_dirty(const struct vis_window *w)
{
	for (const struct vis_window *a = w->parent; a; a = a->parent)
		if (a->live_dirty)
			return true;
	return false;
}

/* The result of a live update that cannot go live: the caller recomputes through the tree. */
#define NOT_LIVE 1

/* Whether an ancestor of w up to d (w in d's subtree) has a shape. O(depth below d). */
static bool shaped_within(const struct vis_window *w, const struct vis_window *d)
{
	for (const struct vis_window *a = w; a != d; a = a->parent)
		if (a->parent->look.shaped)
			return true;
	return false;
}

/*
 * The changed windows past which an update recomputes the states through the tree (keeping the
 * structures) rather than walk for each: a burst, such as a client's pipelined changes read in
 * one turn. Below 2,048 windows a handful, as that recompute costs little there: through visd
 * at 1,000 windows and 100 subscribers, with 4 + n / 512 pipelined changes went at 52-57k a
 * second and one at a time (5% of them batches of 8) at p50 / p99 35-38 / 401-453 µs; with
 * 64 + n / 32, 27-36k a second. Above, n / 32 and a few (a base of 4 or 64 measured the same at
 * 10^4 and 10^5 windows).
 */
static size_t burst_windows(const struct vis_wtree *tree)
{
	return 4 + tree->count / (tree->count < 2048 ? 512 : 32);
}

/*
 * Finds the changed subtrees' roots (moved to the front of dirty; returns how many) and marks
 * their windows viewable or not; -1 when the changes would leave a viewable window under a shaped
 * ancestor (the live engine does not cut by ancestors' shapes). *many: they take more windows
 * than burst_windows().
 */
static long roots_of(struct vis_wtree *tree, struct vis_wtree_live *lv, bool *many)
{
	size_t roots = 0, windows = 0, budget = burst_windows(tree);
	bool look = false;
	for (size_t i = 0; i < lv->n_dirty; i++) {
		struct vis_window *d = lv->dirty[i];
		if (under_dirty(d))
			continue;
		lv->dirty[i] = lv->dirty[roots];
		lv->dirty[roots++] = d;
		bool d_under = wtree_live_under_shape(d);
		for (struct vis_window *v = d; v; v = vis_wtree_next_within(v, d)) {
			v->live_viewable = v->mapped &&
					   (v == d ? vis_wtree_viewable(v->parent) : v->parent->live_viewable);
			look |= v->live_viewable && (d_under || shaped_within(v, d));
			windows++;
		}
	}
	/* The slots of the moved entries: clear_notes() zeroes them all at the end. */
	for (size_t i = 0; i < lv->n_dirty; i++)
		lv->dirty[i]->live_dirty = (uint32_t)(i + 1);
	*many = windows > budget;
	return look ? -1 : (long)roots;
}

/*
 * Takes the changed subtrees out of the grid, keeping what each of their windows saw as an
 * exposure under its old key.
 */
static int unindex(struct vis_wtree_live *lv, size_t roots)
{
	lv->n_saved = 0;
	for (size_t r = 0; r < roots; r++) {
		struct vis_window *d = lv->dirty[r];
		for (struct vis_window *v = d; v; v = vis_wtree_next_within(v, d)) {
			if (grow(&lv->saved, &lv->cap_saved, lv->n_saved, sizeof *lv->saved) < 0)
				return -1;
			lv->saved[lv->n_saved++] =
				(struct saved_boxes){ v, v->key, v->box, v->clip, v->inner };
			if (v->live_seen && wtree_live_walk_refine(lv, v) < 0)
				return -1;
			if (v->live_seen)
				expose(lv, v->key, v, &lv->seen[v->live_seen - 1].seen);
			if (v->live_indexed)
				unindex_window(lv, v);
			v->key = 0;
		}
	}
	return 0;
}

/* Places the changed subtrees' viewable windows, indexes them, and takes every window there. */
static int reindex(struct vis_wtree_live *lv, size_t roots)
{
	for (size_t r = 0; r < roots; r++) {
		struct vis_window *d = lv->dirty[r];
		for (struct vis_window *v = d; v; v = vis_wtree_next_within(v, d)) {
			if (!v->live_viewable) {
				if (v->state != VIS_WTREE_STATE_NONE &&
				    wtree_live_take(lv, v, VIS_WTREE_STATE_NONE, true) < 0)
					return -1;
				continue;
			}
			vis_wtree_place(v);
			/* Its ancestors have a viewable descendant now. */
			v->live_leaf = true;
			for (struct vis_window *a = v->parent; a->parent && a->live_leaf; a = a->parent)
				a->live_leaf = false;
			if (v->look.input_only)
				continue;
			if (!vis_box_empty(v->clip) && index_window(lv, v) < 0)
				return -1;
			if (wtree_live_take(lv, v, STATE_UNKNOWN, true) < 0)
				return -1;
		}
	}
	return 0;
}

/* Makes the candidates' states and seen regions the tree's: cannot fail (room is made first). */
static int commit(struct vis_wtree_live *lv)
{
	size_t changed_room = lv->n_changed + lv->n_cands;
	if (seen_reserve(lv, lv->n_cands) < 0)
		return -1;
	while (lv->cap_changed < changed_room)
		if (grow(&lv->changed, &lv->cap_changed, lv->cap_changed, sizeof *lv->changed) < 0)
			return -1;
	for (size_t i = 0; i < lv->n_cands; i++) {
		struct candidate *c = &lv->cands[i];
		struct vis_window *w = c->w;
		bool sees = c->state == VIS_UNOBSCURED || c->state == VIS_PARTIALLY_OBSCURED;
		bool fresh = sees && !w->live_seen;
		if (fresh)
			seen_add(lv, w);
		else if (!sees && w->live_seen)
			seen_remove(lv, w);
		if (sees)
			seen_set(lv, w, c->seen, fresh);
		w->old_state = w->state;
		w->state = c->state;
		list_changed(lv, w);
	}
	return 0;
}

/*
 * The states through the tree, the structures kept: the changed subtrees are in the grid under
 * their new keys already, and the recompute keeps the keys (wtree_live_keeping()); the windows
 * it recomputed then get their clips as seen regions (wtree_live_repair()).
 */
static int through_tree_keeping(struct vis_wtree *tree, struct vis_wtree_live *lv)
{
	/* The recompute finds the boxes as the last one left them, and moves them itself. */
	for (size_t i = 0; i < lv->n_saved; i++) {
		struct saved_boxes *b = &lv->saved[i];
		b->w->box = b->box;
		b->w->clip = b->clip;
		b->w->inner = b->inner;
	}
	tree->stale = false;
	lv->keeping = true;
	int rc = lv->damage_all ? vis_wtree_compute(tree)
				: vis_wtree_compute_damaged(tree, lv->damage, lv->n_damage);
	lv->keeping = false;
	return rc;
}

/* How the one window an update changed, if that is all, moved among the others in the order. */
enum lone { LONE_NO, LONE_IN_PLACE, LONE_LOWERED };

/*
 * Whether the update changed one window alone (none destroyed), viewable before and now and
 * without viewable descendants, and how: in place when its old key lies between the keys of the
 * windows before and after it now, which kept theirs; lowered when its key fell and its clip
 * stayed.
 */
static enum lone lone(const struct vis_wtree *tree, const struct vis_wtree_live *lv)
{
	if (lv->n_saved != 1 || !lv->saved[0].key)
		return LONE_NO;
	for (size_t e = 0; e < lv->n_exposures; e++)
		if (!lv->exposures[e].w)
			return LONE_NO; /* a window destroyed too */
	const struct vis_window *w = lv->saved[0].w, *p = prev_viewable(w),
				*n = vis_wtree_next_viewable(tree, w);
	uint64_t old = lv->saved[0].key;
	struct vis_box was = lv->saved[0].clip;
	/* Its shortcuts take its pixels to be its clip, before and now. */
	if (!w->key || w->state == VIS_WTREE_STATE_NONE || wtree_live_has_look(w) || w->live_looked)
		return LONE_NO;
	if ((!p || p->key < old) && (!n || n->key > old))
		return LONE_IN_PLACE;
	return vis_box_equal(was, w->clip) && w->key < old ? LONE_LOWERED : LONE_NO;
}

/* The exposure of what a changed window saw, or NULL. */
static struct exposure *exposure_of(struct vis_wtree_live *lv, const struct vis_window *w)
{
	for (size_t e = 0; e < lv->n_exposures; e++)
		if (lv->exposures[e].w == w)
			return &lv->exposures[e];
	return NULL;
}

/*
 * A changed window's state and seen region (0, -1 or OVER_BUDGET), as lone() allows; one lowered
 * takes the windows its exposure would, adding to exposed.
 */
static int query_changed(const struct vis_wtree *tree, struct vis_wtree_live *lv,
			 struct candidate *c, size_t changed, pixman_region32_t *exposed)
{
	struct exposure *e;
	switch (changed == 1 ? lone(tree, lv) : LONE_NO) {
	case LONE_IN_PLACE:
		return wtree_live_walk_moved(lv, c, lv->saved[0].clip);
	case LONE_LOWERED:
		/* None when it saw nothing: then it sees nothing now. */
		e = exposure_of(lv, c->w);
		return wtree_live_walk_lowered(lv, c, e, exposed);
	default:
		return wtree_live_walk_query(lv, c);
	}
}

/* The live update proper: 0, NOT_LIVE, or -1 (ENOMEM, the structures then no longer valid). */
static int update(struct vis_wtree *tree, struct vis_wtree_live *lv)
{
	bool many;
	long roots = roots_of(tree, lv, &many);
	if (roots < 0)
		return NOT_LIVE;
	if (++lv->mark == 0) {
		for (struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w))
			w->live_mark = 0;
		lv->mark = 1;
	}
	lv->n_cands = 0;
	lv->n_gains = 0;
	/*
	 * A walk's step (a heap step, a region test) costs 40 ns or so, and the recompute through
	 * the tree 17 (random) to 150 ns (cascade) a window, measured at 10^5: past n steps in all
	 * (narrowing loose boxes aside), the states come from that recompute, and the structures,
	 * up to date by then, stay. At n / 4, a cascade of 10^4 windows fell back on most moves
	 * (1.1 ms at the median against 23 µs at n), and nested's 99th percentile was twice as high.
	 */
	lv->steps = 0;
	lv->budget = lv->fixed_budget ? lv->fixed_budget : tree->count + 256;
	lv->give_up = SIZE_MAX;
	if (unindex(lv, (size_t)roots) < 0)
		return -1;
	for (long r = 0; r < roots; r++) {
		struct vis_window *d = lv->dirty[r];
		if (d->live_viewable && !give_keys(tree, d))
			return NOT_LIVE;
	}
	tree->stale = true; /* the boxes move on: until the states go with them */
	int rc = reindex(lv, (size_t)roots);
	if (rc == 0 && many)
		rc = OVER_BUDGET;
	/* The pixels windows may gain: the others' queries look for gains there alone. */
	pixman_region32_t exposed;
	pixman_region32_init(&exposed);
	/* The changed windows first: what they see now bounds what others lose. */
	size_t changed = lv->n_moved = lv->n_cands;
	for (size_t i = 0; rc == 0 && i < changed; i++)
		if (lv->cands[i].state == STATE_UNKNOWN)
			rc = query_changed(tree, lv, &lv->cands[i], changed, &exposed);
	/* Each one: under an input-only root, descendants see what their root does not. */
	for (size_t i = 0; rc == 0 && i < changed; i++)
		rc = wtree_live_walk_cover(tree, lv, &lv->cands[i]);
	for (size_t e = 0; rc == 0 && e < lv->n_exposures; e++)
		rc = wtree_live_walk_exposed(tree, lv, &lv->exposures[e], &exposed);
	for (size_t i = changed; rc == 0 && i < lv->n_cands; i++)
		if (lv->cands[i].state == STATE_UNKNOWN)
			rc = wtree_live_walk_since(lv, &lv->cands[i], &exposed);
	pixman_region32_fini(&exposed);
	lv->n_moved = 0;
	if (rc == OVER_BUDGET)
		return through_tree_keeping(tree, lv);
	if (rc < 0)
		return -1;
	reset_changed(lv, true);
	if (commit(lv) < 0)
		return -1;
	tree->stale = false;
	tree->n_order = 0; /* positions are not kept: keys order the windows */
	return 0;
}

int vis_wtree_update(struct vis_wtree *tree)
{
	struct vis_wtree_live *lv = live_of(tree);
	if (!lv)
		return vis_wtree_compute(tree);
	/* A grid built for a tree a quarter the size has too few cells: built again at once. */
	if (lv->valid && grid_side(lv->grid_windows) < VIS_ZGRID_SIDE &&
	    tree->count / 4 > lv->grid_windows) {
		lv->valid = false;
		lv->cooldown = 0;
	}
	bool was_valid = lv->valid;
	bool small = tree->count < lv->min_windows;
	if (lv->valid && !small && !tree->stale && !lv->changed_lost) {
		int rc = update(tree, lv);
		if (rc == 0) {
			clear_notes(lv);
			return 0;
		}
		lv->valid = false;
		if (rc < 0) {
			tree->stale = true;
			return -1;
		}
	}
	/* Through the tree: everything when the notes or the last states cannot be trusted. */
	bool full = tree->stale || lv->damage_all || lv->changed_lost;
	int rc = full ? vis_wtree_compute(tree)
		      : vis_wtree_compute_damaged(tree, lv->damage, lv->n_damage);
	if (rc < 0)
		return -1;
	clear_notes(lv);
	/*
	 * Building the structures costs a few full recomputes: not after each change that could
	 * not go live (a desktop of cascades, a burst of changes), but once such changes have
	 * stopped for a while.
	 */
	if (small)
		lv->valid = false; /* rebuilt when the tree has grown */
	else if (was_valid)
		lv->cooldown = LIVE_COOLDOWN;
	else if (lv->cooldown)
		lv->cooldown--;
	else if (rebuild(tree, lv) < 0)
		lv->cooldown = LIVE_COOLDOWN; /* a window under a shape, or no memory: the states are
						 right still */
	return 0;
}

bool vis_wtree_changes(const struct vis_wtree *tree, struct vis_window *const **windows, size_t *n)
{
	const struct vis_wtree_live *lv = tree->live;
	if (!lv || lv->changed_all)
		return false;
	*windows = lv->changed;
	*n = lv->n_changed;
	return true;
}

const char *wtree_live_check(const struct vis_wtree *tree)
{
	const struct vis_wtree_live *lv = tree->live;
	if (!lv || !lv->valid)
		return NULL;
	uint64_t last = 0;
	size_t cells = 0, indexed = 0, seeing = 0;
	for (const struct vis_window *w = tree->root.bottom; w; w = vis_wtree_next(w)) {
		bool viewable = vis_wtree_viewable(w);
		if (!viewable) {
			if (w->key || w->live_indexed || w->live_seen)
				return "an unviewable window has a key, an entry or a seen slot";
			continue;
		}
		if (w->key <= last)
			return "keys do not grow in pre-order";
		if (w->parent->parent && w->parent->live_leaf)
			return "a window with a viewable child is flagged as having none";
		last = w->key;
		bool pixels = !w->look.input_only && !vis_box_empty(w->clip);
		if (w->live_indexed != pixels)
			return "a window with pixels is not indexed, or one without is";
		size_t k;
		if (pixels && !vis_zgrid_holds(&lv->grid, w->clip, w->key, &k))
			return "a window is missing from a cell its clip meets";
		if (pixels) {
			pixman_box32_t c = pbox(w->clip);
			const struct live_slot *sl =
				w->live_slot < lv->n_slots ? &lv->slots[w->live_slot] : NULL;
			if (!sl || sl->w != w || sl->clip.x1 != c.x1 || sl->clip.y1 != c.y1 ||
			    sl->clip.x2 != c.x2 || sl->clip.y2 != c.y2)
				return "an indexed window's slot does not hold it and its clip";
			indexed++;
		}
		cells += pixels ? k : 0;
		bool sees = w->state == VIS_UNOBSCURED || w->state == VIS_PARTIALLY_OBSCURED;
		seeing += sees;
		if (sees != (w->live_seen != 0) ||
		    (sees && (w->live_seen > lv->n_seen || lv->seen[w->live_seen - 1].w != w)))
			return "the seen list does not match the states";
		const struct seen_window *sw = sees ? &lv->seen[w->live_seen - 1] : NULL;
		for (int i = 0; sw && lv->seen_grid_ok && i < (sw->seen.n == SEEN_EXTENTS ? 1 : sw->seen.n); i++)
			if (!(sw->stamp & SEEN_PENDING) &&
			    !vis_sgrid_holds(&lv->seen_grid, vbox(&sw->seen.boxes[i]), w->live_seen - 1,
					     SEEN_STAMP(sw->stamp)))
				return "a seen box is missing from a cell of the seen grid";
	}
	if (vis_zgrid_size(&lv->grid) != cells)
		return "the grid holds stale entries, or a cell is out of order";
	if (seeing + lv->n_free_seen != lv->n_seen)
		return "a seen entry is neither a seeing window's nor free";
	if (indexed + lv->n_free != lv->n_slots)
		return "a slot is neither an indexed window's nor free";
	return NULL;
}

void wtree_live_tune(struct vis_wtree *tree, size_t steps, unsigned seen_boxes,
		     unsigned left_boxes, size_t cover_steps)
{
	struct vis_wtree_live *lv = live_of(tree);
	if (lv) {
		lv->fixed_budget = steps;
		lv->cover_steps = cover_steps;
		lv->seen_boxes = seen_boxes && seen_boxes < SEEN_BOXES ? seen_boxes : SEEN_BOXES;
		lv->left_boxes = left_boxes >= 2 && left_boxes < LEFT_BOXES ? left_boxes : LEFT_BOXES;
	}
}
