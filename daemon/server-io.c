/*
 * A connection's socket and the bytes on their way in and out. With a hundred subscribers, what
 * the fan-out costs is mostly system calls, so each one is made to count:
 * - a readable socket is read once, into the connection's own buffer, for as much as there is
 *   room: no FIONREAD before the read (as evbuffer_read makes) and no second read to find
 *   EAGAIN; epoll's level-triggered readiness calls again while bytes remain;
 * - replies and notices are appended to one buffer, and the end of the turn of the event loop
 *   writes each connection's once, with one write(), whatever the turn queued to it;
 * - write interest (EPOLLOUT) is armed only when the kernel took less than everything, and
 *   disarmed once the buffer drained: a reader that keeps up costs no epoll_ctl at all.
 */
#include <errno.h>
#include <event2/event.h>
#include <string.h>
#include <unistd.h>

#include "log.h"
#include "server.h"

/* The input buffer's first size; it doubles when a read fills it, up to the read bound. */
#define IO_READ_FIRST 4096u
/* An output buffer larger than this is freed once it drains: a burst does not pin its memory. */
#define IO_OUT_KEEP 65536u

static void on_readable(evutil_socket_t fd, short what, void *data);
static void on_writable(evutil_socket_t fd, short what, void *data);

/* Bytes read and not yet run past which a connection is not read from: a maximum request, and
 * 64 KiB more (at least 64 KiB). */
static size_t read_bound(const struct server *server)
{
	uint32_t max = server->opt.max_request;
	return (size_t)(max < 65536 ? 65536 : max) + 65536;
}

int server_io_init(struct client *c, int fd)
{
	struct conn *io = &c->io;
	io->fd = fd;
	vis_buf_init(&io->in);
	vis_buf_init(&io->out);
	io->read_ev = event_new(c->server->base, fd, EV_READ | EV_PERSIST, on_readable, c);
	io->write_ev = event_new(c->server->base, fd, EV_WRITE | EV_PERSIST, on_writable, c);
	if (io->read_ev && io->write_ev)
		return 0;
	if (io->read_ev)
		event_free(io->read_ev);
	if (io->write_ev)
		event_free(io->write_ev);
	return -1;
}

void server_io_finish(struct client *c)
{
	struct conn *io = &c->io;
	if (io->listed)
		TAILQ_REMOVE(&c->server->to_write, c, io.link);
	event_free(io->read_ev);
	event_free(io->write_ev);
	close(io->fd);
	vis_buf_finish(&io->in);
	vis_buf_finish(&io->out);
}

const uint8_t *server_io_input(const struct client *c, size_t *len)
{
	*len = c->io.in.len - c->io.in_used;
	return c->io.in.data + c->io.in_used;
}

void server_io_consume(struct client *c, size_t n)
{
	c->io.in_used += n;
}

/*
 * Reading stops once the bound is read ahead and starts again when half of that has run: a
 * connection that pipelines faster than its turns serve it is read in large reads, not in one
 * small read (and two epoll_ctl) a turn.
 */
void server_io_update(struct client *c)
{
	struct conn *io = &c->io;
	size_t unread = io->in.len - io->in_used, bound = read_bound(c->server);
	bool want = !c->hung_up && !c->closing && !c->read_blocked &&
		    (io->reading ? unread < bound : unread <= bound / 2);
	if (want == io->reading)
		return;
	io->reading = want;
	if (want)
		event_add(io->read_ev, NULL);
	else
		event_del(io->read_ev);
}

/*
 * Makes room at the end of c's input for one read, and returns how much (at least 1; 0 when the
 * read bound is reached or memory ran out). The unread bytes move to the front once they are no
 * more than those already run, so that moving costs no more than reading did.
 */
static size_t input_room(struct client *c)
{
	struct conn *io = &c->io;
	size_t unread = io->in.len - io->in_used, bound = read_bound(c->server);
	if (io->in_used && (io->in_used >= unread || io->in.len == io->in.cap)) {
		vis_buf_consume(&io->in, io->in_used);
		io->in_used = 0;
	}
	if (unread >= bound)
		return 0;
	if ((io->in.len == io->in.cap || io->filled) && io->in.cap < bound) {
		if (vis_buf_reserve(&io->in, io->in.cap ? io->in.cap : IO_READ_FIRST) < 0) {
			log_error("client %u: out of memory for its input", c->id);
			server_client_close(c);
			return 0;
		}
		io->filled = false;
	}
	size_t room = io->in.cap - io->in.len;
	return room < bound - unread ? room : bound - unread;
}

/* The socket is readable: one read, then the requests run. */
static void on_readable(evutil_socket_t fd, short what, void *data)
{
	(void)what;
	struct client *c = data;
	struct conn *io = &c->io;
	size_t room = input_room(c);
	if (!room) {
		server_io_update(c);
		return;
	}
	ssize_t n = read(fd, io->in.data + io->in.len, room);
	if (n > 0) {
		io->in.len += (size_t)n;
		io->filled = (size_t)n == room;
		server_client_input(c);
		return;
	}
	if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR))
		return;
	if (n < 0)
		log_debug("client %u: %s while reading", c->id, strerror(errno));
	c->hung_up = true;
	server_io_update(c);
	server_client_hangup(c);
}

/* Arms or disarms write interest. */
static void set_writing(struct client *c, bool on)
{
	struct conn *io = &c->io;
	if (io->writing == on)
		return;
	io->writing = on;
	if (on)
		event_add(io->write_ev, NULL);
	else
		event_del(io->write_ev);
}

/* Empties the output buffer, freeing it if a burst made it large. */
static void reset_output(struct conn *io)
{
	io->out.len = io->out_sent = 0;
	if (io->out.cap > IO_OUT_KEEP)
		vis_buf_finish(&io->out);
}

/*
 * Writes what waits for c, in one call; what the kernel did not take waits for the socket to be
 * writable. Then, with the output down to a quarter of the bound, c is told (which may free it).
 */
static void write_out(struct client *c)
{
	struct conn *io = &c->io;
	size_t left = io->out.len - io->out_sent;
	if (left) {
		ssize_t n = write(io->fd, io->out.data + io->out_sent, left);
		if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
			log_debug("client %u: %s while writing", c->id, strerror(errno));
			server_client_write_failed(c);
			return;
		}
		if (n > 0)
			io->out_sent += (size_t)n;
		if (io->out_sent == io->out.len) {
			reset_output(io);
		} else if (io->out_sent >= io->out.len - io->out_sent) {
			/* Moving what is left costs no more than what was written. */
			vis_buf_consume(&io->out, io->out_sent);
			io->out_sent = 0;
		}
		set_writing(c, io->out_sent < io->out.len);
	}
	if (server_io_pending(c) <= c->server->opt.max_pending / 4)
		server_client_drained(c);
}

/* The kernel has room again for what it refused. */
static void on_writable(evutil_socket_t fd, short what, void *data)
{
	(void)fd;
	(void)what;
	write_out(data);
}

void server_io_list(struct client *c)
{
	struct conn *io = &c->io;
	if (io->listed || io->writing)
		return; /* a writable socket's callback writes it */
	io->listed = true;
	TAILQ_INSERT_TAIL(&c->server->to_write, c, io.link);
	server_schedule_turn_end(c->server);
}

uint8_t *server_io_reserve(struct client *c, size_t len)
{
	struct conn *io = &c->io;
	if (c->write_failed)
		return NULL;
	if (vis_buf_reserve(&io->out, len) < 0) {
		log_error("client %u: cannot queue %zu bytes: %s", c->id, len, strerror(errno));
		server_client_close(c);
		return NULL;
	}
	uint8_t *p = io->out.data + io->out.len;
	io->out.len += len;
	server_io_list(c);
	return p;
}

size_t server_io_pending(const struct client *c)
{
	return c->io.out.len - c->io.out_sent;
}

void server_io_discard(struct client *c)
{
	reset_output(&c->io);
	set_writing(c, false);
}

void server_io_write_all(struct server *server)
{
	struct client *c;
	while ((c = TAILQ_FIRST(&server->to_write))) {
		TAILQ_REMOVE(&server->to_write, c, io.link);
		c->io.listed = false;
		write_out(c);
	}
}
