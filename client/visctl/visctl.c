/*
 * visctl: the command-line tool. This file reads the global options, finds the subcommand and
 * hands over argv; live subcommands also get the connection settings. It also holds the helpers
 * every subcommand shares.
 */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "visctl.h"

static const struct visctl_command commands[] = {
	{ "compute", cmd_compute, NULL,
	  "[--engine=auto|gmv|gmv-heap|region|brute] [--visible] [--json] [--time] [--svg FILE] SCENE",
	  NULL },
	{ "gen", cmd_gen, NULL, "KIND N SEED [W H]", NULL },
	{ "bench", cmd_bench, NULL, "[OPTIONS]  (see `visctl bench --help`)", NULL },
	{ "plot-service", cmd_plot_service, NULL, "[--note TEXT] CSV SVG", NULL },
	{ "create", NULL, cmd_create,
	  "X Y W H [--parent ID] [--map] [--retain] [--border B] [--input-only] "
	  "[--x11 XID | --external NS:TAG]",
	  "  Creates a window and prints its ID. X Y place its border box's corner (relative\n"
	  "  to the parent's inside), W H is its inside; --border B gives it a border of B\n"
	  "  pixels (X's border_width: the border box is the inside grown by B on every\n"
	  "  side); --input-only makes it X's InputOnly: no pixels, no state, hiding nothing.\n"
	  "  --parent ID puts it under a window (default: the screen), --map maps it at\n"
	  "  once, --retain lets it outlive this connection.\n"
	  "  --x11 XID says the window mirrors that X window (XID hex 0x... or decimal);\n"
	  "  --external NS:TAG, that it mirrors TAG of namespace NS (1 X11, 2 Wayland,\n"
	  "  others private). Only the manager sets them (--role manager), and no two\n"
	  "  windows carry the same one.\n" },
	{ "destroy", NULL, cmd_destroy, "ID", NULL },
	{ "map", NULL, cmd_map, "ID", NULL },
	{ "unmap", NULL, cmd_unmap, "ID", NULL },
	{ "move", NULL, cmd_move, "ID X Y", NULL },
	{ "resize", NULL, cmd_resize, "ID W H", NULL },
	{ "raise", NULL, cmd_raise, "ID", NULL },
	{ "lower", NULL, cmd_lower, "ID", NULL },
	{ "stack", NULL, cmd_stack, "ID above|below SIBLING", NULL },
	{ "border", NULL, cmd_border, "ID B",
	  "  Sets the window's border width to B pixels, keeping its place and inside (a\n"
	  "  configure request with the geometry read from the tree; not inside a batch).\n" },
	{ "shape", NULL, cmd_shape, "ID [X,Y,W,H ...] | ID --box",
	  "  Sets the window's bounding shape (X's SHAPE extension): its pixels are the\n"
	  "  union of the rectangles, in window coordinates (0,0 is the inside's corner;\n"
	  "  negative ones reach into the border), clipped to its border box. No rectangles:\n"
	  "  no pixels at all (it hides nothing, and is fully obscured). --box: its whole\n"
	  "  border box again.\n" },
	{ "opaque", NULL, cmd_opaque, "ID none|all|X,Y,W,H ...",
	  "  Sets which of the window's pixels hide what lies below it: all (the default),\n"
	  "  none (a translucent window), or those inside the rectangles (window\n"
	  "  coordinates, as _NET_WM_OPAQUE_REGION), e.g. the inside of a client-side\n"
	  "  shadow. Windows below show through the rest.\n" },
	{ "load", NULL, cmd_load, "[--retain] [--any-screen] [--json] SCENE", NULL },
	{ "states", NULL, cmd_states, "[--json] [--x11 [--names]]",
	  "  Prints 'ID STATE' for every viewable window the connection may see, ascending ID;\n"
	  "  STATE is unobscured, partially-obscured or fully-obscured. A client sees only\n"
	  "  the windows its connection made (--role observer or manager: every window).\n"
	  "  --json: one object a line, {\"window\":ID,\"state\":STATE}.\n"
	  "  --x11: only the windows that mirror X windows, as 'XID STATE' (XID in lowercase\n"
	  "  hex, 0x1e00003), ascending XID; with --json {\"x11\":\"XID\",\"window\":ID,\n"
	  "  \"state\":STATE}. Without --role it takes the observer role: X windows are\n"
	  "  the bridge's (the manager's), so a plain client sees none.\n"
	  "  --names: with --x11, each window's name and class after its state, as\n"
	  "  xwininfo -tree prints them: 0x1e00003 unobscured \"~/src\" (\"xterm\" \"XTerm\"),\n"
	  "  or (has no name) (); read from the X server on $DISPLAY (visd knows XIDs\n"
	  "  only). With --json, \"name\":NAME|null,\"class\":[INSTANCE,CLASS]|null.\n" },
	{ "tree", NULL, cmd_tree, "[--json]",
	  "  Prints every window the connection may see, bottom to top, each before its\n"
	  "  children, as 'ID PARENT X Y W H MAPPED STATE RETAINED BORDER LOOK EXTERNAL':\n"
	  "  PARENT 0 for the screen (or a parent this connection may not see); X Y its\n"
	  "  border box's corner relative to the parent's inside, W H its inside; MAPPED\n"
	  "  mapped or unmapped; STATE as in states, or none when not viewable (or\n"
	  "  input-only);\n"
	  "  RETAINED retained (outlives its connection) or -; BORDER its border width;\n"
	  "  LOOK shaped, translucent, input-only (joined by commas) or -; EXTERNAL what it\n"
	  "  mirrors: x11:0xXID for an X window, NS:0xTAG in another namespace, or -.\n"
	  "  --json: one object a line with window, parent, x, y, width, height, mapped,\n"
	  "  viewable, retained, parent_hidden (true, false), state, border, shaped,\n"
	  "  translucent, input_only, namespace and external (numbers; 0 and 0: none).\n" },
	{ "region", NULL, cmd_region, "[--json] ID",
	  "  Prints the window's visible pixels as 'X Y W H' rectangles in window\n"
	  "  coordinates (0 0 is its inside's top-left corner, not the screen's; a border\n"
	  "  lies at negative ones), y-x banded: its pixels under no later window and none\n"
	  "  of its children.\n"
	  "  --json: one object a line, {\"x\":X,\"y\":Y,\"width\":W,\"height\":H}.\n" },
	{ "repaint", NULL, cmd_repaint, "[--json] X Y W H",
	  "  Prints, bottom to top, the IDs of the windows whose own pixels show inside the\n"
	  "  screen rectangle X Y W H (screen coordinates).\n"
	  "  --json: one object a line, {\"window\":ID}.\n" },
	{ "look", NULL, cmd_look, "[--json] ID",
	  "  Prints the window's bounding shape and opaque region as set (window\n"
	  "  coordinates, as the scene format and the shape and opaque commands take them):\n"
	  "  'shape box' (no shape: its border box), 'shape' alone (no pixels) or 'shape\n"
	  "  X,Y,W,H ...'; then 'opaque all', 'opaque none' or 'opaque X,Y,W,H ...'.\n"
	  "  --json: one object, {\"window\":ID,\"shaped\":BOOL,\"shape\":[[X,Y,W,H],...],\n"
	  "  \"opaque\":\"all\"|\"none\"|\"rects\",\"opaque_rects\":[...]}.\n" },
	{ "lookup", NULL, cmd_lookup, "--x11 XID | NS TAG",
	  "  Prints the ID of the window that mirrors X window XID (hex 0x... or decimal),\n"
	  "  or that carries TAG in namespace NS (1 X11, 2 Wayland, others private). Without\n"
	  "  --role it takes the observer role: only the manager gives windows external IDs,\n"
	  "  so a plain client has none to find.\n" },
	{ "snapshot", NULL, cmd_snapshot, "--svg FILE", NULL },
	{ "watch", NULL, cmd_watch, "[--json] [--count N] [ID...] | --x11 [XID...]", NULL },
	{ "script", NULL, cmd_script, "FILE|-", NULL },
	{ "sync", NULL, cmd_sync, "", NULL },
	{ "stress", NULL, cmd_stress, "[OPTIONS]  (see `visctl stress --help`)", NULL },
};

#define N_COMMANDS (sizeof(commands) / sizeof(commands[0]))

const struct visctl_command *visctl_command_find(const char *name)
{
	for (size_t i = 0; i < N_COMMANDS; i++)
		if (strcmp(name, commands[i].name) == 0)
			return &commands[i];
	return NULL;
}

/* Prints the list of subcommands, to stdout when asked for and to stderr after a mistake. */
static void usage(FILE *f)
{
	fprintf(f, "usage: visctl [-s SOCKET] [--role client|observer|manager] COMMAND [ARGS]\n"
		   "       visctl help | --version\n"
		   "commands:\n");
	for (size_t i = 0; i < N_COMMANDS; i++)
		fprintf(f, "  visctl %s%s%s\n", commands[i].name, commands[i].usage[0] ? " " : "",
			commands[i].usage);
	fprintf(f, "SCENE is a path or '-' for stdin; `visctl COMMAND --help` says more.\n"
		   "Commands from create on talk to visd at SOCKET (-s or --socket; default\n"
		   "$VISD_SOCKET, else $XDG_RUNTIME_DIR/visd-0) in the role --role asks for:\n"
		   "client (the default) sees and changes only the windows its own connection\n"
		   "made (or a script's); observer sees every window and changes none; manager\n"
		   "(one connection at a time) sees and changes every window. visd grants\n"
		   "observer and manager only to its own user, never on its restricted socket.\n"
		   "stress ignores --role and takes the roles it needs.\n"
		   "exit status: 0 ok, 1 runtime or daemon error, 2 usage or bad input\n");
}

/* Reports a mistake in the global options; returns the usage exit status. */
static int bad_usage(const char *fmt, const char *arg)
{
	fputs("visctl: ", stderr);
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	usage(stderr);
	return VISCTL_EXIT_USAGE;
}

/* Parses a role's name. Returns 0, or -1. */
static int parse_role(const char *name, uint32_t *role)
{
	static const char *const names[] = { "client", "observer", "manager" };
	for (uint32_t r = 0; r < 3; r++)
		if (strcmp(name, names[r]) == 0) {
			*role = r;
			return 0;
		}
	return -1;
}

/* Runs a live subcommand on its own connection, and reports a failure to write its output. */
static int run_live(const struct visctl_command *cmd, const char *socket, uint32_t role,
		    bool role_given, int argc, char **argv)
{
	struct live l = { .socket = socket, .role = role, .role_given = role_given,
			  .where = "visctl" };
	int ret = cmd->live(&l, argc, argv);
	vis_client_destroy(l.client);
	if (fflush(stdout) != 0 || ferror(stdout)) {
		fprintf(stderr, "visctl: write error: %s\n", strerror(errno));
		return VISCTL_EXIT_FAILURE;
	}
	return ret;
}

/* Reads the global options, then dispatches to the subcommand, which parses its own. */
int main(int argc, char **argv)
{
	const char *socket = NULL;
	uint32_t role = VIS_ROLE_CLIENT;
	bool role_given = false;
	int i = 1;

	for (; i < argc && argv[i][0] == '-'; i++) {
		const char *a = argv[i], *value = NULL;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			usage(stdout);
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		}
		if (strcmp(a, "--version") == 0) {
			printf("visctl %s (protocol %u)\n", VIS_VERSION, VIS_PROTOCOL_VERSION);
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		}
		bool is_socket = strcmp(a, "-s") == 0 || strcmp(a, "--socket") == 0;
		bool is_role = strcmp(a, "--role") == 0;
		if (strncmp(a, "--socket=", 9) == 0) {
			is_socket = true;
			value = a + 9;
		} else if (strncmp(a, "--role=", 7) == 0) {
			is_role = true;
			value = a + 7;
		} else if (!is_socket && !is_role) {
			return bad_usage("unknown option '%s'", a);
		} else if (i + 1 == argc) {
			return bad_usage("%s needs a value", a);
		} else {
			value = argv[++i];
		}
		if (is_socket && !*value)
			return bad_usage("%s", "empty SOCKET");
		if (is_socket)
			socket = value;
		else if (parse_role(value, &role) < 0)
			return bad_usage("unknown role '%s' (client, observer, manager)", value);
		else
			role_given = true;
	}
	if (i == argc) {
		usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	const char *name = argv[i];
	if (strcmp(name, "help") == 0) {
		usage(stdout);
		return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
	}
	const struct visctl_command *cmd = visctl_command_find(name);
	if (!cmd) {
		fprintf(stderr, "visctl: unknown command '%s'\n", name);
		usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	if (cmd->run)
		return cmd->run(argc - i, argv + i);
	return run_live(cmd, socket, role, role_given, argc - i, argv + i);
}

int visctl_read_all(const char *path, char **data, size_t *len)
{
	bool is_stdin = strcmp(path, "-") == 0;
	int fd = is_stdin ? STDIN_FILENO : open(path, O_RDONLY | O_CLOEXEC);
	struct stat st;
	size_t cap = 1 << 16, n = 0;
	char *buf = NULL;
	int saved;

	if (fd < 0)
		return -1;
	/* Size the buffer from the file when we can, to avoid copying a large scene while growing. */
	if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
	    (uint64_t)st.st_size < SIZE_MAX - 1)
		cap = (size_t)st.st_size + 1;
	if ((buf = malloc(cap)) == NULL)
		goto fail;
	for (;;) {
		if (n == cap) {
			if (cap > SIZE_MAX / 2) {
				errno = ENOMEM;
				goto fail;
			}
			char *p = realloc(buf, cap * 2);
			if (p == NULL)
				goto fail;
			buf = p;
			cap *= 2;
		}
		ssize_t r = read(fd, buf + n, cap - n);
		if (r < 0 && errno == EINTR)
			continue;
		if (r < 0)
			goto fail;
		if (r == 0)
			break;
		n += (size_t)r;
	}
	if (!is_stdin)
		close(fd);
	*data = buf;
	*len = n;
	return 0;

fail:
	saved = errno;
	free(buf);
	if (!is_stdin)
		close(fd);
	errno = saved;
	return -1;
}
