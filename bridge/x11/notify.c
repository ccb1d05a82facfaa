/*
 * Synthetic VisibilityNotify for unmodified X clients (--send-events).
 *
 * For each window the bridge keeps what its clients were last told: X's own VisibilityNotify or
 * the bridge's synthetic one, whichever came last (the bridge selects VisibilityChangeMask on
 * every window, so it sees X's word as the clients do). At the end of a turn, once visd has
 * answered, every window whose clients were told something other than visd's state gets the true
 * one: the bridge's event always comes after X's, which X generated before the bridge could read
 * it, so no client is left with a stale state. X's own event read after the bridge sent one may
 * still be older than it (generated before the server handled the SendEvent): its sequence
 * number says so, and then the bridge's event is what clients saw last. A window that was viewable before the bridge
 * selected its events counts as told something unknown, and gets the truth while a compositor
 * runs. auto sends only then; always also on every change
 * of visd's state; never sends nothing. SendEvent with VisibilityChangeMask and no propagation
 * reaches exactly the clients that selected that mask on that window.
 */
#include <stdint.h>
#include <string.h>

#include "bridge.h"

/* visd's state for w, as it changes. */
static void take_state(struct bridge *b, struct xwin *w, uint8_t state)
{
	if (state == w->vstate)
		return;
	w->vstate = state;
	if (state == VIS_VISIBILITY_NONE)
		w->told = TOLD_NOTHING; /* X speaks again when it is viewable again */
	w->vchanged = true;
	mirror_mark_dirty(b, w);
}

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
	uint8_t state = (uint8_t)n->visibility.state;
	if (!w && b->creates_pending) {
		/* Maybe a window created in this batch: the notice can come before visd's answer
		 * to the create, which names it. Kept until then (a failed put only loses a state). */
		if (vis_idmap_put(&b->early_states, n->window, (void *)(uintptr_t)(state + 1u)) < 0)
			bridge_log(b, 0, "out of memory: the state of visd's window %u is lost",
				   n->window);
		return;
	}
	if (w)
		take_state(b, w, state);
}

void notify_created(struct bridge *b, struct xwin *w)
{
	void *early = vis_idmap_get(&b->early_states, w->vid);
	if (!early)
		return;
	vis_idmap_remove(&b->early_states, w->vid);
	take_state(b, w, (uint8_t)((uintptr_t)early - 1u));
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
	w->told_seq = xcb_send_event(b->x, 0, w->id, XCB_EVENT_MASK_VISIBILITY_CHANGE, buf).sequence;
	w->told_synthetic = true;
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
		/* A word the bridge never heard is wrong only where X's can be: under a compositor
		 * (without one, X's was right, and auto sends nothing). */
		bool wrong = w->told != TOLD_NOTHING && w->told != w->vstate &&
			     (w->told != TOLD_UNKNOWN || b->cm_running);
		if (wrong || (b->send_events == SEND_ALWAYS && changed))
			send_state(b, w);
	}
	b->dirty = NULL;
}
