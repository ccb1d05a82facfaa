/*
 * x11-desk: drives a real X desktop (a window manager, real clients, windows of its own) with
 * seeded random operations and records X's own VisibilityNotify states, to compare them with
 * visd's as the X bridge mirrors that desktop. The parts: the recorder (x11-desk-record.c), the
 * desktop and its clients (x11-desk-build.c), the operations (x11-desk-ops.c), the comparison
 * (x11-desk-check.c), the brute force over X's tree (x11-desk-brute.c), and main (x11-desk.c).
 */
#ifndef VIS_TESTS_X11_DESK_H
#define VIS_TESTS_X11_DESK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>
#include <xcb/xcb.h>

#include "progress.h"
#include "rng.h"

/*
 * A window X told the recorder about; state is X's last non-synthetic VisibilityNotify state,
 * told the last of any kind, X's own or a synthetic one (the bridge's), in arrival order: what
 * an unmodified client that selected VisibilityChangeMask believes.
 */
struct rec_window {
	xcb_window_t xid;
	int state;       /* XCB_VISIBILITY_*, or -1 while X sent none */
	int told;        /* XCB_VISIBILITY_*, or -1 while nobody sent any */
	unsigned long synthetic, synthetic_mark; /* synthetic events for it: all, at the last check */
	bool input_only; /* InputOnly: never selects VisibilityChange, has no state */
	bool late;       /* viewable when adopted: its state awaits the cover (x11-desk-record.c) */
	bool inferred;   /* state set by the cover's rule, not by an event */
};

/* The recorder's table: every window that exists (destroyed ones are dropped), unordered. */
struct recorder {
	struct rec_window *w;
	size_t n, cap;
	unsigned long visibility_events, synthetic_events, x_errors;
	unsigned long late_windows, inferred, refreshes;
	bool late_pending;
	xcb_window_t cover; /* the late windows' cover, 0 until needed */
	xcb_atom_t sync_atom, synced_atom;
	uint32_t synced; /* the last value of _VISD_X11_SYNCED read */
	/* X's own events but the handshake's: when it moves, the desktop changed. */
	unsigned long changes;
	/* A second connection that selects nothing but SubstructureNotify and PropertyChange on
	 * the root: no VisibilityNotify may ever reach it, the bridge's included. */
	xcb_connection_t *bystander;
	unsigned long bystander_visibility;
};

/* Where a managed top-level stands as the operations intend it (not as the WM has it yet). */
enum top_state { TOP_NORMAL, TOP_ICONIC, TOP_WITHDRAWN };

/* A top-level the operations drive: one of ours, or a client's (which is never destroyed). */
struct top {
	xcb_window_t xid;
	enum top_state state;
	bool ours;
	int32_t x, y;
	uint32_t w, h;
	xcb_window_t kids[4];
	int n_kids;
	bool translucent; /* _NET_WM_WINDOW_OPACITY below 100% on it and its frame */
};

/* A started client process and the top-level window it mapped. */
struct client {
	const char *argv0;
	pid_t pid;
	xcb_window_t xid;
};

#define DESK_MAX_TOPS 24
#define DESK_N_OVERRIDE 2
#define DESK_MAX_CLIENTS 3

/* The atoms the operations use, interned once. */
enum desk_atom {
	ATOM_WM_CHANGE_STATE,
	ATOM_WM_STATE,
	ATOM_NET_ACTIVE_WINDOW,
	ATOM_NET_RESTACK_WINDOW,
	ATOM_COUNT
};

/* What the bridge was started with (--send-events): what x11-desk expects of synthetic events. */
enum send_mode { SEND_AUTO, SEND_ALWAYS, SEND_NEVER };

struct desk {
	xcb_connection_t *c;
	const char *display;
	bool compositor; /* a compositing manager runs: the comparisons of --compositor */
	enum send_mode send_events;
	xcb_screen_t *screen;
	xcb_window_t root;
	struct recorder rec;
	struct vis_rng rng;
	bool verbose;
	struct top tops[DESK_MAX_TOPS];
	int n_tops;
	xcb_window_t override[DESK_N_OVERRIDE];
	bool override_mapped[DESK_N_OVERRIDE];
	struct client clients[DESK_MAX_CLIENTS];
	int n_clients;
	xcb_visualid_t argb_visual; /* 0: none */
	xcb_colormap_t argb_colormap;
	xcb_window_t argb_top; /* the top-level of ours made with it, 0: none now */
	bool shape; /* the SHAPE extension is there */
	xcb_atom_t atoms[ATOM_COUNT];
	unsigned long op_counts[32];
	unsigned long harness_failures; /* viewable InputOutput windows without X's state */
	unsigned long redirected;       /* windows left out of comparisons: X redirects them */
	unsigned long past_box; /* X partially obscured, visd unobscured: a shape past the box */
	xcb_atom_t atom_opacity, atom_opaque_region;
	/* --compositor: windows whose last non-synthetic state differs from visd's; windows
	 * nobody told anything (viewable before the recorder saw them, under a compositor, which
	 * the cover cannot restate); the brute force's windows compared with visd's. */
	unsigned long x_wrong, untold, brute_checked;
	/* visd's states at the previous quiet point, for --send-events always: the changes seen
	 * since, and those not followed by a synthetic event. */
	struct x_view *prev_visd;
	size_t n_prev_visd;
	unsigned long visd_changes, changes_untold;
	/* The processes whose work the waits follow (progress.h): the X server, then those of
	 * --working (the bridge, visd, the window manager, the compositor). */
	pid_t working[PROGRESS_MAX_PIDS];
	size_t n_working;
};


/* x11-desk.c: prints "x11-desk: MESSAGE", cleans up (children killed) and exits with status. */
_Noreturn void desk_die(struct desk *d, int status, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
/* Dies with the lost-connection message when the X connection is broken. */
void desk_check_connection(struct desk *d);

/* x11-desk-record.c */
/*
 * Selects the events on the root and adopts every window that exists (under a server grab);
 * returns the root's _VISD_X11_SYNC value (a previous run's), which the handshake goes on from.
 */
uint32_t record_start(struct desk *d);
void record_finish(struct recorder *r);
/* Handles one event (the recorder's, and errors); frees nothing. */
void record_event(struct desk *d, xcb_generic_event_t *ev);
/* Reads and handles every event that has arrived; returns how many. */
int record_drain(struct desk *d);
/* One X round trip, then every event it brought in. */
void record_round_trip(struct desk *d);
/* Round trip, then events until none for 40 ms while the X server and the --working processes
 * rest (at most 20 s: x11-desk-record.c). */
void record_quiet(struct desk *d);
/* The _VISD_X11_SYNC / _VISD_X11_SYNCED handshake with the bridge for value k (dies when the
 * bridge, visd and X stop working without answering: record_until). */
void record_sync(struct desk *d, uint32_t k);
/* Reads events for up to ms milliseconds (returns early when done() says so). */
void record_wait(struct desk *d, int ms, bool (*done)(struct desk *d, void *arg), void *arg);
/*
 * Reads events until done() says so, as long as the X server, the --working processes or the n
 * pids make progress (progress.h); dies saying what was awaited when they stop working, one of
 * them dies, or the ceiling passes.
 */
void record_until(struct desk *d, const pid_t *pids, size_t n,
		  bool (*done)(struct desk *d, void *arg), void *arg, const char *what);
struct rec_window *record_find(struct recorder *r, xcb_window_t xid);
/* Enters a window this connection creates, with its events selected at creation. */
void record_own(struct desk *d, xcb_window_t xid, bool input_only);
/* The event mask the recorder wants on a window of the class. */
uint32_t record_mask(bool input_only);
xcb_atom_t record_intern(struct desk *d, const char *name);

/* x11-desk-build.c */
void build_desktop(struct desk *d, int n_tops);
/* A new top-level of ours, mapped (the WM manages it); returns its index in d->tops, or -1. */
int build_top(struct desk *d);
void build_kill_clients(struct desk *d);

/* x11-desk-ops.c: one random operation; returns its kind's name, written into what. */
const char *ops_step(struct desk *d, char *what, size_t what_size);
/* The kinds' names, for the per-kind counts (NULL-terminated). */
extern const char *const ops_kind_names[];

/* x11-desk-record.c: the bystander's VisibilityNotify events so far (a round trip first). */
unsigned long record_bystander(struct desk *d);

/* x11-desk-brute.c */
/* A viewable InputOutput window's state by the brute force, and by visd's engine on that tree. */
struct brute {
	xcb_window_t xid;
	uint8_t state, engine;
};
/* Reads X's tree under a grab and computes every viewable InputOutput window's state; sorted. */
struct brute *brute_states(struct desk *d, size_t *n);
const struct brute *brute_find(const struct brute *b, size_t n, xcb_window_t xid);

/* x11-desk-check.c */
/* The viewable InputOutput windows X has, each with its state as the recorder has it. */
struct x_view {
	xcb_window_t xid;
	int state;
	int told; /* what its clients were told last (rec_window.told) */
	/* In the subtree of a window X redirects by itself (Composite's automatic redirection of a
	 * 32-bit window in a parent of another depth, such as openbox's frame around an ARGB
	 * client): X's states there do not follow the stacking, so they are not compared. */
	bool redirected;
};
/* Every viewable InputOutput window under the root (not the root), sorted by XID; *n set. */
struct x_view *check_x_views(struct desk *d, size_t *n);
/* Prints "step K: 0x… STATE" for each (the --no-bridge mode). */
void check_print(struct desk *d, unsigned long step);
/* What a check compares, read at a quiet point: cmd's states, X's views and the brute force. */
struct check_read {
	struct x_view *c, *x;
	size_t nc, nx;
	struct brute *b;
	size_t nb;
};
void check_read(struct desk *d, const char *cmd, struct check_read *r);
void check_read_free(struct check_read *r);
/* Compares what was read (and takes r's states of cmd as the next check's previous ones);
 * prints each difference; returns the number of differences. */
unsigned long check_compare(struct desk *d, struct check_read *r, unsigned long step,
			    const char *what, unsigned long *checked);
const char *check_state_name(int state);
/* Prints the path from the root down to xid: each window's geometry, border, map state, class,
 * override-redirect and shape. */
void check_print_path(FILE *f, struct desk *d, xcb_window_t xid);

#endif
