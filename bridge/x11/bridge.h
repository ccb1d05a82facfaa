/*
 * visd-x11: mirrors an X screen's window tree into visd, as visd's manager.
 *
 * The mirror is a copy of X's tree: every window of the screen below the root, with X's geometry
 * (x, y of the border box in the parent's inside; width × height the inside; the border), map
 * state, class, depth, bounding shape, stacking (children bottom to top) and the properties the
 * translucency rule reads. X's events keep it current; every change of a turn reaches visd in one
 * batch, so visd recomputes once a turn.
 *
 * Invariants: every window in the mirror has SubstructureNotify, PropertyChange, VisibilityChange
 * and ShapeNotify selected by the bridge, so no change of a child list escapes it; a window's
 * children list is X's order at the bridge's last word on it; visd holds the same tree (its
 * windows carry the X window ID as their external ID, namespace X11).
 */
#ifndef VISD_X11_BRIDGE_H
#define VISD_X11_BRIDGE_H

#include <stdbool.h>
#include <stdint.h>

#include <xcb/xcb.h>

#include "idmap.h"
#include "vis/visclient.h"

enum send_events { SEND_AUTO, SEND_ALWAYS, SEND_NEVER };
enum translucency { TRANSLUCENCY_AUTO, TRANSLUCENCY_ON, TRANSLUCENCY_OFF };

/* What clients were last told of a window's state: one of enum vis_visibility, or these. */
#define TOLD_NOTHING 0xffu /* nothing since it became viewable: X speaks first */
/* Something the bridge never heard: X's word went out before the bridge selected its events. */
#define TOLD_UNKNOWN 0xfeu

struct xwin {
	xcb_window_t id;
	uint32_t vid;       /* visd's window; 0 for the root, or while its create is unanswered */
	bool pending;       /* its create is on its way to visd */
	struct xwin *parent; /* NULL for the root */
	struct xwin *below, *above;   /* siblings, in stacking order */
	struct xwin *bottom, *top;    /* children */
	int32_t x, y;
	uint32_t width, height, border;
	bool mapped, input_only, argb;
	/* Its bounding shape (window coordinates), when shaped. */
	bool shaped;
	uint32_t n_shape;
	struct vis_rect32 *shape;
	/* _NET_WM_WINDOW_OPACITY (0xffffffff when unset) and _NET_WM_OPAQUE_REGION. */
	uint32_t opacity;
	bool has_opaque_region;
	uint32_t n_opaque_region;
	struct vis_rect32 *opaque_region;
	/* The opaque mode visd has for it (enum vis_opaque_mode), to send only changes. */
	uint32_t opaque_mode;
	/*
	 * What the bridge read of it, as X sequence numbers (the grab of a read: see xread.c).
	 * snap: its own place and geometry, read with its parent's children; events about it
	 * generated before are older than what the mirror has and are skipped. csnap: its list of
	 * children; an event that adds to the list before that is skipped too.
	 */
	uint32_t snap, csnap;
	/* It left its parent, for a window whose children were read after it arrived there (so it
	 * had gone on by then): its next event or read places it, within the turn. */
	bool limbo;
	bool look_due;   /* its shape or opaque region waits for its visd ID (bridge.look_due) */
	bool reread_due; /* on the list of windows whose children are read again at the turn's end */
	uint32_t seen;         /* the number of the last tree read that found it */
	uint32_t reparent_seq; /* the sequence of the last ReparentNotify applied (each comes twice) */
	/* Its state: visd's, and what its clients were last told (X's own VisibilityNotify or the
	 * bridge's synthetic event, whichever came last). */
	uint8_t vstate, told;
	/* The X sequence number of the bridge's last synthetic event about it: X's own events
	 * numbered below it were generated before the server sent ours, so every client got them
	 * first, whenever the bridge reads them. */
	uint32_t told_seq;
	bool told_synthetic; /* told_seq is set */
	bool vchanged;  /* visd's state changed this turn */
	bool vis_dirty; /* on the dirty list: visd's or X's word changed this turn */
	struct xwin *next_dirty;
};

struct xread;

/* A growing list of X window IDs (windows can go while listed: look them up again). */
struct xid_list {
	xcb_window_t *ids;
	size_t n, cap;
};

struct bridge {
	xcb_connection_t *x;
	xcb_screen_t *screen;
	int screen_number;
	struct vis_client *vc;
	enum send_events send_events;
	enum translucency translucency;
	int verbose;

	struct xwin *root;
	/* The bits of an XID that name its client (above the setup's resource_id_mask): none are
	 * set in the server's own windows (see server_window()). */
	uint32_t client_bits;
	struct vis_idmap by_xid, by_vid;
	/* visd's states of windows whose creation visd has not answered yet (its notice can come
	 * first), by visd ID: state + 1, until created_cb() hands them to notify_created(). A
	 * notice of an unknown ID is about such a window or one already removed: visd's IDs come in
	 * no order, so both are kept while creates_pending, and forgotten once none is (visd never
	 * reuses an ID: a removed window's state is never asked for). */
	struct vis_idmap early_states;
	uint32_t creates_pending; /* creates sent whose answer has not come */
	uint32_t n_windows;
	uint32_t read_number; /* tree reads so far (xwin.seen) */
	uint32_t screen_snap; /* events older than the last whole-screen read are stale */

	bool shape_ext; /* the X server has SHAPE */
	uint8_t shape_event; /* its first event */
	bool xfixes_ext;
	uint8_t xfixes_event;

	xcb_atom_t atom_opacity, atom_opaque_region, atom_cm, atom_sync, atom_synced;
	bool cm_running;      /* someone owns _NET_WM_CM_Sn */
	bool translucent_now; /* the translucency rule applies (cm_running, or --translucency on) */

	struct xread *prefetch; /* this turn's new windows, read at once (xread.c) */
	xcb_generic_event_t **events_read; /* the events of a turn, and its new windows */
	xcb_window_t *new_windows;
	size_t cap_events;
	bool grabbed;         /* the server is grabbed around more than one read (check_mirror) */
	/* Windows whose look waits for visd's answer to their creation: sent with the next batch
	 * after it, rather than one round trip each. */
	struct xid_list look_due;
	bool batch_open;      /* a visd batch is open this turn */
	uint32_t visd_sent;   /* visd requests since the last round trip */
	bool resync_needed;   /* the mirror drifted: read the whole tree again */
	uint32_t n_limbo;     /* windows with limbo set */
	/* Windows whose children's order an old event could not settle (see events.c): read again
	 * at the end of the turn. */
	struct xid_list reread;
	const char *resync_reason;
	bool sync_asked;      /* _VISD_X11_SYNC changed this turn */
	struct xwin *dirty;   /* windows whose state words changed this turn */
	bool x_failed, visd_failed;
	/* visd refused a request (a limit: windows, depth, rectangles): its tree can no longer be
	 * the mirror's, so the bridge stops (exit status 1) rather than drift. */
	bool visd_refused;
	uint32_t refusals;
	uint64_t events, turns, resyncs, synthetic_sent;
	uint64_t requests; /* visd requests sent in all */
};

/*
 * A window the server made for itself, not a client: besides the root, the composite overlay
 * window a compositor draws the screen into, and the screen saver's. QueryTree leaves them out of
 * X's tree, though their CreateNotify and MapNotify reach the root's listeners; the bridge leaves
 * them out too (the overlay shows the windows below it).
 */
static inline bool server_window(const struct bridge *b, xcb_window_t id)
{
	return (id & b->client_bits) == 0;
}

/* visd's error for one of the bridge's requests: logged, and the bridge stops. */
void bridge_refused(struct bridge *b, const struct vis_error *err, xcb_window_t xid);

/* Logging: errors always, -v information. */
void bridge_log(const struct bridge *b, int level, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/* Appends id; 0, or -1 when memory ran out. */
int xid_list_push(struct xid_list *l, xcb_window_t id);

/* mirror.c: the tree and its twin in visd. */
struct xwin *mirror_find(const struct bridge *b, xcb_window_t id);
int mirror_init(struct bridge *b);
void mirror_finish(struct bridge *b);
/* A new window on top of parent's children, sent to visd (created mapped if w is mapped). */
struct xwin *mirror_add(struct bridge *b, struct xwin *parent, xcb_window_t id);
void mirror_create_in_visd(struct bridge *b, struct xwin *w);
/* Removes w and its subtree from the mirror and from visd. */
void mirror_remove(struct bridge *b, struct xwin *w);
void mirror_set_mapped(struct bridge *b, struct xwin *w, bool mapped);
void mirror_set_geometry(struct bridge *b, struct xwin *w, int32_t x, int32_t y, uint32_t width,
			 uint32_t height, uint32_t border);
/* Puts w just above sibling (NULL: at the bottom), in the mirror and in visd when it moved. */
void mirror_place(struct bridge *b, struct xwin *w, struct xwin *sibling);
/* Moves w under parent, on top of its children, at x, y. */
void mirror_reparent(struct bridge *b, struct xwin *w, struct xwin *parent, int32_t x, int32_t y);
/* Gives w a bounding shape (shaped false: its border box); takes rects, sends only a change. */
void mirror_set_shape(struct bridge *b, struct xwin *w, bool shaped, struct vis_rect32 *rects,
		      uint32_t n);
/* Sets w's translucency properties (takes region) and applies the rule to its subtree. */
void mirror_set_opacity(struct bridge *b, struct xwin *w, uint32_t opacity);
void mirror_set_opaque_region(struct bridge *b, struct xwin *w, bool has, struct vis_rect32 *region,
			      uint32_t n);
/* Brings visd's opaque regions of w's subtree in line with the translucency rule. */
void mirror_refresh_opaque(struct bridge *b, struct xwin *w);
/* The visd request helpers: open the turn's batch, and make sure w's visd ID is known. */
void visd_begin(struct bridge *b);
int visd_ensure(struct bridge *b, struct xwin *w);
int visd_end_turn(struct bridge *b);
void mirror_mark_dirty(struct bridge *b, struct xwin *w);
void mirror_set_limbo(struct bridge *b, struct xwin *w, bool limbo);

/* xread.c: reading windows from X. */
/* Reads the whole screen under a grab into the mirror (start-up and resynchronization). */
int xread_screen(struct bridge *b);
/*
 * Reads the subtree of a window just learnt of and sends it to visd: w itself is placed by its
 * parent's events, and with_geometry takes its geometry and map state from the read as well.
 * A window the turn's prefetch read is taken from it.
 */
int xread_subtree(struct bridge *b, struct xwin *w, bool with_geometry);
/*
 * Reads the subtrees of the turn's new windows under one grab before the turn's events are
 * applied (one round of requests a level instead of one grab a window); the read is as good as
 * one made when each CreateNotify is applied, since it comes after every event of the turn.
 */
void xread_prefetch(struct bridge *b, const xcb_window_t *tops, uint32_t k);
void xread_prefetch_done(struct bridge *b);
/* Re-reads one window's bounding shape, and its translucency properties. */
void xread_shape(struct bridge *b, struct xwin *w);
void xread_property(struct bridge *b, struct xwin *w, xcb_atom_t atom);
void xread_cm(struct bridge *b);
/* Asks for w's children to be read again at the end of the turn. */
void xread_later(struct bridge *b, struct xwin *w);
/* At the end of a turn: finds where the windows in limbo went (asking X), then reads again the
 * children of every window xread_later() named. */
void xread_pending(struct bridge *b);

/* twin.c: visd's copy of the mirror. */
/* Compares visd's tree with the mirror: 0 equal, 1 not (why says where), -1 visd failed. */
int twin_check(struct bridge *b, char *why, size_t size);
/* Makes visd's windows again from the mirror; 0, or -1 when visd failed. */
int twin_rebuild(struct bridge *b);

/* events.c: X's events. */
void events_handle(struct bridge *b, xcb_generic_event_t *ev);

/* notify.c: synthetic VisibilityNotify for unmodified X clients. */
void notify_flush(struct bridge *b);
void notify_on_visd(void *data, const struct vis_notice *n);
/* A window visd just answered the creation of: the state its notice gave before, if any. */
void notify_created(struct bridge *b, struct xwin *w);

#endif
