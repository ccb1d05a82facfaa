/*
 * x11-order: what an unmodified X client sees of its window's visibility while visd-x11 runs
 * (x11-order.c says what is measured and how). The parts: the two connections, the client's
 * events as they arrive and the handshake with the bridge (x11-order-conn.c); the changes, their
 * figures and main (x11-order.c).
 */
#ifndef VIS_TESTS_X11_ORDER_H
#define VIS_TESTS_X11_ORDER_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <xcb/xcb.h>

#include "progress.h"
#include "rect.h"

#define MAX_SEEN 64 /* events kept of one change */

/* W, the cover (over W's place), the part cover (over part of it), the far window (elsewhere). */
enum { WIN_W, WIN_COVER, WIN_PART, WIN_FAR, N_WINS };

/* What the client got: one of these, with a state for VisibilityNotify, and its arrival time. */
enum seen_what { SEEN_CONFIGURE, SEEN_MAP, SEEN_UNMAP, SEEN_EXPOSE, SEEN_X_VIS, SEEN_SYN_VIS,
		 SEEN_OTHER };
struct seen {
	uint8_t what, state;
	uint64_t t; /* ns after the world's request */
};

/*
 * The two connections and what the client was told. The client's events are read as they come
 * (conn_collect, and every wait of x11-order-conn.c reads them), so each has its arrival time;
 * while collecting, those of the change being measured are kept in seen[], timed from t_req.
 */
struct order {
	xcb_connection_t *client, *world;
	xcb_screen_t *screen;
	xcb_window_t win[N_WINS];
	/* The world's model: rectangles, map states, stacking (stack[0] at the bottom). */
	struct vis_rect rect[N_WINS];
	bool mapped[N_WINS];
	int stack[N_WINS];
	xcb_atom_t sync, synced;
	uint32_t k;       /* the handshake's last value */
	bool synced_seen; /* _VISD_X11_SYNCED changed since the flag was cleared */
	int told, x_told; /* W's last VisibilityNotify state, any and X's own; -1: none since map */
	bool collecting;
	uint64_t t_req;
	struct seen seen[MAX_SEEN];
	size_t n_seen;
	unsigned long n_events; /* the client's events, all */
	int quiet_ms;
	const char *check;
	bool verbose;
	/* What the waits for an answer follow (progress.h): the X server, then --working's. */
	pid_t working[PROGRESS_MAX_PIDS];
	size_t n_working;
};

/* x11-order.c: prints "x11-order: MESSAGE" and exits 1. */
_Noreturn void order_die(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* x11-order-conn.c */
/* The monotonic clock, in nanoseconds. */
uint64_t conn_now_ns(void);
/* Reads every event that has come on both connections (dies when either is broken). */
void conn_collect(struct order *o);
/* The reply to request seq on c (the caller frees it), the client's events read meanwhile; dies
 * on an error or when X and the --working processes stop making progress without one. */
void *conn_await_reply(struct order *o, xcb_connection_t *c, unsigned seq, const char *what);
/* A round trip on c: every event X generated for c before it is then read. */
void conn_round_trip(struct order *o, xcb_connection_t *c, const char *what);
/* The root's _VISD_X11_SYNC or _VISD_X11_SYNCED (0 when unset). */
uint32_t conn_read_counter(struct order *o, xcb_atom_t atom);
/* The handshake with the bridge (see x11-order.c); dies when it stops making progress unanswered. */
void conn_handshake(struct order *o);
/* Reads the client's events until none came for quiet_ms (2 s at most). */
void conn_quiet(struct order *o);
xcb_atom_t conn_intern(struct order *o, const char *name);
/* Whether someone owns the selection name; waits (progress.h) for one when wait is set. */
bool conn_owned(struct order *o, const char *name, bool wait);

#endif
