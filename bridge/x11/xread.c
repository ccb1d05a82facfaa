/*
 * Reading windows from X. A subtree is read under a server grab, level by level with every
 * request of a level in flight at once: no other client runs meanwhile, so what is read is one
 * moment of the tree, and the bridge's selections are in place before anything can change again.
 * Events generated before the grab describe an older tree than the read: the windows read get
 * the grab's sequence number (xwin.snap), and events about them older than it are skipped.
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
	bool ok, mapped, input_only, argb, override_redirect, shaped, has_region;
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
				s->override_redirect = a->override_redirect;
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

/* Gives the mirror's w what was read of it (its own placement aside). */
static void take_look(struct bridge *b, struct xwin *w, struct snode *s)
{
	w->input_only = s->input_only;
	w->argb = s->argb;
	w->override_redirect = s->override_redirect;
	mirror_set_shape(b, w, s->shaped, s->shape, s->n_shape);
	s->shape = NULL;
	mirror_set_opacity(b, w, s->opacity);
	mirror_set_opaque_region(b, w, s->has_region, s->region, s->n_region);
	s->region = NULL;
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

/* Makes the mirror's subtree of top what was read, and visd's with it. */
static void apply(struct bridge *b, struct xwin *top, struct snode *nodes, uint32_t n,
		  uint32_t snap)
{
	b->read_number++;
	top->seen = b->read_number;
	if (top != b->root) {
		/* A window just created: its look and class, then itself in visd, before its
		 * children. */
		if (nodes[0].ok)
			take_look(b, top, &nodes[0]);
		if (!top->vid && !top->pending) {
			if (top->input_only)
				top->border = 0;
			mirror_create_in_visd(b, top);
		}
	}
	/* Parents come before children: creations, reparentings, geometry, map state. */
	for (uint32_t i = 1; i < n; i++) {
		struct snode *s = &nodes[i];
		if (!s->ok)
			continue;
		struct xwin *p = mirror_find(b, nodes[s->parent].id);
		struct xwin *w = mirror_find(b, s->id);
		if (!w) {
			w = mirror_add(b, p, s->id);
			if (!w) {
				b->resync_needed = true;
				b->resync_reason = "out of memory";
				return;
			}
			w->x = s->x;
			w->y = s->y;
			w->width = s->width;
			w->height = s->height;
			w->border = s->input_only ? 0 : s->border;
			w->mapped = s->mapped;
			w->input_only = s->input_only;
			w->argb = s->argb;
			w->override_redirect = s->override_redirect;
			w->opacity = s->opacity;
			w->has_opaque_region = s->has_region;
			w->opaque_region = s->region;
			w->n_opaque_region = s->n_region;
			s->region = NULL;
			w->shaped = s->shaped;
			w->shape = s->shape;
			w->n_shape = s->shaped ? s->n_shape : 0;
			s->shape = NULL;
			mirror_create_in_visd(b, w);
		} else {
			if (w->parent != p)
				mirror_reparent(b, w, p, s->x, s->y);
			mirror_set_geometry(b, w, s->x, s->y, s->width, s->height, s->border);
			mirror_set_mapped(b, w, s->mapped);
			take_look(b, w, s);
		}
		w->snap = snap;
		w->seen = b->read_number;
	}
	/* The children's order, bottom to top. */
	for (uint32_t i = 0; i < n; i++) {
		struct snode *s = &nodes[i];
		struct xwin *prev = NULL;
		for (uint32_t j = 0; s->ok && j < s->n_children; j++) {
			struct snode *c = &nodes[s->first_child + j];
			struct xwin *cw = c->ok ? mirror_find(b, c->id) : NULL;
			if (!cw)
				continue;
			mirror_place(b, cw, prev);
			prev = cw;
		}
	}
	sweep_unseen(b, top);
	mirror_refresh_opaque(b, top);
}

/* Reads top's subtree under a grab and applies it; 0, or -1 when X failed. */
static int read_subtree(struct bridge *b, struct xwin *top)
{
	uint32_t n = 1, cap = 64;
	struct snode *nodes = calloc(cap, sizeof(*nodes));
	if (!nodes)
		return -1;
	nodes[0] = (struct snode){ .id = top->id, .parent = UINT32_MAX };
	xcb_void_cookie_t grab = xcb_grab_server(b->x);
	int rc = 0;
	for (uint32_t lo = 0, hi = 1; lo < hi; lo = hi, hi = n) {
		if (read_level(b, &nodes, &n, &cap, lo, hi) < 0) {
			rc = -1;
			break;
		}
	}
	xcb_ungrab_server(b->x);
	xcb_flush(b->x);
	if (xcb_connection_has_error(b->x))
		rc = -1;
	if (rc == 0) {
		apply(b, top, nodes, n, grab.sequence);
		if (top == b->root)
			b->screen_snap = grab.sequence;
	}
	for (uint32_t i = 0; i < n; i++) {
		free(nodes[i].shape);
		free(nodes[i].region);
	}
	free(nodes);
	return rc;
}

int xread_screen(struct bridge *b)
{
	return read_subtree(b, b->root);
}

int xread_subtree(struct bridge *b, struct xwin *w)
{
	return read_subtree(b, w);
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
