/* One connection: reading requests, holding batches, queueing replies and notices, closing. */
#include <errno.h>
#include <event2/buffer.h>
#include <event2/bufferevent.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"
#include "wire.h"

static void on_read(struct bufferevent *bev, void *data);
static void on_write(struct bufferevent *bev, void *data);
static void on_event(struct bufferevent *bev, short what, void *data);
static void on_resume(evutil_socket_t fd, short what, void *data);

void server_refuse(struct server *server, int fd, const char *fmt, ...)
{
	char msg[200];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	/* A flood must not flood the log too. */
	if (server->refused++ % 1000 == 0)
		log_warn("refusing a connection: %s (%llu so far)", msg,
			 (unsigned long long)server->refused);
	union vis_arg a[4] = { { .u = 1 }, { .u = VIS_OP_HELLO }, { .u = VIS_ERROR_LIMIT } };
	a[3].s.p = msg;
	a[3].s.len = (uint32_t)strlen(msg);
	struct vis_buf *b = &server->scratch;
	b->len = 0;
	/* One small message into an empty socket buffer: it fits, or the peer is gone anyway. */
	if (vis_msg_encode(b, VIS_OP_ERROR, a) == 0 &&
	    send(fd, b->data, b->len, MSG_DONTWAIT | MSG_NOSIGNAL) < 0)
		log_debug("refused connection: %s", strerror(errno));
	close(fd);
}

/* A connection that has not completed hello in time is closed, saying why. */
static void on_hello_timeout(evutil_socket_t fd, short what, void *data)
{
	(void)fd;
	(void)what;
	struct client *c = data;
	if (!c->hello_done && !c->closing)
		server_client_error(c, c->seq + 1, VIS_OP_HELLO, VIS_ERROR_HANDSHAKE,
				    "no hello within %u s (visd --hello-timeout)",
				    c->server->opt.hello_timeout);
}

void server_client_accept(struct server *server, int fd, bool restricted)
{
	/* The peer's uid first: the bounds on connections depend on it. */
	struct ucred cred;
	socklen_t len = sizeof cred;
	if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) < 0) {
		log_warn("refusing a connection: SO_PEERCRED: %s", strerror(errno));
		close(fd);
		return;
	}
	if (!server_quota_admit(server, fd, cred.uid, restricted))
		return;
	struct client *c = calloc(1, sizeof *c);
	struct bufferevent *bev = bufferevent_socket_new(server->base, fd, BEV_OPT_CLOSE_ON_FREE);
	struct evbuffer *batch = evbuffer_new();
	struct event *resume = evtimer_new(server->base, on_resume, c);
	struct event *hello_timer = evtimer_new(server->base, on_hello_timeout, c);
	if (!c || !bev || !batch || !resume || !hello_timer) {
		log_error("refusing a connection: out of memory");
		server_quota_leave(server, cred.uid, restricted);
		free(c);
		if (bev)
			bufferevent_free(bev);
		else
			close(fd);
		if (batch)
			evbuffer_free(batch);
		if (resume)
			event_free(resume);
		if (hello_timer)
			event_free(hello_timer);
		return;
	}
	c->resume = resume;
	c->hello_timer = hello_timer;
	c->server = server;
	c->bev = bev;
	c->batch = batch;
	c->uid = cred.uid;
	c->restricted = restricted;
	c->id = server->next_client++;
	if (!server->next_client)
		server->next_client = 1; /* 0 is "no owner" */
	if (vis_idmap_put(&server->clients_by_id, c->id, c) < 0) {
		log_error("refusing a connection: out of memory");
		server_quota_leave(server, cred.uid, restricted);
		bufferevent_free(bev);
		evbuffer_free(batch);
		event_free(resume);
		event_free(hello_timer);
		free(c);
		return;
	}
	server_output_init(c);
	TAILQ_INSERT_TAIL(&server->clients, c, link);
	server->n_clients++;
	bufferevent_setcb(bev, on_read, on_write, on_event, c);
	/*
	 * Input stops being read past a request or two (the budget may leave some unread); the write
	 * callback runs once the output is down to a quarter of the bound, to release what waits.
	 */
	uint32_t max = server->opt.max_request;
	bufferevent_setwatermark(bev, EV_READ, 0, (max < 65536 ? 65536 : max) + 65536);
	bufferevent_setwatermark(bev, EV_WRITE, server->opt.max_pending / 4, 0);
	bufferevent_enable(bev, EV_READ | EV_WRITE);
	evtimer_add(hello_timer, &(struct timeval){ .tv_sec = server->opt.hello_timeout });
	log_debug("client %u connected (uid %u, pid %d%s)", c->id, (unsigned)cred.uid,
		  (int)cred.pid, restricted ? ", restricted socket" : "");
}

/* Destroys the windows a departing connection owns, except retained ones, which it orphans. */
static void drop_windows(struct client *c)
{
	struct server *server = c->server;
	size_t n = 0, cap = 0;
	uint32_t *ids = NULL;
	for (struct vis_window *w = server->tree.root.bottom; w; w = vis_wtree_next(w)) {
		if (w->owner == c->id) {
			if (n == cap) {
				cap = cap ? 2 * cap : 64;
				uint32_t *more = realloc(ids, cap * sizeof *ids);
				if (!more) {
					log_error("out of memory while dropping client %u", c->id);
					break;
				}
				ids = more;
			}
			ids[n++] = w->id;
		}
	}
	for (size_t i = 0; i < n; i++) {
		struct vis_window *v = vis_wtree_find(&server->tree, ids[i]);
		if (!v)
			continue; /* went with an ancestor */
		if (v->retained) {
			v->owner = 0;
			c->n_windows--;
		} else
			server_destroy_window(server, v);
	}
	free(ids);
}

void server_client_free(struct client *c)
{
	struct server *server = c->server;
	TAILQ_REMOVE(&server->clients, c, link);
	server->n_clients--;
	if (server->manager == c)
		server->manager = NULL;
	server_unsubscribe_all(c);
	free(c->subs);
	drop_windows(c);
	/* After its windows: their destruction finds the owner to count them off. */
	vis_idmap_remove(&server->clients_by_id, c->id);
	log_debug("client %u gone", c->id);
	server_output_finish(c);
	bufferevent_free(c->bev);
	evbuffer_free(c->batch);
	event_free(c->resume);
	event_free(c->hello_timer);
	server_quota_leave(server, c->uid, c->restricted);
	free(c);
	server_schedule_flush(server);
}

/* Ends the connection once what is queued has been written. */
void server_client_close(struct client *c)
{
	c->closing = true;
	bufferevent_disable(c->bev, EV_READ);
}

void server_client_send(struct client *c, uint32_t opcode, const union vis_arg *args)
{
	server_output_release(c); /* replies come after the notices of earlier requests */
	server_client_write(c, opcode, args);
}

void server_client_write(struct client *c, uint32_t opcode, const union vis_arg *args)
{
	struct vis_buf *b = &c->server->scratch;
	b->len = 0;
	if (c->closing && opcode != VIS_OP_ERROR)
		return;
	if (vis_msg_encode(b, opcode, args) < 0 || bufferevent_write(c->bev, b->data, b->len) < 0) {
		log_error("client %u: cannot queue a %s message: %s", c->id,
			  vis_msg_type_find(opcode)->name, strerror(errno));
		server_client_close(c);
	}
}

void server_client_error(struct client *c, uint32_t seq, uint32_t opcode, uint32_t code,
			 const char *fmt, ...)
{
	char msg[256];
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(msg, sizeof msg, fmt, ap);
	va_end(ap);
	const struct vis_msg_type *t = vis_msg_type_find(opcode);
	bool fatal = code == VIS_ERROR_MALFORMED || code == VIS_ERROR_OPCODE ||
		     code == VIS_ERROR_HANDSHAKE;
	log_write(fatal ? LOG_INFO : LOG_DEBUG, __FILE__, __LINE__, "client %u: request %u (%s): %s%s",
		  c->id, seq, t ? t->name : "?", msg, fatal ? "; closing the connection" : "");
	union vis_arg a[4];
	a[0].u = seq;
	a[1].u = opcode;
	a[2].u = code;
	a[3].s.p = msg;
	a[3].s.len = (uint32_t)strlen(msg);
	server_client_send(c, VIS_OP_ERROR, a);
	if (fatal)
		server_client_close(c);
}

const struct sub *server_client_sub_for(const struct client *c, const struct vis_window *w,
					uint32_t mask)
{
	const struct sub *all = NULL;
	for (size_t i = 0; i < c->n_subs; i++) {
		const struct sub *s = &c->subs[i];
		if (!(s->mask & mask))
			continue;
		if (s->window == w->id)
			return s;
		if (!s->window && server_may_see(c, w))
			all = s;
	}
	return all;
}

/*
 * Runs the requests held since batch-begin in order, with one recompute at the end: queries met on
 * the way answer from the states computed before the batch, so that replies keep request order
 * and nobody sees a state between the batch's changes.
 */
static void commit_batch(struct client *c)
{
	struct server *server = c->server;
	c->in_batch = false;
	server->deferring = true;
	while (evbuffer_get_length(c->batch) && !c->closing) {
		uint8_t *p = evbuffer_pullup(c->batch, 4 + VIS_MSG_HEADER);
		uint32_t seq = vis_wire_get_u32(p), size = vis_wire_get_u32(p + 4);
		p = evbuffer_pullup(c->batch, 4 + (ssize_t)size);
		struct vis_msg m;
		char why[200];
		if (vis_msg_decode(p + 4, size, size, 1, &m, why, sizeof why) != VIS_DECODE_OK) {
			log_error("client %u: a held request no longer decodes: %s", c->id, why);
		} else if (server_output_pending(c) >
			   (size_t)server->opt.max_pending + server->opt.max_batch) {
			/* Replies are never dropped and a batch cannot wait for the output to drain:
			 * its replies may pass the bound by what the batch may hold, no more. */
			server_client_error(c, seq, m.type->opcode, VIS_ERROR_LIMIT,
					    "the batch's replies take over %zu bytes; closing the "
					    "connection",
					    (size_t)server->opt.max_pending + server->opt.max_batch);
			server_client_close(c);
		} else if (m.type->opcode == VIS_OP_BATCH_BEGIN)
			server_client_error(c, seq, VIS_OP_BATCH_BEGIN, VIS_ERROR_STATE,
					    "batch-begin inside a batch");
		else
			server_client_dispatch(c, seq, &m);
		evbuffer_drain(c->batch, 4 + (size_t)size);
	}
	evbuffer_drain(c->batch, evbuffer_get_length(c->batch));
	server->deferring = false;
	server_flush(server);
}

/* Routes one well-formed request: the handshake first, batches, then the request itself. */
static void handle(struct client *c, uint32_t seq, const struct vis_msg *m, const uint8_t *raw)
{
	uint32_t op = m->type->opcode;
	if (!c->hello_done && op != VIS_OP_HELLO) {
		server_client_error(c, seq, op, VIS_ERROR_HANDSHAKE,
				    "%s before the handshake: hello must come first", m->type->name);
		return;
	}
	if (c->hello_done && op == VIS_OP_HELLO) {
		server_client_error(c, seq, op, VIS_ERROR_HANDSHAKE, "a second hello");
		return;
	}
	if (!c->in_batch) {
		if (op == VIS_OP_BATCH_COMMIT)
			server_client_error(c, seq, op, VIS_ERROR_STATE, "batch-commit without a batch");
		else if (op == VIS_OP_BATCH_BEGIN)
			c->in_batch = true;
		else
			server_client_dispatch(c, seq, m);
		return;
	}
	if (op == VIS_OP_BATCH_COMMIT) {
		commit_batch(c);
	} else if (evbuffer_get_length(c->batch) + 4 + m->size > c->server->opt.max_batch) {
		/* Fatal: answering now would break the order of the replies to what is held. */
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "the batch holds over %u bytes; closing the connection",
				    c->server->opt.max_batch);
		server_client_close(c);
	} else {
		uint8_t s[4];
		vis_wire_put_u32(s, seq);
		if (evbuffer_add(c->batch, s, 4) < 0 || evbuffer_add(c->batch, raw, m->size) < 0) {
			log_error("client %u: out of memory holding a batch", c->id);
			server_client_close(c);
		}
	}
}

/* Serves c again on the next turn of the event loop, after others had theirs. */
static void resume_next_turn(struct client *c)
{
	static const struct timeval now = { 0, 0 };
	evtimer_add(c->resume, &now);
}

/*
 * Whether a request that reports states should wait for the recompute at the end of this turn,
 * which the others' changes of the turn share, rather than force one of its own now. A request
 * waits once at most, so that others' changes cannot hold it back turn after turn.
 */
static bool wait_for_recompute(struct client *c, uint32_t op)
{
	if (!c->server->dirty || c->in_batch || c->waited)
		return false;
	switch (op) {
	case VIS_OP_CREATE:
	case VIS_OP_SUBSCRIBE:
	case VIS_OP_GET_STATE:
	case VIS_OP_GET_STATES:
	case VIS_OP_GET_TREE:
	case VIS_OP_GET_REGION:
	case VIS_OP_GET_REPAINT:
	case VIS_OP_SYNC:
		c->waited = true;
		return true;
	default:
		return false;
	}
}

/*
 * Runs the complete requests that have arrived, up to the budget, then leaves the recompute to the
 * end of this turn of the event loop, so that others' requests read in the same turn share it. A
 * connection whose output is full is not read from until it drains.
 */
static void serve(struct client *c)
{
	struct server *server = c->server;
	struct evbuffer *in = bufferevent_get_input(c->bev);
	uint32_t max = server->opt.max_request;
	uint64_t recomputes = server->recomputes;
	for (int budget = SERVER_REQUEST_BUDGET; !c->closing; budget--) {
		size_t avail = evbuffer_get_length(in);
		if (avail < VIS_MSG_HEADER)
			break;
		if (server_output_pending(c) >= server->opt.max_pending) {
			c->read_blocked = true;
			break;
		}
		const uint8_t *p = evbuffer_pullup(in, VIS_MSG_HEADER);
		uint32_t size;
		char why[200];
		struct vis_msg m;
		if (vis_msg_peek(p, avail, max, &size, why, sizeof why) == VIS_DECODE_OK) {
			if (avail < size)
				break;
			if (!budget || server->recomputes != recomputes) {
				resume_next_turn(c);
				break;
			}
			p = evbuffer_pullup(in, size);
		}
		enum vis_decode r = vis_msg_decode(p, avail, max, 1, &m, why, sizeof why);
		if (r == VIS_DECODE_OK && wait_for_recompute(c, m.type->opcode)) {
			resume_next_turn(c);
			break;
		}
		c->waited = false;
		uint32_t seq = ++c->seq;
		if (r == VIS_DECODE_MALFORMED) {
			uint32_t op = vis_wire_get_u16(p + 4);
			const struct vis_msg_type *t = vis_msg_type_find(op);
			bool known = t && t->dir == VIS_DIR_REQUEST;
			server_client_error(c, seq, op, known ? VIS_ERROR_MALFORMED : VIS_ERROR_OPCODE,
					    "%s", why);
			break;
		}
		handle(c, seq, &m, p);
		evbuffer_drain(in, size);
	}
	server_schedule_flush(server);
	if (c->closing && !server_output_pending(c))
		server_client_free(c);
}

static void on_read(struct bufferevent *bev, void *data)
{
	(void)bev;
	serve(data);
}

/* The budget left requests unread: their turn has come. */
static void on_resume(evutil_socket_t fd, short what, void *data)
{
	(void)fd;
	(void)what;
	serve(data);
}

/*
 * The output is down to a quarter of the bound (or empty): send what was held, read again if
 * reading stopped, and free a closing connection once its last message is out.
 */
static void on_write(struct bufferevent *bev, void *data)
{
	(void)bev;
	struct client *c = data;
	if (!c->closing)
		server_output_release(c);
	if (c->read_blocked && server_output_pending(c) < c->server->opt.max_pending / 2) {
		c->read_blocked = false;
		resume_next_turn(c);
	}
	if (c->closing && !server_output_pending(c))
		server_client_free(c);
}

/* The peer hung up or the socket failed: the connection ends, its windows with it. */
static void on_event(struct bufferevent *bev, short what, void *data)
{
	(void)bev;
	struct client *c = data;
	if (what & BEV_EVENT_ERROR)
		log_debug("client %u: %s", c->id, strerror(EVUTIL_SOCKET_ERROR()));
	if (what & (BEV_EVENT_EOF | BEV_EVENT_ERROR))
		server_client_free(c);
}
