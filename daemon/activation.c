/* Socket activation: taking the listening sockets a service manager passes (sd_listen_fds(3)). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include "activation.h"
#include "log.h"

/* The most sockets visd takes: the main one and the restricted one. */
#define MAX_SOCKETS 2
/* The name LISTEN_FDNAMES gives the restricted socket (systemd's FileDescriptorName=). */
#define RESTRICTED_NAME "restricted"

/* Parses a decimal number made of digits only, as sd_listen_fds does. Returns 0, or -1. */
static int parse_number(const char *s, unsigned long max, unsigned long *n)
{
	if (*s < '0' || *s > '9')
		return -1;
	char *end;
	errno = 0;
	unsigned long v = strtoul(s, &end, 10);
	if (errno || *end || v > max)
		return -1;
	*n = v;
	return 0;
}

/* What a descriptor that is not a socket is, for the error that refuses it. */
static const char *file_kind(mode_t mode)
{
	switch (mode & S_IFMT) {
	case S_IFREG: return "a regular file";
	case S_IFDIR: return "a directory";
	case S_IFCHR: return "a character device";
	case S_IFBLK: return "a block device";
	case S_IFIFO: return "a pipe";
	default: return "a file of another kind";
	}
}

/*
 * Checks that fd is a listening Unix stream socket, then makes it non-blocking (libevent's
 * listener accepts until EAGAIN) and close-on-exec, and finds where it is bound. Returns 0, or
 * -1 after logging why, naming LISTEN_FDS (its value is fds) and the descriptor.
 */
static int take_socket(int fd, const char *fds, struct activation_socket *s)
{
	struct stat st;
	struct sockaddr_un addr;
	socklen_t len = sizeof addr;
	int type = -1, listening = 0;
	socklen_t optlen = sizeof type;
	if (fcntl(fd, F_GETFD) < 0) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d is not open", fds, fd);
		return -1;
	}
	if (fstat(fd, &st) < 0) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d cannot be examined: %s", fds,
			  fd, strerror(errno));
		return -1;
	}
	if (!S_ISSOCK(st.st_mode)) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d is not a socket (%s)", fds, fd,
			  file_kind(st.st_mode));
		return -1;
	}
	memset(&addr, 0, sizeof addr);
	if (getsockname(fd, (struct sockaddr *)&addr, &len) < 0 || addr.sun_family != AF_UNIX) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d is not a Unix socket "
			  "(address family %d)", fds, fd, (int)addr.sun_family);
		return -1;
	}
	if (getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &optlen) < 0 || type != SOCK_STREAM) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d is not a stream socket "
			  "(SO_TYPE %d)", fds, fd, type);
		return -1;
	}
	optlen = sizeof listening;
	if (getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &optlen) < 0 || !listening) {
		log_error("socket activation: LISTEN_FDS=%s, but fd %d is a socket that is not "
			  "listening", fds, fd);
		return -1;
	}
	int fl = fcntl(fd, F_GETFL);
	if (fl < 0 || fcntl(fd, F_SETFL, fl | O_NONBLOCK) < 0 ||
	    fcntl(fd, F_SETFD, FD_CLOEXEC) < 0) {
		log_error("socket activation: fd %d: cannot make it non-blocking and close-on-exec: %s",
			  fd, strerror(errno));
		return -1;
	}
	s->fd = fd;
	/* sun_path need not end in a NUL when the name fills it: len says how much is the name. */
	size_t n = len > offsetof(struct sockaddr_un, sun_path)
			   ? len - offsetof(struct sockaddr_un, sun_path) : 0;
	if (n > sizeof addr.sun_path)
		n = sizeof addr.sun_path;
	if (n == 0 || (n == 1 && addr.sun_path[0] == '\0')) {
		strcpy(s->name, "(unnamed)");
	} else if (addr.sun_path[0] == '\0') {
		snprintf(s->name, sizeof s->name, "@%.*s", (int)(n - 1), addr.sun_path + 1);
	} else {
		snprintf(s->path, sizeof s->path, "%.*s", (int)n, addr.sun_path);
		strcpy(s->name, s->path);
	}
	return 0;
}

/*
 * Which of the n sockets is the restricted one, by LISTEN_FDNAMES (names, or NULL when unset):
 * its index, n when there is none. Returns -1 after logging why the names do not fit.
 */
static long restricted_index(const char *names, unsigned long n, const char *fds)
{
	unsigned long count = 0, found = n, restricted = 0;
	if (names) {
		for (const char *p = names;; p++) {
			size_t len = strcspn(p, ":");
			if (len == strlen(RESTRICTED_NAME) && !strncmp(p, RESTRICTED_NAME, len)) {
				found = count;
				restricted++;
			}
			count++;
			p += len;
			if (!*p)
				break;
		}
		if (count != n) {
			log_error("socket activation: LISTEN_FDNAMES='%s' names %lu sockets, but "
				  "LISTEN_FDS=%s", names, count, fds);
			return -1;
		}
	}
	if (n == 1 && restricted) {
		log_error("socket activation: LISTEN_FDNAMES='%s' makes fd %d the restricted socket, "
			  "but visd needs its main socket too", names, ACTIVATION_FDS_START);
		return -1;
	}
	if (n == 2 && restricted != 1) {
		log_error("socket activation: LISTEN_FDS=2, so LISTEN_FDNAMES must name one of fd %d "
			  "and fd %d '" RESTRICTED_NAME "' (the restricted socket), but it is %s%s%s",
			  ACTIVATION_FDS_START, ACTIVATION_FDS_START + 1, names ? "'" : "not set",
			  names ? names : "", names ? "'" : "");
		return -1;
	}
	return (long)found;
}

/* activation_take() before it unsets the variables. */
static int take(struct activation *a)
{
	const char *pid = getenv("LISTEN_PID"), *fds = getenv("LISTEN_FDS");
	const char *names = getenv("LISTEN_FDNAMES");
	unsigned long p, n;
	if (!pid)
		return 0;
	if (parse_number(pid, INT_MAX, &p) < 0 || p == 0) {
		log_error("socket activation: LISTEN_PID='%s' is not a process ID", pid);
		return -1;
	}
	if ((pid_t)p != getpid()) {
		log_debug("socket activation: LISTEN_PID=%s is another process, not this one (%ld): "
			  "nothing was passed to visd", pid, (long)getpid());
		return 0;
	}
	if (!fds) {
		log_warn("socket activation: LISTEN_PID=%s is this process, but LISTEN_FDS is not set: "
			 "nothing was passed", pid);
		return 0;
	}
	if (parse_number(fds, INT_MAX - ACTIVATION_FDS_START, &n) < 0 || n == 0) {
		log_error("socket activation: LISTEN_FDS='%s' is not a number of sockets (1 or more)",
			  fds);
		return -1;
	}
	if (n > MAX_SOCKETS) {
		log_error("socket activation: LISTEN_FDS=%s, but visd takes at most %d sockets: its main "
			  "one, and one named '" RESTRICTED_NAME "' in LISTEN_FDNAMES", fds, MAX_SOCKETS);
		return -1;
	}
	long r = restricted_index(names, n, fds);
	if (r < 0)
		return -1;
	for (unsigned long i = 0; i < n; i++) {
		struct activation_socket *s = (long)i == r ? &a->restricted : &a->main;
		if (take_socket(ACTIVATION_FDS_START + (int)i, fds, s) < 0)
			return -1;
	}
	return 1;
}

int activation_take(struct activation *a)
{
	memset(a, 0, sizeof *a);
	a->main.fd = a->restricted.fd = -1;
	int r = take(a);
	unsetenv("LISTEN_PID");
	unsetenv("LISTEN_FDS");
	unsetenv("LISTEN_FDNAMES");
	return r;
}
