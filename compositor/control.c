#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <wayland-server-core.h>
#include <wlr/util/log.h>

#include "control.h"
#include "server.h"

/* The most bytes an answer may hold: `list --json` of thousands of views fits. */
#define MAX_REPLY (16u << 20)
/* The most words of a command line. */
#define MAX_WORDS 16

struct control_conn {
	struct control *control;
	int fd;
	struct wl_event_source *source;
	struct wl_list link; /* control.conns */
	char in[CONTROL_MAX_LINE + 1];
	size_t in_len;
	struct control_reply reply;
	size_t sent; /* of reply.len; the answer is set once reply.data != NULL */
};

struct control {
	struct server *server;
	int fd;
	struct wl_event_source *source;
	struct wl_list conns;
	char path[sizeof(((struct sockaddr_un *)0)->sun_path)];
};

void control_reply_printf(struct control_reply *reply, const char *fmt, ...)
{
	if (reply->failed)
		return;
	for (;;) {
		va_list args;
		va_start(args, fmt);
		size_t room = reply->cap - reply->len;
		int n = vsnprintf(reply->data ? reply->data + reply->len : NULL, room, fmt, args);
		va_end(args);
		if (n < 0) {
			reply->failed = true;
			return;
		}
		if ((size_t)n < room) {
			reply->len += (size_t)n;
			return;
		}
		size_t cap = reply->cap ? reply->cap * 2 : 4096;
		while (cap - reply->len <= (size_t)n)
			cap *= 2;
		char *data = cap <= MAX_REPLY ? realloc(reply->data, cap) : NULL;
		if (data == NULL) {
			reply->failed = true;
			return;
		}
		reply->data = data;
		reply->cap = cap;
	}
}

/* Closes a connection, answered or not. */
static void conn_destroy(struct control_conn *conn)
{
	wl_event_source_remove(conn->source);
	close(conn->fd);
	wl_list_remove(&conn->link);
	free(conn->reply.data);
	free(conn);
}

/* Splits the line into words and runs it; the answer waits in conn->reply. */
static void run_line(struct control_conn *conn)
{
	char *argv[MAX_WORDS + 1];
	int argc = 0;
	char *save = NULL;
	for (char *word = strtok_r(conn->in, " \t\r\n", &save); word != NULL;
	     word = strtok_r(NULL, " \t\r\n", &save)) {
		if (argc == MAX_WORDS) {
			control_reply_printf(&conn->reply, "error: more than %d words\n", MAX_WORDS);
			return;
		}
		argv[argc++] = word;
	}
	argv[argc] = NULL;
	control_command_run(conn->control->server, argc, argv, &conn->reply);
	if (conn->reply.failed) {
		free(conn->reply.data);
		conn->reply = (struct control_reply){ 0 };
		control_reply_printf(&conn->reply, "error: out of memory\n");
	}
}

/* Writes what is left of the answer; true when the connection is done with. */
static bool flush(struct control_conn *conn)
{
	while (conn->sent < conn->reply.len) {
		ssize_t n = send(conn->fd, conn->reply.data + conn->sent,
				 conn->reply.len - conn->sent, MSG_NOSIGNAL);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0 && errno == EAGAIN)
			return false;
		if (n <= 0)
			return true;
		conn->sent += (size_t)n;
	}
	return true;
}

/* Reads a connection's line, runs it once whole, and writes the answer as the socket takes it. */
static int handle_conn(int fd, uint32_t mask, void *data)
{
	(void)fd;
	struct control_conn *conn = data;
	if (conn->reply.data == NULL && (mask & WL_EVENT_READABLE)) {
		ssize_t n = recv(conn->fd, conn->in + conn->in_len, CONTROL_MAX_LINE - conn->in_len, 0);
		if (n < 0 && (errno == EAGAIN || errno == EINTR))
			return 0;
		if (n < 0) {
			conn_destroy(conn);
			return 0;
		}
		conn->in_len += (size_t)n;
		conn->in[conn->in_len] = '\0';
		char *newline = memchr(conn->in, '\n', conn->in_len);
		if (newline != NULL)
			*newline = '\0';
		if (newline == NULL && n > 0 && conn->in_len == CONTROL_MAX_LINE)
			control_reply_printf(&conn->reply, "error: a line longer than %d bytes\n",
					     CONTROL_MAX_LINE);
		else if (newline != NULL || n == 0)
			run_line(conn);
		else
			return 0; /* more to come */
		if (conn->reply.data == NULL)
			control_reply_printf(&conn->reply, "error: out of memory\n");
	} else if (mask & (WL_EVENT_HANGUP | WL_EVENT_ERROR)) {
		conn_destroy(conn);
		return 0;
	}
	if (conn->reply.data == NULL)
		return 0;
	if (flush(conn))
		conn_destroy(conn);
	else
		wl_event_source_fd_update(conn->source, WL_EVENT_WRITABLE);
	return 0;
}

/* Accepts a control connection. */
static int handle_listen(int fd, uint32_t mask, void *data)
{
	(void)mask;
	struct control *control = data;
	int cfd = accept4(fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
	if (cfd < 0) {
		/* EMFILE and the like: this connection is lost, the socket lives on. */
		if (errno != EAGAIN && errno != EINTR)
			wlr_log_errno(WLR_ERROR, "control socket: accept");
		return 0;
	}
	struct control_conn *conn = calloc(1, sizeof(*conn));
	if (conn == NULL) {
		close(cfd);
		return 0;
	}
	conn->control = control;
	conn->fd = cfd;
	conn->source = wl_event_loop_add_fd(control->server->loop, cfd, WL_EVENT_READABLE,
					    handle_conn, conn);
	if (conn->source == NULL) {
		close(cfd);
		free(conn);
		return 0;
	}
	wl_list_insert(&control->conns, &conn->link);
	return 0;
}

/* Whether something listens on the socket at path. */
static bool alive(const struct sockaddr_un *addr)
{
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0)
		return false;
	bool ok = connect(fd, (const struct sockaddr *)addr, sizeof(*addr)) == 0;
	close(fd);
	return ok;
}

struct control *control_create(struct server *server, const char *path, const char *display)
{
	struct control *control = calloc(1, sizeof(*control));
	if (control == NULL)
		return NULL;
	control->server = server;
	control->fd = -1;
	wl_list_init(&control->conns);
	int len;
	if (path != NULL)
		len = snprintf(control->path, sizeof(control->path), "%s", path);
	else
		len = snprintf(control->path, sizeof(control->path), "%s/viscomp-%s.sock",
			       getenv("XDG_RUNTIME_DIR"), display);
	if (len < 0 || (size_t)len >= sizeof(control->path)) {
		wlr_log(WLR_ERROR, "control socket: the path is too long");
		goto fail;
	}
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	memcpy(addr.sun_path, control->path, (size_t)len + 1);
	if (alive(&addr)) {
		wlr_log(WLR_ERROR, "control socket %s: in use", control->path);
		goto fail;
	}
	unlink(control->path);
	control->fd = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
	if (control->fd < 0 ||
	    bind(control->fd, (const struct sockaddr *)&addr, sizeof(addr)) < 0 ||
	    listen(control->fd, 16) < 0) {
		wlr_log_errno(WLR_ERROR, "control socket %s", control->path);
		goto fail;
	}
	control->source = wl_event_loop_add_fd(server->loop, control->fd, WL_EVENT_READABLE,
					       handle_listen, control);
	if (control->source == NULL)
		goto fail;
	return control;
fail:
	if (control->fd >= 0)
		close(control->fd);
	free(control);
	return NULL;
}

void control_destroy(struct control *control)
{
	if (control == NULL)
		return;
	struct control_conn *conn, *tmp;
	wl_list_for_each_safe(conn, tmp, &control->conns, link)
		conn_destroy(conn);
	wl_event_source_remove(control->source);
	close(control->fd);
	unlink(control->path);
	free(control);
}

const char *control_socket_path(const struct control *control)
{
	return control->path;
}
