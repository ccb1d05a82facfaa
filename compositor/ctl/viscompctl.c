/*
 * viscompctl: sends one command to viscomp's control socket and prints the answer (control.h
 * says the format): the answer's lines but its last, which says whether the command worked.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

static const char usage[] =
	"usage: viscompctl [-s PATH] COMMAND [ARG...]\n"
	"  Controls a running viscomp through its control socket.\n"
	"  -s PATH, --socket PATH  the socket (default: $VISCOMP_SOCKET, else\n"
	"                          $XDG_RUNTIME_DIR/viscomp-$WAYLAND_DISPLAY.sock)\n"
	"  -h, --help              this help\n"
	"commands:\n"
	"  list [--json]   the windows, top first: ID X,Y WxH STATE commits=N frames=N pid=PID\n"
	"                  APP_ID TITLE; with --json one object a line (id, app_id, title, pid,\n"
	"                  x, y, width, height, state, focused, frames, commits, frames_total,\n"
	"                  commits_total); frames and commits count the last second\n"
	"  move ID X Y     puts the window's top-left corner at X, Y\n"
	"  resize ID W H   asks the window's client for the size W x H\n"
	"  raise ID        puts the window on top\n"
	"  lower ID        puts the window at the bottom\n"
	"  close ID        asks the window's client to close it\n"
	"  redraw          draws every output whole at its next frame, not only its damage\n"
	"  outputs         the outputs: NAME X,Y WxH frames=N (frames drawn since it came)\n"
	"  stats [--reset] viscomp's own timings, one line each: frame (libvis's update and\n"
	"                  repaint sets in an output frame), cover and uncover (from a move,\n"
	"                  raise or lower to the first frame callback withheld or sent):\n"
	"                  NAME count=N median_us=M p99_us=P max_us=X, cover and uncover\n"
	"                  then max_frames=F (output frames); --reset: then from 0\n";

/* The socket's path: -s, else the environment's. NULL when there is none. */
static const char *socket_path(const char *given, char *buf, size_t size)
{
	if (given != NULL)
		return given;
	const char *env = getenv("VISCOMP_SOCKET");
	if (env != NULL && *env != '\0')
		return env;
	const char *dir = getenv("XDG_RUNTIME_DIR"), *display = getenv("WAYLAND_DISPLAY");
	if (dir == NULL || display == NULL)
		return NULL;
	int n = snprintf(buf, size, "%s/viscomp-%s.sock", dir, display);
	return n > 0 && (size_t)n < size ? buf : NULL;
}

/* Writes all of buf; -1 with errno. */
static int write_all(int fd, const char *buf, size_t len)
{
	while (len > 0) {
		ssize_t n = write(fd, buf, len);
		if (n < 0 && errno == EINTR)
			continue;
		if (n < 0)
			return -1;
		buf += n;
		len -= (size_t)n;
	}
	return 0;
}

int main(int argc, char **argv)
{
	const char *given = NULL;
	int i = 1;
	for (; i < argc && argv[i][0] == '-'; i++) {
		if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0) {
			fputs(usage, stdout);
			return 0;
		} else if ((strcmp(argv[i], "-s") == 0 || strcmp(argv[i], "--socket") == 0) &&
			   i + 1 < argc) {
			given = argv[++i];
		} else {
			fputs(usage, stderr);
			return 2;
		}
	}
	if (i == argc) {
		fputs(usage, stderr);
		return 2;
	}

	char line[1024], buf[108];
	size_t len = 0;
	for (int j = i; j < argc; j++) {
		int n = snprintf(line + len, sizeof(line) - len, "%s%s", j > i ? " " : "", argv[j]);
		if (n < 0 || (size_t)n >= sizeof(line) - len - 1) {
			fputs("viscompctl: the command is too long\n", stderr);
			return 2;
		}
		len += (size_t)n;
	}
	line[len++] = '\n';

	const char *path = socket_path(given, buf, sizeof(buf));
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	if (path == NULL || strlen(path) >= sizeof(addr.sun_path)) {
		fputs("viscompctl: no socket: give -s PATH, or set VISCOMP_SOCKET or "
		      "XDG_RUNTIME_DIR and WAYLAND_DISPLAY\n", stderr);
		return 1;
	}
	strcpy(addr.sun_path, path);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0 || connect(fd, (struct sockaddr *)&addr, sizeof(addr)) < 0) {
		fprintf(stderr, "viscompctl: %s: %s\n", path, strerror(errno));
		return 1;
	}
	if (write_all(fd, line, len) < 0) {
		fprintf(stderr, "viscompctl: %s: %s\n", path, strerror(errno));
		return 1;
	}
	shutdown(fd, SHUT_WR);

	/* The answer, printed line by line but for its last, the status. */
	FILE *in = fdopen(fd, "r");
	if (in == NULL)
		return 1;
	char *text = NULL, *last = NULL;
	size_t cap = 0;
	ssize_t n;
	while ((n = getline(&text, &cap, in)) >= 0) {
		if (last != NULL)
			fputs(last, stdout);
		free(last);
		last = strdup(text);
		if (last == NULL)
			return 1;
	}
	free(text);
	fclose(in);
	int status = 1;
	if (last != NULL && strcmp(last, "ok\n") == 0)
		status = 0;
	else if (last != NULL && strncmp(last, "error: ", 7) == 0)
		fprintf(stderr, "viscompctl: %s", last + 7);
	else
		fprintf(stderr, "viscompctl: viscomp closed the connection without an answer\n");
	free(last);
	return status;
}
