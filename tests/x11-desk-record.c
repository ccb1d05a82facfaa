/*
 * The recorder: X's own truth. It follows every window of the server (SubstructureNotify on the
 * root and on every window it learns of) and keeps, per InputOutput window, the last
 * VisibilityNotify state X sent that was not synthetic (send_event clear); synthetic ones, which
 * any client may send, are only counted.
 *
 * A window is adopted when its CreateNotify arrives: under a server grab, the recorder selects
 * its events on it and queries its subtree, adopting the children too, since they may have been
 * created before the selection and their CreateNotify went to nobody. A window that is already
 * viewable when adopted ("late": its client mapped it before the CreateNotify was read, or it
 * existed before the recorder started) got its VisibilityNotify before the recorder asked for
 * it. For those the recorder maps a screen-sized override-redirect cover on top and unmaps it
 * again: X then sends every viewable window that was not fully obscured a fully-obscured event,
 * and every window that is not fully obscured without the cover its state again. A late window
 * that gets neither was fully obscured all along, by X's rules; its state is set so and counted
 * as inferred.
 */
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "x11-desk.h"

/* A quiet point: no event for QUIET_MS, and the X server and the --working processes (the window
 * manager, the compositor, the bridge, visd) ran less than QUIET_CPU_MS in that time: whatever
 * they were doing about the last change is done, however slow the machine. At most QUIET_MAX_MS,
 * for a desktop that never rests (the reads after it are then made again: x11-desk.c). */
#define QUIET_MS 40
#define QUIET_CPU_MS 1.0
#define QUIET_MAX_MS 20000

/* The monotonic clock in milliseconds, for the waits' deadlines. */
static long now_ms(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

struct rec_window *record_find(struct recorder *r, xcb_window_t xid)
{
	for (size_t i = 0; i < r->n; i++)
		if (r->w[i].xid == xid)
			return &r->w[i];
	return NULL;
}

/* Enters a window the recorder did not know, with no state yet. */
static struct rec_window *add(struct desk *d, xcb_window_t xid)
{
	struct recorder *r = &d->rec;
	if (r->n == r->cap) {
		size_t cap = r->cap ? r->cap * 2 : 64;
		struct rec_window *w = realloc(r->w, cap * sizeof *w);
		if (w == NULL)
			desk_die(d, 1, "out of memory");
		r->w = w;
		r->cap = cap;
	}
	r->w[r->n] = (struct rec_window){ .xid = xid, .state = -1, .told = -1 };
	return &r->w[r->n++];
}

/* Forgets a destroyed window (its XID may come back for another). */
static void drop(struct recorder *r, xcb_window_t xid)
{
	struct rec_window *w = record_find(r, xid);
	if (w != NULL)
		*w = r->w[--r->n];
}

void record_own(struct desk *d, xcb_window_t xid, bool input_only)
{
	add(d, xid)->input_only = input_only;
}

uint32_t record_mask(bool input_only)
{
	/* PropertyChange only so that the quiet point waits for the WM's property changes too
	 * (openbox copies _NET_WM_WINDOW_OPACITY to the frame, which the bridge reads). */
	return XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY | XCB_EVENT_MASK_PROPERTY_CHANGE |
	       (input_only ? 0 : XCB_EVENT_MASK_VISIBILITY_CHANGE);
}

/* Selects the events on xid and adopts its subtree; the caller holds the server grab. */
static void adopt(struct desk *d, xcb_window_t xid)
{
	xcb_get_window_attributes_reply_t *a =
		xcb_get_window_attributes_reply(d->c, xcb_get_window_attributes(d->c, xid), NULL);
	if (a == NULL)
		return; /* destroyed already: its DestroyNotify follows */
	bool io = a->_class == XCB_WINDOW_CLASS_INPUT_OUTPUT;
	uint32_t mask = record_mask(!io);
	/* Keep what this connection selected already (its own windows ask for more). */
	mask |= a->your_event_mask;
	xcb_change_window_attributes(d->c, xid, XCB_CW_EVENT_MASK, &mask);
	struct rec_window *w = record_find(&d->rec, xid);
	if (w == NULL) {
		w = add(d, xid);
		w->input_only = !io;
		if (io && xid != d->root && a->map_state == XCB_MAP_STATE_VIEWABLE) {
			w->late = true;
			d->rec.late_windows++;
			if (d->verbose)
				fprintf(stderr, "x11-desk: 0x%x was viewable when adopted\n", xid);
			d->rec.late_pending = true;
		}
	}
	free(a);
	xcb_query_tree_reply_t *t = xcb_query_tree_reply(d->c, xcb_query_tree(d->c, xid), NULL);
	if (t == NULL)
		return;
	xcb_window_t *kids = xcb_query_tree_children(t);
	for (int i = 0; i < xcb_query_tree_children_length(t); i++)
		adopt(d, kids[i]);
	free(t);
}

/* Adopts xid's subtree under a server grab, so that nothing is created or mapped meanwhile. */
static void adopt_grabbed(struct desk *d, xcb_window_t xid)
{
	xcb_grab_server(d->c);
	adopt(d, xid);
	xcb_ungrab_server(d->c);
	xcb_flush(d->c);
}

/* Reads _VISD_X11_SYNC or _VISD_X11_SYNCED from the root: its one CARDINAL, or 0. */
static uint32_t read_counter(struct desk *d, xcb_atom_t atom)
{
	xcb_get_property_reply_t *p = xcb_get_property_reply(
		d->c, xcb_get_property(d->c, 0, d->root, atom, XCB_ATOM_CARDINAL, 0, 1), NULL);
	uint32_t v = 0;
	if (p != NULL && p->format == 32 && xcb_get_property_value_length(p) >= 4)
		memcpy(&v, xcb_get_property_value(p), 4);
	free(p);
	return v;
}

/* Whether ev is the handshake's own property change on the root. */
static bool handshake(struct desk *d, const xcb_generic_event_t *ev)
{
	const xcb_property_notify_event_t *e = (const void *)ev;
	return (ev->response_type & 0x7f) == XCB_PROPERTY_NOTIFY && e->window == d->root &&
	       (e->atom == d->rec.sync_atom || e->atom == d->rec.synced_atom);
}

void record_event(struct desk *d, xcb_generic_event_t *ev)
{
	struct recorder *r = &d->rec;
	bool synthetic = ev->response_type & 0x80;
	if (!synthetic && ev->response_type != 0 && !handshake(d, ev))
		r->changes++;
	switch (ev->response_type & 0x7f) {
	case 0: {
		xcb_generic_error_t *e = (void *)ev;
		/* Windows vanish under the recorder's and the operations' feet: not worth a word. */
		if (e->error_code == XCB_WINDOW || e->error_code == XCB_DRAWABLE)
			break;
		r->x_errors++;
		if (d->verbose)
			fprintf(stderr, "x11-desk: X error %u (request %u.%u, resource 0x%x)\n",
				e->error_code, e->major_code, e->minor_code, e->resource_id);
		break;
	}
	case XCB_VISIBILITY_NOTIFY: {
		xcb_visibility_notify_event_t *e = (void *)ev;
		struct rec_window *w = record_find(r, e->window);
		if (w == NULL)
			w = add(d, e->window);
		w->told = e->state;
		if (synthetic) {
			r->synthetic_events++;
			w->synthetic++;
			break;
		}
		r->visibility_events++;
		w->state = e->state;
		w->inferred = false;
		break;
	}
	case XCB_CREATE_NOTIFY:
		if (!synthetic)
			adopt_grabbed(d, ((xcb_create_notify_event_t *)ev)->window);
		break;
	case XCB_DESTROY_NOTIFY:
		if (!synthetic)
			drop(r, ((xcb_destroy_notify_event_t *)ev)->window);
		break;
	case XCB_PROPERTY_NOTIFY: {
		xcb_property_notify_event_t *e = (void *)ev;
		if (e->window == d->root && e->atom == r->synced_atom &&
		    e->state == XCB_PROPERTY_NEW_VALUE)
			r->synced = read_counter(d, r->synced_atom);
		break;
	}
	}
}

int record_drain(struct desk *d)
{
	int n = 0;
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(d->c)) != NULL) {
		record_event(d, ev);
		free(ev);
		n++;
	}
	desk_check_connection(d);
	return n;
}

void record_wait(struct desk *d, int ms, bool (*done)(struct desk *d, void *arg), void *arg)
{
	long end = now_ms() + ms;
	for (;;) {
		record_drain(d);
		if (done != NULL && done(d, arg))
			return;
		long left = end - now_ms();
		if (left <= 0)
			return;
		struct pollfd p = { .fd = xcb_get_file_descriptor(d->c), .events = POLLIN };
		poll(&p, 1, (int)left);
	}
}

void record_until(struct desk *d, const pid_t *pids, size_t n,
		  bool (*done)(struct desk *d, void *arg), void *arg, const char *what)
{
	pid_t all[PROGRESS_MAX_PIDS];
	size_t k = 0;
	for (size_t i = 0; i < d->n_working && k < PROGRESS_MAX_PIDS; i++)
		all[k++] = d->working[i];
	for (size_t i = 0; i < n && k < PROGRESS_MAX_PIDS; i++)
		all[k++] = pids[i];
	struct progress p;
	progress_begin(&p, all, k);
	for (;;) {
		record_wait(d, 100, done, arg);
		if (done(d, arg))
			return;
		if (progress_stopped(&p))
			desk_die(d, 1, "%s: %s", what, p.why);
	}
}

void record_round_trip(struct desk *d)
{
	free(xcb_get_input_focus_reply(d->c, xcb_get_input_focus(d->c), NULL));
	record_drain(d);
}

/* Shows and hides a screen-sized cover so that X restates every late window (see the top). */
static void refresh_late(struct desk *d)
{
	struct recorder *r = &d->rec;
	r->late_pending = false;
	if (r->cover == 0) {
		uint32_t values[] = { d->screen->black_pixel, 1, record_mask(false) };
		r->cover = xcb_generate_id(d->c);
		xcb_create_window(d->c, XCB_COPY_FROM_PARENT, r->cover, d->root, 0, 0,
				  d->screen->width_in_pixels, d->screen->height_in_pixels, 0,
				  XCB_WINDOW_CLASS_INPUT_OUTPUT, XCB_COPY_FROM_PARENT,
				  XCB_CW_BACK_PIXEL | XCB_CW_OVERRIDE_REDIRECT | XCB_CW_EVENT_MASK,
				  values);
		record_own(d, r->cover, false);
	}
	uint32_t above = XCB_STACK_MODE_ABOVE;
	xcb_configure_window(d->c, r->cover, XCB_CONFIG_WINDOW_STACK_MODE, &above);
	xcb_map_window(d->c, r->cover);
	unsigned long before = r->visibility_events;
	record_round_trip(d);
	unsigned long mid = r->visibility_events;
	xcb_unmap_window(d->c, r->cover);
	record_round_trip(d);
	if (d->verbose)
		fprintf(stderr, "x11-desk: the cover: %lu VisibilityNotify on map, %lu on unmap\n",
			mid - before, r->visibility_events - mid);
	for (size_t i = 0; i < r->n; i++) {
		struct rec_window *w = &r->w[i];
		if (!w->late)
			continue;
		w->late = false;
		/* Under a compositor the top-levels are redirected: the cover hides none of them,
		 * so X's silence says nothing. Such a window stays without a state. */
		if (w->state < 0 && !d->compositor) {
			if (d->verbose) {
				fprintf(stderr, "x11-desk: 0x%x: fully obscured by inference\n",
					w->xid);
				check_print_path(stderr, d, w->xid);
			}
			w->state = XCB_VISIBILITY_FULLY_OBSCURED;
			if (w->told < 0)
				w->told = w->state;
			w->inferred = true;
			r->inferred++;
		}
	}
	r->refreshes++;
}

void record_quiet(struct desk *d)
{
	long end = now_ms() + QUIET_MAX_MS;
	record_round_trip(d);
	double ran = progress_cpu_ms(d->working, d->n_working);
	for (;;) {
		long left = end - now_ms();
		if (left <= 0)
			break;
		struct pollfd p = { .fd = xcb_get_file_descriptor(d->c), .events = POLLIN };
		if (poll(&p, 1, left < QUIET_MS ? (int)left : QUIET_MS) == 0) {
			double now = progress_cpu_ms(d->working, d->n_working);
			bool idle = now - ran < QUIET_CPU_MS;
			ran = now;
			if (!idle)
				continue;
			if (!d->rec.late_pending)
				break;
			refresh_late(d);
			ran = progress_cpu_ms(d->working, d->n_working);
			continue;
		}
		record_drain(d);
		ran = progress_cpu_ms(d->working, d->n_working);
	}
	if (d->rec.late_pending)
		refresh_late(d);
}

/* Whether the bridge has answered the handshake for *arg. */
static bool synced(struct desk *d, void *arg)
{
	return d->rec.synced >= *(uint32_t *)arg;
}

void record_sync(struct desk *d, uint32_t k)
{
	xcb_change_property(d->c, XCB_PROP_MODE_REPLACE, d->root, d->rec.sync_atom,
			    XCB_ATOM_CARDINAL, 32, 1, &k);
	xcb_flush(d->c);
	char what[64];
	snprintf(what, sizeof what, "the bridge did not answer sync %u", k);
	record_until(d, NULL, 0, synced, &k, what);
	record_round_trip(d);
}

xcb_atom_t record_intern(struct desk *d, const char *name)
{
	xcb_intern_atom_reply_t *a = xcb_intern_atom_reply(
		d->c, xcb_intern_atom(d->c, 0, (uint16_t)strlen(name), name), NULL);
	if (a == NULL)
		desk_die(d, 1, "cannot intern %s", name);
	xcb_atom_t atom = a->atom;
	free(a);
	return atom;
}

uint32_t record_start(struct desk *d)
{
	struct recorder *r = &d->rec;
	r->sync_atom = record_intern(d, "_VISD_X11_SYNC");
	r->synced_atom = record_intern(d, "_VISD_X11_SYNCED");
	adopt_grabbed(d, d->root);
	r->synced = read_counter(d, r->synced_atom);
	r->bystander = xcb_connect(d->display, NULL);
	if (xcb_connection_has_error(r->bystander))
		desk_die(d, 1, "the bystander cannot connect to the X server");
	uint32_t mask = XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY | XCB_EVENT_MASK_PROPERTY_CHANGE;
	xcb_change_window_attributes(r->bystander, d->root, XCB_CW_EVENT_MASK, &mask);
	record_bystander(d);
	return read_counter(d, r->sync_atom);
}

unsigned long record_bystander(struct desk *d)
{
	struct recorder *r = &d->rec;
	free(xcb_get_input_focus_reply(r->bystander, xcb_get_input_focus(r->bystander), NULL));
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(r->bystander)) != NULL) {
		if ((ev->response_type & 0x7f) == XCB_VISIBILITY_NOTIFY) {
			xcb_visibility_notify_event_t *e = (void *)ev;
			if (r->bystander_visibility++ < 5)
				printf("x11-desk: the bystander got a%s VisibilityNotify for 0x%x\n",
				       ev->response_type & 0x80 ? " synthetic" : "n", e->window);
		}
		free(ev);
	}
	if (xcb_connection_has_error(r->bystander))
		desk_die(d, 1, "the bystander's connection broke");
	return r->bystander_visibility;
}

void record_finish(struct recorder *r)
{
	if (r->bystander != NULL)
		xcb_disconnect(r->bystander);
	r->bystander = NULL;
	free(r->w);
	r->w = NULL;
	r->n = r->cap = 0;
}
