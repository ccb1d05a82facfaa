/*
 * Synthetic VisibilityNotify for unmodified X clients (--send-events).
 *
 * For each window the bridge keeps what its clients were last told: X's own VisibilityNotify or
 * the bridge's synthetic one, whichever came last (the bridge selects VisibilityChangeMask on
 * every window, so it sees X's word as the clients do). At the end of a turn, once visd has
 * answered, every window whose clients were told something other than visd's state gets the true
 * one: the bridge's event always comes after X's, which X generated before the bridge could read
 * it, so no client is left with a stale state. auto sends only then; always also on every change
 * of visd's state; never sends nothing. SendEvent with VisibilityChangeMask and no propagation
 * reaches exactly the clients that selected that mask on that window.
 */
#include <string.h>

#include "bridge.h"

/* visd's notices: the state of every window, as it changes. */
void notify_on_visd(void *data, const struct vis_notice *n)
{
	struct bridge *b = data;
	if (n->kind == VIS_NOTICE_KIND_OVERFLOW) {
		bridge_log(b, 0, "visd dropped %u notices; their states come again", n->overflow.dropped);
		return;
	}
	if (n->kind != VIS_NOTICE_KIND_VISIBILITY)
		return;
	struct xwin *w = vis_idmap_get(&b->by_vid, n->window);
	if (!w)
		return;
	uint8_t state = (uint8_t)n->visibility.state;
	if (state == w->vstate)
		return;
	w->vstate = state;
	if (state == VIS_VISIBILITY_NONE)
		w->told = TOLD_NOTHING; /* X speaks again when it is viewable again */
	w->vchanged = true;
	mirror_mark_dirty(b, w);
}

static void send_state(struct bridge *b, struct xwin *w)
{
	xcb_visibility_notify_event_t ev;
	char buf[32];
	memset(&ev, 0, sizeof(ev));
	ev.response_type = XCB_VISIBILITY_NOTIFY;
	ev.window = w->id;
	ev.state = w->vstate;
	memset(buf, 0, sizeof(buf));
	memcpy(buf, &ev, sizeof(ev) < sizeof(buf) ? sizeof(ev) : sizeof(buf));
	xcb_send_event(b->x, 0, w->id, XCB_EVENT_MASK_VISIBILITY_CHANGE, buf);
	w->told = w->vstate;
	b->synthetic_sent++;
	bridge_log(b, 2, "told 0x%x: %s", w->id, vis_visibility_name(w->vstate));
}

void notify_flush(struct bridge *b)
{
	for (struct xwin *w = b->dirty, *next; w; w = next) {
		next = w->next_dirty;
		w->vis_dirty = false;
		w->next_dirty = NULL;
		bool changed = w->vchanged;
		w->vchanged = false;
		if (b->send_events == SEND_NEVER || w->input_only ||
		    w->vstate == VIS_VISIBILITY_NONE || w->pending || !w->vid)
			continue;
		/* X speaks first when a window becomes viewable: until then, auto waits. */
		bool wrong = w->told != TOLD_NOTHING && w->told != w->vstate;
		if (wrong || (b->send_events == SEND_ALWAYS && changed))
			send_state(b, w);
	}
	b->dirty = NULL;
}
