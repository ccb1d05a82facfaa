/* The daemon's state: the window tree, the connections, and what ties them together. */
#ifndef VISD_SERVER_H
#define VISD_SERVER_H

#include <event2/event.h>
#include <event2/listener.h>
#include <pixman.h>
#include <stdbool.h>
#include <sys/queue.h>
#include <sys/types.h>

#include "codec.h"
#include "libvis-private.h" /* libvis, and the core under it (wtree.h) */

struct server_options {
	const char *socket_path;
	const char *restricted_path; /* NULL: none */
	/* Listening sockets passed by the service manager (socket activation), served as they are;
	 * -1: bind socket_path (restricted_path) instead. The paths then only name them in logs. */
	int socket_fd, restricted_fd;
	int32_t screen_width, screen_height;
	uint32_t max_request;   /* bytes, header included */
	uint32_t max_batch;     /* bytes held by one open batch */
	uint64_t id_key;        /* window IDs' permutation key (vis_wtree_set_id_key); 0: sequential */
	uint32_t max_clients;   /* connections at once */
	uint32_t owner_reserve; /* of max_clients, slots kept for allowed_uid on the main socket */
	uint32_t max_clients_per_uid;    /* connections of one uid other than allowed_uid */
	uint32_t max_restricted_clients; /* connections on the restricted socket */
	uint32_t hello_timeout; /* seconds a connection has to complete hello */
	uint32_t max_windows;   /* windows one connection owns */
	uint32_t max_look_rects; /* shape and opaque rectangles of the windows one connection owns */
	uint32_t max_look_pieces; /* the pieces those looks cut into (vis_wtree_cut()) */
	uint32_t max_depth;     /* window tree depth (top-level windows: 1) */
	uint32_t live_from;     /* windows from which recomputes go live (vis_wtree_live_from) */
	uint32_t max_subs;      /* subscriptions per connection */
	uint32_t max_pending;   /* bytes waiting to be written to one connection */
	uint32_t max_retained_per_uid; /* retained windows that exist, made by one uid */
	uint32_t max_retained;  /* retained windows that exist */
	uid_t allowed_uid;      /* peers with this uid may take roles */
};

/*
 * Requests one connection may run per turn of the event loop before others get theirs; a request
 * that made the daemon recompute (a query or sync after a change) ends the turn too.
 */
#define SERVER_REQUEST_BUDGET 64
/*
 * Windows one connection's requests may walk per turn (queries that list every window, reparents
 * that walk a subtree): past it, the turn ends. About a millisecond of work.
 */
#define SERVER_TURN_WORK (1u << 17)
/* Replies held by a committed batch that go out per turn, after the changes' one recompute. */
#define SERVER_REPLY_BUDGET 4096
/*
 * Windows the changes of one batch may walk in all (reparents walk the subtree they move), or
 * their worth of cutting looks again (server-look.c): the changes run in one turn, atomically,
 * so this bounds how long others wait for them.
 */
#define SERVER_BATCH_WORK (1u << 22)

/* A subscription: window 0 means every window the connection may see. */
struct sub {
	uint32_t window;
	uint32_t mask;       /* enum vis_notice_mask */
	uint32_t rect_limit; /* exposure rectangles before collapsing to the bounding box */
};

/* A notice held for a lagging connection: the latest state and the merged exposures of a window. */
struct held {
	uint32_t window;
	bool visibility, exposure;
	uint32_t state, previous;           /* previous: what the connection was last told */
	uint32_t visibility_count, exposure_count; /* notices folded in */
	/* Today's window coordinates, converted for the connection's version as it goes out (with
	 * the window's border as it is then: server_compat_rects()). */
	pixman_region32_t exposed;
};

/* The words of a stack notice after its serial: change window parent x y width height sibling
 * flags border namespace, then the 64-bit external ID as two words, low first (as the wire's
 * little-endian q field). */
#define SERVER_STACK_WORDS 13

/* A stack notice held for a lagging connection: its words after the serial. */
struct held_stack {
	uint32_t words[SERVER_STACK_WORDS];
};

/*
 * What a connection has not been sent yet (server-output.c). Below half of max_pending waiting,
 * notices are written at once. Above, the connection lags: notices are held, one per window
 * (stack notices in order), and go out when the output drains or before the next reply. When what
 * waits plus what is held passes max_pending, the held notices are dropped and counted: the
 * connection overflowed and gets an overflow notice and a resync once it drains.
 */
struct output {
	bool lagging, overflowed;
	struct held *held;
	size_t n_held, cap_held;
	struct vis_idmap held_index; /* window → index in held, plus 1 */
	struct held_stack *stack;
	size_t n_stack, cap_stack;
	size_t held_bytes;           /* what the held notices take encoded */
	uint32_t dropped;            /* notices lost since the overflow */
};

/*
 * A connection's socket and its bytes on their way in and out (server-io.c). Invariants:
 * in.data[in_used, in.len) was read and has not run yet, no more than the read bound (a maximum
 * request and 64 KiB); out.data[out_sent, out.len) waits to be written; reading (the read event is
 * added) only while the connection is not hung up, closing or blocked, and under the read bound
 * (once it stopped there, from when half of that has run); writing (the write event is added)
 * only while something waits that the kernel refused; listed (on the server's list of
 * connections to write at the end of the turn) only while not writing.
 */
struct conn {
	int fd;
	struct event *read_ev, *write_ev;
	struct vis_buf in, out;
	size_t in_used, out_sent;
	bool reading, writing, listed;
	bool filled; /* the last read took all the room it had: the input buffer may grow */
	TAILQ_ENTRY(client) link; /* on the server's list to write */
};

/*
 * One connection. Invariants: requests are numbered from 1 in arrival order (seq is the last one
 * received); serial is the last notice's number; while in_batch, requests wait in batch, each
 * prefixed with its number, until batch-commit; after a commit, answers holds, in request order,
 * the replies of the batch's changes and the held requests that run after them, and nothing new
 * is read until it is empty; once closing, nothing more is read and the connection ends when its
 * output has drained; read_blocked while its output is full (no requests are read until it
 * drains); once hung_up, the peer sends no more: what it sent runs, then the connection closes;
 * once write_failed, nothing more can reach the peer and output is dropped.
 */
struct client {
	struct server *server;
	struct conn io;
	TAILQ_ENTRY(client) link;
	uint32_t id;
	uid_t uid;
	bool restricted, hello_done, in_batch, closing, read_blocked, hung_up, write_failed;
	bool close_after_answers; /* a batch's fatal error waits in answers */
	bool waited; /* its next request waited a turn for the shared recompute */
	uint32_t role;
	/* The protocol version its hello asked for, which it speaks from then on (server-compat.c);
	 * 0 before hello. */
	uint32_t version;
	uint32_t seq;
	uint64_t serial;
	struct evbuffer *batch;
	/* The held requests' bytes, what a batch is charged (the numbers batch prefixes them with
	 * are the daemon's own bookkeeping): at most opt.max_batch. */
	size_t batch_bytes;
	struct evbuffer *answers;
	struct vis_buf *capture; /* while a batch's change runs: where its reply goes */
	struct sub *subs;
	size_t n_subs, cap_subs;
	bool all_exposure; /* holds a subscription to every window with exposures */
	uint32_t n_windows; /* windows it owns */
	uint64_t n_look_rects; /* shape and opaque rectangles of the windows it owns */
	uint64_t n_look_pieces; /* the pieces their looks cut into: their cuts' (vis_wtree_cut()) */
	struct output out;
	struct event *resume; /* runs the requests left over by the budget, next turn */
	struct event *hello_timer; /* ends it if hello has not succeeded within hello_timeout */
};

TAILQ_HEAD(client_list, client);

/*
 * What the daemon keeps for a window: its libvis handle's user pointer (vis_window.data is the
 * handle, struct vis_win). Every retained window has it from its creation on: its count must be
 * found after the connection that made it is gone. What a window showed, for its exposures, is
 * libvis's (vis_win.region, while tracked).
 */
struct window_data {
	uint32_t exposure_subs; /* subscriptions naming this window with exposures */
	uint32_t subs;          /* subscriptions naming this window */
	uid_t retained_by;      /* a retained window's creator, whose quota counts it */
};

struct server {
	struct event_base *base;
	struct server_options opt;
	struct evconnlistener *listener, *restricted_listener;
	struct event *listener_retry;
	int reserve_fd; /* spent to refuse connections when descriptors run out */
	/*
	 * The model: libvis's tree (vis->core the core's, each window's data its vis_win). Every
	 * change goes through server_damage(), so that vis_tree_update() recomputes it and lists
	 * what it did; libvis tracks the exposures of the windows some subscription wants them of.
	 */
	struct vis_tree *vis;
	struct client_list clients;
	struct client_list to_write; /* connections with output queued in this turn (conn.listed) */
	uint32_t n_clients;
	uint32_t n_restricted; /* connections on the restricted socket */
	uint32_t n_retained;   /* retained windows */
	struct vis_idmap quotas; /* uid + 1 → what it holds (server-quota.c) */
	uint64_t refused; /* connections refused so far */
	struct vis_idmap clients_by_id; /* window owners' connections, by ID */
	uint32_t next_client;
	struct client *manager;
	uint32_t role_all_exposure; /* observers and managers with exposures of every window */
	/* A subscription with exposures ended: the next recompute first stops tracking the windows
	 * that no subscription wants exposures of any more. */
	bool untrack_due;
	uint64_t recomputes;
	bool deferring; /* replaying a batch: recompute once at its end */
	uint64_t work;  /* windows walked by requests so far (see SERVER_TURN_WORK) */
	uint64_t walk_left; /* windows the batch being committed may still walk, or their worth */
	/* The end of the turn of the event loop: the recompute after this turn's requests, then one
	 * write to each connection that has output. */
	struct event *turn_event;
	bool turn_due; /* turn_event is active: it runs before the loop waits again */
	struct vis_buf scratch;
};

/* Sets up the server and its listening sockets. 0, or -1 after logging why. */
int server_init(struct server *server, struct event_base *base, const struct server_options *opt);
/* Closes every connection and listener and frees everything. */
void server_finish(struct server *server);

/* Whether a connection may see / change a window. */
bool server_may_see(const struct client *c, const struct vis_window *w);
bool server_may_change(const struct client *c, const struct vis_window *w);

/* Recomputes the states if the tree changed, and sends the notices that follow. */
void server_flush(struct server *server);
/*
 * Tells libvis that w changed where it and its subtree lie (libvis_damage()): the tree is dirty,
 * the windows there get their exposures recomputed, the live recompute notes it. Called before
 * and after a change moves w.
 */
void server_damage(struct server *server, struct vis_window *w);
/* Whether the tree changed since the last recompute. */
bool server_dirty(const struct server *server);
/* Recomputes once every request read in this turn of the event loop has run. */
void server_schedule_flush(struct server *server);
/* Makes the end of this turn of the event loop (the recompute, the writes) come. */
void server_schedule_turn_end(struct server *server);

/*
 * A window's ID as viewer may know it: 0 for NULL, the screen, or a window viewer may not see,
 * which does not exist for it. A NULL viewer sees every window.
 */
uint32_t server_seen_id(const struct client *viewer, const struct vis_window *w);
/*
 * The flags of a window in the tree reply and in stack notices, the one place that decides them:
 * mapped, viewable (it and all its ancestors mapped, input-only windows too), retained, parent
 * hidden (seen_parent, the parent's ID as the connection may see it, is 0 for a window that has
 * one), shaped, translucent (vis_wtree_translucent()), input-only. O(depth).
 */
uint32_t server_window_flags(const struct vis_window *w, uint32_t seen_parent);

/*
 * A stack notice's words after the serial, as viewer may see them (NULL: as a connection that
 * sees every window): change, window, parent, geometry, sibling, flags, border, external ID (the
 * window's own: whoever may see it may know what it mirrors). For a client, parent is 0
 * when it may not see the parent (x, y stay relative to it), and sibling is the window just
 * below w among its siblings when the client may see it, else 0. O(depth).
 */
void server_stack_words(const struct client *viewer, const struct vis_window *w, uint32_t change,
			uint32_t words[SERVER_STACK_WORDS]);
/* Sends a stack notice about w to the connections subscribed to it, each as it may see it. */
void server_notify_stack(struct server *server, struct vis_window *w, uint32_t change);

/* The window's daemon data, allocated on first use; NULL when memory runs out. */
struct window_data *server_window_data(struct vis_window *w);
/* The window's daemon data, NULL when it has none. */
static inline struct window_data *server_data_of(const struct vis_window *w)
{
	return vis_win_get_data(w->data);
}

/* A region's rectangles as x, y, w, h words (malloc'd; *count rectangles), or NULL. */
uint32_t *server_region_words(pixman_region32_t *region, uint32_t *count);

/*
 * Starts libvis's exposure tracking of w when a subscription wants its exposures: from what it
 * shows now when the tree is computed, else (a window just created) from nothing.
 */
void server_track(struct vis_window *w, struct server *server);

/* Gives w, just created in the core, its libvis handle. 0, or -1 when memory runs out. */
int server_wrap_window(struct server *server, struct vis_window *w);
/* Destroys w and its subtree, with notices. */
void server_destroy_window(struct server *server, struct vis_window *w);
/* Destroys w, created half-way by a request that failed, of which nobody has heard: no notices. */
void server_discard_window(struct server *server, struct vis_window *w);

/* A connection's socket (server-io.c). */
/* Sets up c's socket fd, not yet read from; 0, or -1 when memory runs out (fd stays open). */
int server_io_init(struct client *c, int fd);
/* Frees c's events and buffers and closes its socket. */
void server_io_finish(struct client *c);
/* The bytes read from c that have not run yet; *len of them. */
const uint8_t *server_io_input(const struct client *c, size_t *len);
/* Takes n bytes from the start of c's input, once they ran. */
void server_io_consume(struct client *c, size_t n);
/* Reads from c's socket, or stops, as its state says (hung up, closing, blocked, input full). */
void server_io_update(struct client *c);
/*
 * Appends len bytes to c's output, for the caller to fill at once, written at the end of the turn;
 * NULL when nothing can reach the peer any more, or when memory ran out (c is then closed).
 */
uint8_t *server_io_reserve(struct client *c, size_t len);
/* Bytes waiting to be written to c. */
size_t server_io_pending(const struct client *c);
/* Drops what waits to be written to c (its peer can read no more). */
void server_io_discard(struct client *c);
/* Makes c's end of turn come even with nothing to write: a closing connection is freed there. */
void server_io_list(struct client *c);
/* Writes once to each connection with output queued this turn (the end of the turn). */
void server_io_write_all(struct server *server);

/* Connections: accepting, dispatch and replies (server-client.c). */
void server_client_accept(struct server *server, int fd, bool restricted);
/* Answers a connection's hello in advance with a limit error and closes it. */
void server_refuse(struct server *server, int fd, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));
void server_client_free(struct client *c);
/* Queues a reply or error to c after what is held for it; on failure the connection is closed. */
void server_client_send(struct client *c, uint32_t opcode, const union vis_arg *args);
/* Encodes and queues one message to c now; on failure the connection is closed. */
void server_client_write(struct client *c, uint32_t opcode, const union vis_arg *args);
/* Queues encoded bytes to c (nothing once the peer cannot read); on failure it is closed. */
void server_client_queue(struct client *c, const void *data, size_t len);
/* Ends the connection once what is queued has been written. */
void server_client_close(struct client *c);
/* What server-io.c tells a connection: requests read; the peer hung up (end of file or a read
 * error); a write failed (the peer can read no more); the output is down to a quarter of the bound
 * after a write. Each may free c. */
void server_client_input(struct client *c);
void server_client_hangup(struct client *c);
void server_client_write_failed(struct client *c);
void server_client_drained(struct client *c);
/* Sends an error reply; fatal ones close the connection once the error is written. */
void server_client_error(struct client *c, uint32_t seq, uint32_t opcode, uint32_t code,
			 const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* The subscription of c that covers w with some of mask, or NULL. */
const struct sub *server_client_sub_for(const struct client *c, const struct vis_window *w,
					uint32_t mask);
/* Runs subscribe or unsubscribe (server-subscribe.c). */
void server_subscription(struct client *c, uint32_t seq, uint32_t op, const union vis_arg *a);
/* Ends every subscription of c. */
void server_unsubscribe_all(struct client *c);
/* Runs one decoded request. */
void server_client_dispatch(struct client *c, uint32_t seq, const struct vis_msg *m);

/* What windows' looks cost their owners (server-look.c). */
/* The pieces of w's look counted against its owner: its cut's, kept up to date by the two below. */
uint64_t server_look_charged(const struct vis_window *w);
/* The shape and opaque rectangles of w's look, counted against its owner. */
uint64_t server_look_rects(const struct vis_window *w);
/*
 * Whether window w, its look and inside becoming look and width × height, keeps its owner within
 * --max-look-pieces. If so, cut holds the pieces (zero when the look cuts nothing inside the
 * border box), for server_look_keep() once the change is made; if not, the error is sent for
 * request seq of opcode op. O(k log k + b) for the look's k rectangles and b pieces.
 */
bool server_look_pieces_ok(struct client *c, uint32_t seq, uint32_t op, const struct vis_window *w,
			   const struct vis_look *look, int32_t width, int32_t height,
			   struct vis_look_cut *cut);
/* Once w's change is made: counts cut's pieces against w's owner instead of old (what
 * server_look_charged() said before the change), and gives them to w. */
void server_look_keep(struct server *server, struct vis_window *w, uint64_t old,
		      struct vis_look_cut *cut);

/*
 * The protocol versions the daemon speaks, and what differs between them (server-compat.c): the
 * one place that knows what an older version reads otherwise.
 */
/* Whether the daemon speaks version (VIS_PROTOCOL_OLDEST_VERSION to VIS_PROTOCOL_VERSION). */
bool server_compat_speaks(uint32_t version);
/* Whether c reads rectangles about w (region replies, exposures) other than today's version. */
bool server_compat_rects_differ(const struct client *c, const struct vis_window *w);
/*
 * Converts n rectangles about w, as x, y, width, height words in today's window coordinates
 * (clipped to w's border box), to what c's version reads, in place. O(n).
 */
void server_compat_rects(const struct client *c, const struct vis_window *w, uint32_t *words,
			 uint32_t n);

/* Per-uid quotas (server-quota.c). */
/*
 * Counts a new connection of uid, or refuses it with server_refuse() when a bound is reached:
 * --max-restricted-clients, --max-clients-per-uid (uids other than the daemon's), --max-clients,
 * and --owner-reserve (the last slots, for the daemon's uid on the main socket).
 */
bool server_quota_admit(struct server *server, int fd, uid_t uid, bool restricted);
/* Counts off a connection that server_quota_admit() counted. */
void server_quota_leave(struct server *server, uid_t uid, bool restricted);
/*
 * Whether c may create one more retained window under --max-retained-per-uid (its uid's retained
 * windows that exist, whether their connections are alive or gone) and --max-retained (all that
 * exist); if not, sends the limit error for request seq.
 */
bool server_quota_may_retain(struct client *c, uint32_t seq);
/* Marks w (just created by c) retained and counts it against c's uid; -1 when memory ran out. */
int server_quota_retain(struct client *c, struct vis_window *w);
/* Counts off a retained window as it is destroyed, alone or with a subtree (before its data
 * goes). */
void server_quota_release(struct server *server, struct vis_window *w);
/*
 * Counts a change of w's look, rects shape and opaque rectangles and pieces (either may be
 * negative), against who holds it: its owner and the owner's uid while it is connected, else,
 * for a retained window, its creator's uid, as a window left behind.
 */
void server_quota_look(struct server *server, const struct vis_window *w, int64_t rects,
		       int64_t pieces);
/* As w's owner leaves and w stays (retained): its look is now one its creator's uid left. */
void server_quota_orphan(struct server *server, struct vis_window *w, struct client *owner);
/*
 * Whether w's look may grow by rects and pieces, request seq of opcode op asking: within
 * --max-look-rects and --max-look-pieces for its owner with the retained windows its uid left
 * behind, and for a uid other than the daemon's, for all the uid's windows (its connections are
 * many). If not, sends the limit error naming the option. The manager's windows, and those
 * without an owner (left behind, changed by the manager), always may: they are the desktop's.
 */
bool server_quota_look_room(struct client *c, uint32_t seq, uint32_t op,
			    const struct vis_window *w, uint64_t rects, uint64_t pieces);
/* Frees what is kept per uid. */
void server_quota_finish(struct server *server);

/*
 * A committed batch's answers (server-batch.c): records of kind, request number and size (12
 * bytes), then the bytes: an encoded reply to send, or a held request to run.
 */
enum { SERVER_ANSWER_REPLY, SERVER_ANSWER_REQUEST };
#define SERVER_ANSWER_HEADER 12
/*
 * Whether a request is one of a batch's changes (or a nested batch-begin, answered with them),
 * applied at commit with one recompute; queries, syncs and subscriptions run after them, as if
 * sent just after the commit.
 */
bool server_batch_change(uint32_t op);
/* Whether a request does nothing but answer or send notices: queries, sync, subscriptions. */
bool server_batch_no_effect(uint32_t op);
/*
 * Applies the changes held since batch-begin in order, then recomputes once, all in this turn:
 * nobody sees a state between them. Their replies, and the held requests that are not changes,
 * go to c->answers in request order, for serve() to send and run at the connection's fair rate:
 * a batch of a million queries must not hold everyone else up.
 */
void server_batch_commit(struct client *c);

/*
 * Notices and the bound on pending output (server-output.c). The fan-out encodes a notice once
 * for every connection it goes to, and each copy gets the connection's own serial (bytes 8 to 15
 * of the message).
 */
/* A visibility or stack notice as the fan-out encodes it, on first use. */
struct server_notice {
	uint32_t size; /* 0: not encoded yet */
	uint8_t bytes[VIS_MSG_HEADER + 8 + 4 * SERVER_STACK_WORDS];
};
/*
 * A window's exposure, and its notice as the fan-out encodes it, on first use: [0] with the
 * rectangles, [1] collapsed to their bounding box (past a subscription's rect_limit); and the
 * region they make, built on first use too (only lagging connections, which merge what they
 * hold, need one).
 */
struct server_exposure {
	const struct vis_rect32 *rects; /* window coordinates, a region's rectangles (libvis's) */
	const uint32_t *words;          /* the same as x, y, width, height */
	uint32_t n;
	struct vis_buf encoded[2];
	bool built; /* region holds them */
	pixman_region32_t region;
};
/* Frees what the fan-out encoded of an exposure. */
void server_exposure_finish(struct server_exposure *e);
void server_output_init(struct client *c);
void server_output_finish(struct client *c);
/* Bytes waiting to be written to c. */
size_t server_output_pending(const struct client *c);
/* Sends, holds or drops (after an overflow) a notice to c; once is shared by one fan-out. */
void server_notice_visibility(struct client *c, const struct vis_window *w,
			      struct server_notice *once);
/* The first visibility notice of a new subscription: w's state, previous VIS_VISIBILITY_INITIAL. */
void server_notice_initial(struct client *c, const struct vis_window *w);
void server_notice_exposure(struct client *c, const struct sub *s, const struct vis_window *w,
			    struct server_exposure *once);
/* once: NULL for words that are c's alone (a client's view of the stack). */
void server_notice_stack(struct client *c, const uint32_t words[SERVER_STACK_WORDS],
			 struct server_notice *once);
/* Sends what is held for c (and the resync after an overflow); before replies and on drain. */
void server_output_release(struct client *c);

#endif
