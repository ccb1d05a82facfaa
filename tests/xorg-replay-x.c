/*
 * The X side of xorg-replay: one manager connection makes the desktop and sends the operations,
 * S subscriber connections each select VisibilityChangeMask on every window and keep the last
 * state they heard of. One thread, one poll loop, as visctl stress's.
 *
 * When is an operation done? X delivers the VisibilityNotify events a request causes into every
 * subscriber's output before it processes any later request, and answers a request only after
 * every earlier one on that connection. So after each operation the manager makes a round trip
 * (GetInputFocus, as XSync does): once its reply is in, X has processed the operation and queued
 * its events. Then a round trip on every subscriber: each reply comes after every event X queued
 * to that subscriber before, so once all are in, every event the operation caused has arrived.
 * The latency runs from the operation's start (before its request is written) to the later of the
 * manager's reply and the arrival of the last VisibilityNotify before the subscribers' replies;
 * an operation that causes no event counts until the manager's reply. An event "arrives" when
 * the poll loop sees its connection readable, as in visctl stress.
 */
#include <errno.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <xcb/xcb.h>
#include <xcb/xcbext.h>

#include "idmap.h"
#include "vis/visclient.h"
#include "proc-cpu.h"
#include "progress.h"
#include "xorg-replay.h"

#define NS UINT64_C(1000000000)
/* Without a reply or an event from X for this long, and without X using CPU time meanwhile
 * (progress.h: a server busy with other clients' requests answers late), the replay gives up
 * rather than hang: 30 s an operation; 10 minutes while setting up, since X maps n windows in
 * O(n²) (MapSubwindows walks the siblings below each window it maps: about a minute at 100,000
 * windows). */
#define STALL_NS (30 * NS)
#define SETUP_STALL_NS (600 * NS)
/* Requests sent before a round trip while setting up or reading back, so no queue grows without
 * bound. */
#define CHUNK 4096
#define REPORT_LIMIT 10

/* A subscriber: its connection and the last state it heard of for each window (by slot). */
struct sub {
	xcb_connection_t *c;
	uint8_t *view;
	unsigned int seq; /* the round trip it is waiting for */
	bool waiting;
};

/* A replay in progress. */
struct replay {
	const struct replay_options *o;
	const struct replay_script *s;
	struct replay_result *r;
	xcb_connection_t *mgr;
	xcb_window_t root;
	xcb_window_t *xid;      /* by slot */
	struct vis_idmap by_xid; /* XID → slot + 1 */
	struct sub *subs;
	struct pollfd *pfd;     /* the manager's, then each subscriber's */
	uint64_t now, last_event, last_heard;
	uint64_t stall;         /* STALL_NS or SETUP_STALL_NS */
	pid_t x_pid;            /* the X server's, for its CPU time (0: unknown) */
	double x_cpu_ms;        /* its CPU time when it last counted as progress */
	bool failed;            /* an X error came */
};

static uint64_t now_ns(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * NS + (uint64_t)ts.tv_nsec;
}

/* X's name for an error code of the core protocol. */
static const char *error_name(uint8_t code)
{
	static const char *const names[] = { NULL, "Request", "Value", "Window", "Pixmap",
		"Atom", "Cursor", "Font", "Match", "Drawable", "Access", "Alloc", "Colormap",
		"GContext", "IDChoice", "Name", "Length", "Implementation" };
	return code < sizeof(names) / sizeof(names[0]) && names[code] ? names[code] : "unknown";
}

/* Says that a connection broke; returns -1. */
static int lost(struct replay *rp, xcb_connection_t *c, const char *who)
{
	int err = xcb_connection_has_error(c);
	fprintf(stderr, "xorg-replay: %s: the connection to the X server broke (xcb error %d%s)\n",
		who, err, err == XCB_CONN_ERROR ? ": did the server exit?" : "");
	rp->failed = true;
	return -1;
}

/* Takes one event of a connection (sub: its subscriber, or NULL for the manager). */
static void take_event(struct replay *rp, struct sub *sub, xcb_generic_event_t *ev)
{
	uint8_t type = ev->response_type & 0x7f;
	if (type == 0) {
		xcb_generic_error_t *e = (xcb_generic_error_t *)ev;
		if (!rp->failed)
			fprintf(stderr, "xorg-replay: %s: X error Bad%s (code %u) on request %u.%u, "
					"resource 0x%x\n", sub ? "a subscriber" : "the manager",
				error_name(e->error_code), e->error_code, e->major_code,
				e->minor_code, e->resource_id);
		rp->failed = true;
	} else if (type == XCB_VISIBILITY_NOTIFY && sub) {
		xcb_visibility_notify_event_t *v = (xcb_visibility_notify_event_t *)ev;
		uintptr_t at = (uintptr_t)vis_idmap_get(&rp->by_xid, v->window);
		if (at && v->state <= VIS_VISIBILITY_FULLY_OBSCURED)
			sub->view[at - 1] = v->state;
		rp->r->notices++;
		rp->last_event = rp->now;
	}
	free(ev);
}

/* Takes the events a connection has read already (read: also what its socket holds). 0, or -1
 * when it broke. */
static int drain(struct replay *rp, xcb_connection_t *c, struct sub *sub, bool read)
{
	xcb_generic_event_t *ev;
	while ((ev = read ? xcb_poll_for_event(c) : xcb_poll_for_queued_event(c)))
		take_event(rp, sub, ev);
	return xcb_connection_has_error(c) ? lost(rp, c, sub ? "a subscriber" : "the manager") : 0;
}

/* Whether the reply to request seq is in (taking it); -1 when the connection broke. */
static int replied(struct replay *rp, xcb_connection_t *c, unsigned int seq)
{
	void *reply = NULL;
	xcb_generic_error_t *e = NULL;
	int got = xcb_poll_for_reply(c, seq, &reply, &e);
	if (e)
		take_event(rp, NULL, (xcb_generic_event_t *)e);
	free(reply);
	if (!got && xcb_connection_has_error(c))
		return lost(rp, c, "a round trip");
	return got;
}

/*
 * Waits until something arrives on any connection (or a second passes) and takes the events of
 * those readable, all stamped with the time poll returned. 0, or -1 (a broken connection, a
 * stall).
 */
static int wait_io(struct replay *rp)
{
	uint32_t nfd = rp->o->clients + 1;
	for (uint32_t i = 0; i < nfd; i++) {
		xcb_connection_t *c = i ? rp->subs[i - 1].c : rp->mgr;
		/* While setting up, the subscribers not yet connected are skipped (fd -1). */
		rp->pfd[i] = (struct pollfd){ .fd = c ? xcb_get_file_descriptor(c) : -1,
					      .events = POLLIN };
	}
	int n = poll(rp->pfd, nfd, 1000);
	rp->now = now_ns();
	if (n < 0 && errno != EINTR) {
		fprintf(stderr, "xorg-replay: poll: %s\n", strerror(errno));
		return -1;
	}
	if (n <= 0) {
		/* Only while X is silent: a /proc read an operation would weigh on the latencies. */
		double cpu = progress_cpu_ms(&rp->x_pid, 1);
		if (cpu >= rp->x_cpu_ms + PROGRESS_MIN_CPU_MS) {
			rp->x_cpu_ms = cpu;
			rp->last_heard = rp->now;
		}
		if (rp->now - rp->last_heard <= rp->stall)
			return 0;
		fprintf(stderr, "xorg-replay: the X server has answered nothing and done nothing "
				"for %llu s\n",
			(unsigned long long)(rp->stall / NS));
		return -1;
	}
	rp->last_heard = rp->now;
	for (uint32_t i = 0; i < nfd; i++)
		if (rp->pfd[i].fd >= 0 && rp->pfd[i].revents && drain(rp, i ? rp->subs[i - 1].c : rp->mgr,
						i ? &rp->subs[i - 1] : NULL, true) < 0)
			return -1;
	return 0;
}

/* A round trip on one connection, taking its events meanwhile. 0, or -1. */
static int roundtrip(struct replay *rp, xcb_connection_t *c, struct sub *sub)
{
	unsigned int seq = xcb_get_input_focus(c).sequence;
	xcb_flush(c);
	rp->last_heard = now_ns();
	for (;;) {
		if (drain(rp, c, sub, false) < 0)
			return -1;
		int got = replied(rp, c, seq);
		if (got)
			return got < 0 ? -1 : 0;
		if (wait_io(rp) < 0)
			return -1;
	}
}

/* A round trip on every connection, taking their events. 0, or -1 (said why). */
static int roundtrip_all(struct replay *rp)
{
	if (roundtrip(rp, rp->mgr, NULL) < 0)
		return -1;
	for (uint32_t i = 0; i < rp->o->clients; i++)
		if (roundtrip(rp, rp->subs[i].c, &rp->subs[i]) < 0)
			return -1;
	return rp->failed ? -1 : 0;
}

/* Connects to the X server; NULL after saying why. */
static xcb_connection_t *connect_x(const struct replay_options *o, int *screen)
{
	xcb_connection_t *c = xcb_connect(o->display, screen);
	if (xcb_connection_has_error(c)) {
		const char *d = o->display ? o->display : getenv("DISPLAY");
		fprintf(stderr, "xorg-replay: cannot connect to the X server %s (xcb error %d)%s\n",
			d ? d : "(DISPLAY is not set)", xcb_connection_has_error(c),
			d ? ": is it running?" : "");
		xcb_disconnect(c);
		return NULL;
	}
	return c;
}

/*
 * X's count of a window's children: QueryTree's nChildren is 16 bits, so past 65,535 children it
 * wraps, while the reply still lists every one; its length (in 4-byte units) counts them all.
 */
static uint32_t children(const xcb_query_tree_reply_t *t)
{
	return t->length > (uint32_t)xcb_query_tree_children_length(t)
		       ? t->length
		       : (uint32_t)xcb_query_tree_children_length(t);
}

/*
 * Checks the screen (the record's size) and that it has no windows yet: others' would take part
 * in every state, and the desktop is mapped at once with MapSubwindows on the root. 0, or -1
 * after saying why.
 */
static int check_server(struct replay *rp, int screen_num)
{
	const struct replay_script *s = rp->s;
	xcb_screen_iterator_t it = xcb_setup_roots_iterator(xcb_get_setup(rp->mgr));
	for (int i = 0; i < screen_num && it.rem; i++)
		xcb_screen_next(&it);
	if (!it.rem) {
		fprintf(stderr, "xorg-replay: the X server has no screen %d\n", screen_num);
		return -1;
	}
	rp->root = it.data->root;
	if (it.data->width_in_pixels != s->screen_w || it.data->height_in_pixels != s->screen_h) {
		fprintf(stderr, "xorg-replay: the X screen is %ux%u, the record's %dx%d: start the "
				"server with that size (Xvfb -screen 0 %dx%dx24)\n",
			it.data->width_in_pixels, it.data->height_in_pixels, s->screen_w, s->screen_h,
			s->screen_w, s->screen_h);
		return -1;
	}
	xcb_query_tree_reply_t *t =
		xcb_query_tree_reply(rp->mgr, xcb_query_tree(rp->mgr, rp->root), NULL);
	if (!t)
		return lost(rp, rp->mgr, "query-tree");
	uint32_t n = children(t);
	free(t);
	if (n) {
		fprintf(stderr, "xorg-replay: the X server has %u windows already; the replay needs a "
				"server of its own, without a window manager or other clients\n", n);
		return -1;
	}
	return 0;
}

/*
 * Makes the desktop: the windows unmapped in the record's order (each new one on top), override-
 * redirect, border 0, InputOutput; the subscribers' selections; then every window mapped at once
 * (MapSubwindows: one validation of the tree, where a MapWindow each costs X O(n) apiece), so
 * that each subscriber hears each window's first state once. 0, or -1.
 */
static int make_desktop(struct replay *rp)
{
	const struct replay_script *s = rp->s;
	uint32_t on = 1, mask = XCB_EVENT_MASK_VISIBILITY_CHANGE;
	for (uint32_t k = 0; k < s->n; k++) {
		struct vis_rect r = s->rects[k];
		rp->xid[k] = xcb_generate_id(rp->mgr);
		if (rp->xid[k] == UINT32_MAX || vis_idmap_put(&rp->by_xid, rp->xid[k],
							    (void *)(uintptr_t)(k + 1)) < 0) {
			fprintf(stderr, "xorg-replay: no window ID for window @%u\n", k + 1);
			return -1;
		}
		xcb_create_window(rp->mgr, XCB_COPY_FROM_PARENT, rp->xid[k], rp->root, (int16_t)r.x,
				  (int16_t)r.y, (uint16_t)r.w, (uint16_t)r.h, 0,
				  XCB_WINDOW_CLASS_INPUT_OUTPUT, XCB_COPY_FROM_PARENT,
				  XCB_CW_OVERRIDE_REDIRECT, &on);
		if (k % CHUNK == CHUNK - 1 && roundtrip(rp, rp->mgr, NULL) < 0)
			return -1;
	}
	if (roundtrip(rp, rp->mgr, NULL) < 0 || rp->failed)
		return -1;
	for (uint32_t i = 0; i < rp->o->clients; i++) {
		struct sub *u = &rp->subs[i];
		int screen;
		if (!(u->view = malloc(s->n ? s->n : 1))) {
			fprintf(stderr, "xorg-replay: %s\n", strerror(ENOMEM));
			return -1;
		}
		memset(u->view, VIS_VISIBILITY_NONE, s->n);
		if (!(u->c = connect_x(rp->o, &screen)))
			return -1;
		for (uint32_t k = 0; k < s->n; k++) {
			xcb_change_window_attributes(u->c, rp->xid[k], XCB_CW_EVENT_MASK, &mask);
			if (k % CHUNK == CHUNK - 1 && roundtrip(rp, u->c, u) < 0)
				return -1;
		}
		if (roundtrip(rp, u->c, u) < 0 || rp->failed)
			return -1;
	}
	xcb_map_subwindows(rp->mgr, rp->root);
	return roundtrip_all(rp);
}

/* Sends one operation's request on the manager's connection. */
static void send_op(struct replay *rp, const struct replay_op *op)
{
	xcb_window_t w = rp->xid[op->slot];
	switch (op->kind) {
	case REPLAY_MOVE: {
		uint32_t v[] = { (uint32_t)op->a, (uint32_t)op->b };
		xcb_configure_window(rp->mgr, w, XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y, v);
		break;
	}
	case REPLAY_RESIZE: {
		uint32_t v[] = { (uint32_t)op->a, (uint32_t)op->b };
		xcb_configure_window(rp->mgr, w, XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT,
				     v);
		break;
	}
	case REPLAY_RAISE:
	case REPLAY_LOWER: {
		uint32_t v = op->kind == REPLAY_RAISE ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW;
		xcb_configure_window(rp->mgr, w, XCB_CONFIG_WINDOW_STACK_MODE, &v);
		break;
	}
	case REPLAY_RESTACK: {
		uint32_t v[] = { rp->xid[op->sibling],
				 op->above ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW };
		xcb_configure_window(rp->mgr, w,
				     XCB_CONFIG_WINDOW_SIBLING | XCB_CONFIG_WINDOW_STACK_MODE, v);
		break;
	}
	case REPLAY_MAP:
		xcb_map_window(rp->mgr, w);
		break;
	case REPLAY_UNMAP:
		xcb_unmap_window(rp->mgr, w);
		break;
	}
}

/* Runs one operation and measures it (see the top of the file). 0, or -1. */
static int run_op(struct replay *rp, const struct replay_op *op)
{
	uint32_t S = rp->o->clients, pending = S;
	uint64_t start = now_ns(), applied = 0;
	uint64_t events = rp->r->notices;
	rp->last_event = 0;
	send_op(rp, op);
	unsigned int seq = xcb_get_input_focus(rp->mgr).sequence;
	xcb_flush(rp->mgr);
	rp->last_heard = start;
	for (;;) {
		rp->now = now_ns();
		for (uint32_t i = 0; i <= S; i++)
			if (drain(rp, i ? rp->subs[i - 1].c : rp->mgr, i ? &rp->subs[i - 1] : NULL,
				  false) < 0)
				return -1;
		if (!applied) {
			int got = replied(rp, rp->mgr, seq);
			if (got < 0)
				return -1;
			if (got) {
				applied = rp->now;
				for (uint32_t i = 0; i < S; i++) {
					struct sub *u = &rp->subs[i];
					u->seq = xcb_get_input_focus(u->c).sequence;
					u->waiting = true;
					xcb_flush(u->c);
				}
				continue; /* the flushes may have read events */
			}
		}
		for (uint32_t i = 0; applied && i < S; i++) {
			struct sub *u = &rp->subs[i];
			if (!u->waiting)
				continue;
			int got = replied(rp, u->c, u->seq);
			if (got < 0)
				return -1;
			if (got) {
				u->waiting = false;
				pending--;
			}
		}
		if (applied && !pending)
			break;
		if (wait_io(rp) < 0)
			return -1;
	}
	if (rp->failed)
		return -1;
	uint64_t end = rp->last_event > applied ? rp->last_event : applied;
	histogram_record(&rp->r->latency, end - start);
	histogram_record(&rp->r->kind_latency[op->kind], end - start);
	rp->r->ops++;
	rp->r->kind_ops[op->kind]++;
	rp->r->ops_without_notices += rp->r->notices == events;
	return 0;
}

/* Counts a difference, saying it while few have been said. */
__attribute__((format(printf, 2, 3))) static void differ(struct replay *rp, const char *fmt, ...)
{
	if (rp->r->mismatches++ < REPORT_LIMIT) {
		va_list ap;
		va_start(ap, fmt);
		fputs("xorg-replay: ", stderr);
		vfprintf(stderr, fmt, ap);
		fputc('\n', stderr);
		va_end(ap);
	}
}

/*
 * X's stacking order (QueryTree lists the root's children bottom to top), each window's place,
 * size and map state, against what the script's operations leave. 0, or -1 (X failed).
 */
static int check_tree(struct replay *rp)
{
	const struct replay_script *s = rp->s;
	xcb_query_tree_reply_t *t =
		xcb_query_tree_reply(rp->mgr, xcb_query_tree(rp->mgr, rp->root), NULL);
	if (!t)
		return lost(rp, rp->mgr, "query-tree");
	xcb_window_t *kids = xcb_query_tree_children(t);
	uint32_t nk = children(t), at = 0;
	for (uint32_t i = 0; i < nk; i++) {
		uintptr_t slot = (uintptr_t)vis_idmap_get(&rp->by_xid, kids[i]);
		if (!slot)
			continue;
		if (at < s->n && slot - 1 != s->order[at])
			differ(rp, "stack position %u: X has window @%u, the record @%u", at,
			       (unsigned)slot, s->order[at] + 1);
		at++;
	}
	free(t);
	if (at != s->n)
		differ(rp, "X has %u of the record's %u windows", at, s->n);
	for (uint32_t k0 = 0; k0 < s->n; k0 += CHUNK) {
		uint32_t k1 = s->n - k0 < CHUNK ? s->n : k0 + CHUNK;
		xcb_get_geometry_cookie_t g[CHUNK];
		xcb_get_window_attributes_cookie_t a[CHUNK];
		for (uint32_t k = k0; k < k1; k++) {
			g[k - k0] = xcb_get_geometry(rp->mgr, rp->xid[k]);
			a[k - k0] = xcb_get_window_attributes(rp->mgr, rp->xid[k]);
		}
		for (uint32_t k = k0; k < k1; k++) {
			xcb_get_geometry_reply_t *gr = xcb_get_geometry_reply(rp->mgr, g[k - k0], NULL);
			xcb_get_window_attributes_reply_t *ar =
				xcb_get_window_attributes_reply(rp->mgr, a[k - k0], NULL);
			struct vis_rect e = s->end[k];
			bool mapped = s->want[k] != VIS_VISIBILITY_NONE;
			if (!gr || !ar) {
				free(gr);
				free(ar);
				if (xcb_connection_has_error(rp->mgr))
					return lost(rp, rp->mgr, "reading the windows back");
				differ(rp, "window @%u is gone", k + 1);
				continue;
			}
			if (gr->x != e.x || gr->y != e.y || gr->width != e.w || gr->height != e.h ||
			    (ar->map_state != XCB_MAP_STATE_UNMAPPED) != mapped)
				differ(rp, "window @%u: X has it at %d,%d %ux%u %s, the record at %d,%d "
					   "%dx%d %s", k + 1, gr->x, gr->y, gr->width, gr->height,
				       ar->map_state != XCB_MAP_STATE_UNMAPPED ? "mapped" : "unmapped",
				       e.x, e.y, e.w, e.h, mapped ? "mapped" : "unmapped");
			free(gr);
			free(ar);
		}
	}
	return 0;
}

/* Every subscriber's last state of every viewable window against the record's final state. */
static void check_states(struct replay *rp)
{
	const struct replay_script *s = rp->s;
	for (uint32_t k = 0; k < s->n; k++) {
		if (s->want[k] == VIS_VISIBILITY_NONE)
			continue;
		for (uint32_t i = 0; i < rp->o->clients; i++) {
			uint8_t got = rp->subs[i].view[k];
			if (got == s->want[k])
				continue;
			if (got == VIS_VISIBILITY_NONE)
				differ(rp, "window @%u (0x%x): subscriber %u got no VisibilityNotify; "
					   "the record's final state is %s", k + 1, rp->xid[k], i + 1,
				       vis_visibility_name(s->want[k]));
			else
				differ(rp, "window @%u (0x%x): subscriber %u's last VisibilityNotify "
					   "says %s, the record's final state (visd's) is %s", k + 1,
				       rp->xid[k], i + 1, vis_visibility_name(got),
				       vis_visibility_name(s->want[k]));
		}
	}
}

/* A line a second on stderr while the operations run. */
static void progress(struct replay *rp, uint64_t t0, uint64_t *last)
{
	if (!rp->o->progress || rp->now - *last < NS)
		return;
	*last = rp->now;
	double t = (double)(rp->now - t0) / 1e9;
	fprintf(stderr, "xorg-replay: %llu of %zu operations in %.1f s, p99 %.0f us\n",
		(unsigned long long)rp->r->ops, rp->s->n_ops, t,
		(double)histogram_percentile(&rp->r->latency, 99) / 1e3);
}

int replay_x_run(const struct replay_options *o, const struct replay_script *s,
		 struct replay_result *r)
{
	struct replay rp = { .o = o, .s = s, .r = r, .stall = SETUP_STALL_NS };
	int ret = -1, screen;
	memset(r, 0, sizeof(*r));
	r->server_cpu = -1;
	vis_idmap_init(&rp.by_xid);
	if (!(rp.xid = calloc(s->n ? s->n : 1, sizeof(*rp.xid))) ||
	    !(rp.subs = calloc(o->clients ? o->clients : 1, sizeof(*rp.subs))) ||
	    !(rp.pfd = calloc(o->clients + 1, sizeof(*rp.pfd)))) {
		fprintf(stderr, "xorg-replay: %s\n", strerror(ENOMEM));
		goto out;
	}
	uint64_t t0 = now_ns();
	if (!(rp.mgr = connect_x(o, &screen)))
		goto out;
	rp.x_pid = o->pid ? o->pid : progress_peer_pid(xcb_get_file_descriptor(rp.mgr));
	rp.x_cpu_ms = progress_cpu_ms(&rp.x_pid, 1);
	if (check_server(&rp, screen) < 0 || make_desktop(&rp) < 0)
		goto out;
	r->setup_seconds = (double)(now_ns() - t0) / 1e9;

	r->notices = 0; /* the operations' alone, not the first states */
	rp.stall = STALL_NS;
	double cpu0 = proc_cpu_seconds(o->pid);
	uint64_t start = now_ns(), last_progress = start;
	for (size_t i = 0; i < s->n_ops; i++) {
		if (run_op(&rp, &s->ops[i]) < 0)
			goto out;
		progress(&rp, start, &last_progress);
	}
	r->seconds = (double)(now_ns() - start) / 1e9;
	double cpu1 = proc_cpu_seconds(o->pid);
	if (cpu0 >= 0 && cpu1 >= 0)
		r->server_cpu = cpu1 - cpu0;
	if (check_tree(&rp) < 0)
		goto out;
	check_states(&rp);
	if (r->mismatches > REPORT_LIMIT)
		fprintf(stderr, "xorg-replay: … and %llu more differences\n",
			(unsigned long long)(r->mismatches - REPORT_LIMIT));
	ret = 0;
	/* Away in two requests: left to the disconnection, X would unmap the windows one by one,
	 * each a validation of the tree, and keep the server busy for minutes at 100,000 windows. */
	rp.stall = SETUP_STALL_NS;
	xcb_unmap_subwindows(rp.mgr, rp.root);
	xcb_destroy_subwindows(rp.mgr, rp.root);
	if (roundtrip(&rp, rp.mgr, NULL) < 0)
		ret = -1;
out:
	for (uint32_t i = 0; rp.subs && i < o->clients; i++) {
		if (rp.subs[i].c)
			xcb_disconnect(rp.subs[i].c);
		free(rp.subs[i].view);
	}
	if (rp.mgr)
		xcb_disconnect(rp.mgr);
	vis_idmap_finish(&rp.by_xid);
	free(rp.xid);
	free(rp.subs);
	free(rp.pfd);
	return ret;
}
