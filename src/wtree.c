/* The window tree: creation, destruction and restacking; states in wtree-compute.c, queries in
 * wtree-query.c. */
#include <errno.h>
#include <stdlib.h>

#include "wtree-live.h"

void vis_wtree_init(struct vis_wtree *tree, int32_t width, int32_t height)
{
	*tree = (struct vis_wtree){ 0 };
	tree->root.width = width;
	tree->root.height = height;
	tree->root.mapped = true;
	tree->root.box = (struct vis_box){ 0, 0, width, height };
	tree->root.clip = tree->root.inner = tree->root.box;
	vis_idmap_init(&tree->ids);
	vis_idmap_init(&tree->externals);
	tree->next_id = 1;
}

void vis_wtree_finish(struct vis_wtree *tree)
{
	while (tree->root.top)
		vis_wtree_destroy(tree, tree->root.top, NULL, NULL);
	vis_idmap_finish(&tree->ids);
	vis_idmap_finish(&tree->externals);
	free(tree->order);
	vis_wtree_work_destroy(tree->work);
	vis_wtree_live_destroy(tree->live);
}

void vis_wtree_set_id_key(struct vis_wtree *tree, uint64_t key)
{
	tree->id_key = key;
}

/* The Feistel network: 16-bit halves, round keys drawn from key by a 64-bit mix. */
static uint32_t feistel(uint64_t key, uint32_t x)
{
	uint32_t l = x >> 16, r = x & 0xffff;
	for (uint64_t round = 1; round <= 6; round++) {
		uint64_t h = (key ^ (round << 56) ^ r) * 0x9e3779b97f4a7c15ull;
		h ^= h >> 31;
		h *= 0xbf58476d1ce4e5b9ull;
		h ^= h >> 29;
		uint32_t next = l ^ (uint32_t)(h >> 48);
		l = r;
		r = next;
	}
	return l << 16 | r;
}

uint32_t vis_wtree_id_permute(uint64_t key, uint32_t n)
{
	if (key == 0)
		return n;
	uint32_t id = feistel(key, n);
	while (id == 0)
		id = feistel(key, id);
	return id;
}

struct vis_window *vis_wtree_find(const struct vis_wtree *tree, uint32_t id)
{
	return vis_idmap_get(&tree->ids, id);
}

/* The externals key of a pair: a 64-bit mix of both, folded to 32 bits, never 0 (empty). */
static uint32_t external_key(uint32_t ext_namespace, uint64_t external)
{
	uint64_t h = (external ^ (uint64_t)ext_namespace << 32 ^ ext_namespace) * 0x9e3779b97f4a7c15ull;
	h ^= h >> 29;
	h *= 0xbf58476d1ce4e5b9ull;
	uint32_t k = (uint32_t)(h >> 32) ^ (uint32_t)h;
	return k ? k : 1;
}

struct vis_window *vis_wtree_find_external(const struct vis_wtree *tree, uint32_t ext_namespace,
					   uint64_t external)
{
	if (!ext_namespace)
		return NULL;
	struct vis_window *w = vis_idmap_get(&tree->externals, external_key(ext_namespace, external));
	while (w && (w->ext_namespace != ext_namespace || w->external != external))
		w = w->ext_next;
	return w;
}

int vis_wtree_set_external(struct vis_wtree *tree, struct vis_window *window,
			   uint32_t ext_namespace, uint64_t external)
{
	if (!ext_namespace || window->ext_namespace) {
		errno = EINVAL;
		return -1;
	}
	if (vis_wtree_find_external(tree, ext_namespace, external)) {
		errno = EEXIST;
		return -1;
	}
	uint32_t key = external_key(ext_namespace, external);
	struct vis_window *first = vis_idmap_get(&tree->externals, key);
	if (vis_idmap_put(&tree->externals, key, window) < 0)
		return -1;
	window->ext_next = first;
	window->ext_namespace = ext_namespace;
	window->external = external;
	return 0;
}

/* Takes a destroyed window's external ID out of the index. */
static void forget_external(struct vis_wtree *tree, struct vis_window *w)
{
	uint32_t key = external_key(w->ext_namespace, w->external);
	struct vis_window *first = vis_idmap_get(&tree->externals, key);
	if (first == w) {
		if (w->ext_next) /* replaces the value in place: cannot fail */
			vis_idmap_put(&tree->externals, key, w->ext_next);
		else
			vis_idmap_remove(&tree->externals, key);
		return;
	}
	for (struct vis_window *v = first; v; v = v->ext_next)
		if (v->ext_next == w) {
			v->ext_next = w->ext_next;
			return;
		}
}

/* Takes a window out of its parent's child list. */
static void unlink_window(struct vis_window *w)
{
	struct vis_window *p = w->parent;
	if (w->below)
		w->below->above = w->above;
	else
		p->bottom = w->above;
	if (w->above)
		w->above->below = w->below;
	else
		p->top = w->below;
	w->above = w->below = NULL;
}

/* Links a window into parent's child list just above below (NULL: at the bottom). */
static void link_above(struct vis_window *w, struct vis_window *parent, struct vis_window *below)
{
	w->parent = parent;
	w->below = below;
	w->above = below ? below->above : parent->bottom;
	if (w->below)
		w->below->above = w;
	else
		parent->bottom = w;
	if (w->above)
		w->above->below = w;
	else
		parent->top = w;
}

struct vis_window *vis_wtree_create(struct vis_wtree *tree, struct vis_window *parent,
				    int32_t x, int32_t y, int32_t width, int32_t height,
				    uint32_t owner)
{
	if (tree->next_id == 0) {
		errno = EOVERFLOW;
		return NULL;
	}
	struct vis_window *w = calloc(1, sizeof *w);
	if (!w)
		return NULL;
	w->id = vis_wtree_id_permute(tree->id_key, tree->next_id);
	if (vis_idmap_put(&tree->ids, w->id, w) < 0) {
		free(w);
		return NULL;
	}
	tree->next_id++; /* wraps to 0 after the last ID: see above */
	tree->count++;
	w->owner = owner;
	w->x = x;
	w->y = y;
	w->width = width;
	w->height = height;
	w->depth = parent->depth + 1;
	w->state = w->old_state = VIS_WTREE_STATE_NONE;
	link_above(w, parent, parent->top);
	return w;
}

void vis_wtree_destroy(struct vis_wtree *tree, struct vis_window *window,
		       void (*gone)(void *data, struct vis_window *w), void *data)
{
	struct vis_window *stop = window->parent, *w = window;
	unlink_window(window);
	window->parent = NULL; /* the walk ends when it climbs above window */
	while (w) {
		if (w->top) {
			w = w->top;
			continue;
		}
		struct vis_window *parent = w->parent;
		if (gone) {
			w->parent = parent ? parent : stop;
			gone(data, w);
			w->parent = parent;
		}
		if (parent)
			unlink_window(w);
		/* Until the next compute, the order may be read (queries in a batch): drop w from it. */
		if (w->pos < tree->n_order && tree->order[w->pos] == w)
			tree->order[w->pos] = NULL;
		wtree_live_forget(tree, w);
		vis_idmap_remove(&tree->ids, w->id);
		if (w->ext_namespace)
			forget_external(tree, w);
		tree->count--;
		free(w->look.shape);
		free(w->look.opaque_rects);
		if (w->cut)
			vis_look_cut_finish(w->cut);
		free(w->cut);
		free(w);
		w = parent;
	}
}

void vis_wtree_restack(struct vis_window *window, struct vis_window *sibling, bool above)
{
	if (window == sibling)
		return;
	struct vis_window *parent = window->parent;
	unlink_window(window);
	link_above(window, parent, above ? sibling : sibling->below);
}

void vis_wtree_raise(struct vis_window *window)
{
	struct vis_window *parent = window->parent;
	unlink_window(window);
	link_above(window, parent, parent->top);
}

void vis_wtree_lower(struct vis_window *window)
{
	struct vis_window *parent = window->parent;
	unlink_window(window);
	link_above(window, parent, NULL);
}

bool vis_wtree_is_ancestor(const struct vis_window *a, const struct vis_window *b)
{
	for (; b; b = b->parent)
		if (a == b)
			return true;
	return false;
}

struct vis_window *vis_wtree_next_within(const struct vis_window *w, const struct vis_window *top)
{
	if (w->bottom)
		return w->bottom;
	for (; w != top && w->parent; w = w->parent)
		if (w->above)
			return w->above;
	return NULL;
}

void vis_wtree_reparent(struct vis_window *window, struct vis_window *parent, int32_t x, int32_t y)
{
	unlink_window(window);
	link_above(window, parent, parent->top);
	window->x = x;
	window->y = y;
	for (struct vis_window *v = window; v; v = vis_wtree_next_within(v, window))
		v->depth = v->parent->depth + 1;
}

/* The first mapped window from w upwards among its siblings, or NULL. */
static struct vis_window *mapped_from(struct vis_window *w)
{
	while (w && !w->mapped)
		w = w->above;
	return w;
}

struct vis_window *vis_wtree_next_viewable(const struct vis_wtree *tree,
					   const struct vis_window *w)
{
	if (!w)
		return mapped_from(tree->root.bottom);
	struct vis_window *c = mapped_from(w->bottom);
	if (c)
		return c;
	for (; w->parent; w = w->parent)
		if ((c = mapped_from(w->above)))
			return c;
	return NULL;
}

struct vis_window *vis_wtree_next(const struct vis_window *w)
{
	return vis_wtree_next_within(w, NULL);
}

struct vis_box vis_wtree_box(const struct vis_window *window)
{
	int64_t b2 = 2 * (int64_t)window->look.border;
	struct vis_box b = { window->x, window->y, (int64_t)window->x + window->width + b2,
			     (int64_t)window->y + window->height + b2 };
	for (const struct vis_window *p = window->parent; p && p->parent; p = p->parent) {
		/* A child's origin is its parent's inside's corner. */
		int64_t dx = (int64_t)p->x + p->look.border, dy = (int64_t)p->y + p->look.border;
		b.x1 += dx;
		b.x2 += dx;
		b.y1 += dy;
		b.y2 += dy;
	}
	return b;
}

int vis_wtree_set_size(struct vis_window *window, int32_t width, int32_t height, int32_t border)
{
	/* Positions are checked where pieces are cut, against the clip: only the sizes here. */
	if (width < 1 || height < 1 || border < 0 || (border && window->look.input_only) ||
	    (int64_t)width + 2 * (int64_t)border > INT32_MAX ||
	    (int64_t)height + 2 * (int64_t)border > INT32_MAX) {
		errno = EINVAL;
		return -1;
	}
	window->width = width;
	window->height = height;
	window->look.border = border;
	return 0;
}

/*
 * Gives window room for the pieces of a look that will (cuts) or will not cut inside its box,
 * emptied (a zero cut fits no window): the look is about to change. 0, or -1 with ENOMEM
 * (nothing changed then).
 */
static int prepare_cut(struct vis_window *window, bool cuts)
{
	if (window->cut)
		vis_look_cut_finish(window->cut);
	if (!cuts) {
		free(window->cut);
		window->cut = NULL;
		return 0;
	}
	if (!window->cut && !(window->cut = calloc(1, sizeof(*window->cut)))) {
		errno = ENOMEM;
		return -1;
	}
	return 0;
}

const struct vis_look_cut *vis_wtree_cut(const struct vis_window *window)
{
	struct vis_look_cut *cut = window->cut;
	if (!cut) {
		errno = EINVAL;
		return NULL;
	}
	if (cut->border == window->look.border && cut->width == window->width &&
	    cut->height == window->height)
		return cut;
	return vis_look_cut_fill(cut, &window->look, window->width, window->height) < 0 ? NULL
											 : cut;
}

void vis_wtree_keep_cut(struct vis_window *window, struct vis_look_cut *cut)
{
	if (window->cut) {
		vis_look_cut_finish(window->cut);
		*window->cut = *cut;
	} else {
		vis_look_cut_finish(cut);
	}
	*cut = (struct vis_look_cut){ 0 };
}

int vis_wtree_set_border(struct vis_window *window, int32_t border)
{
	return vis_wtree_set_size(window, window->width, window->height, border);
}

/* Copies n rectangles into a new array (NULL for none). 0, or -1 with ENOMEM. */
static int copy_rects(const struct vis_rect *rects, uint32_t n, struct vis_rect **out)
{
	*out = NULL;
	if (n == 0)
		return 0;
	*out = malloc((size_t)n * sizeof(**out));
	if (*out == NULL) {
		errno = ENOMEM;
		return -1;
	}
	for (uint32_t k = 0; k < n; k++)
		(*out)[k] = rects[k];
	return 0;
}

/*
 * Gives the window the look next (whose arrays become the window's, the old ones freed), with
 * room for its pieces. 0, or -1 with ENOMEM (nothing changes then, next's arrays freed).
 */
static int set_look(struct vis_window *window, struct vis_look next)
{
	if (prepare_cut(window, vis_look_cuts_inside(&next)) < 0) {
		if (next.shape != window->look.shape)
			free(next.shape);
		if (next.opaque_rects != window->look.opaque_rects)
			free(next.opaque_rects);
		return -1;
	}
	if (next.shape != window->look.shape)
		free(window->look.shape);
	if (next.opaque_rects != window->look.opaque_rects)
		free(window->look.opaque_rects);
	window->look = next;
	return 0;
}

bool vis_wtree_translucent(const struct vis_window *window)
{
	if (!window->cut)
		return !window->look.input_only && window->look.opaque == VIS_OPAQUE_NONE;
	const struct vis_look_cut *cut = vis_wtree_cut(window);
	/* Without memory to cut the look, say what its mode says. */
	return cut ? vis_look_cut_translucent(cut) : window->look.opaque != VIS_OPAQUE_ALL;
}

int vis_wtree_set_shape(struct vis_window *window, bool shaped, const struct vis_rect *rects,
			uint32_t n)
{
	struct vis_look next = window->look;
	if (window->look.input_only) {
		errno = EINVAL;
		return -1;
	}
	if (copy_rects(rects, shaped ? n : 0, &next.shape) < 0)
		return -1;
	next.n_shape = shaped ? n : 0;
	next.shaped = shaped;
	return set_look(window, next);
}

int vis_wtree_set_opaque(struct vis_window *window, enum vis_opaque mode,
			 const struct vis_rect *rects, uint32_t n)
{
	struct vis_look next = window->look;
	if (window->look.input_only || (unsigned)mode > VIS_OPAQUE_RECTS) {
		errno = EINVAL;
		return -1;
	}
	if (copy_rects(rects, mode == VIS_OPAQUE_RECTS ? n : 0, &next.opaque_rects) < 0)
		return -1;
	next.n_opaque = mode == VIS_OPAQUE_RECTS ? n : 0;
	next.opaque = (uint8_t)mode;
	return set_look(window, next);
}

void vis_wtree_set_input_only(struct vis_window *window)
{
	window->look.input_only = true;
}

bool vis_wtree_viewable(const struct vis_window *window)
{
	for (; window; window = window->parent)
		if (!window->mapped)
			return false;
	return true;
}

void vis_wtree_place(struct vis_window *w)
{
	const struct vis_window *p = w->parent;
	int64_t b = w->look.border;
	struct vis_box box = { p->box.x1 + p->look.border + w->x, p->box.y1 + p->look.border + w->y,
			       0, 0 };
	box.x2 = box.x1 + w->width + 2 * b;
	box.y2 = box.y1 + w->height + 2 * b;
	struct vis_box in = { box.x1 + b, box.y1 + b, box.x2 - b, box.y2 - b };
	w->box = box;
	w->clip = vis_box_intersect(box, p->inner);
	w->inner = vis_box_intersect(in, w->clip);
}
