/*
 * Window trees against a real X server: random trees of windows with borders, children, bounding
 * shapes (SHAPE) and InputOnly leaves are made in X and, the same, in a running visd through
 * libvisclient; every window's last VisibilityNotify state from X must be visd's state, and
 * InputOnly windows must get none from either. Shaped windows have children too: X clips them
 * to their parent's shape, and so does visd.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <xcb/shape.h>
#include <xcb/xcb.h>

#include "rng.h"
#include "vis/visclient.h"
#include "xorg-shape.h"
#include "xorg-tree.h"

#define MAX_NODES 40

struct node {
	int parent; /* index, -1: the root */
	int32_t x, y;
	uint32_t w, h, border;
	bool input_only, shaped, past_box, has_children;
	uint32_t n_shape;
	xcb_rectangle_t shape[4];
	xcb_window_t xid;
	uint32_t vid;
	int x_state; /* -1: no VisibilityNotify */
};

/* A random tree on a W×H screen: up to MAX_NODES windows, three levels deep. */
static int make_tree(struct vis_rng *rng, struct node *t, int32_t W, int32_t H)
{
	int n = 0, tops = 1 + (int)vis_rng_below(rng, 8);
	for (int i = 0; i < tops && n < MAX_NODES; i++) {
		int stack[MAX_NODES], depth_of[MAX_NODES], sp = 0;
		struct node *r = &t[n];
		memset(r, 0, sizeof *r);
		r->parent = -1;
		r->x = (int32_t)vis_rng_range(rng, -6, W);
		r->y = (int32_t)vis_rng_range(rng, -6, H);
		r->w = 1 + (uint32_t)vis_rng_below(rng, (uint64_t)W * 2 / 3);
		r->h = 1 + (uint32_t)vis_rng_below(rng, (uint64_t)H * 2 / 3);
		r->border = (uint32_t)vis_rng_below(rng, 3);
		stack[sp] = n;
		depth_of[sp++] = 1;
		n++;
		while (sp > 0 && n < MAX_NODES) {
			int p = stack[--sp], d = depth_of[sp];
			int kids = d < 3 && !t[p].input_only ? (int)vis_rng_below(rng, 4) : 0;
			for (int k = 0; k < kids && n < MAX_NODES; k++) {
				struct node *c = &t[n];
				memset(c, 0, sizeof *c);
				c->parent = p;
				t[p].has_children = true;
				c->x = (int32_t)vis_rng_range(rng, -3, (int64_t)t[p].w);
				c->y = (int32_t)vis_rng_range(rng, -3, (int64_t)t[p].h);
				c->w = 1 + (uint32_t)vis_rng_below(rng, t[p].w);
				c->h = 1 + (uint32_t)vis_rng_below(rng, t[p].h);
				c->input_only = vis_rng_below(rng, 8) == 0;
				c->border = c->input_only ? 0 : (uint32_t)vis_rng_below(rng, 3);
				stack[sp] = n;
				depth_of[sp++] = d + 1;
				n++;
			}
		}
	}
	/* Shapes: halves of the border box, a corner, nothing, or a piece past the box. */
	for (int i = 0; i < n; i++) {
		struct node *v = &t[i];
		if (v->input_only || vis_rng_below(rng, 3) != 0)
			continue;
		v->shaped = true;
		v->n_shape = xorg_random_shape(rng, v->w, v->h, v->border, v->shape, &v->past_box);
	}
	return n;
}

/* Makes the tree in X, mapped, and reads each window's last VisibilityNotify state. */
static int x_make(xcb_connection_t *c, xcb_window_t root, struct node *t, int n)
{
	for (int i = 0; i < n; i++) {
		struct node *v = &t[i];
		uint32_t values[] = { 1, XCB_EVENT_MASK_VISIBILITY_CHANGE };
		v->xid = xcb_generate_id(c);
		v->x_state = -1;
		xcb_create_window(c, v->input_only ? 0 : XCB_COPY_FROM_PARENT, v->xid,
				  v->parent < 0 ? root : t[v->parent].xid, (int16_t)v->x,
				  (int16_t)v->y, (uint16_t)v->w, (uint16_t)v->h, (uint16_t)v->border,
				  v->input_only ? XCB_WINDOW_CLASS_INPUT_ONLY
						: XCB_WINDOW_CLASS_INPUT_OUTPUT,
				  XCB_COPY_FROM_PARENT, XCB_CW_OVERRIDE_REDIRECT | XCB_CW_EVENT_MASK,
				  values);
		if (v->shaped)
			xcb_shape_rectangles(c, XCB_SHAPE_SO_SET, XCB_SHAPE_SK_BOUNDING,
					     XCB_CLIP_ORDERING_UNSORTED, v->xid, 0, 0, v->n_shape,
					     v->shape);
	}
	for (int i = 0; i < n; i++)
		xcb_map_window(c, t[i].xid);
	free(xcb_get_input_focus_reply(c, xcb_get_input_focus(c), NULL));
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(c))) {
		if ((ev->response_type & 0x7f) == XCB_VISIBILITY_NOTIFY) {
			xcb_visibility_notify_event_t *e = (void *)ev;
			for (int i = 0; i < n; i++)
				if (t[i].xid == e->window)
					t[i].x_state = e->state;
		}
		free(ev);
	}
	return xcb_connection_has_error(c) ? -1 : 0;
}

static void x_destroy(xcb_connection_t *c, struct node *t, int n)
{
	for (int i = 0; i < n; i++)
		if (t[i].parent < 0)
			xcb_destroy_window(c, t[i].xid);
	free(xcb_get_input_focus_reply(c, xcb_get_input_focus(c), NULL));
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(c)))
		free(ev);
}

/* Makes the tree in visd, mapped; returns 0, or -1. */
static int visd_make(struct vis_client *v, struct node *t, int n)
{
	for (int i = 0; i < n; i++) {
		struct node *w = &t[i];
		if (vis_client_create_window(v, w->parent < 0 ? VIS_WINDOW_ROOT : t[w->parent].vid, w->x,
					     w->y, w->w, w->h, w->border,
					     VIS_CREATE_MAP | (w->input_only ? VIS_CREATE_INPUT_ONLY : 0),
					     &w->vid) < 0)
			return -1;
		if (w->shaped) {
			struct vis_rect32 r[4];
			for (uint32_t k = 0; k < w->n_shape; k++)
				r[k] = (struct vis_rect32){ w->shape[k].x, w->shape[k].y, w->shape[k].width,
							    w->shape[k].height };
			vis_client_set_shape(v, w->vid, 1, r, w->n_shape);
		}
	}
	return vis_client_sync(v);
}

int xorg_trees(xcb_connection_t *c, xcb_window_t root, int32_t W, int32_t H, const char *sock,
	       unsigned long count, unsigned long seed0, unsigned long *quirks)
{
	struct vis_client *v = vis_client_connect(sock, VIS_ROLE_MANAGER);
	if (vis_client_error(v)) {
		fprintf(stderr, "test-xorg: cannot reach visd at %s\n", sock);
		vis_client_destroy(v);
		return -1;
	}
	int failed = 0;
	for (unsigned long k = 0; k < count; k++) {
		struct vis_rng rng = { seed0 + k };
		struct node t[MAX_NODES];
		int n = make_tree(&rng, t, W, H);
		uint32_t *state = calloc((size_t)n, sizeof *state);
		if (!state || x_make(c, root, t, n) < 0 || visd_make(v, t, n) < 0) {
			fprintf(stderr, "test-xorg: tree seed %lu: X or visd failed\n", seed0 + k);
			free(state);
			failed++;
			break;
		}
		struct vis_window_info *info;
		size_t ni;
		if (vis_client_get_tree(v, &info, &ni) < 0 || ni != (size_t)n) {
			fprintf(stderr, "test-xorg: tree seed %lu: visd's tree\n", seed0 + k);
			failed++;
			free(state);
			break;
		}
		for (int i = 0; i < n; i++)
			for (size_t q = 0; q < ni; q++)
				if (info[q].window == t[i].vid)
					state[i] = info[q].state;
		free(info);
		bool bad = false;
		for (int i = 0; i < n && !bad; i++) {
			int want = t[i].x_state < 0 ? VIS_VISIBILITY_NONE : t[i].x_state;
			if (want == VIS_VISIBILITY_PARTIALLY_OBSCURED &&
			    state[i] == VIS_VISIBILITY_UNOBSCURED && t[i].past_box) {
				++*quirks;
				continue;
			}
			if (state[i] == (uint32_t)want)
				continue;
			bad = true;
			fprintf(stderr,
				"test-xorg: tree seed %lu: window %d (parent %d, %d,%d %ux%u border %u%s%s): "
				"X says %d, visd %u\n",
				seed0 + k, i, t[i].parent, t[i].x, t[i].y, t[i].w, t[i].h, t[i].border,
				t[i].input_only ? ", input-only" : "", t[i].shaped ? ", shaped" : "", want,
				state[i]);
		}
		failed += bad;
		free(state);
		x_destroy(c, t, n);
		for (int i = 0; i < n; i++)
			if (t[i].parent < 0)
				vis_client_destroy_window(v, t[i].vid);
		if (vis_client_sync(v) < 0) {
			failed++;
			break;
		}
	}
	vis_client_destroy(v);
	return failed;
}
