/*
 * viscomp: a stacking Wayland compositor whose model of what can be seen is libvis. Options,
 * the backend, the control socket, the child command, the event loop.
 */
#include <errno.h>
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <wlr/backend.h>
#include <wlr/util/log.h>

#include "control.h"
#include "mirror.h"
#include "server.h"
#include "server-init.h"

#define MAX_HEADS 16

static const char usage[] =
	"usage: viscomp [--headless WxH[,WxH...]] [--visd SOCKET] [--control PATH] [-v]\n"
	"               [-- COMMAND...]\n"
	"  A stacking Wayland compositor on libvis: surfaces that cannot be seen get no frame\n"
	"  callbacks, and each frame draws only what can be seen of the damage.\n"
	"  --headless WxH[,WxH...]  no display: one headless output of each size, drawn by pixman\n"
	"                           (without it, wlroots picks: a window in X11 or Wayland, or DRM)\n"
	"  --visd SOCKET            mirror the windows and their states into the visd there, as\n"
	"                           its manager (a visd screen at least as large as the outputs)\n"
	"  --control PATH           the control socket viscompctl talks to (default:\n"
	"                           $XDG_RUNTIME_DIR/viscomp-$WAYLAND_DISPLAY.sock)\n"
	"  -v, --verbose            log more (twice: wlroots' debug log too)\n"
	"  -h, --help               this help\n"
	"  COMMAND                  started once viscomp listens, with WAYLAND_DISPLAY and\n"
	"                           VISCOMP_SOCKET set; viscomp ends when it exits\n";

/* Parses "WxH[,WxH...]" into heads; their count, or -1. */
static int parse_heads(const char *text, struct server_head *heads)
{
	int n = 0;
	const char *p = text;
	while (*p != '\0') {
		if (n == MAX_HEADS)
			return -1;
		char *end;
		errno = 0;
		long w = strtol(p, &end, 10);
		if (end == p || *end != 'x' || errno != 0 || w < 1 || w > 16384)
			return -1;
		p = end + 1;
		long h = strtol(p, &end, 10);
		if (end == p || (*end != ',' && *end != '\0') || errno != 0 || h < 1 || h > 16384)
			return -1;
		heads[n++] = (struct server_head){ (int32_t)w, (int32_t)h };
		p = *end == ',' ? end + 1 : end;
	}
	return n;
}

static pid_t child = -1;
static int child_status;

/* Starts the command, in its own process group so that signals meant for viscomp stay here. */
static int spawn(char **argv)
{
	pid_t pid = fork();
	if (pid < 0)
		return -1;
	if (pid == 0) {
		setpgid(0, 0);
		sigset_t none;
		sigemptyset(&none);
		sigprocmask(SIG_SETMASK, &none, NULL);
		execvp(argv[0], argv);
		fprintf(stderr, "viscomp: cannot start %s: %s\n", argv[0], strerror(errno));
		_exit(127);
	}
	child = pid;
	return 0;
}

/* SIGINT and SIGTERM end viscomp; SIGCHLD reaps, and ends it when the command exits. */
static int handle_signal(int signal, void *data)
{
	struct wl_display *display = data;
	if (signal == SIGCHLD) {
		int status;
		pid_t pid;
		while ((pid = waitpid(-1, &status, WNOHANG)) > 0) {
			if (pid == child) {
				child_status = status;
				child = -1;
				wl_display_terminate(display);
			}
		}
		return 0;
	}
	wl_display_terminate(display);
	return 0;
}

int main(int argc, char **argv)
{
	static const struct option longopts[] = {
		{ "headless", required_argument, NULL, 'H' },
		{ "control", required_argument, NULL, 'c' },
		{ "visd", required_argument, NULL, 'V' },
		{ "verbose", no_argument, NULL, 'v' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct server_head heads[MAX_HEADS];
	struct server_options options = { heads, 0 };
	const char *control_path = NULL, *visd_path = NULL;
	int verbose = 0, opt;
	while ((opt = getopt_long(argc, argv, "+vh", longopts, NULL)) != -1) {
		switch (opt) {
		case 'H': {
			int n = parse_heads(optarg, heads);
			if (n <= 0) {
				fprintf(stderr, "viscomp: --headless wants WxH[,WxH...] (at most %d)\n",
					MAX_HEADS);
				return 2;
			}
			options.n_heads = (size_t)n;
			break;
		}
		case 'c':
			control_path = optarg;
			break;
		case 'V':
			visd_path = optarg;
			break;
		case 'v':
			verbose++;
			break;
		case 'h':
			fputs(usage, stdout);
			return 0;
		default:
			fputs(usage, stderr);
			return 2;
		}
	}
	char **command = optind < argc ? argv + optind : NULL;

	wlr_log_init(verbose >= 2 ? WLR_DEBUG : verbose ? WLR_INFO : WLR_ERROR, NULL);
	if (getenv("XDG_RUNTIME_DIR") == NULL) {
		fprintf(stderr, "viscomp: XDG_RUNTIME_DIR is not set (wlroots and clients need it)\n");
		return 1;
	}
	/* A child's exit is a signal we want; a dead control client's socket must not kill us. */
	signal(SIGPIPE, SIG_IGN);

	struct server server = { 0 };
	int status = 1;
	if (server_init(&server, &options) < 0)
		goto out;
	struct wl_event_source *signals[] = {
		wl_event_loop_add_signal(server.loop, SIGINT, handle_signal, server.display),
		wl_event_loop_add_signal(server.loop, SIGTERM, handle_signal, server.display),
		wl_event_loop_add_signal(server.loop, SIGCHLD, handle_signal, server.display),
	};
	const char *socket = wl_display_add_socket_auto(server.display);
	if (socket == NULL) {
		wlr_log(WLR_ERROR, "cannot open a Wayland socket");
		goto out_signals;
	}
	setenv("WAYLAND_DISPLAY", socket, 1);
	server.control = control_create(&server, control_path, socket);
	if (server.control == NULL)
		goto out_signals;
	setenv("VISCOMP_SOCKET", control_socket_path(server.control), 1);
	if (visd_path != NULL && (server.mirror = mirror_create(&server, visd_path)) == NULL)
		goto out_signals;
	if (!wlr_backend_start(server.backend)) {
		wlr_log(WLR_ERROR, "cannot start the backend");
		goto out_signals;
	}
	/* The clients' and the test's cue: we listen on both sockets. */
	wlr_log(WLR_INFO, "viscomp: WAYLAND_DISPLAY=%s VISCOMP_SOCKET=%s", socket,
		control_socket_path(server.control));
	if (command != NULL && spawn(command) < 0) {
		wlr_log_errno(WLR_ERROR, "cannot start %s", command[0]);
		goto out_signals;
	}
	wl_display_run(server.display);
	status = 0;
	if (command != NULL && child < 0)
		status = WIFEXITED(child_status) ? WEXITSTATUS(child_status) : 1;
out_signals:
	for (size_t i = 0; i < sizeof(signals) / sizeof(signals[0]); i++)
		if (signals[i] != NULL)
			wl_event_source_remove(signals[i]);
	if (child > 0)
		kill(-child, SIGTERM);
out:
	server_finish(&server);
	return status;
}
