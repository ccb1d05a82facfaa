/*
 * Reading windows from X. A subtree is read under a server grab, level by level with every
 * request of a level in flight at once: no other client runs meanwhile, so what is read is one
 * moment of the tree, and the bridge's selections are in place before anything can change again.
 * Events generated before the grab describe an older tree than the read: the windows read get
 * the grab's sequence number (xwin.snap and csnap), and events older than it about them, or
 * adding to their children, are skipped (events.c).
 */
#include <stdlib.h>
#include <string.h>

#include <xcb/shape.h>

#include "bridge.h"

/* A window as read. Children of node i are nodes first_child … first_child + n_children − 1. */
struct snode {
	xcb_window_t id;
	uint32_t parent, first_child, n_children;
	int32_t x, y;
	uint32_t width, height, border;
	bool ok, mapped, viewable, input_only, argb, shaped, has_region;
	uint32_t n_shape, n_region, opacity;
	struct vis_rect32 *shape, *region;
};

struct level_cookies {
	xcb_get_window_attributes_cookie_t attrs;
	xcb_get_geometry_cookie_t geom;
	xcb_query_tree_cookie_t tree;
	xcb_shape_query_extents_cookie_t extents;
	xcb_get_property_cookie_t opacity, region;
};

static const uint32_t window_events = XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY |
				      XCB_EVENT_MASK_PROPERTY_CHANGE |
				      XCB_EVENT_MASK_VISIBILITY_CHANGE;

/* Rectangles from xcb's, or NULL for none (n 0) or no memory (*failed). */
static struct vis_rect32 *rects_from_x(const xcb_rectangle_t *r, uint32_t n)
{
	if (!n)
		return NULL;
	struct vis_rect32 *out = malloc(n * sizeof(*out));
	if (!out)
		return NULL;
	for (uint32_t i = 0; i < n; i++)
		out[i] = (struct vis_rect32){ r[i].x, r[i].y, r[i].width, r[i].height };
	return out;
}

/* _NET_WM_OPAQUE_REGION's CARDINAL quadruples, x y w h (x, y read as signed, as clients mean). */
static struct vis_rect32 *region_from_property(xcb_get_property_reply_t *r, uint32_t *n,
					       bool *has)
{
	*n = 0;
	*has = false;
	if (!r || r->type != XCB_ATOM_CARDINAL || r->format != 32)
		return NULL;
	*has = true;
	uint32_t words = (uint32_t)xcb_get_property_value_length(r) / 4;
	const uint32_t *v = xcb_get_property_value(r);
	uint32_t count = words / 4;
	if (count > VIS_LOOK_MAX_RECTS)
		count = VIS_LOOK_MAX_RECTS;
	struct vis_rect32 *out = count ? malloc(count * sizeof(*out)) : NULL;
	if (count && !out)
		return NULL;
	for (uint32_t i = 0; i < count; i++)
		out[i] = (struct vis_rect32){ (int32_t)v[4 * i], (int32_t)v[4 * i + 1],
					      v[4 * i + 2], v[4 * i + 3] };
	*n = count;
	return out;
}

static uint32_t opacity_from_property(xcb_get_property_reply_t *r)
{
	if (!r || r->type != XCB_ATOM_CARDINAL || r->format != 32 ||
	    xcb_get_property_value_length(r) < 4)
		return 0xffffffffu;
	return *(const uint32_t *)xcb_get_property_value(r);
}

static xcb_get_property_cookie_t ask_property(struct bridge *b, xcb_window_t w, xcb_atom_t a,
					      uint32_t words)
{
	return xcb_get_property(b->x, 0, w, a, XCB_ATOM_CARDINAL, 0, words);
}

/*
 * Reads nodes [lo, hi), appending their children; the top (lo 0) is read without its geometry,
 * which its parent's events give (the root has none to read).
 */
static int read_level(struct bridge *b, struct snode **nodes, uint32_t *n, uint32_t *cap,
		      uint32_t lo, uint32_t hi)
{
	struct level_cookies *c = calloc(hi - lo, sizeof(*c));
	if (!c)
		return -1;
	for (uint32_t i = lo; i < hi; i++) {
		xcb_window_t id = (*nodes)[i].id;
		struct level_cookies *k = &c[i - lo];
		bool is_root = id == b->root->id;
		uint32_t mask = is_root ? XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY |
						  XCB_EVENT_MASK_PROPERTY_CHANGE
					: window_events;
		xcb_change_window_attributes(b->x, id, XCB_CW_EVENT_MASK, &mask);
		k->tree = xcb_query_tree(b->x, id);
		if (is_root)
			continue;
		if (b->shape_ext)
			xcb_shape_select_input(b->x, id, 1);
		k->attrs = xcb_get_window_attributes(b->x, id);
		k->geom = xcb_get_geometry(b->x, id);
		if (b->shape_ext)
			k->extents = xcb_shape_query_extents(b->x, id);
		k->opacity = ask_property(b, id, b->atom_opacity, 1);
		k->region = ask_property(b, id, b->atom_opaque_region, 4 * VIS_LOOK_MAX_RECTS);
	}
	int rc = 0;
	for (uint32_t i = lo; i < hi; i++) {
		struct level_cookies *k = &c[i - lo];
		struct snode *s = &(*nodes)[i];
		bool is_root = s->id == b->root->id;
		xcb_query_tree_reply_t *t = xcb_query_tree_reply(b->x, k->tree, NULL);
		if (!is_root) {
			xcb_get_window_attributes_reply_t *a =
				xcb_get_window_attributes_reply(b->x, k->attrs, NULL);
			xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(b->x, k->geom, NULL);
			xcb_shape_query_extents_reply_t *e =
				b->shape_ext ? xcb_shape_query_extents_reply(b->x, k->extents, NULL)
					     : NULL;
			xcb_get_property_reply_t *op = xcb_get_property_reply(b->x, k->opacity, NULL);
			xcb_get_property_reply_t *rg = xcb_get_property_reply(b->x, k->region, NULL);
			s->ok = t && a && g;
			if (s->ok) {
				s->input_only = a->_class == XCB_WINDOW_CLASS_INPUT_ONLY;
				s->mapped = a->map_state != XCB_MAP_STATE_UNMAPPED;
				s->viewable = a->map_state == XCB_MAP_STATE_VIEWABLE;
				s->x = g->x;
				s->y = g->y;
				s->width = g->width;
				s->height = g->height;
				s->border = g->border_width;
				s->argb = g->depth == 32;
				s->shaped = e && e->bounding_shaped;
				s->opacity = opacity_from_property(op);
				s->region = region_from_property(rg, &s->n_region, &s->has_region);
			}
			free(a);
			free(g);
			free(e);
			free(op);
			free(rg);
		} else {
			s->ok = t != NULL;
		}
		if (s->ok) {
			uint32_t nc = (uint32_t)xcb_query_tree_children_length(t);
			if (*n + nc > *cap) {
				uint32_t ncap = (*cap + nc) * 2;
				struct snode *g = realloc(*nodes, ncap * sizeof(*g));
				if (!g) {
					free(t);
					rc = -1;
					break;
				}
				*nodes = g;
				*cap = ncap;
				s = &(*nodes)[i];
			}
			const xcb_window_t *ch = xcb_query_tree_children(t);
			s->first_child = *n;
			s->n_children = nc;
			for (uint32_t j = 0; j < nc; j++)
				(*nodes)[(*n)++] = (struct snode){ .id = ch[j], .parent = i };
		}
		free(t);
	}
	free(c);
	/* The shapes of the shaped windows of the level: a second round. */
	for (uint32_t i = lo; rc == 0 && i < hi; i++) {
		struct snode *s = &(*nodes)[i];
		if (!s->ok || !s->shaped)
			continue;
		xcb_shape_get_rectangles_reply_t *r = xcb_shape_get_rectangles_reply(
			b->x, xcb_shape_get_rectangles(b->x, s->id, XCB_SHAPE_SK_BOUNDING), NULL);
		if (r) {
			s->n_shape = (uint32_t)xcb_shape_get_rectangles_rectangles_length(r);
			s->shape = rects_from_x(xcb_shape_get_rectangles_rectangles(r), s->n_shape);
			if (s->n_shape && !s->shape)
				s->n_shape = 0;
		}
		free(r);
	}
	return rc;
}

/*
 * A window new to the mirror that X already has viewable became so before the bridge selected
 * VisibilityChange on it: X's word reached its clients and will not reach the bridge until the
 * state changes in X's eyes, which under a compositor may be never. Its clients get the truth.
 */
static void told_unknown(struct xwin *w, const struct snode *s)
{
	if (s->viewable && !s->input_only && w->told == TOLD_NOTHING)
		w->told = TOLD_UNKNOWN;
}

/* Gives w the geometry and map state read, before it is in visd. */
static void take_geometry(struct xwin *w, const struct snode *s)
{
	w->x = s->x;
	w->y = s->y;
	w->width = s->width;
	w->height = s->height;
	w->border = s->input_only ? 0 : s->border;
	w->mapped = s->mapped;
}

/* A copy of rects[0 … n) (NULL for none, or when memory ran out: *n is then 0). */
static struct vis_rect32 *copy_rects(const struct vis_rect32 *rects, uint32_t *n)
{
	struct vis_rect32 *c = *n ? malloc(*n * sizeof(*c)) : NULL;
	if (c)
		memcpy(c, rects, *n * sizeof(*c));
	else
		*n = 0;
	return c;
}

/* Gives the mirror's w what was read of it (its own placement aside); s stays as read, since a
 * window can be read into more than one subtree of a read. */
static void take_look(struct bridge *b, struct xwin *w, const struct snode *s)
{
	w->input_only = s->input_only;
	w->argb = s->argb;
	uint32_t n_shape = s->n_shape, n_region = s->n_region;
	mirror_set_shape(b, w, s->shaped, copy_rects(s->shape, &n_shape), n_shape);
	mirror_set_opacity(b, w, s->opacity);
	mirror_set_opaque_region(b, w, s->has_region, copy_rects(s->region, &n_region), n_region);
}

/* Removes the windows under w that the read did not find (their subtrees with them). */
static void sweep_unseen(struct bridge *b, struct xwin *w)
{
	for (struct xwin *c = w->bottom, *next; c; c = next) {
		next = c->above;
		if (c->seen != b->read_number)
			mirror_remove(b, c);
		else
			sweep_unseen(b, c);
	}
}

/* One read under one grab: the subtrees of its tops, nodes[0 … n_tops), level by level. */
struct xread {
	struct snode *nodes;
	uint32_t n, cap, n_tops;
	uint32_t snap;          /* the grab's sequence number */
	struct vis_idmap tops;  /* a top's XID → its index + 1 */
};

static void xread_free(struct xread *r)
{
	if (!r)
		return;
	for (uint32_t i = 0; i < r->n; i++) {
		free(r->nodes[i].shape);
		free(r->nodes[i].region);
	}
	free(r->nodes);
	vis_idmap_finish(&r->tops);
	free(r);
}

/* Reads the subtrees of tops[0 … k) under one grab; NULL when X or memory failed. */
static struct xread *read_tops(struct bridge *b, const xcb_window_t *tops, uint32_t k)
{
	struct xread *r = calloc(1, sizeof(*r));
	if (!r)
		return NULL;
	vis_idmap_init(&r->tops);
	r->cap = k < 32 ? 64 : 2 * k;
	r->nodes = calloc(r->cap, sizeof(*r->nodes));
	if (!r->nodes) {
		xread_free(r);
		return NULL;
	}
	for (uint32_t i = 0; i < k; i++) {
		if (vis_idmap_get(&r->tops, tops[i]))
			continue;
		r->nodes[r->n] = (struct snode){ .id = tops[i], .parent = UINT32_MAX };
		if (vis_idmap_put(&r->tops, tops[i], (void *)(uintptr_t)(r->n + 1)) < 0) {
			xread_free(r);
			return NULL;
		}
		r->n++;
	}
	r->n_tops = r->n;
	xcb_void_cookie_t grab = xcb_grab_server(b->x);
	r->snap = grab.sequence;
	bridge_log(b, 3, "reading %u windows' subtrees under grab %u", r->n_tops, r->snap);
	int rc = 0;
	for (uint32_t lo = 0, hi = r->n; lo < hi && rc == 0; lo = hi, hi = r->n)
		rc = read_level(b, &r->nodes, &r->n, &r->cap, lo, hi);
	if (!b->grabbed) /* an outer grab (SIGUSR1's check) ends where it began */
		xcb_ungrab_server(b->x);
	xcb_flush(b->x);
	if (rc < 0 || xcb_connection_has_error(b->x)) {
		xread_free(r);
		return NULL;
	}
	return r;
}

/* Creates or updates one window read, under p; false when memory ran out. */
static bool apply_one(struct bridge *b, struct xread *r, struct xwin *p, struct snode *s)
{
	struct xwin *w = mirror_find(b, s->id);
	if (!w) {
		w = mirror_add(b, p, s->id);
		if (!w) {
			b->resync_needed = true;
			b->resync_reason = "out of memory";
			return false;
		}
		take_geometry(w, s);
		told_unknown(w, s);
		take_look(b, w, s); /* kept: the window is not in visd yet */
		mirror_create_in_visd(b, w);
	} else {
		if (w->parent != p)
			mirror_reparent(b, w, p, s->x, s->y);
		mirror_set_geometry(b, w, s->x, s->y, s->width, s->height, s->border);
		mirror_set_mapped(b, w, s->mapped);
		take_look(b, w, s);
	}
	w->snap = w->csnap = r->snap;
	w->seen = b->read_number;
	mirror_set_limbo(b, w, false);
	return true;
}

/*
 * Creates or updates, in the mirror and in visd, the windows below node top, level by level: a
 * level's creations wait for their parents' IDs once, not once a parent.
 */
static void apply_below(struct bridge *b, struct xread *r, uint32_t top)
{
	uint32_t *queue = malloc(r->n * sizeof(*queue));
	if (!queue) {
		b->resync_needed = true;
		b->resync_reason = "out of memory";
		return;
	}
	uint32_t head = 0, tail = 0;
	queue[tail++] = top;
	while (head < tail) {
		uint32_t i = queue[head++];
		struct snode *ps = &r->nodes[i];
		struct xwin *p = mirror_find(b, ps->id);
		for (uint32_t j = 0; p && ps->ok && j < ps->n_children; j++) {
			struct snode *s = &r->nodes[ps->first_child + j];
			if (!s->ok)
				continue;
			if (!apply_one(b, r, p, s))
				break;
			queue[tail++] = ps->first_child + j;
		}
	}
	free(queue);
}

/* Puts the children of node i and of its descendants in the order read, bottom to top. */
static void order_below(struct bridge *b, struct xread *r, uint32_t i)
{
	struct snode *s = &r->nodes[i];
	struct xwin *prev = NULL;
	for (uint32_t j = 0; s->ok && j < s->n_children; j++) {
		struct snode *c = &r->nodes[s->first_child + j];
		struct xwin *cw = c->ok ? mirror_find(b, c->id) : NULL;
		if (!cw)
			continue;
		mirror_place(b, cw, prev);
		prev = cw;
		order_below(b, r, s->first_child + j);
	}
}

/*
 * Makes the mirror's subtree of top (node ti of the read) what was read, and visd's with it;
 * with_geometry: top's geometry and map state too (otherwise they come from its parent's events).
 */
static void apply(struct bridge *b, struct xwin *top, struct xread *r, uint32_t ti,
		  bool with_geometry)
{
	struct snode *t = &r->nodes[ti];
	b->read_number++;
	top->seen = b->read_number;
	top->csnap = r->snap;
	if (top != b->root) {
		/* A window just learnt of: its look and class, then itself in visd, before its
		 * children. */
		if (t->ok) {
			take_look(b, top, t);
			told_unknown(top, t);
			if (with_geometry)
				take_geometry(top, t);
		}
		if (!top->vid && !top->pending) {
			if (top->input_only)
				top->border = 0;
			mirror_create_in_visd(b, top);
		}
	}
	apply_below(b, r, ti);
	order_below(b, r, ti);
	sweep_unseen(b, top);
	mirror_refresh_opaque(b, top);
}

/* Reads top's subtree under a grab and applies it; 0, or -1 when X failed. */
static int read_subtree(struct bridge *b, struct xwin *top, bool with_geometry)
{
	struct xread *r = read_tops(b, &top->id, 1);
	if (!r)
		return -1;
	apply(b, top, r, 0, with_geometry);
	if (top == b->root)
		b->screen_snap = r->snap;
	xread_free(r);
	return 0;
}

int xread_screen(struct bridge *b)
{
	return read_subtree(b, b->root, false);
}

void xread_prefetch(struct bridge *b, const xcb_window_t *tops, uint32_t k)
{
	xread_free(b->prefetch);
	b->prefetch = k ? read_tops(b, tops, k) : NULL;
}

void xread_prefetch_done(struct bridge *b)
{
	xread_free(b->prefetch);
	b->prefetch = NULL;
}

int xread_subtree(struct bridge *b, struct xwin *w, bool with_geometry)
{
	uintptr_t i = b->prefetch ? (uintptr_t)vis_idmap_get(&b->prefetch->tops, w->id) : 0;
	if (i) {
		/* Once: a later event naming the window again is newer than this read. */
		vis_idmap_remove(&b->prefetch->tops, w->id);
		apply(b, w, b->prefetch, (uint32_t)(i - 1), with_geometry);
		return 0;
	}
	return read_subtree(b, w, with_geometry);
}

void xread_shape(struct bridge *b, struct xwin *w)
{
	if (!b->shape_ext)
		return;
	xcb_shape_query_extents_reply_t *e =
		xcb_shape_query_extents_reply(b->x, xcb_shape_query_extents(b->x, w->id), NULL);
	if (!e)
		return; /* destroyed meanwhile: its DestroyNotify follows */
	struct vis_rect32 *rects = NULL;
	uint32_t n = 0;
	if (e->bounding_shaped) {
		xcb_shape_get_rectangles_reply_t *r = xcb_shape_get_rectangles_reply(
			b->x, xcb_shape_get_rectangles(b->x, w->id, XCB_SHAPE_SK_BOUNDING), NULL);
		if (!r) {
			free(e);
			return;
		}
		n = (uint32_t)xcb_shape_get_rectangles_rectangles_length(r);
		rects = rects_from_x(xcb_shape_get_rectangles_rectangles(r), n);
		if (n && !rects)
			n = 0;
		free(r);
	}
	mirror_set_shape(b, w, e->bounding_shaped, rects, n);
	free(e);
}

void xread_property(struct bridge *b, struct xwin *w, xcb_atom_t atom)
{
	bool opacity = atom == b->atom_opacity;
	xcb_get_property_reply_t *r = xcb_get_property_reply(
		b->x, ask_property(b, w->id, atom, opacity ? 1 : 4 * VIS_LOOK_MAX_RECTS), NULL);
	if (opacity) {
		mirror_set_opacity(b, w, opacity_from_property(r));
	} else {
		uint32_t n;
		bool has;
		struct vis_rect32 *region = region_from_property(r, &n, &has);
		mirror_set_opaque_region(b, w, has, region, n);
	}
	free(r);
}

void xread_cm(struct bridge *b)
{
	xcb_get_selection_owner_reply_t *r =
		xcb_get_selection_owner_reply(b->x, xcb_get_selection_owner(b->x, b->atom_cm), NULL);
	bool running = r && r->owner != XCB_NONE;
	free(r);
	bool now = b->translucency == TRANSLUCENCY_ON ||
		   (b->translucency == TRANSLUCENCY_AUTO && running);
	if (running != b->cm_running)
		bridge_log(b, 1, "a compositing manager %s", running ? "runs" : "is gone");
	b->cm_running = running;
	if (now != b->translucent_now) {
		b->translucent_now = now;
		mirror_refresh_opaque(b, b->root);
	}
}

void xread_later(struct bridge *b, struct xwin *w)
{
	if (w->reread_due)
		return;
	if (xid_list_push(&b->reread, w->id) < 0) {
		b->resync_needed = true;
		b->resync_reason = "out of memory";
		return;
	}
	w->reread_due = true;
}

/*
 * A window still in limbo at the end of a turn moved through windows the bridge did not watch
 * then (each event that would say so went to nobody): X says where it is now, and its parent's
 * children are read again, which places it; one that is gone is dropped. Events of the reads'
 * time are still to come, and the reads' sequence numbers sort them out as for any read.
 */
static void find_limbo(struct bridge *b)
{
	for (size_t i = 0; i < b->by_xid.cap && b->n_limbo; i++) {
		struct xwin *w = b->by_xid.keys[i] ? b->by_xid.values[i] : NULL;
		if (!w || !w->limbo)
			continue;
		xcb_query_tree_reply_t *t =
			xcb_query_tree_reply(b->x, xcb_query_tree(b->x, w->id), NULL);
		struct xwin *p = t ? mirror_find(b, t->parent) : NULL;
		free(t);
		if (!t) {
			bridge_log(b, 2, "0x%x: gone while out of sight", w->id);
			mirror_remove(b, w);
			i = (size_t)-1; /* the map changed: from the start again */
		} else if (p) {
			bridge_log(b, 2, "0x%x: found in 0x%x", w->id, p->id);
			xread_later(b, p);
		}
	}
}

void xread_pending(struct bridge *b)
{
	if (b->n_limbo)
		find_limbo(b);
	bool screen = false;
	for (size_t i = 0; i < b->reread.n; i++) {
		struct xwin *w = mirror_find(b, b->reread.ids[i]);
		if (w)
			w->reread_due = false;
		screen |= w == b->root;
	}
	if (screen) {
		/* The root's children are the whole screen: it makes every other read moot. */
		bridge_log(b, 2, "reading the whole screen again");
		xread_screen(b);
	} else {
		for (size_t i = 0; i < b->reread.n; i++) {
			struct xwin *w = mirror_find(b, b->reread.ids[i]);
			if (!w)
				continue;
			bridge_log(b, 2, "reading the children of 0x%x again", w->id);
			if (read_subtree(b, w, false) < 0)
				break;
		}
	}
	b->reread.n = 0;
	if (b->n_limbo && !b->resync_needed) {
		/* Not where X said a moment ago: it moves faster than the bridge reads. */
		b->resync_needed = true;
		b->resync_reason = "a window moved out of sight and could not be found";
	}
}
