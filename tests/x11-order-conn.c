/*
 * x11-order's connections: the client's, whose events are read as they arrive and timed, and the
 * world's, which makes the changes and the handshake with the bridge. Every wait reads both, so
 * that no event of the client's waits in a socket while the program waits for something else;
 * the client's ConfigureNotify, MapNotify, UnmapNotify, Expose and VisibilityNotify are kept with
 * their arrival times while a change is measured, and W's last VisibilityNotify state always.
 */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <xcb/xcbext.h> /* xcb_poll_for_reply: a reply awaited while events are read */

#include "x11-order.h"

#define QUIET_MAX_MS 2000

uint64_t conn_now_ns(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Records one of the client's events: W's last words always, the change's events while timed. */
static void client_event(struct order *o, xcb_generic_event_t *ev, uint64_t t)
{
	uint8_t type = ev->response_type & 0x7f, what = SEEN_OTHER, state = 0;
	o->n_events++;
	if (ev->response_type == 0) {
		xcb_generic_error_t *e = (void *)ev;
		order_die("X error %u on the client's request %u.%u", e->error_code, e->major_code,
			  e->minor_code);
	}
	switch (type) {
	case XCB_CONFIGURE_NOTIFY:
		what = SEEN_CONFIGURE;
		break;
	case XCB_MAP_NOTIFY:
		what = SEEN_MAP;
		break;
	case XCB_UNMAP_NOTIFY:
		what = SEEN_UNMAP;
		o->told = o->x_told = -1; /* nothing holds until X speaks again */
		break;
	case XCB_EXPOSE:
		what = SEEN_EXPOSE;
		break;
	case XCB_VISIBILITY_NOTIFY: {
		xcb_visibility_notify_event_t *v = (void *)ev;
		if (v->window != o->win[WIN_W])
			break;
		state = v->state;
		o->told = state;
		if (ev->response_type & 0x80) {
			what = SEEN_SYN_VIS;
		} else {
			what = SEEN_X_VIS;
			o->x_told = state;
		}
		break;
	}
	}
	if (o->collecting && o->n_seen < MAX_SEEN)
		o->seen[o->n_seen++] =
			(struct seen){ what, state, t > o->t_req ? t - o->t_req : 0 };
}

/* Reads every event that has come on both connections: the client's timed, the world's for the
 * handshake. */
void conn_collect(struct order *o)
{
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(o->client)) != NULL) {
		client_event(o, ev, conn_now_ns());
		free(ev);
	}
	if (xcb_connection_has_error(o->client))
		order_die("the X server closed the client's connection");
	while ((ev = xcb_poll_for_event(o->world)) != NULL) {
		xcb_property_notify_event_t *p = (void *)ev;
		if (ev->response_type == 0)
			order_die("X error %u on the world's request %u.%u",
				  ((xcb_generic_error_t *)ev)->error_code,
				  ((xcb_generic_error_t *)ev)->major_code,
				  ((xcb_generic_error_t *)ev)->minor_code);
		if ((ev->response_type & 0x7f) == XCB_PROPERTY_NOTIFY &&
		    p->window == o->screen->root && p->atom == o->synced &&
		    p->state == XCB_PROPERTY_NEW_VALUE)
			o->synced_seen = true;
		free(ev);
	}
	if (xcb_connection_has_error(o->world))
		order_die("the X server closed the world's connection");
}

/* Sleeps until either connection has something, or ms pass. */
static void wait_input(struct order *o, int ms)
{
	struct pollfd p[2] = { { xcb_get_file_descriptor(o->client), POLLIN, 0 },
			       { xcb_get_file_descriptor(o->world), POLLIN, 0 } };
	poll(p, 2, ms < 0 ? 0 : ms);
}

/* A wait for an answer: it follows the work of X and the --working processes. */
static struct progress working(const struct order *o)
{
	struct progress p;
	progress_begin(&p, o->working, o->n_working);
	return p;
}

/* The reply to request seq on c, the client's events read and timed meanwhile. */
void *conn_await_reply(struct order *o, xcb_connection_t *c, unsigned seq, const char *what)
{
	for (struct progress p = working(o);;) {
		conn_collect(o);
		void *reply = NULL;
		xcb_generic_error_t *e = NULL;
		if (xcb_poll_for_reply(c, seq, &reply, &e)) {
			if (e != NULL)
				order_die("X error %u on %s", e->error_code, what);
			if (reply == NULL)
				order_die("no answer to %s: the X server closed the connection",
					  what);
			conn_collect(o); /* what was read with the reply */
			return reply;
		}
		if (progress_stopped(&p))
			order_die("the X server did not answer %s: %s", what, p.why);
		wait_input(o, 100);
	}
}

/* A round trip on c, the client's events read and timed meanwhile. */
void conn_round_trip(struct order *o, xcb_connection_t *c, const char *what)
{
	xcb_get_input_focus_cookie_t ck = xcb_get_input_focus(c);
	xcb_flush(c);
	free(conn_await_reply(o, c, ck.sequence, what));
}

/* Reads _VISD_X11_SYNC or _VISD_X11_SYNCED (0 when unset), through the world. */
uint32_t conn_read_counter(struct order *o, xcb_atom_t atom)
{
	xcb_get_property_cookie_t ck =
		xcb_get_property(o->world, 0, o->screen->root, atom, XCB_ATOM_CARDINAL, 0, 1);
	xcb_flush(o->world);
	xcb_get_property_reply_t *r = conn_await_reply(o, o->world, ck.sequence, "GetProperty");
	uint32_t v = 0;
	if (r->format == 32 && xcb_get_property_value_length(r) >= 4)
		memcpy(&v, xcb_get_property_value(r), 4);
	free(r);
	return v;
}

/* The handshake: the bridge has applied everything X told it so far, and sent its events. */
void conn_handshake(struct order *o)
{
	o->k++;
	o->synced_seen = false;
	xcb_change_property(o->world, XCB_PROP_MODE_REPLACE, o->screen->root, o->sync,
			    XCB_ATOM_CARDINAL, 32, 1, &o->k);
	xcb_flush(o->world);
	for (struct progress p = working(o);;) {
		conn_collect(o);
		if (o->synced_seen) {
			o->synced_seen = false;
			if (conn_read_counter(o, o->synced) == o->k)
				return;
			continue;
		}
		if (progress_stopped(&p))
			order_die("visd-x11 did not answer the _VISD_X11_SYNC handshake (%u): %s; is "
				  "it running on this display?",
				  o->k, p.why);
		wait_input(o, 100);
	}
}

/* Reads events until none came for quiet_ms (at most QUIET_MAX_MS). */
void conn_quiet(struct order *o)
{
	uint64_t end = conn_now_ns() + QUIET_MAX_MS * 1000000ull;
	for (;;) {
		unsigned long before = o->n_events;
		uint64_t until = conn_now_ns() + (uint64_t)o->quiet_ms * 1000000u;
		for (uint64_t t; (t = conn_now_ns()) < until;) {
			wait_input(o, (int)((until - t) / 1000000u) + 1);
			conn_collect(o);
		}
		if (o->n_events == before || conn_now_ns() >= end)
			return;
	}
}
/* The atom of name, through the world. */
xcb_atom_t conn_intern(struct order *o, const char *name)
{
	xcb_intern_atom_reply_t *a = xcb_intern_atom_reply(
		o->world, xcb_intern_atom(o->world, 0, (uint16_t)strlen(name), name), NULL);
	if (a == NULL)
		order_die("cannot intern %s", name);
	xcb_atom_t atom = a->atom;
	free(a);
	return atom;
}

/* Whether someone owns the selection name; waits (progress.h) for one when wait is set. */
bool conn_owned(struct order *o, const char *name, bool wait)
{
	xcb_atom_t atom = conn_intern(o, name);
	for (struct progress p = working(o);;) {
		xcb_get_selection_owner_reply_t *r = xcb_get_selection_owner_reply(
			o->world, xcb_get_selection_owner(o->world, atom), NULL);
		bool yes = r != NULL && r->owner != XCB_NONE;
		free(r);
		if (yes || !wait)
			return yes;
		if (progress_stopped(&p))
			order_die("nobody owns %s: %s", name, p.why);
		nanosleep(&(struct timespec){ 0, 50000000 }, NULL);
	}
}
