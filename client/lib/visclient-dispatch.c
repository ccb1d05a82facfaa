/*
 * libvisclient's dispatch: what each message from the daemon means. The daemon is trusted no
 * more than it trusts its clients: every message has been through the codec, and a reply that
 * does not answer the oldest request waiting for one, a notice out of sequence or a value that
 * does not exist breaks the connection (EPROTO), never the process.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "visclient-private.h"

/* The most a chunked reply may gather: the daemon must not make us allocate without bound. */
#define REPLY_LIMIT ((size_t)1 << 30)

/* The reply opcode a kind of request waits for. */
static uint32_t reply_opcode(enum vis_reply_kind kind)
{
	static const uint32_t ops[] = {
		[VIS_REPLY_HELLO] = VIS_OP_HELLO_REPLY, [VIS_REPLY_CREATED] = VIS_OP_CREATED,
		[VIS_REPLY_STATE] = VIS_OP_STATE,       [VIS_REPLY_STATES] = VIS_OP_STATES,
		[VIS_REPLY_TREE] = VIS_OP_TREE,         [VIS_REPLY_REGION] = VIS_OP_REGION,
		[VIS_REPLY_REPAINT] = VIS_OP_REPAINT,   [VIS_REPLY_SYNCED] = VIS_OP_SYNCED,
		[VIS_REPLY_LOOK] = VIS_OP_LOOK,         [VIS_REPLY_FOUND] = VIS_OP_FOUND,
	};
	return ops[kind];
}

/* The size of one gathered record of a chunked reply. */
static size_t item_size(enum vis_reply_kind kind)
{
	switch (kind) {
	case VIS_REPLY_STATES:
		return sizeof(struct vis_window_state);
	case VIS_REPLY_TREE:
		return sizeof(struct vis_window_info);
	case VIS_REPLY_REGION:
		return sizeof(struct vis_rect32);
	default:
		return sizeof(uint32_t);
	}
}

/* The record letter (messages.h) of a chunked reply's array. */
static char record(enum vis_reply_kind kind)
{
	switch (kind) {
	case VIS_REPLY_STATES:
		return 'S';
	case VIS_REPLY_TREE:
		return 'T';
	case VIS_REPLY_REGION:
		return 'R';
	default:
		return 'W';
	}
}

/* Takes the oldest waiting request off the queue; the caller owns its items from then on. */
static struct vis_pending pop(struct vis_client *c)
{
	struct vis_pending p = c->pending[c->head++];
	if (c->head == c->len)
		c->head = c->len = 0;
	c->answered = p.seq;
	return p;
}

/* Calls a waiting request's callback with an error, its other arguments empty. */
static void call_failed(const struct vis_pending *p, const struct vis_error *e)
{
	switch (p->kind) {
	case VIS_REPLY_CREATED:
	case VIS_REPLY_FOUND:
		if (p->cb.create)
			p->cb.create(p->data, e, 0);
		break;
	case VIS_REPLY_STATE:
		if (p->cb.state)
			p->cb.state(p->data, e, 0, 0);
		break;
	case VIS_REPLY_STATES:
		if (p->cb.states)
			p->cb.states(p->data, e, NULL, 0);
		break;
	case VIS_REPLY_TREE:
		if (p->cb.tree)
			p->cb.tree(p->data, e, NULL, 0);
		break;
	case VIS_REPLY_REGION:
		if (p->cb.rects)
			p->cb.rects(p->data, e, NULL, 0);
		break;
	case VIS_REPLY_REPAINT:
		if (p->cb.windows)
			p->cb.windows(p->data, e, NULL, 0);
		break;
	case VIS_REPLY_SYNCED:
		if (p->cb.done)
			p->cb.done(p->data, e);
		break;
	case VIS_REPLY_LOOK:
		if (p->cb.look)
			p->cb.look(p->data, e, NULL);
		break;
	default:
		break;
	}
}

/* The errno a refused handshake leaves, so that callers can tell a denied role from a dead socket. */
static int handshake_errno(uint32_t code)
{
	switch (code) {
	case VIS_ERROR_ACCESS:
		return EACCES;
	case VIS_ERROR_STATE:
		return EBUSY;
	case VIS_ERROR_HANDSHAKE:
		return EPROTONOSUPPORT;
	case VIS_ERROR_LIMIT:
		return EAGAIN; /* too many clients, or the daemon is out of descriptors: try later */
	default:
		return ECONNREFUSED;
	}
}

/* Whether the daemon closes the connection after sending an error with this code. */
static int is_fatal(uint32_t code)
{
	return code == VIS_ERROR_MALFORMED || code == VIS_ERROR_OPCODE ||
	       code == VIS_ERROR_HANDSHAKE;
}

/*
 * Handles an error reply. Its seq must name a request sent and not yet answered, and no later
 * than the oldest one waiting for a reply (answers come in request order). Fatal codes may name
 * any request, or none: the daemon closes the connection after them anyway.
 */
static void handle_error(struct vis_client *c, const struct vis_msg *m)
{
	struct vis_error e;
	e.seq = m->args[0].u;
	e.opcode = m->args[1].u;
	e.code = m->args[2].u;
	size_t len = m->args[3].s.len;
	if (len >= sizeof(e.message))
		len = sizeof(e.message) - 1;
	memcpy(e.message, m->args[3].s.p, len);
	e.message[len] = '\0';

	struct vis_pending *head = c->head < c->len ? &c->pending[c->head] : NULL;
	int fatal = is_fatal(e.code);
	const struct vis_msg_type *t = vis_msg_type_find(e.opcode);
	int known = (e.seq > c->answered && e.seq < c->next_seq && (!head || e.seq <= head->seq) &&
		     t && t->dir == VIS_DIR_REQUEST && (!head || e.seq != head->seq ||
							e.opcode == head->opcode));
	if (!known && !(fatal && e.seq < c->next_seq)) {
		vis_client_fail(c, EPROTO, "error reply for request %u (%s), which is not waiting for one",
		     e.seq, vis_request_name(e.opcode));
		return;
	}
	c->last_error = e;
	c->has_last_error = 1;
	c->error_count++;
	if (head && e.seq == head->seq) {
		struct vis_pending p = pop(c);
		free(p.items);
		if (p.kind == VIS_REPLY_HELLO)
			vis_client_fail(c, handshake_errno(e.code), "hello: %s: %s",
			     vis_error_code_name(e.code), e.message);
		else
			call_failed(&p, &e);
	} else {
		if (known)
			c->answered = e.seq;
		if (c->on_error)
			c->on_error(c->error_data, &e);
	}
	if (fatal)
		vis_client_fail(c, EPROTO, "the daemon closed the connection: %s: %s: %s",
		     vis_request_name(e.opcode), vis_error_code_name(e.code), e.message);
}

/* Appends a chunk's records to the waiting request, converting them from the wire. */
static int gather(struct vis_client *c, struct vis_pending *p, const union vis_arg *a, char rec)
{
	size_t k = a->a.n, size = item_size(p->kind);
	if (k > REPLY_LIMIT / size - p->n) {
		vis_client_fail(c, EPROTO, "%s reply longer than %zu bytes", vis_request_name(p->opcode),
		     REPLY_LIMIT);
		return -1;
	}
	if (p->n + k > p->cap) {
		size_t cap = p->cap ? p->cap : 64;
		while (cap < p->n + k)
			cap *= 2;
		void *items = realloc(p->items, cap * size);
		if (!items) {
			vis_client_fail(c, ENOMEM, "out of memory reading a %s reply",
			     vis_request_name(p->opcode));
			return -1;
		}
		p->items = items;
		p->cap = cap;
	}
	for (uint32_t i = 0; i < a->a.n; i++) {
		size_t at = p->n + i;
		if (rec == 'S') {
			struct vis_window_state *s = (struct vis_window_state *)p->items + at;
			s->window = vis_arg_word(a, rec, i, 0);
			s->state = vis_arg_word(a, rec, i, 1);
			if (s->state > VIS_VISIBILITY_FULLY_OBSCURED)
				goto bad_state;
		} else if (rec == 'T') {
			struct vis_window_info *w = (struct vis_window_info *)p->items + at;
			w->window = vis_arg_word(a, rec, i, 0);
			w->parent = vis_arg_word(a, rec, i, 1);
			w->x = (int32_t)vis_arg_word(a, rec, i, 2);
			w->y = (int32_t)vis_arg_word(a, rec, i, 3);
			w->width = vis_arg_word(a, rec, i, 4);
			w->height = vis_arg_word(a, rec, i, 5);
			w->border = vis_arg_word(a, rec, i, 6);
			w->flags = vis_arg_word(a, rec, i, 7);
			w->state = vis_arg_word(a, rec, i, 8);
			w->ext_namespace = vis_arg_word(a, rec, i, 9);
			w->external = (uint64_t)vis_arg_word(a, rec, i, 10) |
				      (uint64_t)vis_arg_word(a, rec, i, 11) << 32;
			if (w->state > VIS_VISIBILITY_NONE)
				goto bad_state;
			if (!w->ext_namespace && w->external)
				goto bad_external;
		} else if (rec == 'R') {
			struct vis_rect32 *r = (struct vis_rect32 *)p->items + at;
			r->x = (int32_t)vis_arg_word(a, rec, i, 0);
			r->y = (int32_t)vis_arg_word(a, rec, i, 1);
			r->width = vis_arg_word(a, rec, i, 2);
			r->height = vis_arg_word(a, rec, i, 3);
		} else {
			((uint32_t *)p->items)[at] = vis_arg_word(a, rec, i, 0);
		}
	}
	p->n += k;
	return 0;

bad_state:
	vis_client_fail(c, EPROTO, "%s reply with an unknown visibility state", vis_request_name(p->opcode));
	return -1;
bad_external:
	vis_client_fail(c, EPROTO, "%s reply with an external ID in namespace 0",
			vis_request_name(p->opcode));
	return -1;
}

/* Runs the callback of a completely answered request, then frees what it gathered. */
static void call_done(struct vis_pending *p, uint32_t window, uint32_t state)
{
	switch (p->kind) {
	case VIS_REPLY_CREATED:
	case VIS_REPLY_FOUND:
		if (p->cb.create)
			p->cb.create(p->data, NULL, window);
		break;
	case VIS_REPLY_STATE:
		if (p->cb.state)
			p->cb.state(p->data, NULL, window, state);
		break;
	case VIS_REPLY_STATES:
		if (p->cb.states)
			p->cb.states(p->data, NULL, p->items, p->n);
		break;
	case VIS_REPLY_TREE:
		if (p->cb.tree)
			p->cb.tree(p->data, NULL, p->items, p->n);
		break;
	case VIS_REPLY_REGION:
		if (p->cb.rects)
			p->cb.rects(p->data, NULL, p->items, p->n);
		break;
	case VIS_REPLY_REPAINT:
		if (p->cb.windows)
			p->cb.windows(p->data, NULL, p->items, p->n);
		break;
	case VIS_REPLY_SYNCED:
		if (p->cb.done)
			p->cb.done(p->data, NULL);
		break;
	default:
		break;
	}
	free(p->items);
}

/*
 * Handles the hello-reply: the handshake's answers, checked before the connection is usable. A
 * request limit no daemon can have would fail every later request with EMSGSIZE (or, at 0, lift
 * the limit): it breaks the connection instead.
 */
static void handle_hello(struct vis_client *c, const struct vis_msg *m)
{
	uint32_t max = m->args[6].u;
	if (m->args[1].u != VIS_PROTOCOL_VERSION || m->args[3].u > VIS_ROLE_MANAGER ||
	    max < VIS_PROTOCOL_MIN_MAX_REQUEST || max > VIS_PROTOCOL_MAX_MESSAGE) {
		vis_client_fail(c, EPROTO, "hello-reply with version %u, role %u, max_request %u",
		     m->args[1].u, m->args[3].u, max);
		return;
	}
	struct vis_pending p = pop(c);
	free(p.items);
	c->id = m->args[2].u;
	c->role = m->args[3].u;
	c->screen_width = m->args[4].u;
	c->screen_height = m->args[5].u;
	c->max_request = max;
	c->connected = 1;
}

/* Reads an R array into new rectangles (NULL when empty or out of memory: *ok says which). */
static struct vis_rect32 *read_rects(const union vis_arg *a, bool *ok)
{
	struct vis_rect32 *r = NULL;
	*ok = true;
	if (a->a.n == 0)
		return NULL;
	if (!(r = malloc((size_t)a->a.n * sizeof(*r)))) {
		*ok = false;
		return NULL;
	}
	for (uint32_t i = 0; i < a->a.n; i++)
		r[i] = (struct vis_rect32){ (int32_t)vis_arg_word(a, 'R', i, 0),
					    (int32_t)vis_arg_word(a, 'R', i, 1),
					    vis_arg_word(a, 'R', i, 2), vis_arg_word(a, 'R', i, 3) };
	return r;
}

/* Handles a look reply: the values must be ones the protocol has, the rectangles real ones. */
static void handle_look(struct vis_client *c, const struct vis_msg *m, struct vis_pending *p)
{
	struct vis_look_info l = { .window = m->args[1].u, .shaped = m->args[2].u,
				   .mode = m->args[3].u, .n_shape = m->args[4].a.n,
				   .n_opaque = m->args[5].a.n };
	if (l.window != p->window || l.shaped > 1 || l.mode > VIS_OPAQUE_MODE_RECTS ||
	    (!l.shaped && l.n_shape) || (l.mode != VIS_OPAQUE_MODE_RECTS && l.n_opaque)) {
		vis_client_fail(c, EPROTO, "look reply for window %u with shaped %u, mode %u, %u and %u "
			      "rectangles, asked for %u", l.window, l.shaped, l.mode, l.n_shape,
			      l.n_opaque, p->window);
		return;
	}
	bool ok1, ok2;
	l.shape = read_rects(&m->args[4], &ok1);
	l.opaque = read_rects(&m->args[5], &ok2);
	if (!ok1 || !ok2) {
		free(l.shape);
		free(l.opaque);
		vis_client_fail(c, ENOMEM, "out of memory reading a look reply");
		return;
	}
	struct vis_pending done = pop(c);
	if (done.cb.look)
		done.cb.look(done.data, NULL, &l);
	free(done.items);
	free(l.shape);
	free(l.opaque);
}

/* Handles a reply other than an error: it must answer the oldest request waiting for one. */
static void handle_reply(struct vis_client *c, const struct vis_msg *m)
{
	const char *name = m->type->name;
	uint32_t seq = m->args[0].u;
	if (c->head == c->len) {
		vis_client_fail(c, EPROTO, "%s reply for request %u, which is not waiting for one", name, seq);
		return;
	}
	struct vis_pending *p = &c->pending[c->head];
	if (seq != p->seq || m->type->opcode != reply_opcode(p->kind)) {
		vis_client_fail(c, EPROTO, "%s reply for request %u; request %u (%s) waits for %s", name, seq,
		     p->seq, vis_request_name(p->opcode),
		     vis_msg_type_find(reply_opcode(p->kind))->name);
		return;
	}
	uint32_t window = 0, state = 0, more = 0;
	switch (p->kind) {
	case VIS_REPLY_HELLO:
		handle_hello(c, m);
		return;
	case VIS_REPLY_LOOK:
		handle_look(c, m, p);
		return;
	case VIS_REPLY_CREATED:
	case VIS_REPLY_FOUND:
		window = m->args[1].u;
		if (window == VIS_WINDOW_ROOT) {
			vis_client_fail(c, EPROTO, "%s reply with window 0", name);
			return;
		}
		break;
	case VIS_REPLY_STATE:
		window = m->args[1].u;
		state = m->args[2].u;
		if (window != p->window || state > VIS_VISIBILITY_NONE) {
			vis_client_fail(c, EPROTO, "state reply for window %u in state %u, asked for %u",
			     window, state, p->window);
			return;
		}
		break;
	case VIS_REPLY_REGION:
		if (m->args[1].u != p->window) {
			vis_client_fail(c, EPROTO, "region reply for window %u, asked for %u", m->args[1].u,
			     p->window);
			return;
		}
		more = m->args[2].u;
		if (more <= 1 && gather(c, p, &m->args[3], record(p->kind)) < 0)
			return;
		break;
	case VIS_REPLY_STATES:
	case VIS_REPLY_TREE:
	case VIS_REPLY_REPAINT:
		more = m->args[1].u;
		if (more <= 1 && gather(c, p, &m->args[2], record(p->kind)) < 0)
			return;
		break;
	default:
		break;
	}
	if (more > 1) {
		vis_client_fail(c, EPROTO, "%s reply with more = %u", name, more);
		return;
	}
	if (more)
		return;
	struct vis_pending done = pop(c);
	call_done(&done, window, state);
}

/* Handles a notice: its serial must be the next one, its values known ones. */
static void handle_notice(struct vis_client *c, const struct vis_msg *m)
{
	struct vis_notice n;
	struct vis_rect32 *rects = NULL;
	memset(&n, 0, sizeof(n));
	n.serial = m->args[0].q;
	if (!c->connected || n.serial != c->next_serial) {
		vis_client_fail(c, EPROTO, "%s notice with serial %llu, expected %llu", m->type->name,
		     (unsigned long long)n.serial, (unsigned long long)c->next_serial);
		return;
	}
	c->next_serial++;
	int bad = 0;
	switch (m->type->opcode) {
	case VIS_OP_VISIBILITY:
		n.kind = VIS_NOTICE_KIND_VISIBILITY;
		n.window = m->args[1].u;
		n.visibility.state = m->args[2].u;
		n.visibility.previous = m->args[3].u;
		n.visibility.coalesced = m->args[4].u;
		bad = n.visibility.state > VIS_VISIBILITY_NONE ||
		      n.visibility.previous > VIS_VISIBILITY_INITIAL;
		break;
	case VIS_OP_EXPOSURE:
		n.kind = VIS_NOTICE_KIND_EXPOSURE;
		n.window = m->args[1].u;
		n.exposure.flags = m->args[2].u;
		n.exposure.coalesced = m->args[3].u;
		n.exposure.n_rects = m->args[4].a.n;
		bad = (n.exposure.flags & ~VIS_EXPOSURE_COLLAPSED) != 0;
		if (bad || !n.exposure.n_rects)
			break;
		/* A copy, not the input buffer: a handler may read more input before it returns. */
		rects = malloc((size_t)n.exposure.n_rects * sizeof(*rects));
		if (!rects) {
			vis_client_fail(c, ENOMEM, "out of memory reading an exposure notice");
			return;
		}
		for (uint32_t i = 0; i < n.exposure.n_rects; i++) {
			rects[i].x = (int32_t)vis_arg_word(&m->args[4], 'R', i, 0);
			rects[i].y = (int32_t)vis_arg_word(&m->args[4], 'R', i, 1);
			rects[i].width = vis_arg_word(&m->args[4], 'R', i, 2);
			rects[i].height = vis_arg_word(&m->args[4], 'R', i, 3);
		}
		n.exposure.rects = rects;
		break;
	case VIS_OP_OVERFLOW:
		n.kind = VIS_NOTICE_KIND_OVERFLOW;
		n.overflow.dropped = m->args[1].u;
		n.overflow.resync = m->args[2].u;
		break;
	default:
		n.kind = VIS_NOTICE_KIND_STACK;
		n.stack.change = m->args[1].u;
		n.window = m->args[2].u;
		n.stack.parent = m->args[3].u;
		n.stack.x = m->args[4].i;
		n.stack.y = m->args[5].i;
		n.stack.width = m->args[6].u;
		n.stack.height = m->args[7].u;
		n.stack.sibling = m->args[8].u;
		n.stack.flags = m->args[9].u;
		n.stack.border = m->args[10].u;
		n.stack.ext_namespace = m->args[11].u;
		n.stack.external = m->args[12].q;
		bad = n.stack.change > VIS_STACK_LOOK ||
		      (!n.stack.ext_namespace && n.stack.external);
		break;
	}
	if (bad)
		vis_client_fail(c, EPROTO, "%s notice %llu with an unknown value", m->type->name,
		     (unsigned long long)n.serial);
	else if (c->notice)
		c->notice(c->notice_data, &n);
	free(rects);
}

/* Handles one decoded message. Nothing of m is used after a callback runs. */
static void handle(struct vis_client *c, const struct vis_msg *m)
{
	if (m->type->dir == VIS_DIR_NOTICE)
		handle_notice(c, m);
	else if (m->type->opcode == VIS_OP_ERROR)
		handle_error(c, m);
	else if (!c->connected && m->type->opcode != VIS_OP_HELLO_REPLY)
		vis_client_fail(c, EPROTO, "%s reply before the handshake", m->type->name);
	else
		handle_reply(c, m);
}

/* Handles the complete messages received, stopping at the first connection error. */
int vis_client_process(struct vis_client *c)
{
	int handled = 0;
	while (!c->error && c->in_off < c->in.len) {
		struct vis_msg m;
		char why[200];
		enum vis_decode r = vis_msg_decode(c->in.data + c->in_off, c->in.len - c->in_off,
						   VIS_PROTOCOL_MAX_MESSAGE, 0, &m, why,
						   sizeof(why));
		if (r == VIS_DECODE_MORE)
			break;
		if (r == VIS_DECODE_MALFORMED) {
			vis_client_fail(c, EPROTO, "malformed message from the daemon: %s", why);
			break;
		}
		c->in_off += m.size;
		handle(c, &m);
		handled++;
	}
	return handled;
}
