/* One connection: reading requests, holding batches, queueing replies and notices, closing. */
#include <errno.h>
#include <event2/buffer.h>
#include <event2/event.h>
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
	struct evbuffer *batch = evbuffer_new(), *answers = evbuffer_new();
	struct event *resume = evtimer_new(server->base, on_resume, c);
	struct event *hello_timer = evtimer_new(server->base, on_hello_timeout, c);
	bool io = false;
	if (c) {
		c->server = server;
		io = server_io_init(c, fd) == 0;
	}
	if (!io || !batch || !answers || !resume || !hello_timer) {
		log_error("refusing a connection: out of memory");
		server_quota_leave(server, cred.uid, restricted);
		if (io)
			server_io_finish(c); /* closes fd */
		else
			close(fd);
		free(c);
		if (batch)
			evbuffer_free(batch);
		if (answers)
			evbuffer_free(answers);
		if (resume)
			event_free(resume);
		if (hello_timer)
			event_free(hello_timer);
		return;
	}
	c->resume = resume;
	c->hello_timer = hello_timer;
	c->batch = batch;
	c->answers = answers;
	c->uid = cred.uid;
	c->restricted = restricted;
	c->id = server->next_client++;
	if (!server->next_client)
		server->next_client = 1; /* 0 is "no owner" */
	if (vis_idmap_put(&server->clients_by_id, c->id, c) < 0) {
		log_error("refusing a connection: out of memory");
		server_quota_leave(server, cred.uid, restricted);
		server_io_finish(c);
		evbuffer_free(batch);
		evbuffer_free(answers);
		event_free(resume);
		event_free(hello_timer);
		free(c);
		return;
	}
	server_output_init(c);
	TAILQ_INSERT_TAIL(&server->clients, c, link);
	server->n_clients++;
	server_io_update(c); /* reading starts */
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
	if (!c->n_windows)
		return; /* no walk of the tree for each connection that made no window */
	for (struct vis_window *w = server->vis->core.root.bottom; w; w = vis_wtree_next(w)) {
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
		struct vis_window *v = vis_wtree_find(&server->vis->core, ids[i]);
		if (!v)
			continue; /* went with an ancestor */
		if (v->retained) {
			server_quota_orphan(server, v, c);
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
	server_io_finish(c);
	evbuffer_free(c->batch);
	evbuffer_free(c->answers);
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
	server_io_update(c);
	server_io_list(c); /* the end of the turn frees it once its output is out */
}

void server_client_send(struct client *c, uint32_t opcode, const union vis_arg *args)
{
	if (c->capture) {
		/* A batch's change: the reply waits in answers for the replies before it. */
		if (vis_msg_encode(c->capture, opcode, args) < 0) {
			log_error("client %u: cannot hold a %s reply", c->id,
				  vis_msg_type_find(opcode)->name);
			server_client_close(c);
		}
		return;
	}
	server_output_release(c); /* replies come after the notices of earlier requests */
	server_client_write(c, opcode, args);
}

void server_client_write(struct client *c, uint32_t opcode, const union vis_arg *args)
{
	struct vis_buf *b = &c->server->scratch;
	b->len = 0;
	if (c->closing && opcode != VIS_OP_ERROR)
		return;
	if (vis_msg_encode(b, opcode, args) < 0) {
		log_error("client %u: cannot encode a %s message", c->id,
			  vis_msg_type_find(opcode)->name);
		server_client_close(c);
		return;
	}
	server_client_queue(c, b->data, b->len);
}

void server_client_queue(struct client *c, const void *data, size_t len)
{
	uint8_t *p = server_io_reserve(c, len);
	if (p)
		memcpy(p, data, len);
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
		if (c->write_failed && server_batch_no_effect(op))
			return; /* nobody can read its answer: it would be work for nothing */
		if (op == VIS_OP_BATCH_COMMIT)
			server_client_error(c, seq, op, VIS_ERROR_STATE, "batch-commit without a batch");
		else if (op == VIS_OP_BATCH_BEGIN) {
			c->in_batch = true;
			c->batch_bytes = 0;
		}
		else
			server_client_dispatch(c, seq, m);
		return;
	}
	if (op == VIS_OP_BATCH_COMMIT) {
		server_batch_commit(c);
	} else if (c->batch_bytes + m->size > c->server->opt.max_batch) {
		/* Fatal: answering now would break the order of the replies to what is held. */
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "the batch's requests would take over %u bytes; closing the "
				    "connection",
				    c->server->opt.max_batch);
		server_client_close(c);
	} else {
		uint8_t s[4];
		c->batch_bytes += m->size;
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
 * Stops reading from c until its output drains. The socket's read event goes too: with it, a
 * client that sends without reading kept the event loop spinning on its unread input.
 */
static void block_reading(struct client *c)
{
	c->read_blocked = true;
	server_io_update(c);
}

/* Reads from c again, and serves what waits, next turn. */
static void unblock_reading(struct client *c)
{
	c->read_blocked = false;
	server_io_update(c);
	resume_next_turn(c);
}

/* What one connection has spent of its turn of the event loop. */
struct turn {
	int budget;          /* requests it may still run */
	uint64_t recomputes; /* the server's counts when the turn began */
	uint64_t work;
};

/*
 * Whether c may run another request in this turn: not past the budget, nor once a request made
 * the daemon recompute or walk SERVER_TURN_WORK windows. If not, c is served again next turn.
 */
static bool turn_left(struct client *c, struct turn *t)
{
	struct server *server = c->server;
	if (t->budget > 0 && server->recomputes == t->recomputes &&
	    server->work - t->work < SERVER_TURN_WORK)
		return true;
	resume_next_turn(c);
	return false;
}

/*
 * Whether a request that reports states should wait for the recompute at the end of this turn,
 * which the others' changes of the turn share, rather than force one of its own now. A request
 * waits once at most, so that others' changes cannot hold it back turn after turn.
 */
static bool wait_for_recompute(struct client *c, const struct vis_msg *m)
{
	if (!server_dirty(c->server) || c->in_batch || c->waited)
		return false;
	switch (m->type->opcode) {
	case VIS_OP_CREATE:
		if (!(m->args[5].u & VIS_CREATE_MAP))
			return false; /* reports no state: created unmapped */
		/* fall through */
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
 * Sends and runs what a committed batch left in answers, in request order, as requests read after
 * the commit would run: within the turn's budget, and not while the output is full. True once
 * answers is empty.
 */
static bool run_answers(struct client *c, struct turn *t)
{
	struct server *server = c->server;
	int replies = SERVER_REPLY_BUDGET;
	while (evbuffer_get_length(c->answers) && !c->closing) {
		if (server_output_pending(c) >= server->opt.max_pending) {
			block_reading(c);
			return false;
		}
		uint8_t *p = evbuffer_pullup(c->answers, SERVER_ANSWER_HEADER);
		uint32_t kind = vis_wire_get_u32(p), seq = vis_wire_get_u32(p + 4);
		uint32_t size = vis_wire_get_u32(p + 8);
		if (kind == SERVER_ANSWER_REPLY && !replies--) {
			resume_next_turn(c);
			return false;
		}
		if (kind == SERVER_ANSWER_REQUEST && !turn_left(c, t))
			return false;
		p = evbuffer_pullup(c->answers, SERVER_ANSWER_HEADER + (ssize_t)size);
		struct vis_msg m;
		char why[200];
		if (kind == SERVER_ANSWER_REPLY) {
			server_output_release(c); /* as server_client_send() */
			server_client_queue(c, p + SERVER_ANSWER_HEADER, size);
		} else if (vis_msg_decode(p + SERVER_ANSWER_HEADER, size, size, 1, &m, why,
					  sizeof why) != VIS_DECODE_OK) {
			log_error("client %u: a held request no longer decodes: %s", c->id, why);
		} else if (c->write_failed) {
			/* Nobody can read its answer. */
		} else if (wait_for_recompute(c, &m)) {
			resume_next_turn(c);
			return false;
		} else {
			c->waited = false;
			t->budget--;
			server_client_dispatch(c, seq, &m);
		}
		evbuffer_drain(c->answers, SERVER_ANSWER_HEADER + (size_t)size);
	}
	if (c->close_after_answers)
		server_client_close(c);
	return !c->closing;
}

/* The peer hung up and everything it sent has run: say what could not, and close. */
static void finish_hangup(struct client *c)
{
	size_t left;
	server_io_input(c, &left);
	if (left)
		log_info("client %u hung up in the middle of a request: %zu bytes dropped", c->id,
			 left);
	if (c->in_batch)
		log_info("client %u hung up inside a batch: %zu bytes of held requests dropped",
			 c->id, evbuffer_get_length(c->batch));
	server_client_close(c);
}

/*
 * Runs the complete requests that have arrived, up to the turn's budget, then leaves the
 * recompute to the end of this turn of the event loop, so that others' requests read in the same
 * turn share it. A connection whose output is full is not read from until it drains. A committed
 * batch's answers go first: nothing new is read until they are done.
 */
static void serve(struct client *c)
{
	struct server *server = c->server;
	uint32_t max = server->opt.max_request;
	struct turn t = { SERVER_REQUEST_BUDGET, server->recomputes, server->work };
	bool starved = false; /* stopped for want of a whole request */
	while (run_answers(c, &t)) {
		size_t avail;
		const uint8_t *p = server_io_input(c, &avail);
		if (avail < VIS_MSG_HEADER) {
			starved = true;
			break;
		}
		if (server_output_pending(c) >= server->opt.max_pending) {
			block_reading(c);
			break;
		}
		uint32_t size;
		char why[200];
		struct vis_msg m;
		if (vis_msg_peek(p, avail, max, &size, why, sizeof why) == VIS_DECODE_OK) {
			if (avail < size) {
				starved = true;
				break;
			}
			if (!turn_left(c, &t))
				break;
		}
		enum vis_decode r = vis_msg_decode(p, avail, max, 1, &m, why, sizeof why);
		if (r == VIS_DECODE_OK && wait_for_recompute(c, &m)) {
			resume_next_turn(c);
			break;
		}
		c->waited = false;
		t.budget--;
		uint32_t seq = ++c->seq;
		if (r == VIS_DECODE_MALFORMED) {
			uint32_t op = vis_wire_get_u16(p + 4);
			const struct vis_msg_type *ty = vis_msg_type_find(op);
			bool known = ty && ty->dir == VIS_DIR_REQUEST;
			server_client_error(c, seq, op, known ? VIS_ERROR_MALFORMED : VIS_ERROR_OPCODE,
					    "%s", why);
			break;
		}
		handle(c, seq, &m, p);
		server_io_consume(c, size);
	}
	server_io_update(c); /* what ran made room to read more */
	server_schedule_flush(server);
	if (c->hung_up && starved && !c->closing)
		finish_hangup(c);
	if (c->closing && (c->write_failed || !server_output_pending(c)))
		server_client_free(c);
}

void server_client_input(struct client *c)
{
	serve(c);
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
void server_client_drained(struct client *c)
{
	if (!c->closing)
		server_output_release(c);
	if (c->read_blocked && server_output_pending(c) < c->server->opt.max_pending / 2)
		unblock_reading(c);
	if (c->closing && !server_output_pending(c))
		server_client_free(c);
}

/*
 * The peer hung up, or writing to it failed. What the peer sent before still runs, in order, as if
 * it had stayed (a client may create retained windows and exit at once); after a half-close every
 * reply is delivered first. Once writing fails, what it would be sent is dropped instead.
 */
static void peer_gone(struct client *c)
{
	if (c->closing) {
		if (c->write_failed || !server_output_pending(c))
			server_client_free(c);
		return;
	}
	if (!c->read_blocked)
		serve(c); /* else server_client_drained() or the resume does */
}

void server_client_hangup(struct client *c)
{
	peer_gone(c);
}

void server_client_write_failed(struct client *c)
{
	c->write_failed = true;
	server_io_discard(c);
	if (c->read_blocked)
		unblock_reading(c);
	peer_gone(c);
}
