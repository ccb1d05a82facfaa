/*
 * The operations: each step is one thing a user (or a client) does to the desktop, drawn from
 * the seed. Requests on managed top-levels go through the window manager as a client's would
 * (ConfigureRequest, MapRequest, the ICCCM and EWMH client messages to the root); the
 * override-redirect windows and the subwindows of our own top-levels are changed directly. The
 * choice depends only on the seed and the model of what the operations asked for (struct top's
 * state), never on what the WM made of it, so a seed gives the same operations on every run.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <xcb/shape.h>

#include "x11-desk.h"
#include "xorg-shape.h"

enum op {
	OP_MOVE,
	OP_RESIZE,
	OP_RAISE,
	OP_LOWER,
	OP_ACTIVATE,
	OP_RESTACK,
	OP_ICONIFY,
	OP_DEICONIFY,
	OP_WITHDRAW,
	OP_MAP,
	OP_REPLACE,
	OP_SHAPE,
	OP_KID_MOVE,
	OP_OPACITY,
	OP_OPAQUE_REGION,
	OP_OR_MOVE,
	OP_OR_RESIZE,
	OP_OR_RAISE,
	OP_OR_MAP,
	OP_OR_UNMAP,
	OP_COUNT
};

const char *const ops_kind_names[] = {
	"move",	    "resize",	"raise",     "lower",	  "activate", "restack",
	"iconify",  "deiconify", "withdraw", "map",	  "replace",  "shape",
	"kid-move", "opacity",	"opaque-region", "or-move", "or-resize", "or-raise",
	"or-map",   "or-unmap",
	NULL,
};

_Static_assert(sizeof ops_kind_names / sizeof *ops_kind_names == OP_COUNT + 1, "a name per op");

#define ICONIC_STATE 3 /* WM_CHANGE_STATE's IconicState (ICCCM 4.1.4) */
#define SOURCE_PAGER 2 /* EWMH source indication: a pager, which the WM obeys */

/* Whether the operation can apply to top t as the model has it. */
static bool eligible(enum op op, const struct top *t)
{
	switch (op) {
	case OP_DEICONIFY:
		return t->state == TOP_ICONIC;
	case OP_MAP:
		return t->state == TOP_WITHDRAWN;
	case OP_REPLACE:
		return t->ours;
	case OP_SHAPE:
		return t->ours;
	case OP_KID_MOVE:
		return t->ours && t->n_kids > 0;
	case OP_OPAQUE_REGION:
		return t->ours;
	default:
		return t->state == TOP_NORMAL;
	}
}

/* A client message to the root, as the EWMH and ICCCM have clients ask the WM. */
static void to_root(struct desk *d, xcb_window_t xid, xcb_atom_t type, uint32_t d0, uint32_t d1,
		    uint32_t d2)
{
	xcb_client_message_event_t ev;
	memset(&ev, 0, sizeof ev);
	ev.response_type = XCB_CLIENT_MESSAGE;
	ev.format = 32;
	ev.window = xid;
	ev.type = type;
	ev.data.data32[0] = d0;
	ev.data.data32[1] = d1;
	ev.data.data32[2] = d2;
	xcb_send_event(d->c, 0, d->root,
		       XCB_EVENT_MASK_SUBSTRUCTURE_REDIRECT | XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY,
		       (const char *)&ev);
}

/* Withdraws a normal top-level as ICCCM 4.1.4 says: unmap, then a synthetic UnmapNotify. */
static void withdraw(struct desk *d, xcb_window_t xid)
{
	xcb_unmap_window(d->c, xid);
	xcb_unmap_notify_event_t ev;
	memset(&ev, 0, sizeof ev);
	ev.response_type = XCB_UNMAP_NOTIFY;
	ev.event = d->root;
	ev.window = xid;
	xcb_send_event(d->c, 0, d->root,
		       XCB_EVENT_MASK_SUBSTRUCTURE_REDIRECT | XCB_EVENT_MASK_SUBSTRUCTURE_NOTIFY,
		       (const char *)&ev);
}

/* The child of the root that xid is in (its WM frame), or xid itself. */
static xcb_window_t frame_of(struct desk *d, xcb_window_t xid)
{
	for (;;) {
		xcb_query_tree_reply_t *t = xcb_query_tree_reply(d->c, xcb_query_tree(d->c, xid), NULL);
		xcb_window_t parent = t != NULL ? t->parent : XCB_NONE;
		free(t);
		if (parent == XCB_NONE || parent == d->root)
			return xid;
		xid = parent;
	}
}

/*
 * Gives top t _NET_WM_WINDOW_OPACITY below 100% or takes it away, on the client window and on its
 * frame, as window managers copy it there (openbox does; the frame, a child of the root, is what
 * compositors and the bridge read).
 */
static void set_opacity(struct desk *d, struct top *t, char *what, size_t size, const char *who)
{
	xcb_window_t frame = frame_of(d, t->xid);
	t->translucent = !t->translucent;
	uint32_t opacity = 0x40000000u + (uint32_t)vis_rng_below(&d->rng, 0xbfffffffu);
	xcb_window_t on[2] = { t->xid, frame };
	for (int i = 0; i < (frame != t->xid ? 2 : 1); i++) {
		if (t->translucent)
			xcb_change_property(d->c, XCB_PROP_MODE_REPLACE, on[i], d->atom_opacity,
					    XCB_ATOM_CARDINAL, 32, 1, &opacity);
		else
			xcb_delete_property(d->c, on[i], d->atom_opacity);
	}
	if (t->translucent)
		snprintf(what, size, "opacity 0x%x (%s, frame 0x%x): 0x%08x", t->xid, who, frame,
			 opacity);
	else
		snprintf(what, size, "opacity 0x%x (%s, frame 0x%x): none", t->xid, who, frame);
}

/* Sets a random _NET_WM_OPAQUE_REGION on top t or one of its subwindows, or takes it away. */
static void set_opaque_region(struct desk *d, struct top *t, char *what, size_t size)
{
	xcb_window_t xid = t->xid;
	uint32_t w = t->w, h = t->h;
	if (t->n_kids > 0 && vis_rng_below(&d->rng, 3) == 0) {
		xid = t->kids[vis_rng_below(&d->rng, (uint64_t)t->n_kids)];
		xcb_get_geometry_reply_t *g =
			xcb_get_geometry_reply(d->c, xcb_get_geometry(d->c, xid), NULL);
		w = g != NULL ? g->width : 10;
		h = g != NULL ? g->height : 10;
		free(g);
	}
	uint32_t kind = (uint32_t)vis_rng_below(&d->rng, 6);
	if (kind < 2) {
		xcb_delete_property(d->c, xid, d->atom_opaque_region);
		snprintf(what, size, "opaque-region 0x%x of 0x%x: none", xid, t->xid);
		return;
	}
	/* kind 2: set but empty (hides nothing); else one or two rectangles, past the edges too. */
	uint32_t n = kind == 2 ? 0 : kind == 5 ? 2 : 1, v[8];
	for (uint32_t i = 0; i < n; i++) {
		v[4 * i] = (uint32_t)vis_rng_range(&d->rng, -5, (int64_t)w);
		v[4 * i + 1] = (uint32_t)vis_rng_range(&d->rng, -5, (int64_t)h);
		v[4 * i + 2] = 1 + (uint32_t)vis_rng_below(&d->rng, w + 5);
		v[4 * i + 3] = 1 + (uint32_t)vis_rng_below(&d->rng, h + 5);
	}
	xcb_change_property(d->c, XCB_PROP_MODE_REPLACE, xid, d->atom_opaque_region,
			    XCB_ATOM_CARDINAL, 32, 4 * n, v);
	snprintf(what, size, "opaque-region 0x%x of 0x%x: %u rectangles", xid, t->xid, n);
}

/* What a top-level is, for the step's description: ours, or the client's name. */
static const char *label(const struct desk *d, const struct top *t)
{
	if (t->ours)
		return t->xid == d->argb_top ? "ours, argb" : "ours";
	for (int i = 0; i < d->n_clients; i++)
		if (d->clients[i].xid == t->xid)
			return d->clients[i].argv0;
	return "?";
}

/* A ConfigureWindow: the WM gets it as a ConfigureRequest for a managed window. */
static void configure(struct desk *d, xcb_window_t xid, uint16_t mask, const uint32_t *values)
{
	xcb_configure_window(d->c, xid, mask, values);
}

/* An operation on the override-redirect window i; returns false when it does not apply. */
static bool override_op(struct desk *d, enum op op, int i, char *what, size_t size)
{
	xcb_window_t xid = d->override[i];
	int32_t W = d->screen->width_in_pixels, H = d->screen->height_in_pixels;
	bool mapped = d->override_mapped[i];
	if ((op == OP_OR_MAP && mapped) || ((op == OP_OR_UNMAP || op == OP_OR_RAISE) && !mapped))
		return false;
	uint32_t v[2];
	switch (op) {
	case OP_OR_MOVE:
		v[0] = (uint32_t)vis_rng_range(&d->rng, -30, W - 10);
		v[1] = (uint32_t)vis_rng_range(&d->rng, -30, H - 10);
		configure(d, xid, XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y, v);
		snprintf(what, size, "or-move 0x%x to %d,%d", xid, (int32_t)v[0], (int32_t)v[1]);
		break;
	case OP_OR_RESIZE:
		v[0] = 1 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)W / 2);
		v[1] = 1 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)H / 2);
		configure(d, xid, XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT, v);
		snprintf(what, size, "or-resize 0x%x to %ux%u", xid, v[0], v[1]);
		break;
	case OP_OR_RAISE:
		v[0] = XCB_STACK_MODE_ABOVE;
		configure(d, xid, XCB_CONFIG_WINDOW_STACK_MODE, v);
		snprintf(what, size, "or-raise 0x%x", xid);
		break;
	case OP_OR_MAP:
		xcb_map_window(d->c, xid);
		d->override_mapped[i] = true;
		snprintf(what, size, "or-map 0x%x", xid);
		break;
	default:
		xcb_unmap_window(d->c, xid);
		d->override_mapped[i] = false;
		snprintf(what, size, "or-unmap 0x%x", xid);
	}
	return true;
}

/* Destroys our top-level t and makes another in its place at the end of the list. */
static void replace(struct desk *d, int i, char *what, size_t size)
{
	xcb_window_t old = d->tops[i].xid;
	xcb_destroy_window(d->c, old);
	if (d->argb_top == old)
		d->argb_top = 0;
	memmove(&d->tops[i], &d->tops[i + 1], (size_t)(d->n_tops - i - 1) * sizeof d->tops[0]);
	d->n_tops--;
	int k = build_top(d);
	snprintf(what, size, "replace 0x%x by 0x%x (%ux%u at %d,%d)", old, d->tops[k].xid,
		 d->tops[k].w, d->tops[k].h, d->tops[k].x, d->tops[k].y);
}

/* An operation on top-level i (eligible for it). */
static void top_op(struct desk *d, enum op op, int i, char *what, size_t size)
{
	struct top *t = &d->tops[i];
	int32_t W = d->screen->width_in_pixels, H = d->screen->height_in_pixels;
	const char *name = ops_kind_names[op], *who = label(d, t);
	uint32_t v[2];
	switch (op) {
	case OP_MOVE:
		t->x = (int32_t)vis_rng_range(&d->rng, -(int32_t)t->w / 3, W - (int32_t)t->w / 2);
		t->y = (int32_t)vis_rng_range(&d->rng, -(int32_t)t->h / 3, H - (int32_t)t->h / 2);
		v[0] = (uint32_t)t->x;
		v[1] = (uint32_t)t->y;
		configure(d, t->xid, XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y, v);
		snprintf(what, size, "move 0x%x (%s) to %d,%d", t->xid, who, t->x, t->y);
		return;
	case OP_RESIZE:
		t->w = v[0] = 20 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)W * 2 / 3);
		t->h = v[1] = 20 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)H * 2 / 3);
		configure(d, t->xid, XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT, v);
		snprintf(what, size, "resize 0x%x (%s) to %ux%u", t->xid, who, t->w, t->h);
		return;
	case OP_RAISE:
	case OP_LOWER:
		v[0] = op == OP_RAISE ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW;
		configure(d, t->xid, XCB_CONFIG_WINDOW_STACK_MODE, v);
		break;
	case OP_ACTIVATE:
		to_root(d, t->xid, d->atoms[ATOM_NET_ACTIVE_WINDOW], SOURCE_PAGER, XCB_CURRENT_TIME, 0);
		break;
	case OP_RESTACK: {
		bool above = vis_rng_below(&d->rng, 2);
		to_root(d, t->xid, d->atoms[ATOM_NET_RESTACK_WINDOW], SOURCE_PAGER, XCB_NONE,
			above ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW);
		snprintf(what, size, "restack 0x%x (%s) %s", t->xid, who, above ? "above" : "below");
		return;
	}
	case OP_ICONIFY:
		to_root(d, t->xid, d->atoms[ATOM_WM_CHANGE_STATE], ICONIC_STATE, 0, 0);
		t->state = TOP_ICONIC;
		break;
	case OP_DEICONIFY:
	case OP_MAP:
		xcb_map_window(d->c, t->xid);
		t->state = TOP_NORMAL;
		break;
	case OP_WITHDRAW:
		withdraw(d, t->xid);
		t->state = TOP_WITHDRAWN;
		break;
	case OP_REPLACE:
		replace(d, i, what, size);
		return;
	case OP_SHAPE: {
		xcb_rectangle_t r[2];
		bool past;
		if (!d->shape)
			break;
		if (vis_rng_below(&d->rng, 3) == 0) {
			xcb_shape_mask(d->c, XCB_SHAPE_SO_SET, XCB_SHAPE_SK_BOUNDING, t->xid, 0, 0,
				       XCB_NONE);
			snprintf(what, size, "shape 0x%x (%s): none", t->xid, who);
			return;
		}
		uint32_t n = xorg_random_shape(&d->rng, t->w, t->h, 0, r, &past);
		xcb_shape_rectangles(d->c, XCB_SHAPE_SO_SET, XCB_SHAPE_SK_BOUNDING,
				     XCB_CLIP_ORDERING_UNSORTED, t->xid, 0, 0, n, r);
		snprintf(what, size, "shape 0x%x (%s): %u rectangles", t->xid, who, n);
		return;
	}
	case OP_OPACITY:
		set_opacity(d, t, what, size, who);
		return;
	case OP_OPAQUE_REGION:
		set_opaque_region(d, t, what, size);
		return;
	case OP_KID_MOVE: {
		xcb_window_t kid = t->kids[vis_rng_below(&d->rng, (uint64_t)t->n_kids)];
		v[0] = (uint32_t)vis_rng_range(&d->rng, -10, (int64_t)t->w);
		v[1] = (uint32_t)vis_rng_range(&d->rng, -10, (int64_t)t->h);
		configure(d, kid, XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y, v);
		snprintf(what, size, "kid-move 0x%x of 0x%x to %d,%d", kid, t->xid, (int32_t)v[0],
			 (int32_t)v[1]);
		return;
	}
	default:
		break;
	}
	snprintf(what, size, "%s 0x%x (%s)", name, t->xid, who);
}

const char *ops_step(struct desk *d, char *what, size_t size)
{
	for (;;) {
		enum op op = (enum op)vis_rng_below(&d->rng, OP_COUNT);
		if (op >= OP_OR_MOVE) {
			int i = (int)vis_rng_below(&d->rng, DESK_N_OVERRIDE);
			if (!override_op(d, op, i, what, size))
				continue;
			d->op_counts[op]++;
			return ops_kind_names[op];
		}
		int pick[DESK_MAX_TOPS], n = 0;
		for (int i = 0; i < d->n_tops; i++)
			if (eligible(op, &d->tops[i]))
				pick[n++] = i;
		if (n == 0)
			continue;
		top_op(d, op, pick[vis_rng_below(&d->rng, (uint64_t)n)], what, size);
		d->op_counts[op]++;
		return ops_kind_names[op];
	}
}
