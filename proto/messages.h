/*
 * Every message of the protocol, defined once. The codec (codec.c), the names in logs and
 * visctl, and the message table of PROTOCOL.md (checked by the proto-doc test) all follow from
 * this table.
 *
 * A signature is a list of fields, "TYPE:NAME" separated by spaces, each TYPE one of:
 *   u  uint32          i  int32          q  uint64
 *   s  string: uint32 length, the bytes (no NUL), zero padding to a multiple of 4
 *   aW aS aR aT  array: uint32 count, then count records of 32-bit words:
 *      W window (1 word: window), S state (2: window state),
 *      R rectangle (4: x y w h, x y signed),
 *      T tree node (12: window parent x y w h border flags state namespace external_lo
 *        external_hi: the 64-bit external ID as two words, low first)
 * Replies start with the sequence number of the request they answer; notices with their own
 * 64-bit sequence number, gapless per connection.
 */
#ifndef VIS_PROTO_MESSAGES_H
#define VIS_PROTO_MESSAGES_H

/* M(ENUM, opcode, direction, name, signature, what it does) */
#define VIS_MESSAGES(M)                                                                           \
	M(HELLO, 1, REQUEST, "hello", "u:magic u:version u:role",                                 \
	  "The handshake; must come first. Asks for a role (0 client, 1 observer, 2 manager).")    \
	M(CREATE, 2, REQUEST, "create",                                                           \
	  "u:parent i:x i:y u:width u:height u:flags u:border u:namespace q:external",            \
	  "Creates a window (parent 0: the screen), unmapped unless flags has MAP; x, y place its " \
	  "border box, width x height is its inside; namespace 0 or the external ID it mirrors "   \
	  "(managers only). Replies created.")                                                     \
	M(DESTROY, 3, REQUEST, "destroy", "u:window", "Destroys a window and its descendants.")    \
	M(MAP, 4, REQUEST, "map", "u:window", "Maps a window.")                                   \
	M(UNMAP, 5, REQUEST, "unmap", "u:window", "Unmaps a window.")                             \
	M(MOVE, 6, REQUEST, "move", "u:window i:x i:y", "Moves a window (parent coordinates).")    \
	M(RESIZE, 7, REQUEST, "resize", "u:window u:width u:height", "Resizes a window.")         \
	M(RAISE, 8, REQUEST, "raise", "u:window", "Puts a window above its siblings.")            \
	M(LOWER, 9, REQUEST, "lower", "u:window", "Puts a window below its siblings.")            \
	M(RESTACK, 10, REQUEST, "restack", "u:window u:mode u:sibling",                           \
	  "Stacks a window just above (mode 0) or below (mode 1) a sibling.")                     \
	M(REPARENT, 11, REQUEST, "reparent", "u:window u:parent i:x i:y",                         \
	  "Moves a window under a new parent (0: the screen), on top of its new siblings.")       \
	M(BATCH_BEGIN, 12, REQUEST, "batch-begin", "",                                            \
	  "Holds this connection's requests until batch-commit.")                                 \
	M(BATCH_COMMIT, 13, REQUEST, "batch-commit", "",                                          \
	  "Applies the held requests in order, with one recompute.")                              \
	M(SUBSCRIBE, 14, REQUEST, "subscribe", "u:window u:mask u:rect_limit",                    \
	  "Asks for notices about a window (0: every window the connection may see); "            \
	  "rect_limit 0 means 25.")                                                               \
	M(UNSUBSCRIBE, 15, REQUEST, "unsubscribe", "u:window",                                    \
	  "Ends the subscription made with the same window argument.")                            \
	M(GET_STATE, 16, REQUEST, "get-state", "u:window", "Asks for one window's state.")        \
	M(GET_STATES, 17, REQUEST, "get-states", "",                                              \
	  "Asks for the state of every viewable window the connection may see.")                  \
	M(GET_TREE, 18, REQUEST, "get-tree", "",                                                  \
	  "Asks for every window the connection may see, in stacking order (pre-order).")         \
	M(GET_REGION, 19, REQUEST, "get-region", "u:window",                                      \
	  "Asks for a window's visible region, in window coordinates.")                           \
	M(GET_REPAINT, 20, REQUEST, "get-repaint", "i:x i:y u:width u:height",                    \
	  "Asks which windows show pixels of their own inside a damaged screen rectangle.")       \
	M(SYNC, 21, REQUEST, "sync", "",                                                          \
	  "A round trip: the reply comes once every effect of earlier requests has been sent.")   \
	M(CONFIGURE, 22, REQUEST, "configure", "u:window i:x i:y u:width u:height u:border",      \
	  "Moves and resizes a window and sets its border width at once.")                        \
	M(SET_SHAPE, 23, REQUEST, "set-shape", "u:window u:shaped aR:rects",                      \
	  "Sets a window's bounding shape (window coordinates; none: no pixels), or with shaped 0 " \
	  "its border box again.")                                                                \
	M(SET_OPAQUE, 24, REQUEST, "set-opaque", "u:window u:mode aR:rects",                      \
	  "Sets which pixels hide what is below: mode 0 all, 1 none, 2 the rects (window "        \
	  "coordinates).")                                                                        \
	M(GET_LOOK, 25, REQUEST, "get-look", "u:window",                                          \
	  "Asks for a window's bounding shape and opaque region.")                                \
	M(LOOKUP, 26, REQUEST, "lookup", "u:namespace q:external",                                \
	  "Finds the window carrying an external ID. Replies found.")                             \
	M(HELLO_REPLY, 64, REPLY, "hello-reply",                                                  \
	  "u:seq u:version u:client u:role u:screen_width u:screen_height u:max_request",         \
	  "Accepts the handshake; says the role granted and the largest request accepted.")       \
	M(CREATED, 65, REPLY, "created", "u:seq u:window", "The new window's ID.")                \
	M(STATE, 66, REPLY, "state", "u:seq u:window u:state", "One window's state.")             \
	M(STATES, 67, REPLY, "states", "u:seq u:more aS:windows",                                 \
	  "States, ascending window ID; more = 1 when another states reply follows.")             \
	M(TREE, 68, REPLY, "tree", "u:seq u:more aT:windows",                                     \
	  "Windows in pre-order; more = 1 when another tree reply follows.")                      \
	M(REGION, 69, REPLY, "region", "u:seq u:window u:more aR:rects",                          \
	  "Visible rectangles in window coordinates, y-x banded; more = 1 when another follows.") \
	M(REPAINT, 70, REPLY, "repaint", "u:seq u:more aW:windows",                               \
	  "Windows to repaint, bottom to top; more = 1 when another repaint reply follows.")      \
	M(SYNCED, 71, REPLY, "synced", "u:seq", "Answers sync.")                                  \
	M(LOOK, 72, REPLY, "look", "u:seq u:window u:shaped u:mode aR:shape aR:opaque",           \
	  "A window's look: shaped 1 with its shape's rectangles (0: its border box); opaque "    \
	  "mode 0 all, 1 none, 2 the opaque rectangles; window coordinates.")                     \
	M(FOUND, 73, REPLY, "found", "u:seq u:window", "The window carrying the external ID.")    \
	M(ERROR, 96, REPLY, "error", "u:seq u:opcode u:code s:message",                           \
	  "A request failed: its sequence number and opcode, the code, a reason.")                \
	M(VISIBILITY, 128, NOTICE, "visibility",                                                  \
	  "q:serial u:window u:state u:previous u:coalesced",                                     \
	  "A window's state changed, it became viewable (previous 3), or a subscription began "   \
	  "(previous 4); coalesced: how many notices this one stands for beyond itself.")         \
	M(EXPOSURE, 129, NOTICE, "exposure", "q:serial u:window u:flags u:coalesced aR:rects",    \
	  "Newly visible rectangles, window coordinates; flags 1: collapsed to the bounding box; " \
	  "coalesced: how many notices were merged into this one.")                               \
	M(STACK, 130, NOTICE, "stack",                                                            \
	  "q:serial u:change u:window u:parent i:x i:y u:width u:height u:sibling u:flags "       \
	  "u:border u:namespace q:external",                                                      \
	  "The stack changed: what, which window, its new geometry, the sibling below it, its "   \
	  "external ID.")                                                                         \
	M(OVERFLOW, 131, NOTICE, "overflow", "q:serial u:dropped u:resync",                        \
	  "The connection fell too far behind: dropped notices were lost; the next resync "       \
	  "notices restate everything its subscriptions cover.")

enum vis_msg_dir {
	VIS_DIR_REQUEST, /* client to daemon */
	VIS_DIR_REPLY,   /* daemon to client, answering one request */
	VIS_DIR_NOTICE,  /* daemon to client, unasked */
};

enum vis_opcode {
#define VIS_MSG_ENUM(e, op, dir, name, sig, doc) VIS_OP_##e = op,
	VIS_MESSAGES(VIS_MSG_ENUM)
#undef VIS_MSG_ENUM
};

#endif
