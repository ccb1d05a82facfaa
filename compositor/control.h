/*
 * The control socket: a Unix stream socket viscompctl (or anyone) connects to, sends one
 * command line and reads the answer, after which viscomp closes the connection.
 *
 * A command: one line of at most CONTROL_MAX_LINE bytes, words separated by spaces, ending
 * with a newline (or the end of what the client sends): "list", "list --json", "move ID X Y",
 * "resize ID W H", "raise ID", "lower ID", "close ID", "redraw", "stats". The answer: the
 * command's output, lines, then a last line "ok", or "error: REASON". control-command.c runs
 * the commands.
 */
#ifndef VISCOMP_CONTROL_H
#define VISCOMP_CONTROL_H

#include <stdbool.h>
#include <stddef.h>

#define CONTROL_MAX_LINE 1024

struct server;
struct control;

/* An answer being written: grows as needed; failed once memory ran out. */
struct control_reply {
	char *data;
	size_t len, cap;
	bool failed;
};

/* Appends printf-formatted text to a reply. */
void control_reply_printf(struct control_reply *reply, const char *fmt, ...)
	__attribute__((format(printf, 2, 3)));

/* Runs one command line (its words in argv[0 … argc)), writing its output and the status line. */
void control_command_run(struct server *server, int argc, char **argv, struct control_reply *reply);

/*
 * Listens on path, or on $XDG_RUNTIME_DIR/viscomp-DISPLAY.sock for NULL (DISPLAY: the Wayland
 * socket's name), replacing a stale socket file but not a live one. NULL on failure (logged).
 */
struct control *control_create(struct server *server, const char *path, const char *display);

/* Stops listening, closes the connections and unlinks the socket. NULL: no-op. */
void control_destroy(struct control *control);

/* The path it listens on. */
const char *control_socket_path(const struct control *control);

#endif
