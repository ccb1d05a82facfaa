/* The requests: checks of rights and arguments, the change to the tree, the reply. */
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "radix.h"
#include "server.h"
#include "vis/protocol.h"

/* Records per list reply: well under the message maximum for the largest record (48 bytes). */
#define CHUNK_RECORDS 16384u

/* Looks up a window argument the connection may see; sends WINDOW and returns NULL otherwise. */
static struct vis_window *window_arg(struct client *c, uint32_t seq, uint32_t op, uint32_t id)
{
	struct vis_window *w = vis_wtree_find(&c->server->vis->core, id);
	if (!w || !server_may_see(c, w)) {
		server_client_error(c, seq, op, VIS_ERROR_WINDOW, "no such window %u", id);
		return NULL;
	}
	return w;
}

/* As window_arg(), for a window the request changes (ACCESS when it may only see it). */
static struct vis_window *changeable_arg(struct client *c, uint32_t seq, uint32_t op, uint32_t id)
{
	struct vis_window *w = window_arg(c, seq, op, id);
	if (w && !server_may_change(c, w)) {
		server_client_error(c, seq, op, VIS_ERROR_ACCESS, "window %u is not yours to change%s",
				    id, c->role == VIS_ROLE_OBSERVER ? " (observers change nothing)" : "");
		return NULL;
	}
	return w;
}

/* A parent argument: 0 for the screen, else a window the connection may change. */
static struct vis_window *parent_arg(struct client *c, uint32_t seq, uint32_t op, uint32_t id)
{
	if (id == VIS_WINDOW_ROOT) {
		if (c->role == VIS_ROLE_OBSERVER) {
			server_client_error(c, seq, op, VIS_ERROR_ACCESS, "observers change nothing");
			return NULL;
		}
		return &c->server->vis->core.root;
	}
	return changeable_arg(c, seq, op, id);
}

/* Checks a width or height: 1 … INT32_MAX. */
static bool size_ok(struct client *c, uint32_t seq, uint32_t op, uint32_t w, uint32_t h)
{
	if (w >= 1 && h >= 1 && w <= INT32_MAX && h <= INT32_MAX)
		return true;
	server_client_error(c, seq, op, VIS_ERROR_VALUE,
			    "size %ux%u: width and height must be 1 to 2147483647", w, h);
	return false;
}

/*
 * Checks a border width for a window of width × height: the border box's sides within INT32_MAX,
 * none for an input-only window (X's BadMatch).
 */
static bool border_ok(struct client *c, uint32_t seq, uint32_t op, const struct vis_window *w,
		      uint32_t width, uint32_t height, uint32_t border)
{
	if (border != 0 && w != NULL && w->look.input_only) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "window %u is input-only: it has no border", w->id);
		return false;
	}
	if ((uint64_t)width + 2 * (uint64_t)border > INT32_MAX ||
	    (uint64_t)height + 2 * (uint64_t)border > INT32_MAX) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE,
				    "border %u: the border box of a %ux%u window would be wider or "
				    "taller than 2147483647",
				    border, width, height);
		return false;
	}
	return true;
}

/*
 * Checks create's external ID: none (namespace 0, tag 0), or one only the manager may set (what a
 * window mirrors is the bridge's to say) and no window carries already.
 */
static bool external_ok(struct client *c, uint32_t seq, uint32_t ns, uint64_t tag)
{
	uint32_t op = VIS_OP_CREATE;
	if (!ns && tag) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE,
				    "external ID %#llx without a namespace (namespace 0 takes 0)",
				    (unsigned long long)tag);
		return false;
	}
	if (ns && c->role != VIS_ROLE_MANAGER) {
		server_client_error(c, seq, op, VIS_ERROR_ACCESS,
				    "only the manager sets external IDs (namespace %u)", ns);
		return false;
	}
	struct vis_window *other = vis_wtree_find_external(&c->server->vis->core, ns, tag);
	if (other) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "external ID %u:%#llx is window %u's", ns,
				    (unsigned long long)tag, other->id);
		return false;
	}
	return true;
}

static void changed(struct client *c, struct vis_window *w, uint32_t change)
{
	server_notify_stack(c->server, w, change);
	server_damage(c->server, w);
}

static void do_hello(struct client *c, uint32_t seq, const union vis_arg *a)
{
	struct server *server = c->server;
	uint32_t op = VIS_OP_HELLO;
	if (a[0].u != VIS_PROTOCOL_MAGIC) {
		server_client_error(c, seq, op, VIS_ERROR_HANDSHAKE, "not a visd client (magic %#x)",
				    a[0].u);
		return;
	}
	if (!server_compat_speaks(a[1].u)) {
		server_client_error(c, seq, op, VIS_ERROR_HANDSHAKE,
				    "protocol version %u is not supported (this daemon speaks %u to %u)",
				    a[1].u, VIS_PROTOCOL_OLDEST_VERSION, VIS_PROTOCOL_VERSION);
		return;
	}
	uint32_t role = a[2].u;
	if (role > VIS_ROLE_MANAGER) {
		server_client_error(c, seq, op, VIS_ERROR_HANDSHAKE, "unknown role %u", role);
		return;
	}
	if (role != VIS_ROLE_CLIENT && (c->restricted || c->uid != server->opt.allowed_uid)) {
		server_client_error(c, seq, op, VIS_ERROR_ACCESS, "role %s refused: %s",
				    role == VIS_ROLE_MANAGER ? "manager" : "observer",
				    c->restricted ? "clients of the restricted socket get no role"
						  : "the peer's uid is not allowed roles");
		server_client_close(c);
		return;
	}
	if (role == VIS_ROLE_MANAGER && server->manager) {
		server_client_error(c, seq, op, VIS_ERROR_STATE,
				    "the manager role is taken (client %u)", server->manager->id);
		server_client_close(c);
		return;
	}
	c->hello_done = true;
	c->role = role;
	c->version = a[1].u;
	if (role == VIS_ROLE_MANAGER)
		server->manager = c;
	union vis_arg r[7];
	r[0].u = seq;
	r[1].u = c->version;
	r[2].u = c->id;
	r[3].u = role;
	r[4].u = (uint32_t)server->vis->core.root.width;
	r[5].u = (uint32_t)server->vis->core.root.height;
	r[6].u = server->opt.max_request;
	server_client_send(c, VIS_OP_HELLO_REPLY, r);
}

static void do_create(struct client *c, uint32_t seq, const union vis_arg *a)
{
	uint32_t op = VIS_OP_CREATE;
	struct vis_window *parent = parent_arg(c, seq, op, a[0].u);
	if (!parent || !size_ok(c, seq, op, a[3].u, a[4].u))
		return;
	if (a[5].u & ~(uint32_t)(VIS_CREATE_MAP | VIS_CREATE_RETAIN | VIS_CREATE_INPUT_ONLY)) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE, "unknown flags %#x", a[5].u);
		return;
	}
	bool input_only = a[5].u & VIS_CREATE_INPUT_ONLY;
	if (input_only && a[6].u != 0) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "an input-only window has no border (border %u)", a[6].u);
		return;
	}
	if (!border_ok(c, seq, op, NULL, a[3].u, a[4].u, a[6].u) || !external_ok(c, seq, a[7].u, a[8].q))
		return;
	const struct server_options *opt = &c->server->opt;
	if (c->n_windows >= opt->max_windows) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "this connection owns %u windows, the limit (visd --max-windows)",
				    c->n_windows);
		return;
	}
	if (parent->depth + 1 > opt->max_depth) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "a window under %u would be %u deep, past the limit of %u "
				    "(visd --max-depth)",
				    parent->id, parent->depth + 1, opt->max_depth);
		return;
	}
	bool retain = a[5].u & VIS_CREATE_RETAIN;
	if (retain && !server_quota_may_retain(c, seq))
		return;
	struct vis_window *w = vis_wtree_create(&c->server->vis->core, parent, a[1].i, a[2].i,
						(int32_t)a[3].u, (int32_t)a[4].u, c->id);
	/* The pair was checked to be free: setting it fails only when memory runs out. */
	if (w && ((a[7].u && vis_wtree_set_external(&c->server->vis->core, w, a[7].u, a[8].q) < 0) ||
		  server_wrap_window(c->server, w) < 0)) {
		vis_wtree_destroy(&c->server->vis->core, w, NULL, NULL);
		w = NULL;
		errno = ENOMEM;
	}
	if (!w || (retain && server_quota_retain(c, w) < 0)) {
		if (w) /* nobody has heard of it yet */
			server_discard_window(c->server, w);
		server_client_error(c, seq, op, VIS_ERROR_LIMIT, "cannot create a window: %s",
				    !w && errno == EOVERFLOW ? "window IDs are exhausted"
							     : "out of memory");
		return;
	}
	c->n_windows++;
	vis_wtree_set_border(w, (int32_t)a[6].u); /* checked above: cannot fail */
	if (input_only)
		vis_wtree_set_input_only(w);
	changed(c, w, VIS_STACK_CREATE);
	server_track(w, c->server); /* wanted: from nothing, all it will show is exposed */
	if (a[5].u & VIS_CREATE_MAP) {
		w->mapped = true;
		changed(c, w, VIS_STACK_MAP);
	}
	/* The window's notices precede the reply: an unmapped one has none but its stack notice. */
	if (w->mapped)
		server_flush(c->server);
	union vis_arg r[2] = { { .u = seq }, { .u = w->id } };
	server_client_send(c, VIS_OP_CREATED, r);
}

/* The stack changes that take one window: destroy, map, unmap, raise, lower. */
static void do_simple(struct client *c, uint32_t seq, uint32_t op, uint32_t id)
{
	struct vis_window *w = changeable_arg(c, seq, op, id);
	if (!w)
		return;
	switch (op) {
	case VIS_OP_DESTROY:
		server_destroy_window(c->server, w);
		break;
	case VIS_OP_MAP:
	case VIS_OP_UNMAP:
		if (w->mapped != (op == VIS_OP_MAP)) {
			w->mapped = op == VIS_OP_MAP;
			changed(c, w, w->mapped ? VIS_STACK_MAP : VIS_STACK_UNMAP);
		}
		break;
	case VIS_OP_RAISE:
		vis_wtree_raise(w);
		changed(c, w, VIS_STACK_RESTACK);
		break;
	case VIS_OP_LOWER:
		vis_wtree_lower(w);
		changed(c, w, VIS_STACK_RESTACK);
		break;
	}
}

static void do_configure(struct client *c, uint32_t seq, uint32_t op, const union vis_arg *a)
{
	struct vis_window *w = changeable_arg(c, seq, op, a[0].u);
	if (!w)
		return;
	uint32_t width = op == VIS_OP_MOVE ? (uint32_t)w->width : a[op == VIS_OP_RESIZE ? 1 : 3].u;
	uint32_t height = op == VIS_OP_MOVE ? (uint32_t)w->height : a[op == VIS_OP_RESIZE ? 2 : 4].u;
	uint32_t border = op == VIS_OP_CONFIGURE ? a[5].u : (uint32_t)w->look.border;
	if (op != VIS_OP_MOVE && !size_ok(c, seq, op, width, height))
		return;
	if (!border_ok(c, seq, op, w, width, height, border))
		return;
	/* A look cut inside the border box cuts again at another size. */
	struct vis_look_cut cut = { 0 };
	bool recut = w->cut && (w->width != (int32_t)width || w->height != (int32_t)height ||
				w->look.border != (int32_t)border);
	struct vis_look next = w->look;
	next.border = (int32_t)border;
	if (recut &&
	    !server_look_pieces_ok(c, seq, op, w, &next, (int32_t)width, (int32_t)height, &cut))
		return;
	uint64_t old = server_look_charged(w);
	server_damage(c->server, w); /* where it was */
	if (op != VIS_OP_RESIZE) {
		w->x = a[1].i;
		w->y = a[2].i;
	}
	bool reshaped = op == VIS_OP_RESIZE ||
			(op == VIS_OP_CONFIGURE &&
			 (w->width != (int32_t)width || w->height != (int32_t)height ||
			  w->look.border != (int32_t)border));
	vis_wtree_set_size(w, (int32_t)width, (int32_t)height, (int32_t)border); /* checked above */
	if (recut)
		server_look_keep(c->server, w, old, &cut);
	if (reshaped) {
		/* As X with ForgetGravity: a resized window's contents are gone, all of it is exposed. */
		libvis_forget_shown(w->data);
	}
	changed(c, w, VIS_STACK_CONFIGURE);
}

/*
 * Reads the rectangles of a set-shape or set-opaque request (their count is bounded by the request
 * size, checked by the decoder), each 1 … INT32_MAX wide and high. Returns a new array (NULL with
 * n 0), or NULL with the error sent.
 */
static struct vis_rect *rects_arg(struct client *c, uint32_t seq, uint32_t op,
				  const union vis_arg *arr, bool *failed)
{
	*failed = false;
	if (arr->a.n == 0)
		return NULL;
	struct vis_rect *r = malloc((size_t)arr->a.n * sizeof(*r));
	if (!r) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT, "out of memory");
		*failed = true;
		return NULL;
	}
	for (uint32_t i = 0; i < arr->a.n; i++) {
		uint32_t w = vis_arg_word(arr, 'R', i, 2), h = vis_arg_word(arr, 'R', i, 3);
		if (w < 1 || h < 1 || w > INT32_MAX || h > INT32_MAX) {
			server_client_error(c, seq, op, VIS_ERROR_VALUE,
					    "rectangle %u: size %ux%u: width and height must be 1 to "
					    "2147483647",
					    i + 1, w, h);
			free(r);
			*failed = true;
			return NULL;
		}
		r[i] = (struct vis_rect){ (int32_t)vis_arg_word(arr, 'R', i, 0),
					  (int32_t)vis_arg_word(arr, 'R', i, 1), (int32_t)w,
					  (int32_t)h };
	}
	return r;
}

/* set-shape and set-opaque: the window's pixels, or which of them hide what is below. */
static void do_look(struct client *c, uint32_t seq, uint32_t op, const union vis_arg *a)
{
	struct vis_window *w = changeable_arg(c, seq, op, a[0].u);
	if (!w)
		return;
	if (w->look.input_only) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "window %u is input-only: it has no pixels", w->id);
		return;
	}
	uint32_t mode = a[1].u, n = a[2].a.n;
	if (op == VIS_OP_SET_SHAPE && mode > 1) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE,
				    "shaped %u: 0 (its border box) or 1 (the rectangles)", mode);
		return;
	}
	if (op == VIS_OP_SET_OPAQUE && mode > VIS_OPAQUE_MODE_RECTS) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE,
				    "unknown mode %u (0 all, 1 none, 2 the rectangles)", mode);
		return;
	}
	bool rects_wanted = op == VIS_OP_SET_SHAPE ? mode == 1 : mode == VIS_OPAQUE_MODE_RECTS;
	if (!rects_wanted && n != 0) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "%s %u takes no rectangles (got %u)",
				    op == VIS_OP_SET_SHAPE ? "shaped" : "mode", mode, n);
		return;
	}
	if (n > VIS_LOOK_MAX_RECTS) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "%u rectangles: a shape or opaque region has at most %u", n,
				    VIS_LOOK_MAX_RECTS);
		return;
	}
	/* The rectangles count against the window's owner and its uid, as its windows do: a
	 * connection cannot hold the daemon's memory and recomputes without bound. */
	uint32_t replaced = op == VIS_OP_SET_SHAPE ? w->look.n_shape : w->look.n_opaque;
	if (n > replaced && !server_quota_look_room(c, seq, op, w, n - replaced, 0))
		return;
	bool failed;
	struct vis_rect *r = rects_arg(c, seq, op, &a[2], &failed);
	if (failed)
		return;
	struct vis_look next = w->look;
	if (op == VIS_OP_SET_SHAPE) {
		next.shaped = mode == 1;
		next.shape = r;
		next.n_shape = mode == 1 ? n : 0;
	} else {
		next.opaque = (uint8_t)mode;
		next.opaque_rects = r;
		next.n_opaque = mode == VIS_OPAQUE_MODE_RECTS ? n : 0;
	}
	struct vis_look_cut cut;
	if (!server_look_pieces_ok(c, seq, op, w, &next, w->width, w->height, &cut)) {
		free(r);
		return;
	}
	uint64_t old = server_look_charged(w);
	int rc = op == VIS_OP_SET_SHAPE ? vis_wtree_set_shape(w, mode == 1, r, n)
					 : vis_wtree_set_opaque(w, (enum vis_opaque)mode, r, n);
	free(r);
	if (rc < 0) {
		vis_look_cut_finish(&cut);
		server_client_error(c, seq, op, VIS_ERROR_LIMIT, "out of memory");
		return;
	}
	server_look_keep(c->server, w, old, &cut);
	server_quota_look(c->server, w,
			  (int64_t)(op == VIS_OP_SET_SHAPE ? w->look.n_shape : w->look.n_opaque) -
				  (int64_t)replaced,
			  0);
	/* The pixels changed inside the border box: it is the damage, as it was and is. */
	changed(c, w, VIS_STACK_LOOK);
}

static void do_restack(struct client *c, uint32_t seq, const union vis_arg *a)
{
	uint32_t op = VIS_OP_RESTACK;
	struct vis_window *w = changeable_arg(c, seq, op, a[0].u);
	if (!w)
		return;
	if (a[1].u > VIS_RESTACK_BELOW) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE, "unknown mode %u (0 above, 1 below)",
				    a[1].u);
		return;
	}
	struct vis_window *s = window_arg(c, seq, op, a[2].u);
	if (!s)
		return;
	if (s == w || s->parent != w->parent) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH, "window %u is not a sibling of %u",
				    s->id, w->id);
		return;
	}
	vis_wtree_restack(w, s, a[1].u == VIS_RESTACK_ABOVE);
	changed(c, w, VIS_STACK_RESTACK);
}

/*
 * How many levels w's subtree holds below w, walking at most *budget windows (charged to the
 * turn's work); -1 when it would walk more. O(size of the subtree).
 */
static long subtree_height(struct server *server, const struct vis_window *w, uint64_t *budget)
{
	uint32_t most = w->depth;
	const struct vis_window *end = w;
	while (end->top)
		end = end->top; /* the subtree's last window in pre-order */
	for (const struct vis_window *v = w; v; v = v == end ? NULL : vis_wtree_next(v)) {
		if (!*budget)
			return -1;
		--*budget;
		server->work++;
		if (v->depth > most)
			most = v->depth;
	}
	return most - w->depth;
}

static void do_reparent(struct client *c, uint32_t seq, const union vis_arg *a)
{
	uint32_t op = VIS_OP_REPARENT;
	struct server *server = c->server;
	struct vis_window *w = changeable_arg(c, seq, op, a[0].u);
	struct vis_window *p = w ? parent_arg(c, seq, op, a[1].u) : NULL;
	if (!p)
		return;
	if (vis_wtree_is_ancestor(w, p)) {
		server_client_error(c, seq, op, VIS_ERROR_MATCH,
				    "window %u cannot go under itself or its descendant %u", w->id,
				    p->id);
		return;
	}
	/* Only a window that goes deeper can take its subtree past the limit. */
	if (p->depth + 1 > w->depth) {
		long height = subtree_height(server, w, &server->walk_left);
		if (height < 0) {
			server_client_error(c, seq, op, VIS_ERROR_LIMIT,
					    "the batch's reparents walked over %u windows; send the "
					    "rest in another batch",
					    SERVER_BATCH_WORK);
			return;
		}
		uint32_t deepest = p->depth + 1 + (uint32_t)height;
		if (deepest > server->opt.max_depth) {
			server_client_error(c, seq, op, VIS_ERROR_LIMIT,
					    "under %u, window %u's subtree would reach depth %u, past "
					    "the limit of %u (visd --max-depth)",
					    p->id, w->id, deepest, server->opt.max_depth);
			return;
		}
	}
	server_damage(server, w); /* where it was */
	vis_wtree_reparent(w, p, a[2].i, a[3].i);
	changed(c, w, VIS_STACK_REPARENT);
}

/* Sends the rest of a list reply: records of `words` words each, in chunks, more = 1 but last. */
static void send_list(struct client *c, uint32_t opcode, union vis_arg *r, int at,
		      const uint32_t *data, size_t n, uint32_t words)
{
	size_t i = 0;
	do {
		size_t k = n - i < CHUNK_RECORDS ? n - i : CHUNK_RECORDS;
		r[at - 1].u = i + k < n;
		r[at].a.words = data + i * words;
		r[at].a.n = (uint32_t)k;
		r[at].a.raw = NULL;
		server_client_send(c, opcode, r);
		i += k;
	} while (i < n);
}

/* Grows a word array by one record; false when memory ran out (the error is sent). */
static bool push_words(struct client *c, uint32_t seq, uint32_t op, uint32_t **v, size_t *n,
		       size_t *cap, const uint32_t *rec, uint32_t words)
{
	if (*n + words > *cap) {
		size_t ncap = *cap ? 2 * *cap : 256;
		uint32_t *more = realloc(*v, ncap * sizeof **v);
		if (!more) {
			server_client_error(c, seq, op, VIS_ERROR_LIMIT, "out of memory");
			return false;
		}
		*v = more;
		*cap = ncap;
	}
	memcpy(*v + *n, rec, words * sizeof *rec);
	*n += words;
	return true;
}

static void do_get_states(struct client *c, uint32_t seq)
{
	struct vis_wtree *tree = &c->server->vis->core;
	size_t n = 0;
	uint64_t *keys = malloc((tree->count ? tree->count : 1) * sizeof *keys);
	uint32_t *vals = malloc((tree->count ? tree->count : 1) * sizeof *vals);
	uint32_t *words = malloc((tree->count ? tree->count : 1) * 2 * sizeof *words);
	if (!keys || !vals || !words) {
		server_client_error(c, seq, VIS_OP_GET_STATES, VIS_ERROR_LIMIT, "out of memory");
		goto out;
	}
	for (struct vis_window *w = vis_wtree_next_viewable(tree, NULL); w;
	     w = vis_wtree_next_viewable(tree, w))
		/* Input-only windows are viewable but have no state: none is listed. */
		if (w->state != VIS_WTREE_STATE_NONE && server_may_see(c, w)) {
			keys[n] = w->id;
			vals[n++] = w->state;
		}
	if (vis_radix_sort(keys, vals, n) < 0) {
		server_client_error(c, seq, VIS_OP_GET_STATES, VIS_ERROR_LIMIT, "out of memory");
		goto out;
	}
	for (size_t i = 0; i < n; i++) {
		words[2 * i] = (uint32_t)keys[i];
		words[2 * i + 1] = vals[i];
	}
	union vis_arg r[3] = { { .u = seq } };
	send_list(c, VIS_OP_STATES, r, 2, words, n, 2);
out:
	free(keys);
	free(vals);
	free(words);
}

static void do_get_tree(struct client *c, uint32_t seq)
{
	uint32_t *v = NULL;
	size_t n = 0, cap = 0;
	for (struct vis_window *w = c->server->vis->core.root.bottom; w; w = vis_wtree_next(w)) {
		if (server_may_see(c, w)) {
			/* A parent it may not see is 0, as in stack notices. */
			uint32_t parent = server_seen_id(c, w->parent);
			uint32_t flags = server_window_flags(w, parent);
			uint32_t rec[12] = { w->id,
					     parent,
					     (uint32_t)w->x,
					     (uint32_t)w->y,
					     (uint32_t)w->width,
					     (uint32_t)w->height,
					     (uint32_t)w->look.border,
					     flags,
					     w->state,
					     w->ext_namespace,
					     (uint32_t)w->external,
					     (uint32_t)(w->external >> 32) };
			if (!push_words(c, seq, VIS_OP_GET_TREE, &v, &n, &cap, rec, 12))
				goto out;
		}
	}
	union vis_arg r[3] = { { .u = seq } };
	send_list(c, VIS_OP_TREE, r, 2, v, n / 12, 12);
out:
	free(v);
}

static void do_get_region(struct client *c, uint32_t seq, uint32_t id)
{
	struct vis_window *w = window_arg(c, seq, VIS_OP_GET_REGION, id);
	if (!w)
		return;
	pixman_region32_t reg;
	pixman_region32_init(&reg);
	uint32_t n = 0;
	uint32_t *v = NULL;
	if (vis_wtree_visible_region(&c->server->vis->core, w, &reg) < 0 ||
	    !(v = server_region_words(&reg, &n))) {
		server_client_error(c, seq, VIS_OP_GET_REGION, VIS_ERROR_LIMIT, "out of memory");
		goto out;
	}
	server_compat_rects(c, w, v, n);
	union vis_arg r[4] = { { .u = seq }, { .u = id } };
	send_list(c, VIS_OP_REGION, r, 3, v, n, 4);
out:
	free(v);
	pixman_region32_fini(&reg);
}

/* Copies rectangles into words of the R record (the count is at most VIS_LOOK_MAX_RECTS). */
static uint32_t *rect_words(const struct vis_rect *r, uint32_t n)
{
	uint32_t *v = malloc(((size_t)n * 4 + 1) * sizeof *v);
	for (uint32_t i = 0; v && i < n; i++) {
		v[4 * i] = (uint32_t)r[i].x;
		v[4 * i + 1] = (uint32_t)r[i].y;
		v[4 * i + 2] = (uint32_t)r[i].w;
		v[4 * i + 3] = (uint32_t)r[i].h;
	}
	return v;
}

static void do_get_look(struct client *c, uint32_t seq, uint32_t id)
{
	struct vis_window *w = window_arg(c, seq, VIS_OP_GET_LOOK, id);
	if (!w)
		return;
	const struct vis_look *l = &w->look;
	uint32_t *shape = rect_words(l->shape, l->n_shape);
	uint32_t *opaque = rect_words(l->opaque_rects, l->n_opaque);
	if (!shape || !opaque) {
		server_client_error(c, seq, VIS_OP_GET_LOOK, VIS_ERROR_LIMIT, "out of memory");
	} else {
		union vis_arg r[6] = { { .u = seq }, { .u = id }, { .u = l->shaped }, { .u = l->opaque } };
		r[4].a.words = shape;
		r[4].a.n = l->n_shape;
		r[4].a.raw = NULL;
		r[5].a.words = opaque;
		r[5].a.n = l->n_opaque;
		r[5].a.raw = NULL;
		server_client_send(c, VIS_OP_LOOK, r);
	}
	free(shape);
	free(opaque);
}

/* The window carrying an external ID, if the connection may see it: as for any window argument,
 * one it may not see does not exist for it. */
static void do_lookup(struct client *c, uint32_t seq, const union vis_arg *a)
{
	uint32_t op = VIS_OP_LOOKUP, ns = a[0].u;
	uint64_t tag = a[1].q;
	if (!ns) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE,
				    "namespace 0 names no external ID");
		return;
	}
	struct vis_window *w = vis_wtree_find_external(&c->server->vis->core, ns, tag);
	if (!w || !server_may_see(c, w)) {
		server_client_error(c, seq, op, VIS_ERROR_WINDOW, "no window carries external ID %u:%#llx",
				    ns, (unsigned long long)tag);
		return;
	}
	union vis_arg r[2] = { { .u = seq }, { .u = w->id } };
	server_client_send(c, VIS_OP_FOUND, r);
}

static void do_get_repaint(struct client *c, uint32_t seq, const union vis_arg *a)
{
	if (!size_ok(c, seq, VIS_OP_GET_REPAINT, a[2].u, a[3].u))
		return;
	struct vis_wtree *tree = &c->server->vis->core;
	struct vis_box damage = { a[0].i, a[1].i, (int64_t)a[0].i + a[2].u,
				  (int64_t)a[1].i + a[3].u };
	struct vis_window **out = malloc((tree->count ? tree->count : 1) * sizeof *out);
	uint32_t *ids = malloc((tree->count ? tree->count : 1) * sizeof *ids);
	long k = out && ids ? vis_wtree_repaint(tree, damage, out) : -1;
	if (k < 0) {
		server_client_error(c, seq, VIS_OP_GET_REPAINT, VIS_ERROR_LIMIT, "out of memory");
	} else {
		size_t n = 0;
		for (long i = 0; i < k; i++)
			if (server_may_see(c, out[i]))
				ids[n++] = out[i]->id;
		union vis_arg r[3] = { { .u = seq } };
		send_list(c, VIS_OP_REPAINT, r, 2, ids, n, 1);
	}
	free(out);
	free(ids);
}

void server_client_dispatch(struct client *c, uint32_t seq, const struct vis_msg *m)
{
	const union vis_arg *a = m->args;
	uint32_t op = m->type->opcode;
	switch (op) {
	case VIS_OP_HELLO:
		do_hello(c, seq, a);
		return;
	case VIS_OP_CREATE:
		do_create(c, seq, a);
		return;
	case VIS_OP_DESTROY:
	case VIS_OP_MAP:
	case VIS_OP_UNMAP:
	case VIS_OP_RAISE:
	case VIS_OP_LOWER:
		do_simple(c, seq, op, a[0].u);
		return;
	case VIS_OP_MOVE:
	case VIS_OP_RESIZE:
	case VIS_OP_CONFIGURE:
		do_configure(c, seq, op, a);
		return;
	case VIS_OP_SET_SHAPE:
	case VIS_OP_SET_OPAQUE:
		do_look(c, seq, op, a);
		return;
	case VIS_OP_RESTACK:
		do_restack(c, seq, a);
		return;
	case VIS_OP_REPARENT:
		do_reparent(c, seq, a);
		return;
	case VIS_OP_SUBSCRIBE:
	case VIS_OP_UNSUBSCRIBE:
		server_subscription(c, seq, op, a);
		return;
	}
	/* Queries and sync answer for the current states: recompute first if needed. */
	server_flush(c->server);
	/* What a query walks, for the turn's work: every window, whatever it may see. */
	if (op != VIS_OP_SYNC && op != VIS_OP_GET_STATE && op != VIS_OP_LOOKUP)
		c->server->work += c->server->vis->core.count + 1;
	switch (op) {
	case VIS_OP_GET_STATE: {
		struct vis_window *w = window_arg(c, seq, op, a[0].u);
		if (w) {
			union vis_arg r[3] = { { .u = seq }, { .u = w->id }, { .u = w->state } };
			server_client_send(c, VIS_OP_STATE, r);
		}
		return;
	}
	case VIS_OP_GET_STATES:
		do_get_states(c, seq);
		return;
	case VIS_OP_GET_TREE:
		do_get_tree(c, seq);
		return;
	case VIS_OP_GET_REGION:
		do_get_region(c, seq, a[0].u);
		return;
	case VIS_OP_GET_REPAINT:
		do_get_repaint(c, seq, a);
		return;
	case VIS_OP_GET_LOOK:
		do_get_look(c, seq, a[0].u);
		return;
	case VIS_OP_LOOKUP:
		do_lookup(c, seq, a);
		return;
	case VIS_OP_SYNC: {
		union vis_arg r[1] = { { .u = seq } };
		server_client_send(c, VIS_OP_SYNCED, r);
		return;
	}
	}
	log_error("client %u: request %s reached dispatch unhandled", c->id, m->type->name);
}
