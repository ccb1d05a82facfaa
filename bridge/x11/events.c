/*
 * X's events, applied to the mirror. The bridge selects SubstructureNotify on every window, so
 * each change of a child list reaches it once (a ReparentNotify twice: through the old parent and
 * the new); synthetic events (SendEvent: a client's withdrawal notice, a window manager's
 * ConfigureNotify to its client) describe nothing X did and are skipped. An event that cannot be
 * applied (an unknown parent or sibling) means the mirror drifted: the whole tree is read again.
 */
#include <stdio.h>
#include <stdlib.h>

#include <xcb/shape.h>
#include <xcb/xfixes.h>

#include "bridge.h"

static void drift(struct bridge *b, const char *reason)
{
	if (!b->resync_needed) {
		b->resync_needed = true;
		b->resync_reason = reason;
	}
}

/* An event about w generated before the bridge's last read of w (or of the screen). */
static bool stale(const struct bridge *b, const struct xwin *w, uint32_t seq)
{
	return (int32_t)(seq - b->screen_snap) < 0 || (w && (int32_t)(seq - w->snap) < 0);
}

/* The window an event is about, or NULL when it is stale or unknown (drift unless stale). */
static struct xwin *subject(struct bridge *b, xcb_window_t id, uint32_t seq, const char *what)
{
	struct xwin *w = mirror_find(b, id);
	if (stale(b, w, seq))
		return NULL;
	if (!w || w == b->root) {
		if (!w) {
			bridge_log(b, 1, "%s of unknown window 0x%x", what, id);
			drift(b, "an event named a window the mirror does not have");
		}
		return NULL;
	}
	return w;
}

static void on_create(struct bridge *b, xcb_create_notify_event_t *ev, uint32_t seq)
{
	struct xwin *w = mirror_find(b, ev->window);
	if (w) {
		if (!stale(b, w, seq))
			drift(b, "a window was created twice");
		return; /* already read with its parent's subtree */
	}
	struct xwin *p = mirror_find(b, ev->parent);
	if (!p) {
		if (!stale(b, NULL, seq))
			drift(b, "a window was created in an unknown parent");
		return;
	}
	w = mirror_add(b, p, ev->window);
	if (!w) {
		drift(b, "out of memory");
		return;
	}
	w->x = ev->x;
	w->y = ev->y;
	w->width = ev->width;
	w->height = ev->height;
	w->border = ev->border_width;
	w->override_redirect = ev->override_redirect;
	/* Its class, depth, shape, properties and any children come from a read, which sends
	 * it to visd. */
	xread_subtree(b, w);
	bridge_log(b, 2, "created 0x%x in 0x%x", w->id, p->id);
}

static void on_configure(struct bridge *b, xcb_configure_notify_event_t *ev, uint32_t seq)
{
	if (ev->window == b->root->id)
		return;
	struct xwin *w = subject(b, ev->window, seq, "ConfigureNotify");
	if (!w)
		return;
	mirror_set_geometry(b, w, ev->x, ev->y, ev->width, ev->height, ev->border_width);
	struct xwin *sibling = NULL;
	if (ev->above_sibling != XCB_NONE) {
		sibling = mirror_find(b, ev->above_sibling);
		if (!sibling || sibling->parent != w->parent) {
			drift(b, "a window was stacked above a window that is not its sibling");
			return;
		}
	}
	mirror_place(b, w, sibling);
}

static void on_reparent(struct bridge *b, xcb_reparent_notify_event_t *ev, uint32_t seq)
{
	struct xwin *w = subject(b, ev->window, seq, "ReparentNotify");
	if (!w)
		return;
	/* It comes through the old parent and the new: the second is the same change. */
	if (w->reparent_seq == seq && w->parent && w->parent->id == ev->parent && w->x == ev->x &&
	    w->y == ev->y)
		return;
	struct xwin *p = mirror_find(b, ev->parent);
	if (!p) {
		drift(b, "a window was reparented into an unknown window");
		return;
	}
	for (struct xwin *a = p; a; a = a->parent)
		if (a == w) {
			drift(b, "a window was reparented into its own subtree");
			return;
		}
	w->reparent_seq = seq;
	mirror_reparent(b, w, p, ev->x, ev->y);
}

static void on_circulate(struct bridge *b, xcb_circulate_notify_event_t *ev, uint32_t seq)
{
	struct xwin *w = subject(b, ev->window, seq, "CirculateNotify");
	if (!w)
		return;
	if (ev->place == XCB_PLACE_ON_TOP)
		mirror_place(b, w, w->parent->top == w ? w->below : w->parent->top);
	else
		mirror_place(b, w, NULL);
}

static void on_property(struct bridge *b, xcb_property_notify_event_t *ev, uint32_t seq)
{
	if (ev->window == b->root->id) {
		if (ev->atom == b->atom_sync && ev->state == XCB_PROPERTY_NEW_VALUE)
			b->sync_asked = true;
		return;
	}
	if (ev->atom != b->atom_opacity && ev->atom != b->atom_opaque_region)
		return;
	struct xwin *w = subject(b, ev->window, seq, "PropertyNotify");
	if (w)
		xread_property(b, w, ev->atom);
}

static void on_visibility(struct bridge *b, xcb_visibility_notify_event_t *ev)
{
	struct xwin *w = mirror_find(b, ev->window);
	if (!w || w == b->root || ev->state > VIS_VISIBILITY_FULLY_OBSCURED)
		return;
	w->xstate = ev->state;
	w->told = ev->state;
	mirror_mark_dirty(b, w);
}

static void on_error(struct bridge *b, xcb_generic_error_t *e)
{
	/* A window destroyed between an event and the bridge's request about it: its
	 * DestroyNotify is on its way. */
	bool race = e->error_code == XCB_WINDOW || e->error_code == XCB_DRAWABLE ||
		    e->error_code == XCB_MATCH;
	bridge_log(b, race ? 2 : 0, "X error %u on request %u.%u, resource 0x%x%s", e->error_code,
		   e->major_code, e->minor_code, e->resource_id,
		   race ? ": a window destroyed meanwhile" : "");
}

void events_handle(struct bridge *b, xcb_generic_event_t *ev)
{
	uint8_t type = ev->response_type & 0x7f;
	uint32_t seq = ev->full_sequence;
	b->events++;
	if (type == 0) {
		on_error(b, (xcb_generic_error_t *)ev);
		return;
	}
	if (ev->response_type & 0x80)
		return; /* synthetic: our own VisibilityNotify, or a client's notice */
	if (b->shape_ext && type == b->shape_event + XCB_SHAPE_NOTIFY) {
		xcb_shape_notify_event_t *s = (xcb_shape_notify_event_t *)ev;
		struct xwin *w;
		if (s->shape_kind == XCB_SHAPE_SK_BOUNDING &&
		    (w = subject(b, s->affected_window, seq, "ShapeNotify")))
			xread_shape(b, w);
		return;
	}
	if (b->xfixes_ext && type == b->xfixes_event + XCB_XFIXES_SELECTION_NOTIFY) {
		xread_cm(b);
		return;
	}
	struct xwin *w;
	switch (type) {
	case XCB_CREATE_NOTIFY:
		on_create(b, (xcb_create_notify_event_t *)ev, seq);
		break;
	case XCB_DESTROY_NOTIFY:
		w = mirror_find(b, ((xcb_destroy_notify_event_t *)ev)->window);
		if (w && w != b->root && !stale(b, w, seq))
			mirror_remove(b, w);
		break;
	case XCB_MAP_NOTIFY:
		if ((w = subject(b, ((xcb_map_notify_event_t *)ev)->window, seq, "MapNotify")))
			mirror_set_mapped(b, w, true);
		break;
	case XCB_UNMAP_NOTIFY:
		if ((w = subject(b, ((xcb_unmap_notify_event_t *)ev)->window, seq, "UnmapNotify")))
			mirror_set_mapped(b, w, false);
		break;
	case XCB_CONFIGURE_NOTIFY:
		on_configure(b, (xcb_configure_notify_event_t *)ev, seq);
		break;
	case XCB_REPARENT_NOTIFY:
		on_reparent(b, (xcb_reparent_notify_event_t *)ev, seq);
		break;
	case XCB_CIRCULATE_NOTIFY:
		on_circulate(b, (xcb_circulate_notify_event_t *)ev, seq);
		break;
	case XCB_GRAVITY_NOTIFY: {
		xcb_gravity_notify_event_t *g = (xcb_gravity_notify_event_t *)ev;
		if ((w = subject(b, g->window, seq, "GravityNotify")))
			mirror_set_geometry(b, w, g->x, g->y, w->width, w->height, w->border);
		break;
	}
	case XCB_PROPERTY_NOTIFY:
		on_property(b, (xcb_property_notify_event_t *)ev, seq);
		break;
	case XCB_VISIBILITY_NOTIFY:
		on_visibility(b, (xcb_visibility_notify_event_t *)ev);
		break;
	default:
		break;
	}
}
