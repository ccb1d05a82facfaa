/*
 * libvisclient: talk to visd, the window-visibility daemon.
 *
 * A connection is one struct vis_client. The library never exits, aborts or prints, and never
 * blocks except inside the calls documented as synchronous. Errors are of two kinds:
 * - connection errors are sticky: once the connection fails (the daemon went away, sent bytes
 *   that do not parse, or memory ran out), every later call fails at once with the same error;
 *   vis_client_error() and vis_client_error_message() say what it was;
 * - protocol errors answer one request; the last one is kept (vis_client_last_error()). An error
 *   for a request with a callback goes to that callback; any other (a request without a reply,
 *   or a fatal error naming no waiting request) goes to the error handler, if one is set.
 * Once the connection has failed, the callbacks of requests still waiting are never called.
 *
 * Requests are numbered from 1 (hello) on, one per request sent, like X's sequence numbers;
 * functions that send a request return its number (0 on failure). Every window argument is a
 * window ID the daemon assigned. Coordinates are relative to the parent (the screen for top-level
 * windows); a window covers x, y inclusive to x + width, y + height exclusive.
 *
 * Sending: every request is written to the socket when it is made, without blocking, so that
 * none waits for a flush the program never calls; the requests of a batch (vis_client_batch_begin
 * to vis_client_batch_commit) are written together at its commit. What the socket does not take
 * at once stays queued, and goes out with the next request, the next vis_client_dispatch() or
 * vis_client_flush(), or before any synchronous call blocks.
 *
 * Integration with an event loop: poll vis_client_fd() for reading (and for writing while
 * vis_client_flush() returns 1, that is while the socket has not taken everything), then call
 * vis_client_dispatch(), which never blocks.
 */
#ifndef VIS_VISCLIENT_H
#define VIS_VISCLIENT_H

#include <stddef.h>
#include <stdint.h>

#include "vis/common.h" /* VIS_EXPORT, struct vis_rect32 */
#include "vis/protocol.h"
#include "vis/version.h"

/*
 * The version of libvisclient this program is compiled against: visd's release (meson's project
 * version, generated into vis/version.h). vis_client_version() says which library it runs with.
 */
#define VIS_CLIENT_VERSION_MAJOR VIS_VERSION_MAJOR
#define VIS_CLIENT_VERSION_MINOR VIS_VERSION_MINOR
#define VIS_CLIENT_VERSION_MICRO VIS_VERSION_MICRO
#define VIS_CLIENT_VERSION VIS_VERSION

#ifdef __cplusplus
extern "C" {
#endif

struct vis_client;

/*
 * The version of the libvisclient running, "MAJOR.MINOR.MICRO": VIS_CLIENT_VERSION of the library
 * itself, which differs from the program's VIS_CLIENT_VERSION when it was built against another.
 * A static string: valid for the life of the process, nobody frees it. Never fails.
 */
VIS_EXPORT const char *vis_client_version(void);

/* One window of the tree, as get-tree returns it (pre-order: bottom to top). */
struct vis_window_info {
	uint32_t window, parent; /* parent 0: the screen, or a window this connection may not see */
	int32_t x, y;            /* its border box's corner, relative to its parent's inside */
	uint32_t width, height;  /* its inside */
	uint32_t border;         /* its border width: the border box is the inside grown by it */
	uint32_t flags; /* enum vis_window_flags (shaped, translucent, input-only among them) */
	uint32_t state; /* enum vis_visibility; VIS_VISIBILITY_NONE when not viewable */
	/* What it mirrors: an enum vis_external_namespace and the tag (an XID for
	 * VIS_EXTERNAL_X11); VIS_EXTERNAL_NONE and 0 for a window that mirrors nothing. */
	uint32_t ext_namespace;
	uint64_t external;
};

struct vis_window_state {
	uint32_t window;
	uint32_t state; /* enum vis_visibility */
};

enum vis_notice_kind {
	VIS_NOTICE_KIND_VISIBILITY,
	VIS_NOTICE_KIND_EXPOSURE,
	VIS_NOTICE_KIND_STACK,
	VIS_NOTICE_KIND_OVERFLOW, /* the connection fell behind: a resync follows */
};

/* A notice. Pointers stay valid until the handler returns. */
struct vis_notice {
	enum vis_notice_kind kind;
	uint64_t serial; /* gapless per connection, from 1 */
	uint32_t window;
	union {
		struct {
			/* previous VIS_VISIBILITY_NONE: newly viewable; VIS_VISIBILITY_INITIAL: the
			 * first notice of a subscription, the state when it began. */
			uint32_t state, previous;
			uint32_t coalesced;       /* notices this one stands for beyond itself */
		} visibility;
		struct {
			uint32_t flags; /* VIS_EXPOSURE_COLLAPSED */
			uint32_t coalesced; /* notices merged into this one beyond itself */
			uint32_t n_rects;
			const struct vis_rect32 *rects; /* window coordinates */
		} exposure;
		struct {
			uint32_t change; /* enum vis_stack_change */
			uint32_t parent; /* as in vis_window_info */
			int32_t x, y;
			uint32_t width, height;
			/* The sibling just below, 0 if none (for a client: or if not its own). */
			uint32_t sibling;
			uint32_t flags;   /* enum vis_window_flags */
			uint32_t border;
			uint32_t ext_namespace; /* as in vis_window_info */
			uint64_t external;
		} stack;
		struct {
			uint32_t dropped; /* notices lost */
			uint32_t resync;  /* the notices that follow and restate every subscription */
		} overflow;               /* window is 0 */
	};
};

/* A protocol error: which request failed and why. */
struct vis_error {
	uint32_t seq;
	uint32_t opcode;
	uint32_t code; /* enum vis_error_code */
	char message[256];
};

typedef void (*vis_notice_handler)(void *data, const struct vis_notice *notice);
typedef void (*vis_error_handler)(void *data, const struct vis_error *error);

/*
 * The socket path a client uses when given none: $VISD_SOCKET, else $XDG_RUNTIME_DIR/visd-0.
 * Writes it to buf and returns 0, or returns -1 when neither variable is set (or the path does not
 * fit).
 */
VIS_EXPORT int vis_client_default_socket(char *buf, size_t len);

/*
 * Connects to the daemon at path (NULL or "": the default socket, see above) and performs the
 * handshake, asking for role (enum vis_role). Synchronous: blocks until the daemon answers.
 * Returns a connection, which the caller frees with vis_client_destroy() (also when it failed),
 * or NULL only when memory runs out; check vis_client_error() before use (ENOENT: no path and
 * no variable to find the default by). A refused handshake leaves EACCES (role not allowed),
 * EBUSY (the manager role is taken), EPROTONOSUPPORT (version), EAGAIN (the daemon serves as many
 * clients as it may, or is out of descriptors: try later) or ECONNREFUSED, and the daemon's
 * error in vis_client_last_error().
 */
VIS_EXPORT struct vis_client *vis_client_connect(const char *path, uint32_t role);

/* Closes the connection and frees it. NULL is a no-op. */
VIS_EXPORT void vis_client_destroy(struct vis_client *c);

/* 0, or the sticky connection error (an errno value; EPROTO for a daemon that broke protocol). */
VIS_EXPORT int vis_client_error(const struct vis_client *c);
/* What the sticky error was, in words ("" when none). */
VIS_EXPORT const char *vis_client_error_message(const struct vis_client *c);
/* The last protocol error received; returns 0 if there was none, 1 if *err was filled. */
VIS_EXPORT int vis_client_last_error(const struct vis_client *c, struct vis_error *err);

/* The handshake's answers. */
VIS_EXPORT uint32_t vis_client_role(const struct vis_client *c);
VIS_EXPORT uint32_t vis_client_id(const struct vis_client *c);
VIS_EXPORT void vis_client_screen(const struct vis_client *c, uint32_t *width, uint32_t *height);

VIS_EXPORT void vis_client_set_notice_handler(struct vis_client *c, vis_notice_handler handler,
					      void *data);
VIS_EXPORT void vis_client_set_error_handler(struct vis_client *c, vis_error_handler handler,
					     void *data);

/* The connection's file descriptor, for poll and event loops. */
VIS_EXPORT int vis_client_fd(const struct vis_client *c);

/*
 * Reads what the daemon sent without blocking, then runs the handlers and callbacks for every
 * complete message. Returns the number of messages handled, or -1 on a connection error.
 */
VIS_EXPORT int vis_client_dispatch(struct vis_client *c);

/*
 * Writes what is queued without blocking: what the socket did not take when the requests were
 * made (see Sending above). Returns 0 when everything is written, 1 when some remains (poll the
 * fd for writing, then call it again), -1 on a connection error.
 */
VIS_EXPORT int vis_client_flush(struct vis_client *c);

/*
 * Blocks until the daemon has answered every request sent so far (a sync round trip), running
 * handlers on the way. Returns 0, or -1 on a connection error. Protocol errors of earlier
 * requests do not fail it: compare vis_client_last_error()'s seq with the requests sent.
 */
VIS_EXPORT int vis_client_roundtrip(struct vis_client *c);

/*
 * Inside a batch: commits it and blocks until the daemon has answered every request, as a commit
 * then vis_client_roundtrip() would, but in one message (the sync travels inside the batch and
 * runs after its recompute), so that the daemon wakes once for the batch and its answer. Outside
 * a batch, vis_client_roundtrip(). Returns 0, or -1 on a connection error.
 */
VIS_EXPORT int vis_client_batch_roundtrip(struct vis_client *c);

/*
 * Requests without a reply (an error may still come: see vis_client_last_error() and the error
 * handler). Each is written at once, without blocking, or inside a batch at its commit (see
 * Sending above). Return the request's number, 0 on a connection error (or, with errno
 * EMSGSIZE, for a request larger than the daemon takes). A queue the daemon does not drain
 * (64 MiB) fails the connection with ENOBUFS rather than block or grow without bound. None of
 * them blocks.
 */
VIS_EXPORT uint32_t vis_client_destroy_window(struct vis_client *c, uint32_t window);
VIS_EXPORT uint32_t vis_client_map(struct vis_client *c, uint32_t window);
VIS_EXPORT uint32_t vis_client_unmap(struct vis_client *c, uint32_t window);
VIS_EXPORT uint32_t vis_client_move(struct vis_client *c, uint32_t window, int32_t x, int32_t y);
VIS_EXPORT uint32_t vis_client_resize(struct vis_client *c, uint32_t window, uint32_t width,
				      uint32_t height);
VIS_EXPORT uint32_t vis_client_raise(struct vis_client *c, uint32_t window);
VIS_EXPORT uint32_t vis_client_lower(struct vis_client *c, uint32_t window);
VIS_EXPORT uint32_t vis_client_restack(struct vis_client *c, uint32_t window, uint32_t mode,
				       uint32_t sibling);
VIS_EXPORT uint32_t vis_client_reparent(struct vis_client *c, uint32_t window, uint32_t parent,
					int32_t x, int32_t y);
/*
 * X's ConfigureWindow: moves the window's border box to x, y, sets its inside to width × height
 * and its border width to border (the border box's sides at most 2147483647), at once.
 */
VIS_EXPORT uint32_t vis_client_configure(struct vis_client *c, uint32_t window, int32_t x,
					 int32_t y, uint32_t width, uint32_t height,
					 uint32_t border);
/*
 * Sets the window's bounding shape, as X's SHAPE extension: its pixels are the union of the n
 * rectangles (window coordinates: relative to the inside's corner, so negative ones reach into
 * the border), clipped to its border box; n = 0 leaves it no pixels (it then hides nothing and is
 * fully obscured). shaped 0 (rects ignored, n must be 0) gives it its whole border box again.
 * The rectangles are copied. At most (max_request − 20) / 16 of them fit one request.
 */
VIS_EXPORT uint32_t vis_client_set_shape(struct vis_client *c, uint32_t window, uint32_t shaped,
					 const struct vis_rect32 *rects, uint32_t n);
/*
 * Sets which of the window's pixels hide what lies below it, as _NET_WM_OPAQUE_REGION and
 * wl_surface.set_opaque_region: mode VIS_OPAQUE_MODE_ALL (the default) or VIS_OPAQUE_MODE_NONE
 * (a translucent window; n must be 0), or VIS_OPAQUE_MODE_RECTS, those inside the n rectangles
 * (window coordinates, intersected with its shape). The rectangles are copied.
 */
VIS_EXPORT uint32_t vis_client_set_opaque(struct vis_client *c, uint32_t window, uint32_t mode,
					  const struct vis_rect32 *rects, uint32_t n);
VIS_EXPORT uint32_t vis_client_batch_begin(struct vis_client *c);
VIS_EXPORT uint32_t vis_client_batch_commit(struct vis_client *c);
/*
 * Asks for notices about window (VIS_WINDOW_ALL, 0: every window the connection may see, now
 * and later), delivered to the notice handler: mask is a set of enum vis_notice_mask bits
 * (VIS_NOTICE_VISIBILITY 1, VIS_NOTICE_EXPOSURE 2, VIS_NOTICE_STACK 4); rect_limit is the most
 * rectangles an exposure notice carries before it is collapsed to their bounding box (0: 25, as
 * X). Subscribing again with the same window replaces the subscription. A mask of 0 or an
 * unknown bit gets a value error, a window the connection may not see a window error.
 */
VIS_EXPORT uint32_t vis_client_subscribe(struct vis_client *c, uint32_t window, uint32_t mask,
					 uint32_t rect_limit);
/* Ends the subscription made with the same window argument (a value error if there is none). */
VIS_EXPORT uint32_t vis_client_unsubscribe(struct vis_client *c, uint32_t window);

/*
 * Asynchronous requests with a reply. The callback runs from dispatch (or from a synchronous
 * call's wait) with the reply, or with err set (then the other arguments are empty) when the
 * request failed; err is NULL on success. Return the request's number, 0 on failure (the callback
 * is then never called). Arrays passed to callbacks are valid only during the call.
 */
typedef void (*vis_create_cb)(void *data, const struct vis_error *err, uint32_t window);
typedef void (*vis_state_cb)(void *data, const struct vis_error *err, uint32_t window,
			     uint32_t state);
typedef void (*vis_states_cb)(void *data, const struct vis_error *err,
			      const struct vis_window_state *states, size_t n);
typedef void (*vis_tree_cb)(void *data, const struct vis_error *err,
			    const struct vis_window_info *windows, size_t n);
typedef void (*vis_rects_cb)(void *data, const struct vis_error *err,
			     const struct vis_rect32 *rects, size_t n);
typedef void (*vis_windows_cb)(void *data, const struct vis_error *err, const uint32_t *windows,
			       size_t n);
typedef void (*vis_done_cb)(void *data, const struct vis_error *err);

/*
 * A window's look as get-look gives it: shaped 0 (its pixels are its border box) or 1 (the union of
 * shape[0 … n_shape), window coordinates, clipped to the border box); mode an enum
 * vis_opaque_mode, with opaque[0 … n_opaque) for VIS_OPAQUE_MODE_RECTS. The border is in
 * vis_window_info.
 */
struct vis_look_info {
	uint32_t window;
	uint32_t shaped, mode;
	uint32_t n_shape, n_opaque;
	struct vis_rect32 *shape, *opaque;
};
typedef void (*vis_look_cb)(void *data, const struct vis_error *err,
			    const struct vis_look_info *look);

/*
 * Creates a window under parent (VIS_WINDOW_ROOT: the screen), its border box's corner at x, y
 * (parent coordinates: relative to the parent's inside), its inside width × height, with a border
 * of border pixels (X's border_width; 0 for VIS_CREATE_INPUT_ONLY windows); flags are enum
 * vis_create_flags. vis_client_create_async() is this with border 0.
 */
VIS_EXPORT uint32_t vis_client_create_window_async(struct vis_client *c, uint32_t parent,
						   int32_t x, int32_t y, uint32_t width,
						   uint32_t height, uint32_t border, uint32_t flags,
						   vis_create_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_create_async(struct vis_client *c, uint32_t parent, int32_t x,
					    int32_t y, uint32_t width, uint32_t height,
					    uint32_t flags, vis_create_cb cb, void *data);
/*
 * As vis_client_create_window_async(), the window carrying the external ID (ext_namespace, an enum
 * vis_external_namespace other than VIS_EXTERNAL_NONE, and external, e.g. an XID): what it
 * mirrors, kept for its life and found by vis_client_lookup(). Only the manager may set one
 * (access error otherwise); a pair another window carries gets a match error, external ≠ 0 with
 * VIS_EXTERNAL_NONE a value error. The other create functions send none (0, 0).
 */
VIS_EXPORT uint32_t vis_client_create_external_async(struct vis_client *c, uint32_t parent,
						     int32_t x, int32_t y, uint32_t width,
						     uint32_t height, uint32_t border,
						     uint32_t flags, uint32_t ext_namespace,
						     uint64_t external, vis_create_cb cb,
						     void *data);
/*
 * Finds the window carrying the external ID (ext_namespace, external): cb gets its ID. A window
 * error when no window the connection may see carries it (a client sees only its own, so an
 * application looks up its X window with the observer role), a value error for
 * VIS_EXTERNAL_NONE.
 */
VIS_EXPORT uint32_t vis_client_lookup_async(struct vis_client *c, uint32_t ext_namespace,
					    uint64_t external, vis_create_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_get_state_async(struct vis_client *c, uint32_t window,
					       vis_state_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_get_states_async(struct vis_client *c, vis_states_cb cb,
						void *data);
VIS_EXPORT uint32_t vis_client_get_tree_async(struct vis_client *c, vis_tree_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_get_region_async(struct vis_client *c, uint32_t window,
						vis_rects_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_get_repaint_async(struct vis_client *c, struct vis_rect32 damage,
						 vis_windows_cb cb, void *data);
VIS_EXPORT uint32_t vis_client_sync_async(struct vis_client *c, vis_done_cb cb, void *data);
/* The window's shape and opaque region (look is NULL with err). */
VIS_EXPORT uint32_t vis_client_get_look_async(struct vis_client *c, uint32_t window,
					      vis_look_cb cb, void *data);

/*
 * Synchronous forms: send, then block until the reply. Between batch-begin and batch-commit the
 * daemon holds every request, so these (and vis_client_roundtrip/sync) fail at once with errno
 * EDEADLK, sending nothing; use the asynchronous forms there. Return 0, or -1 when the request
 * failed (a protocol error: see vis_client_last_error()) or the connection did
 * (vis_client_error()).
 * Arrays are allocated with malloc; the caller frees them.
 */
VIS_EXPORT int vis_client_create_window(struct vis_client *c, uint32_t parent, int32_t x,
					int32_t y, uint32_t width, uint32_t height, uint32_t border,
					uint32_t flags, uint32_t *window);
VIS_EXPORT int vis_client_create(struct vis_client *c, uint32_t parent, int32_t x, int32_t y,
				 uint32_t width, uint32_t height, uint32_t flags,
				 uint32_t *window);
VIS_EXPORT int vis_client_create_external(struct vis_client *c, uint32_t parent, int32_t x,
					  int32_t y, uint32_t width, uint32_t height,
					  uint32_t border, uint32_t flags, uint32_t ext_namespace,
					  uint64_t external, uint32_t *window);
/* Fills *window with the window carrying the external ID. */
VIS_EXPORT int vis_client_lookup(struct vis_client *c, uint32_t ext_namespace, uint64_t external,
				 uint32_t *window);
VIS_EXPORT int vis_client_get_state(struct vis_client *c, uint32_t window, uint32_t *state);
VIS_EXPORT int vis_client_get_states(struct vis_client *c, struct vis_window_state **states,
				     size_t *n);
VIS_EXPORT int vis_client_get_tree(struct vis_client *c, struct vis_window_info **windows,
				   size_t *n);
VIS_EXPORT int vis_client_get_region(struct vis_client *c, uint32_t window,
				     struct vis_rect32 **rects, size_t *n);
VIS_EXPORT int vis_client_get_repaint(struct vis_client *c, struct vis_rect32 damage,
				      uint32_t **windows, size_t *n);
/* Fills *look; look->shape and look->opaque are malloc'd (NULL when empty): the caller frees them. */
VIS_EXPORT int vis_client_get_look(struct vis_client *c, uint32_t window,
				   struct vis_look_info *look);
/* Sends sync and waits for its reply; returns -1 if the connection failed or if any request
 * since the previous vis_client_sync() got an error. */
VIS_EXPORT int vis_client_sync(struct vis_client *c);

/* Names for logs and tools: "unobscured", "partially-obscured", "fully-obscured", "none",
 * "initial" (a previous state only). */
VIS_EXPORT const char *vis_visibility_name(uint32_t state);
/* An error code's name ("window", "access", …) and a request's ("create", …); "?" if unknown. */
VIS_EXPORT const char *vis_error_code_name(uint32_t code);
VIS_EXPORT const char *vis_request_name(uint32_t opcode);

#ifdef __cplusplus
}
#endif

#endif
