/*
 * libvisclient's typed requests: each one fills the arguments of its message (messages.h) and
 * hands them to vis_client_send; the synchronous forms wait for the reply with vis_client_wait.
 * Also the names of states, error codes and requests, for logs and tools.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "visclient-private.h"

/* Sends a request whose only argument is a window and which has no reply. */
static uint32_t send_window(struct vis_client *c, uint32_t opcode, uint32_t window)
{
	union vis_arg a[1] = { { .u = window } };
	return vis_client_send(c, opcode, a, NULL);
}

uint32_t vis_client_destroy_window(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_DESTROY, window);
}

uint32_t vis_client_map(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_MAP, window);
}

uint32_t vis_client_unmap(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_UNMAP, window);
}

uint32_t vis_client_move(struct vis_client *c, uint32_t window, int32_t x, int32_t y)
{
	union vis_arg a[3] = { { .u = window }, { .i = x }, { .i = y } };
	return vis_client_send(c, VIS_OP_MOVE, a, NULL);
}

uint32_t vis_client_resize(struct vis_client *c, uint32_t window, uint32_t width, uint32_t height)
{
	union vis_arg a[3] = { { .u = window }, { .u = width }, { .u = height } };
	return vis_client_send(c, VIS_OP_RESIZE, a, NULL);
}

uint32_t vis_client_raise(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_RAISE, window);
}

uint32_t vis_client_lower(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_LOWER, window);
}

uint32_t vis_client_restack(struct vis_client *c, uint32_t window, uint32_t mode, uint32_t sibling)
{
	union vis_arg a[3] = { { .u = window }, { .u = mode }, { .u = sibling } };
	return vis_client_send(c, VIS_OP_RESTACK, a, NULL);
}

uint32_t vis_client_reparent(struct vis_client *c, uint32_t window, uint32_t parent, int32_t x,
			     int32_t y)
{
	union vis_arg a[4] = { { .u = window }, { .u = parent }, { .i = x }, { .i = y } };
	return vis_client_send(c, VIS_OP_REPARENT, a, NULL);
}

uint32_t vis_client_batch_begin(struct vis_client *c)
{
	/* Held with the batch: the daemon wakes once for all of it, at the commit. */
	int was = c->in_batch;
	c->in_batch = 1;
	uint32_t seq = vis_client_send(c, VIS_OP_BATCH_BEGIN, NULL, NULL);
	if (!seq)
		c->in_batch = was;
	return seq;
}

uint32_t vis_client_batch_commit(struct vis_client *c)
{
	uint32_t seq = vis_client_send(c, VIS_OP_BATCH_COMMIT, NULL, NULL);
	if (seq) {
		c->in_batch = 0;
		if (vis_client_flush(c) < 0) /* the batch, written together */
			return 0;
	}
	return seq;
}

uint32_t vis_client_subscribe(struct vis_client *c, uint32_t window, uint32_t mask,
			      uint32_t rect_limit)
{
	union vis_arg a[3] = { { .u = window }, { .u = mask }, { .u = rect_limit } };
	return vis_client_send(c, VIS_OP_SUBSCRIBE, a, NULL);
}

uint32_t vis_client_unsubscribe(struct vis_client *c, uint32_t window)
{
	return send_window(c, VIS_OP_UNSUBSCRIBE, window);
}

uint32_t vis_client_create_external_async(struct vis_client *c, uint32_t parent, int32_t x,
					  int32_t y, uint32_t width, uint32_t height, uint32_t border,
					  uint32_t flags, uint32_t ext_namespace, uint64_t external,
					  vis_create_cb cb, void *data)
{
	union vis_arg a[9] = { { .u = parent },	       { .i = x },	{ .i = y },
			       { .u = width },	       { .u = height }, { .u = flags },
			       { .u = border },	       { .u = ext_namespace }, { .q = external } };
	struct vis_pending p = { .kind = VIS_REPLY_CREATED, .cb.create = cb, .data = data };
	return vis_client_send(c, VIS_OP_CREATE, a, &p);
}

uint32_t vis_client_create_window_async(struct vis_client *c, uint32_t parent, int32_t x,
					int32_t y, uint32_t width, uint32_t height, uint32_t border,
					uint32_t flags, vis_create_cb cb, void *data)
{
	return vis_client_create_external_async(c, parent, x, y, width, height, border, flags,
						VIS_EXTERNAL_NONE, 0, cb, data);
}

uint32_t vis_client_lookup_async(struct vis_client *c, uint32_t ext_namespace, uint64_t external,
				 vis_create_cb cb, void *data)
{
	union vis_arg a[2] = { { .u = ext_namespace }, { .q = external } };
	struct vis_pending p = { .kind = VIS_REPLY_FOUND, .cb.create = cb, .data = data };
	return vis_client_send(c, VIS_OP_LOOKUP, a, &p);
}

uint32_t vis_client_create_async(struct vis_client *c, uint32_t parent, int32_t x, int32_t y,
				 uint32_t width, uint32_t height, uint32_t flags, vis_create_cb cb,
				 void *data)
{
	return vis_client_create_window_async(c, parent, x, y, width, height, 0, flags, cb, data);
}

uint32_t vis_client_configure(struct vis_client *c, uint32_t window, int32_t x, int32_t y,
			      uint32_t width, uint32_t height, uint32_t border)
{
	union vis_arg a[6] = { { .u = window }, { .i = x },	   { .i = y },
			       { .u = width },	 { .u = height }, { .u = border } };
	return vis_client_send(c, VIS_OP_CONFIGURE, a, NULL);
}

/* set-shape and set-opaque: a window, a mode and rectangles, copied into host-order words. */
static uint32_t send_rects(struct vis_client *c, uint32_t opcode, uint32_t window, uint32_t mode,
			   const struct vis_rect32 *rects, uint32_t n)
{
	uint32_t *words = NULL;
	if (n != 0) {
		if (n > UINT32_MAX / 16 || !(words = malloc((size_t)n * 4 * sizeof(*words)))) {
			errno = ENOMEM;
			return 0;
		}
		for (uint32_t i = 0; i < n; i++) {
			words[4 * i] = (uint32_t)rects[i].x;
			words[4 * i + 1] = (uint32_t)rects[i].y;
			words[4 * i + 2] = rects[i].width;
			words[4 * i + 3] = rects[i].height;
		}
	}
	union vis_arg a[3] = { { .u = window }, { .u = mode } };
	a[2].a.words = words;
	a[2].a.n = n;
	a[2].a.raw = NULL;
	uint32_t seq = vis_client_send(c, opcode, a, NULL);
	int e = errno;
	free(words);
	errno = e;
	return seq;
}

uint32_t vis_client_set_shape(struct vis_client *c, uint32_t window, uint32_t shaped,
			      const struct vis_rect32 *rects, uint32_t n)
{
	return send_rects(c, VIS_OP_SET_SHAPE, window, shaped, rects, n);
}

uint32_t vis_client_set_opaque(struct vis_client *c, uint32_t window, uint32_t mode,
			       const struct vis_rect32 *rects, uint32_t n)
{
	return send_rects(c, VIS_OP_SET_OPAQUE, window, mode, rects, n);
}

uint32_t vis_client_get_state_async(struct vis_client *c, uint32_t window, vis_state_cb cb,
				    void *data)
{
	union vis_arg a[1] = { { .u = window } };
	struct vis_pending p = { .kind = VIS_REPLY_STATE, .window = window, .cb.state = cb,
				 .data = data };
	return vis_client_send(c, VIS_OP_GET_STATE, a, &p);
}

uint32_t vis_client_get_states_async(struct vis_client *c, vis_states_cb cb, void *data)
{
	struct vis_pending p = { .kind = VIS_REPLY_STATES, .cb.states = cb, .data = data };
	return vis_client_send(c, VIS_OP_GET_STATES, NULL, &p);
}

uint32_t vis_client_get_tree_async(struct vis_client *c, vis_tree_cb cb, void *data)
{
	struct vis_pending p = { .kind = VIS_REPLY_TREE, .cb.tree = cb, .data = data };
	return vis_client_send(c, VIS_OP_GET_TREE, NULL, &p);
}

uint32_t vis_client_get_region_async(struct vis_client *c, uint32_t window, vis_rects_cb cb,
				     void *data)
{
	union vis_arg a[1] = { { .u = window } };
	struct vis_pending p = { .kind = VIS_REPLY_REGION, .window = window, .cb.rects = cb,
				 .data = data };
	return vis_client_send(c, VIS_OP_GET_REGION, a, &p);
}

uint32_t vis_client_get_look_async(struct vis_client *c, uint32_t window, vis_look_cb cb,
				   void *data)
{
	union vis_arg a[1] = { { .u = window } };
	struct vis_pending p = { .kind = VIS_REPLY_LOOK, .window = window, .cb.look = cb,
				 .data = data };
	return vis_client_send(c, VIS_OP_GET_LOOK, a, &p);
}

uint32_t vis_client_get_repaint_async(struct vis_client *c, struct vis_rect32 damage,
				      vis_windows_cb cb, void *data)
{
	union vis_arg a[4] = { { .i = damage.x }, { .i = damage.y }, { .u = damage.width },
			       { .u = damage.height } };
	struct vis_pending p = { .kind = VIS_REPLY_REPAINT, .cb.windows = cb, .data = data };
	return vis_client_send(c, VIS_OP_GET_REPAINT, a, &p);
}

uint32_t vis_client_sync_async(struct vis_client *c, vis_done_cb cb, void *data)
{
	struct vis_pending p = { .kind = VIS_REPLY_SYNCED, .cb.done = cb, .data = data };
	return vis_client_send(c, VIS_OP_SYNC, NULL, &p);
}

/*
 * Where a synchronous call's callback leaves the answer. Arrays are copied: the ones callbacks
 * get live only as long as the call.
 */
struct answer {
	int done, failed;
	uint32_t window, state;
	void *items; /* malloc'd: freed when the request fails */
	size_t n;
	struct vis_look_info *look; /* get-look's: the caller's, filled by on_look() */
};

/* Keeps a copy of a callback's array; a copy that cannot be made fails the call. */
static void keep(struct answer *a, const struct vis_error *err, const void *items, size_t n,
		 size_t size)
{
	a->done = 1;
	a->failed = err != NULL;
	if (err || !n)
		return;
	a->items = malloc(n * size);
	if (!a->items) {
		a->failed = 1;
		return;
	}
	memcpy(a->items, items, n * size);
	a->n = n;
}

/* Called with a created or found reply. */
static void on_created(void *data, const struct vis_error *err, uint32_t window)
{
	struct answer *a = data;
	a->done = 1;
	a->failed = err != NULL;
	a->window = window;
}

/* Called with a state reply. */
static void on_state(void *data, const struct vis_error *err, uint32_t window, uint32_t state)
{
	struct answer *a = data;
	a->done = 1;
	a->failed = err != NULL;
	a->window = window;
	a->state = state;
}

/* Called with the states reply. */
static void on_states(void *data, const struct vis_error *err,
		      const struct vis_window_state *states, size_t n)
{
	keep(data, err, states, n, sizeof(*states));
}

/* Called with the tree reply. */
static void on_tree(void *data, const struct vis_error *err, const struct vis_window_info *windows,
		    size_t n)
{
	keep(data, err, windows, n, sizeof(*windows));
}

/* Called with the region reply. */
static void on_rects(void *data, const struct vis_error *err, const struct vis_rect32 *rects,
		     size_t n)
{
	keep(data, err, rects, n, sizeof(*rects));
}

/* Called with a look reply: keeps copies of its arrays in the caller's vis_look_info. */
static void on_look(void *data, const struct vis_error *err, const struct vis_look_info *l)
{
	struct answer *a = data;
	struct vis_look_info *out = a->look;
	a->done = 1;
	a->failed = err != NULL;
	if (err)
		return;
	*out = *l;
	out->shape = out->opaque = NULL;
	size_t size = sizeof(*l->shape);
	if ((l->n_shape && !(out->shape = malloc(l->n_shape * size))) ||
	    (l->n_opaque && !(out->opaque = malloc(l->n_opaque * size)))) {
		free(out->shape);
		free(out->opaque);
		out->shape = out->opaque = NULL;
		a->failed = 1;
		return;
	}
	if (l->n_shape)
		memcpy(out->shape, l->shape, l->n_shape * size);
	if (l->n_opaque)
		memcpy(out->opaque, l->opaque, l->n_opaque * size);
}

/* Called with the repaint reply. */
static void on_windows(void *data, const struct vis_error *err, const uint32_t *windows, size_t n)
{
	keep(data, err, windows, n, sizeof(*windows));
}

/* Waits for the answer of request seq (0: it was not sent); 0 when it came and did not fail. */
static int await(struct vis_client *c, uint32_t seq, struct answer *a)
{
	if (!seq || vis_client_wait(c, &a->done) < 0 || a->failed) {
		free(a->items);
		a->items = NULL;
		a->n = 0;
		return -1;
	}
	return 0;
}

int vis_client_create_external(struct vis_client *c, uint32_t parent, int32_t x, int32_t y,
			       uint32_t width, uint32_t height, uint32_t border, uint32_t flags,
			       uint32_t ext_namespace, uint64_t external, uint32_t *window)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_create_external_async(c, parent, x, y, width, height, border, flags,
						      ext_namespace, external, on_created, &a),
		  &a) < 0)
		return -1;
	*window = a.window;
	return 0;
}

int vis_client_create_window(struct vis_client *c, uint32_t parent, int32_t x, int32_t y,
			     uint32_t width, uint32_t height, uint32_t border, uint32_t flags,
			     uint32_t *window)
{
	return vis_client_create_external(c, parent, x, y, width, height, border, flags,
					  VIS_EXTERNAL_NONE, 0, window);
}

int vis_client_lookup(struct vis_client *c, uint32_t ext_namespace, uint64_t external,
		      uint32_t *window)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_lookup_async(c, ext_namespace, external, on_created, &a), &a) < 0)
		return -1;
	*window = a.window;
	return 0;
}

int vis_client_create(struct vis_client *c, uint32_t parent, int32_t x, int32_t y, uint32_t width,
		      uint32_t height, uint32_t flags, uint32_t *window)
{
	return vis_client_create_window(c, parent, x, y, width, height, 0, flags, window);
}

int vis_client_get_state(struct vis_client *c, uint32_t window, uint32_t *state)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_state_async(c, window, on_state, &a), &a) < 0)
		return -1;
	*state = a.state;
	return 0;
}

int vis_client_get_states(struct vis_client *c, struct vis_window_state **states, size_t *n)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_states_async(c, on_states, &a), &a) < 0)
		return -1;
	*states = a.items;
	*n = a.n;
	return 0;
}

int vis_client_get_tree(struct vis_client *c, struct vis_window_info **windows, size_t *n)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_tree_async(c, on_tree, &a), &a) < 0)
		return -1;
	*windows = a.items;
	*n = a.n;
	return 0;
}

int vis_client_get_region(struct vis_client *c, uint32_t window, struct vis_rect32 **rects,
			  size_t *n)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_region_async(c, window, on_rects, &a), &a) < 0)
		return -1;
	*rects = a.items;
	*n = a.n;
	return 0;
}

int vis_client_get_repaint(struct vis_client *c, struct vis_rect32 damage, uint32_t **windows,
			   size_t *n)
{
	struct answer a = { 0 };
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_repaint_async(c, damage, on_windows, &a), &a) < 0)
		return -1;
	*windows = a.items;
	*n = a.n;
	return 0;
}

const char *vis_visibility_name(uint32_t state)
{
	static const char *const names[] = { "unobscured", "partially-obscured", "fully-obscured",
					     "none", "initial" };
	return state < sizeof(names) / sizeof(names[0]) ? names[state] : "?";
}

const char *vis_error_code_name(uint32_t code)
{
	static const char *const names[] = { NULL,     "malformed", "opcode", "handshake", "window",
					     "access", "value",	    "match",  "limit",	   "state" };
	return code && code < sizeof(names) / sizeof(names[0]) ? names[code] : "?";
}

const char *vis_request_name(uint32_t opcode)
{
	const struct vis_msg_type *t = vis_msg_type_find(opcode);
	return t && t->dir == VIS_DIR_REQUEST ? t->name : "?";
}

int vis_client_get_look(struct vis_client *c, uint32_t window, struct vis_look_info *look)
{
	struct answer a = { .look = look };
	memset(look, 0, sizeof(*look));
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (await(c, vis_client_get_look_async(c, window, on_look, &a), &a) < 0)
		return -1;
	return 0;
}
