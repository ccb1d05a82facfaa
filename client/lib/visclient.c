/*
 * libvisclient's connection: the socket, reading and writing without blocking, the synchronous
 * waits, and the handshake. What the daemon's messages mean is visclient-dispatch.c's business.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/un.h>
#include <unistd.h>

#include "codec.h"
#include "visclient-private.h"

/* Queued output is written once it reaches this; past the limit the daemon is not reading. */
#define FLUSH_AT (64u << 10)
#define QUEUE_LIMIT (64u << 20)
/* Room asked of each read; a message announced as larger gets room for all of it. */
#define READ_CHUNK (64u << 10)

/* Keeps the first error only: later ones follow from it. */
void vis_client_fail(struct vis_client *c, int err, const char *fmt, ...)
{
	if (c->error)
		return;
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(c->error_message, sizeof(c->error_message), fmt, ap);
	va_end(ap);
	c->error = err ? err : EIO;
}

/*
 * Reads once without blocking, making room for at least READ_CHUNK bytes, or for the whole of a
 * message whose header is in (its size was checked against the protocol's maximum). Returns 1
 * when bytes came, 0 when none were ready, -1 at EOF or on an error (then the error is set,
 * except at EOF, which the caller judges once buffered messages are handled).
 */
static int read_some(struct vis_client *c)
{
	if (c->in_off) {
		vis_buf_consume(&c->in, c->in_off);
		c->in_off = 0;
	}
	size_t want = READ_CHUNK;
	uint32_t size;
	char why[200];
	if (vis_msg_peek(c->in.data, c->in.len, VIS_PROTOCOL_MAX_MESSAGE, &size, why,
			 sizeof(why)) == VIS_DECODE_OK && size > c->in.len + want)
		want = size - c->in.len;
	size_t len = c->in.len;
	if (vis_buf_reserve(&c->in, want) < 0) {
		vis_client_fail(c, ENOMEM, "out of memory reading from the daemon");
		return -1;
	}
	for (;;) {
		ssize_t r = recv(c->fd, c->in.data + len, c->in.cap - len, MSG_DONTWAIT);
		if (r > 0) {
			c->in.len += (size_t)r;
			return 1;
		}
		if (r == 0)
			return -1;
		if (errno == EINTR)
			continue;
		if (errno == EAGAIN || errno == EWOULDBLOCK)
			return 0;
		vis_client_fail(c, errno, "reading from the daemon: %s", strerror(errno));
		return -1;
	}
}

int vis_client_dispatch(struct vis_client *c)
{
	if (c->error)
		return -1;
	if (c->out.len && vis_client_flush(c) < 0) /* what the socket did not take before */
		return -1;
	int r = read_some(c);
	int handled = vis_client_process(c);
	if (r < 0 && !c->error) {
		if (c->in_off < c->in.len)
			vis_client_fail(c, EPROTO, "the daemon closed the connection inside a message");
		else
			vis_client_fail(c, ECONNRESET, "the daemon closed the connection");
	}
	return c->error ? -1 : handled;
}

int vis_client_flush(struct vis_client *c)
{
	if (c->error)
		return -1;
	size_t done = 0;
	int ret = 0;
	while (done < c->out.len) {
		ssize_t r = send(c->fd, c->out.data + done, c->out.len - done,
				 MSG_NOSIGNAL | MSG_DONTWAIT);
		if (r >= 0) {
			done += (size_t)r;
		} else if (errno == EAGAIN || errno == EWOULDBLOCK) {
			ret = 1;
			break;
		} else if (errno != EINTR) {
			int err = errno;
			/* A daemon that refused us said why before it closed: read that first. */
			if (err == EPIPE || err == ECONNRESET) {
				while (read_some(c) > 0)
					;
				vis_client_process(c);
			}
			if (!c->error)
				vis_client_fail(c, err, "writing to the daemon: %s", strerror(err));
			ret = -1;
			break;
		}
	}
	vis_buf_consume(&c->out, done);
	return ret;
}

int vis_client_wait(struct vis_client *c, const int *done)
{
	/* Messages already read (a synchronous call from a handler) may hold the answer. */
	vis_client_process(c);
	while (!*done && !c->error) {
		int f = vis_client_flush(c);
		if (f < 0)
			break;
		struct pollfd pfd = { .fd = c->fd, .events = POLLIN | (f ? POLLOUT : 0) };
		if (poll(&pfd, 1, -1) < 0) {
			if (errno != EINTR)
				vis_client_fail(c, errno, "waiting for the daemon: %s", strerror(errno));
			continue;
		}
		if (pfd.revents & (POLLIN | POLLHUP | POLLERR))
			vis_client_dispatch(c);
	}
	return *done ? 0 : -1;
}

uint32_t vis_client_send(struct vis_client *c, uint32_t opcode, const union vis_arg *args,
			 const struct vis_pending *pending)
{
	if (c->error)
		return 0;
	if (c->next_seq == 0) {
		vis_client_fail(c, EOVERFLOW, "request numbers are used up");
		return 0;
	}
	size_t before = c->out.len;
	if (vis_msg_encode(&c->out, opcode, args) < 0) {
		if (errno == ENOMEM)
			vis_client_fail(c, ENOMEM, "out of memory queuing %s", vis_request_name(opcode));
		return 0;
	}
	if (c->max_request && c->out.len - before > c->max_request) {
		c->out.len = before;
		errno = EMSGSIZE;
		return 0;
	}
	if (pending) {
		if (c->len == c->cap) {
			size_t cap = c->cap ? c->cap * 2 : 16;
			struct vis_pending *p = realloc(c->pending, cap * sizeof(*p));
			if (!p) {
				c->out.len = before;
				vis_client_fail(c, ENOMEM, "out of memory queuing %s", vis_request_name(opcode));
				return 0;
			}
			c->pending = p;
			c->cap = cap;
		}
		struct vis_pending *p = &c->pending[c->len++];
		*p = *pending;
		p->seq = c->next_seq;
		p->opcode = opcode;
		p->items = NULL;
		p->n = p->cap = 0;
	}
	uint32_t seq = c->next_seq++;
	/* Written at once, without blocking, so that no request waits for a flush the program may
	 * never call; a batch's requests go together at its commit (or once FLUSH_AT bytes wait). */
	if ((!c->in_batch || c->out.len >= FLUSH_AT) && vis_client_flush(c) == 1 &&
	    c->out.len > QUEUE_LIMIT)
		vis_client_fail(c, ENOBUFS, "%zu bytes queued: the daemon is not reading", c->out.len);
	return c->error ? 0 : seq;
}

unsigned long vis_client_error_count(const struct vis_client *c)
{
	return c->error_count;
}

/* Called when a sync or roundtrip reply comes. */
static void on_done(void *data, const struct vis_error *err)
{
	(void)err;
	*(int *)data = 1;
}

int vis_client_refuse_in_batch(const struct vis_client *c)
{
	if (!c->in_batch)
		return 0;
	errno = EDEADLK;
	return 1;
}

int vis_client_roundtrip(struct vis_client *c)
{
	int done = 0;
	if (vis_client_refuse_in_batch(c))
		return -1;
	if (!vis_client_sync_async(c, on_done, &done))
		return -1;
	return vis_client_wait(c, &done);
}

int vis_client_batch_roundtrip(struct vis_client *c)
{
	int done = 0;
	if (!c->in_batch)
		return vis_client_roundtrip(c);
	if (!vis_client_sync_async(c, on_done, &done) || !vis_client_batch_commit(c))
		return -1;
	return vis_client_wait(c, &done);
}

int vis_client_sync(struct vis_client *c)
{
	if (vis_client_roundtrip(c) < 0)
		return -1;
	int clean = c->error_count == c->sync_mark;
	c->sync_mark = c->error_count;
	return clean ? 0 : -1;
}

const char *vis_client_version(void)
{
	return VIS_CLIENT_VERSION;
}

int vis_client_default_socket(char *buf, size_t len)
{
	const char *env = getenv("VISD_SOCKET");
	int n;
	if (env && *env)
		n = snprintf(buf, len, "%s", env);
	else if ((env = getenv("XDG_RUNTIME_DIR")) && *env)
		n = snprintf(buf, len, "%s/visd-0", env);
	else
		return -1;
	return n < 0 || (size_t)n >= len ? -1 : 0;
}

/*
 * Whether a process holds an flock on file: visd holds SOCKET.lock while it runs. Reads
 * /proc/locks rather than trying the lock, which could make a visd starting at that moment think
 * another holds it. Returns 1, 0, or -1 when it cannot tell.
 */
static int lock_held(const char *file)
{
	struct stat st;
	if (stat(file, &st) < 0)
		return errno == ENOENT ? 0 : -1;
	FILE *f = fopen("/proc/locks", "re");
	if (!f)
		return -1;
	char line[256], kind[16];
	unsigned maj, min;
	unsigned long long ino;
	int held = 0;
	while (!held && fgets(line, sizeof(line), f))
		held = sscanf(line, "%*s %15s %*s %*s %*d %x:%x:%llu", kind, &maj, &min, &ino) == 4 &&
		       strcmp(kind, "FLOCK") == 0 && maj == major(st.st_dev) &&
		       min == minor(st.st_dev) && ino == (unsigned long long)st.st_ino;
	fclose(f);
	return held;
}

/*
 * Says what refused a connection at path: what is there (a socket nothing listens on is what a
 * visd that was killed or crashed leaves; a file is not a socket at all), and whether a visd
 * runs on the path (holds its lock). "" when path is gone or cannot be read.
 */
static const char *refused_why(const char *path, char *buf, size_t len)
{
	struct stat st;
	char lock[sizeof(((struct sockaddr_un *)0)->sun_path) + 5];
	if (lstat(path, &st) < 0)
		return "";
	snprintf(lock, sizeof(lock), "%s.lock", path);
	int held = lock_held(lock);
	bool sock = S_ISSOCK(st.st_mode), file = S_ISREG(st.st_mode);
	const char *what = sock ? "the socket there has no listener: the visd that made it has gone "
				  "(killed or crashed)"
			   : file		 ? "it is a regular file, not a socket"
			   : S_ISDIR(st.st_mode) ? "it is a directory, not a socket"
						 : "it is not a socket";
	const char *visd = held > 0 ? "; yet a visd holds its .lock: one runs for this path "
				      "(starting, stopping, or its socket was replaced)"
			   : held < 0	       ? ""
			   : sock || file ? "; no visd holds its .lock, so none runs for this path "
					    "(a new one replaces what is there)"
					  : "; no visd holds its .lock, so none runs for this path";
	snprintf(buf, len, ": %s%s", what, visd);
	return buf;
}

/* Opens the socket and sends hello; errors are left sticky on c. */
static void connect_socket(struct vis_client *c, const char *path, uint32_t role)
{
	char def[sizeof(((struct sockaddr_un *)0)->sun_path)];
	if (!path || !*path) { /* "" as NULL: an unset variable passed on is no path at all */
		if (vis_client_default_socket(def, sizeof(def)) < 0) {
			vis_client_fail(c, ENOENT, "no socket given and neither VISD_SOCKET nor "
					"XDG_RUNTIME_DIR is set");
			return;
		}
		path = def;
	}
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	if (strlen(path) >= sizeof(addr.sun_path)) {
		vis_client_fail(c, ENAMETOOLONG, "socket path too long: %s", path);
		return;
	}
	strcpy(addr.sun_path, path);
	c->fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (c->fd < 0) {
		vis_client_fail(c, errno, "socket: %s", strerror(errno));
		return;
	}
	int r;
	do
		r = connect(c->fd, (struct sockaddr *)&addr, sizeof(addr));
	while (r < 0 && errno == EINTR);
	if (r < 0 || fcntl(c->fd, F_SETFL, fcntl(c->fd, F_GETFL) | O_NONBLOCK) < 0) {
		int err = errno;
		char why[200];
		vis_client_fail(c, err, "cannot connect to %s: %s%s", path, strerror(err),
				err == ECONNREFUSED ? refused_why(path, why, sizeof(why)) : "");
		return;
	}
	if (vis_client_hello(c, role))
		vis_client_wait(c, &c->connected);
}

uint32_t vis_client_hello(struct vis_client *c, uint32_t role)
{
	union vis_arg args[3] = { { .u = VIS_PROTOCOL_MAGIC },
				  { .u = VIS_PROTOCOL_VERSION },
				  { .u = role } };
	struct vis_pending p = { .kind = VIS_REPLY_HELLO };
	return vis_client_send(c, VIS_OP_HELLO, args, &p);
}

struct vis_client *vis_client_adopt(int fd)
{
	struct vis_client *c = calloc(1, sizeof(*c));
	if (!c)
		return NULL;
	c->fd = fd;
	c->next_seq = 1;
	c->next_serial = 1;
	vis_buf_init(&c->out);
	vis_buf_init(&c->in);
	return c;
}

struct vis_client *vis_client_connect(const char *path, uint32_t role)
{
	/* No socket yet: connect_socket opens it. */
	struct vis_client *c = vis_client_adopt(-1);
	if (c)
		connect_socket(c, path, role);
	return c;
}

void vis_client_destroy(struct vis_client *c)
{
	if (!c)
		return;
	if (c->fd >= 0)
		close(c->fd);
	for (size_t i = c->head; i < c->len; i++)
		free(c->pending[i].items);
	free(c->pending);
	vis_buf_finish(&c->out);
	vis_buf_finish(&c->in);
	free(c);
}

int vis_client_error(const struct vis_client *c)
{
	return c->error;
}

const char *vis_client_error_message(const struct vis_client *c)
{
	return c->error ? c->error_message : "";
}

int vis_client_last_error(const struct vis_client *c, struct vis_error *err)
{
	if (!c->has_last_error)
		return 0;
	*err = c->last_error;
	return 1;
}

uint32_t vis_client_role(const struct vis_client *c)
{
	return c->role;
}

uint32_t vis_client_id(const struct vis_client *c)
{
	return c->id;
}

void vis_client_screen(const struct vis_client *c, uint32_t *width, uint32_t *height)
{
	*width = c->screen_width;
	*height = c->screen_height;
}

void vis_client_set_notice_handler(struct vis_client *c, vis_notice_handler handler, void *data)
{
	c->notice = handler;
	c->notice_data = data;
}

void vis_client_set_error_handler(struct vis_client *c, vis_error_handler handler, void *data)
{
	c->on_error = handler;
	c->error_data = data;
}

int vis_client_fd(const struct vis_client *c)
{
	return c->fd;
}
