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
	bridge_log(b, 1, "drift: %s", reason);
	if (!b->resync_needed) {
		b->resync_needed = true;
		b->resync_reason = reason;
	}
}

/* Whether X sequence number a comes before b (they wrap). */
static bool before(uint32_t a, uint32_t b)
{
	return (int32_t)(a - b) < 0;
}

/* An event about w generated before the bridge's last read of w (or of the screen). */
static bool stale(const struct bridge *b, const struct xwin *w, uint32_t seq)
{
	return before(seq, b->screen_snap) || (w && before(seq, w->snap));
}

/*
 * The window an event is about, or NULL when it is stale or unknown. An unknown window whose
 * event came through a window that is gone, or whose children were read since, was dropped by
 * that read (or went with an ancestor): its old events say nothing. Any other is drift.
 */
static struct xwin *subject(struct bridge *b, xcb_window_t id, xcb_window_t via, uint32_t seq,
			    const char *what)
{
	struct xwin *w = mirror_find(b, id);
	if (stale(b, w, seq) || w == b->root)
		return NULL;
	if (!w && server_window(b, id))
		return NULL; /* never in the mirror */
	if (!w) {
		struct xwin *v = mirror_find(b, via);
		if (v && v->id != id && !before(seq, v->csnap)) {
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
	/* The bridge selects events only on windows it knows: one it no longer knows was
	 * destroyed, or dropped by a read since, with its old news. */
	struct xwin *p = mirror_find(b, ev->parent);
	if (!p)
		return;
	if (server_window(b, ev->window)) {
		bridge_log(b, 2, "0x%x is the server's own window (a compositor's overlay, or the "
				 "screen saver's): left out, as QueryTree leaves it out", ev->window);
		return;
	}
	/* The parent's children were read since: the window was not among them any more. If it
	 * lives on, an event or a read of its new parent brings it. */
	if (before(seq, p->csnap))
		return;
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
	/* Its class, depth, shape, properties and any children come from a read, which sends
	 * it to visd. */
	xread_subtree(b, w, false);
	bridge_log(b, 2, "created 0x%x in 0x%x", w->id, p->id);
}

static void on_configure(struct bridge *b, xcb_configure_notify_event_t *ev, uint32_t seq)
{
	if (ev->window == b->root->id)
		return;
	struct xwin *w = subject(b, ev->window, ev->event, seq, "ConfigureNotify");
	if (!w)
		return;
	mirror_set_geometry(b, w, ev->x, ev->y, ev->width, ev->height, ev->border_width);
	/* Its siblings' order was read since, or it is between parents: only the geometry. */
	if (w->limbo || before(seq, w->parent->csnap))
		return;
	struct xwin *sibling = NULL;
	if (ev->above_sibling != XCB_NONE) {
		sibling = mirror_find(b, ev->above_sibling);
		if (!sibling || sibling->parent != w->parent) {
			/*
			 * A sibling that has left since, where a read put it (or in limbo, or gone
			 * while out of sight): where it was, the mirror no longer knows, so the
			 * parent's children are read again at the end of the turn.
			 */
			if (!sibling || sibling->limbo || before(seq, sibling->snap) ||
			    before(seq, sibling->csnap))
				xread_later(b, w->parent);
			else
				drift(b, "a window was stacked above a window that is not its sibling");
			return;
		}
	}
	mirror_place(b, w, sibling);
}

/*
 * A window created in a parent the bridge had not yet selected events on, then moved out before
 * the bridge read that parent: its CreateNotify went to nobody, and its ReparentNotify into a
 * known window is the first the bridge hears of it. It is read, like a new window, on top of its
 * new siblings; its later events come through its new parent.
 */
static void adopt_stray(struct bridge *b, xcb_reparent_notify_event_t *ev, uint32_t seq)
{
	struct xwin *p = mirror_find(b, ev->parent);
	if (!p || before(seq, p->csnap))
		return; /* as in on_create */
	struct xwin *w = mirror_add(b, p, ev->window);
	if (!w) {
		drift(b, "out of memory");
		return;
	}
	w->x = ev->x;
	w->y = ev->y;
	w->width = w->height = 1;
	xread_subtree(b, w, true);
	bridge_log(b, 2, "adopted 0x%x in 0x%x: created where the bridge could not see it", w->id,
		   p->id);
}

static void on_reparent(struct bridge *b, xcb_reparent_notify_event_t *ev, uint32_t seq)
{
	struct xwin *w = mirror_find(b, ev->window);
	if (!w && !stale(b, NULL, seq)) {
		adopt_stray(b, ev, seq);
		return;
	}
	w = subject(b, ev->window, ev->event, seq, "ReparentNotify");
	if (!w)
		return;
	/* It comes through the old parent and the new: the second is the same change. */
	if (w->reparent_seq == seq && w->parent && w->parent->id == ev->parent && w->x == ev->x &&
	    w->y == ev->y)
		return;
	struct xwin *p = mirror_find(b, ev->parent);
	if (!p || before(seq, p->csnap)) {
		/*
		 * Into a window the bridge has not heard of yet (created inside one it had not
		 * read yet), or one whose children were read since, without it: where it is now,
		 * a later event or read says, or failing that, the end of the turn asks X.
		 */
		mirror_set_limbo(b, w, true);
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
	struct xwin *w = subject(b, ev->window, ev->event, seq, "CirculateNotify");
	if (!w || w->limbo || before(seq, w->parent->csnap))
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
	struct xwin *w = subject(b, ev->window, ev->window, seq, "PropertyNotify");
	if (w)
		xread_property(b, w, ev->atom);
}

static void on_visibility(struct bridge *b, xcb_visibility_notify_event_t *ev, uint32_t seq)
{
	struct xwin *w = mirror_find(b, ev->window);
	if (!w || w == b->root || ev->state > VIS_VISIBILITY_FULLY_OBSCURED)
		return;
	/* Generated before the server sent the bridge's last event: clients got that one after. */
	if (!w->told_synthetic || (int32_t)(seq - w->told_seq) >= 0)
		w->told = ev->state;
	mirror_mark_dirty(b, w);
}

static void on_error(struct bridge *b, xcb_generic_error_t *e)
{
	/* A window destroyed between an event and the bridge's request about it: its
	 * DestroyNotify is on its way. */
	bool race = e->error_code == XCB_WINDOW || e->error_code == XCB_DRAWABLE ||
		    e->error_code == XCB_MATCH;
	bridge_log(b, race ? 2 : 0, "X error %u on request %u.%u (sequence %u), resource 0x%x%s",
		   e->error_code, e->major_code, e->minor_code, e->full_sequence, e->resource_id,
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
		    (w = subject(b, s->affected_window, s->affected_window, seq, "ShapeNotify")))
			xread_shape(b, w);
		return;
	}
	if (b->xfixes_ext && type == b->xfixes_event + XCB_XFIXES_SELECTION_NOTIFY) {
		xread_cm(b);
		return;
	}
	if (b->verbose >= 3) {
		/* Every structure event has its event window, window and a third window (parent or
		 * sibling) in its first words. */
		const uint32_t *words = (const uint32_t *)ev;
		bridge_log(b, 3, "event %u seq %u: 0x%x 0x%x 0x%x", type, seq, words[1], words[2],
			   words[3]);
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
		if ((w = subject(b, ((xcb_map_notify_event_t *)ev)->window,
				 ((xcb_map_notify_event_t *)ev)->event, seq, "MapNotify")))
			mirror_set_mapped(b, w, true);
		break;
	case XCB_UNMAP_NOTIFY:
		if ((w = subject(b, ((xcb_unmap_notify_event_t *)ev)->window,
				 ((xcb_unmap_notify_event_t *)ev)->event, seq, "UnmapNotify")))
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
		if ((w = subject(b, g->window, g->event, seq, "GravityNotify")))
			mirror_set_geometry(b, w, g->x, g->y, w->width, w->height, w->border);
		break;
	}
	case XCB_PROPERTY_NOTIFY:
		on_property(b, (xcb_property_notify_event_t *)ev, seq);
		break;
	case XCB_VISIBILITY_NOTIFY:
		on_visibility(b, (xcb_visibility_notify_event_t *)ev, seq);
		break;
	default:
		break;
	}
}
