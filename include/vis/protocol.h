/*
 * The values visd's wire protocol shares with its clients: states, roles, notice kinds, error
 * codes. The messages themselves are defined once, in proto/messages.h; proto/PROTOCOL.md
 * describes both.
 */
#ifndef VIS_PROTOCOL_H
#define VIS_PROTOCOL_H

#define VIS_PROTOCOL_MAGIC 0x44534956u /* "VISD" in little-endian bytes */
/* 4: regions and exposures in window coordinates, from the inside's corner (3: external IDs;
 * 2: borders, shapes, opaque regions, input-only). The history is PROTOCOL.md's. */
#define VIS_PROTOCOL_VERSION 4u
/*
 * The oldest version a daemon serves: a daemon speaks every version from this one to its own, each
 * connection the one its hello asks for, byte for byte as that version was (PROTOCOL.md,
 * "Versions"); hello-reply's version is the one the connection speaks.
 */
#define VIS_PROTOCOL_OLDEST_VERSION 3u

/* Every message, either way, is at most this many bytes, header included. */
#define VIS_PROTOCOL_MAX_MESSAGE (16u << 20)
/*
 * The largest request a daemon accepts (hello-reply's max_request) is at least this many bytes,
 * room for every request of fixed size, and at most VIS_PROTOCOL_MAX_MESSAGE.
 */
#define VIS_PROTOCOL_MIN_MAX_REQUEST 64u

/* A window's visibility, numbered as X11's VisibilityNotify states. */
enum vis_visibility {
	VIS_VISIBILITY_UNOBSCURED = 0,
	VIS_VISIBILITY_PARTIALLY_OBSCURED = 1,
	VIS_VISIBILITY_FULLY_OBSCURED = 2, /* the occlusion notice: stop rendering */
	VIS_VISIBILITY_NONE = 3,           /* not viewable: unmapped, or an ancestor is */
	/* Only as a visibility notice's previous: the first notice of a new subscription, giving
	 * the window's state when it subscribed. */
	VIS_VISIBILITY_INITIAL = 4,
};

/* What a connection may see and change, asked for in the handshake. */
enum vis_role {
	VIS_ROLE_CLIENT = 0,   /* its own windows only */
	VIS_ROLE_OBSERVER = 1, /* sees every window, changes none */
	VIS_ROLE_MANAGER = 2,  /* sees and changes every window; one connection at a time */
};

/* Flags of the create request. */
enum vis_create_flags {
	VIS_CREATE_MAP = 1u << 0,    /* map at once */
	VIS_CREATE_RETAIN = 1u << 1, /* outlive the creating connection (X's RetainPermanent) */
	VIS_CREATE_INPUT_ONLY = 1u << 2, /* X's InputOnly: no pixels, no state, hides nothing; border 0 */
};

/* The most rectangles a shape or an opaque region has, so that a look reply always fits. */
#define VIS_LOOK_MAX_RECTS (1u << 18)

/* Modes of the set-opaque request: which of a window's pixels hide what lies below it. */
enum vis_opaque_mode {
	VIS_OPAQUE_MODE_ALL = 0,   /* every pixel of its shape (the default) */
	VIS_OPAQUE_MODE_NONE = 1,  /* none: a translucent window */
	VIS_OPAQUE_MODE_RECTS = 2, /* those inside the rectangles given (window coordinates) */
};

/* Namespaces of external IDs: what a window mirrors. 0: none. Others are free for private use. */
enum vis_external_namespace {
	VIS_EXTERNAL_NONE = 0,
	VIS_EXTERNAL_X11 = 1,     /* the tag is an X window ID (XID) */
	VIS_EXTERNAL_WAYLAND = 2, /* reserved for a Wayland bridge */
};

/* Which notices a subscription asks for. */
enum vis_notice_mask {
	VIS_NOTICE_VISIBILITY = 1u << 0,
	VIS_NOTICE_EXPOSURE = 1u << 1,
	VIS_NOTICE_STACK = 1u << 2,
};
#define VIS_NOTICE_ALL (VIS_NOTICE_VISIBILITY | VIS_NOTICE_EXPOSURE | VIS_NOTICE_STACK)

/* A subscription's window argument that means every window the connection may see. */
#define VIS_WINDOW_ALL 0u
/* The parent argument naming the screen (the root). */
#define VIS_WINDOW_ROOT 0u

/* The exposure rectangles a notice carries before it collapses to their bounding box (X's RECTLIMIT). */
#define VIS_EXPOSURE_RECT_LIMIT 25u
/* Set in an exposure notice's flags when the rectangles were collapsed to their bounding box. */
#define VIS_EXPOSURE_COLLAPSED 1u

/* Modes of the restack request. */
enum vis_restack_mode {
	VIS_RESTACK_ABOVE = 0,
	VIS_RESTACK_BELOW = 1,
};

/* What a stack notice reports. */
enum vis_stack_change {
	VIS_STACK_CREATE = 0,
	VIS_STACK_DESTROY = 1,
	VIS_STACK_MAP = 2,
	VIS_STACK_UNMAP = 3,
	VIS_STACK_CONFIGURE = 4, /* moved or resized */
	VIS_STACK_RESTACK = 5,   /* raised, lowered or stacked against a sibling */
	VIS_STACK_REPARENT = 6,
	VIS_STACK_RESYNC = 7, /* restated after an overflow notice: the window as it is now */
	VIS_STACK_LOOK = 8,   /* its shape or opaque region changed (flags say what it is now) */
};

/* Flags of a window in the tree reply and in stack notices. */
enum vis_window_flags {
	VIS_WINDOW_MAPPED = 1u << 0,
	VIS_WINDOW_VIEWABLE = 1u << 1,
	VIS_WINDOW_RETAINED = 1u << 2,
	/* Its parent is a window the connection may not see: parent reads 0, x and y are still
	 * relative to that parent (a client's window in a manager's frame). */
	VIS_WINDOW_PARENT_HIDDEN = 1u << 3,
	VIS_WINDOW_SHAPED = 1u << 4,      /* it has a bounding shape, not its border box */
	/* Some of its pixels (its shape within its border box) hide nothing: never for a window
	 * without pixels or an input-only one; opaque rectangles covering every pixel leave it clear. */
	VIS_WINDOW_TRANSLUCENT = 1u << 5,
	VIS_WINDOW_INPUT_ONLY = 1u << 6,  /* no pixels, no state */
};

/* Error codes. Errors marked fatal close the connection once the error is sent. */
enum vis_error_code {
	VIS_ERROR_MALFORMED = 1, /* fatal: a message that cannot be parsed */
	VIS_ERROR_OPCODE = 2,    /* fatal: an unknown opcode, or one only the daemon sends */
	VIS_ERROR_HANDSHAKE = 3, /* fatal: a wrong magic or version, or a request before hello */
	VIS_ERROR_WINDOW = 4,    /* no such window, or not one the connection may see */
	VIS_ERROR_ACCESS = 5,    /* the connection may see the window but not change it */
	VIS_ERROR_VALUE = 6,     /* an argument out of range */
	VIS_ERROR_MATCH = 7,     /* arguments that do not fit together (not siblings, a cycle, an
				  * external ID in use) */
	VIS_ERROR_LIMIT = 8,     /* a configured limit was reached */
	VIS_ERROR_STATE = 9,     /* not now: a nested batch, a commit without a batch, a taken role */
};

#endif
