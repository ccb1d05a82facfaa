/*
 * The mirror: X's window tree as the bridge knows it, and every change of it sent on to visd.
 * Each function changes the mirror and sends visd the request that makes visd's tree the same,
 * only when something changed, inside the turn's batch.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "bridge.h"

static uint32_t opaque_mode_of(const struct bridge *b, struct xwin *w);

/* The one bridge of this process, for visd's callbacks, whose data is the window. */
static struct bridge *the_bridge;

struct xwin *mirror_find(const struct bridge *b, xcb_window_t id)
{
	return id ? vis_idmap_get(&b->by_xid, id) : NULL;
}

/* Opens the turn's visd batch, once. */
void visd_begin(struct bridge *b)
{
	if (!b->batch_open) {
		vis_client_batch_begin(b->vc);
		b->batch_open = true;
	}
	b->visd_sent++;
	b->requests++;
}

static void send_shape(struct bridge *b, struct xwin *w);
static void refresh_one(struct bridge *b, struct xwin *w, bool force);

int xid_list_push(struct xid_list *l, xcb_window_t id)
{
	if (l->n == l->cap) {
		size_t cap = l->cap ? 2 * l->cap : 64;
		xcb_window_t *ids = realloc(l->ids, cap * sizeof(*ids));
		if (!ids)
			return -1;
		l->ids = ids;
		l->cap = cap;
	}
	l->ids[l->n++] = id;
	return 0;
}

/* Puts w on the list of windows whose look waits for their visd ID. */
static void look_later(struct bridge *b, struct xwin *w)
{
	if (w->look_due)
		return;
	if (xid_list_push(&b->look_due, w->id) < 0) {
		b->visd_failed = true;
		return;
	}
	w->look_due = true;
}

/* The looks that waited for their windows' IDs, into a new batch. */
static void send_due_looks(struct bridge *b)
{
	size_t n = b->look_due.n;
	b->look_due.n = 0;
	for (size_t i = 0; i < n; i++) {
		struct xwin *w = mirror_find(b, b->look_due.ids[i]);
		if (!w || !w->look_due || !w->vid)
			continue;
		w->look_due = false;
		if (w->shaped)
			send_shape(b, w);
		refresh_one(b, w, true);
	}
}

static int visd_roundtrip(struct bridge *b)
{
	/* The batch, its commit and the sync in one message: visd wakes once a turn. */
	b->batch_open = false;
	if (vis_client_batch_roundtrip(b->vc) < 0) {
		b->visd_failed = true;
		return -1;
	}
	b->visd_sent = 0;
	if (b->look_due.n)
		send_due_looks(b);
	return 0;
}

/*
 * Makes sure w's visd ID is known before a request names it: a window created in this turn's
 * batch has its ID only once visd answered, so the batch is committed and answered first (a
 * window created and configured in one turn costs visd two recomputes).
 */
int visd_ensure(struct bridge *b, struct xwin *w)
{
	if (w == b->root)
		return 0;
	if (w->pending && visd_roundtrip(b) < 0)
		return -1;
	if (w->pending || !w->vid) {
		if (!b->resync_needed && !b->visd_refused) {
			b->resync_needed = true;
			b->resync_reason = "visd refused a window's creation";
		}
		return -1;
	}
	return 0;
}

/* Ends the turn: commits the batch and waits for visd's answer, if anything was sent. */
int visd_end_turn(struct bridge *b)
{
	/* A round trip can open a batch again, with the looks of the windows it created. */
	while (b->batch_open || b->visd_sent)
		if (visd_roundtrip(b) < 0)
			return -1;
	return 0;
}

void mirror_mark_dirty(struct bridge *b, struct xwin *w)
{
	if (w->vis_dirty)
		return;
	w->vis_dirty = true;
	w->next_dirty = b->dirty;
	b->dirty = w;
}

static void unlink_sibling(struct xwin *w)
{
	struct xwin *p = w->parent;
	if (w->below)
		w->below->above = w->above;
	else
		p->bottom = w->above;
	if (w->above)
		w->above->below = w->below;
	else
		p->top = w->below;
	w->below = w->above = NULL;
}

/* Links w just above sibling (NULL: at the bottom) among p's children. */
static void link_above(struct xwin *p, struct xwin *w, struct xwin *sibling)
{
	w->parent = p;
	w->below = sibling;
	w->above = sibling ? sibling->above : p->bottom;
	if (w->below)
		w->below->above = w;
	else
		p->bottom = w;
	if (w->above)
		w->above->below = w;
	else
		p->top = w;
}

int mirror_init(struct bridge *b)
{
	the_bridge = b;
	vis_idmap_init(&b->by_xid);
	vis_idmap_init(&b->by_vid);
	vis_idmap_init(&b->early_states);
	b->root = calloc(1, sizeof(*b->root));
	if (!b->root)
		return -1;
	b->root->id = b->screen->root;
	b->root->mapped = true;
	b->root->opacity = 0xffffffffu;
	return vis_idmap_put(&b->by_xid, b->root->id, b->root);
}

void mirror_set_limbo(struct bridge *b, struct xwin *w, bool limbo)
{
	if (w->limbo == limbo)
		return;
	w->limbo = limbo;
	if (limbo)
		b->n_limbo++;
	else
		b->n_limbo--;
}

static void free_window(struct bridge *b, struct xwin *w)
{
	bridge_log(b, 3, "forgetting 0x%x (in 0x%x)", w->id, w->parent ? w->parent->id : 0);
	mirror_set_limbo(b, w, false);
	while (w->top)
		free_window(b, w->top);
	unlink_sibling(w);
	vis_idmap_remove(&b->by_xid, w->id);
	if (w->vid)
		vis_idmap_remove(&b->by_vid, w->vid);
	if (w->vis_dirty) {
		/* Off the dirty list, which is short: it holds this turn's changes only. */
		struct xwin **pp = &b->dirty;
		while (*pp != w)
			pp = &(*pp)->next_dirty;
		*pp = w->next_dirty;
	}
	free(w->shape);
	free(w->opaque_region);
	free(w);
	b->n_windows--;
}

void mirror_finish(struct bridge *b)
{
	free(b->reread.ids);
	free(b->look_due.ids);
	b->reread = b->look_due = (struct xid_list){ 0 };
	if (!b->root)
		return;
	while (b->root->top)
		free_window(b, b->root->top);
	free(b->root);
	b->root = NULL;
	vis_idmap_finish(&b->by_xid);
	vis_idmap_finish(&b->by_vid);
	vis_idmap_finish(&b->early_states);
}

struct xwin *mirror_add(struct bridge *b, struct xwin *parent, xcb_window_t id)
{
	struct xwin *w = calloc(1, sizeof(*w));
	if (!w || vis_idmap_put(&b->by_xid, id, w) < 0) {
		free(w);
		return NULL;
	}
	w->id = id;
	w->opacity = 0xffffffffu;
	w->opaque_mode = VIS_OPAQUE_MODE_ALL;
	w->vstate = VIS_VISIBILITY_NONE;
	w->told = TOLD_NOTHING;
	link_above(parent, w, parent->top);
	b->n_windows++;
	return w;
}

static void created_cb(void *data, const struct vis_error *err, uint32_t window)
{
	struct xwin *w = data;
	struct bridge *b = the_bridge;
	w->pending = false;
	b->creates_pending--;
	if (err) {
		bridge_refused(b, err, w->id);
	} else {
		w->vid = window;
		if (vis_idmap_put(&b->by_vid, window, w) < 0)
			b->visd_failed = true;
		else
			notify_created(b, w);
	}
	if (!b->creates_pending) { /* what is left is about removed windows */
		vis_idmap_finish(&b->early_states);
		vis_idmap_init(&b->early_states);
	}
}

void mirror_create_in_visd(struct bridge *b, struct xwin *w)
{
	if (visd_ensure(b, w->parent) < 0)
		return;
	visd_begin(b);
	uint32_t flags = (w->mapped ? VIS_CREATE_MAP : 0) | (w->input_only ? VIS_CREATE_INPUT_ONLY : 0);
	if (!vis_client_create_external_async(b->vc, w->parent->vid, w->x, w->y, w->width,
					      w->height, w->input_only ? 0 : w->border, flags,
					      VIS_EXTERNAL_X11, w->id, created_cb, w))
		return;
	w->pending = true;
	b->creates_pending++;
	/* Its look names it: sent after the round trip that gives its ID. */
	w->opaque_mode = VIS_OPAQUE_MODE_ALL;
	if (w->shaped || opaque_mode_of(b, w) != VIS_OPAQUE_MODE_ALL)
		look_later(b, w);
}

/*
 * A window in limbo below w left it already (its move is still to be learnt): it outlives w, in
 * limbo at the top of the screen until the end of the turn places it. visd moves it too, before
 * w's destruction would take it.
 */
static void rescue_limbo(struct bridge *b, struct xwin *w)
{
	for (struct xwin *c = w->bottom, *next; c; c = next) {
		next = c->above;
		if (!c->limbo) {
			rescue_limbo(b, c);
			continue;
		}
		unlink_sibling(c);
		link_above(b->root, c, b->root->top);
		if (visd_ensure(b, c) == 0) {
			visd_begin(b);
			vis_client_reparent(b->vc, c->vid, VIS_WINDOW_ROOT, c->x, c->y);
		}
	}
}

void mirror_remove(struct bridge *b, struct xwin *w)
{
	rescue_limbo(b, w);
	if (w->pending)
		visd_ensure(b, w);
	if (w->vid) {
		visd_begin(b);
		vis_client_destroy_window(b->vc, w->vid);
	}
	free_window(b, w);
}

void mirror_set_mapped(struct bridge *b, struct xwin *w, bool mapped)
{
	if (w->mapped == mapped)
		return;
	w->mapped = mapped;
	if (visd_ensure(b, w) < 0)
		return;
	visd_begin(b);
	if (mapped)
		vis_client_map(b->vc, w->vid);
	else
		vis_client_unmap(b->vc, w->vid);
}

void mirror_set_geometry(struct bridge *b, struct xwin *w, int32_t x, int32_t y, uint32_t width,
			 uint32_t height, uint32_t border)
{
	if (w->input_only)
		border = 0;
	if (w->x == x && w->y == y && w->width == width && w->height == height &&
	    w->border == border)
		return;
	w->x = x;
	w->y = y;
	w->width = width;
	w->height = height;
	w->border = border;
	if (visd_ensure(b, w) < 0)
		return;
	visd_begin(b);
	vis_client_configure(b->vc, w->vid, x, y, width, height, border);
}

void mirror_place(struct bridge *b, struct xwin *w, struct xwin *sibling)
{
	if (w->below == sibling || w == sibling)
		return;
	struct xwin *p = w->parent;
	unlink_sibling(w);
	link_above(p, w, sibling);
	if (visd_ensure(b, w) < 0 || (sibling && visd_ensure(b, sibling) < 0))
		return;
	visd_begin(b);
	if (sibling)
		vis_client_restack(b->vc, w->vid, VIS_RESTACK_ABOVE, sibling->vid);
	else
		vis_client_lower(b->vc, w->vid);
}

void mirror_reparent(struct bridge *b, struct xwin *w, struct xwin *parent, int32_t x, int32_t y)
{
	bridge_log(b, 3, "0x%x: from 0x%x to 0x%x", w->id, w->parent->id, parent->id);
	mirror_set_limbo(b, w, false);
	unlink_sibling(w);
	link_above(parent, w, parent->top);
	w->x = x;
	w->y = y;
	if (visd_ensure(b, w) < 0 || visd_ensure(b, parent) < 0)
		return;
	visd_begin(b);
	vis_client_reparent(b->vc, w->vid, parent->vid, x, y);
	/* Under another top-level, another translucency. */
	mirror_refresh_opaque(b, w);
}

void mirror_set_shape(struct bridge *b, struct xwin *w, bool shaped, struct vis_rect32 *rects,
		      uint32_t n)
{
	if (!shaped)
		n = 0;
	if (w->shaped == shaped && w->n_shape == n &&
	    (!n || !memcmp(w->shape, rects, n * sizeof(*rects)))) {
		free(rects);
		return;
	}
	free(w->shape);
	w->shaped = shaped;
	w->shape = rects;
	w->n_shape = n;
	if (!w->pending && !w->vid)
		return; /* not in visd yet: its create sends it */
	send_shape(b, w);
}

void mirror_set_opacity(struct bridge *b, struct xwin *w, uint32_t opacity)
{
	if (w->opacity == opacity)
		return;
	w->opacity = opacity;
	if (w->parent == b->root && (w->vid || w->pending))
		mirror_refresh_opaque(b, w);
}

void mirror_set_opaque_region(struct bridge *b, struct xwin *w, bool has, struct vis_rect32 *region,
			      uint32_t n)
{
	if (!has)
		n = 0;
	if (w->has_opaque_region == has && w->n_opaque_region == n &&
	    (!n || !memcmp(w->opaque_region, region, n * sizeof(*region)))) {
		free(region);
		return;
	}
	free(w->opaque_region);
	w->has_opaque_region = has;
	w->opaque_region = region;
	w->n_opaque_region = n;
	if (w->vid || w->pending)
		refresh_one(b, w, true);
}

/* Sends w's bounding shape as the mirror has it. */
static void send_shape(struct bridge *b, struct xwin *w)
{
	if (w->pending) {
		look_later(b, w);
		return;
	}
	if (w->input_only || visd_ensure(b, w) < 0)
		return;
	visd_begin(b);
	vis_client_set_shape(b->vc, w->vid, w->shaped, w->shaped ? w->shape : NULL,
			     w->shaped ? w->n_shape : 0);
}

/* The top-level (child of the root) that w is in. */
static struct xwin *top_level(const struct bridge *b, struct xwin *w)
{
	while (w->parent && w->parent != b->root)
		w = w->parent;
	return w;
}

/*
 * The translucency rule. A compositing manager draws a top-level window with its whole subtree
 * at the top-level's opacity, from its pixmap: so where a compositor runs, a top-level that is
 * 32-bit ARGB or has _NET_WM_WINDOW_OPACITY below 100% hides, in its whole subtree, only each
 * window's _NET_WM_OPAQUE_REGION (nothing if unset), whatever the inner windows' depths. Any
 * other window, and every window without a compositor, hides what its shape covers, as X paints.
 */
static uint32_t opaque_mode_of(const struct bridge *b, struct xwin *w)
{
	if (!b->translucent_now)
		return VIS_OPAQUE_MODE_ALL;
	struct xwin *top = top_level(b, w);
	if (!top->argb && top->opacity == 0xffffffffu)
		return VIS_OPAQUE_MODE_ALL;
	return w->has_opaque_region && w->n_opaque_region ? VIS_OPAQUE_MODE_RECTS
							   : VIS_OPAQUE_MODE_NONE;
}

static void refresh_one(struct bridge *b, struct xwin *w, bool force)
{
	if (w->input_only)
		return;
	uint32_t mode = opaque_mode_of(b, w);
	if (mode == w->opaque_mode && !(force && mode == VIS_OPAQUE_MODE_RECTS))
		return;
	if (w->pending) {
		look_later(b, w);
		return;
	}
	w->opaque_mode = mode;
	if (visd_ensure(b, w) < 0)
		return;
	visd_begin(b);
	if (mode == VIS_OPAQUE_MODE_RECTS)
		vis_client_set_opaque(b->vc, w->vid, mode, w->opaque_region, w->n_opaque_region);
	else
		vis_client_set_opaque(b->vc, w->vid, mode, NULL, 0);
}

static void refresh_subtree(struct bridge *b, struct xwin *w, bool force)
{
	refresh_one(b, w, force);
	for (struct xwin *c = w->bottom; c; c = c->above)
		refresh_subtree(b, c, false);
}

void mirror_refresh_opaque(struct bridge *b, struct xwin *w)
{
	if (w == b->root) {
		for (struct xwin *c = w->bottom; c; c = c->above)
			refresh_subtree(b, c, false);
		return;
	}
	refresh_subtree(b, w, true);
}
