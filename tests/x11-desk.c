/*
 * x11-desk: drives a real X desktop and records X's own truth, for checking visd-x11 (the bridge
 * that mirrors an X server's window tree into visd) against X's VisibilityNotify states.
 *
 * It starts the recorder before anything else (x11-desk-record.c), builds a desktop under the
 * running window manager (x11-desk-build.c), then performs --steps random operations from --seed
 * (x11-desk-ops.c). After the desktop is built and after each step it waits for a quiet point:
 * a round trip, then no event for 40 ms while the X server and the --working processes (the WM
 * reacts on its own time) use no CPU time to speak of, at most 20 s. Then,
 * unless --no-bridge, the handshake with the bridge: the root's _VISD_X11_SYNC set to k, and
 * _VISD_X11_SYNCED awaited until it holds k (as long as X and the --working processes, the
 * bridge among them, make progress: progress.h), so that visd has applied everything X told the
 * bridge; then a round trip, so that every VisibilityNotify X sent is in. With --check
 * CMD, CMD's states (visctl -s SOCK states --x11) must equal X's for every viewable InputOutput
 * window (x11-desk-check.c). When X reports a change between the quiet point and the end of
 * these reads (a window manager that acted after the quiet point), they describe no one
 * desktop: the quiet point is awaited and read again, 5 times at most. With --no-bridge, X's
 * states are printed instead, step by step.
 *
 * Without a compositing manager, X's state of a viewable InputOutput window is the last
 * VisibilityNotify it sent for it, which is what visd's must be. With --compositor (one runs:
 * xcompmgr or picom), X's own states go wrong and are only counted ("X wrong"); what a client
 * that selected VisibilityChangeMask was told last, X's event or the bridge's synthetic one, must
 * be visd's state instead (unless --send-events never). In every mode, visd's states must equal
 * the brute force over X's tree read at the quiet point (x11-desk-brute.c, under the translucency
 * rule with --compositor); a bystander connection that selected no VisibilityChange must get no
 * VisibilityNotify; --send-events never allows no synthetic event, and always wants one after
 * every change of visd's state seen between two quiet points.
 * Exit: 0, 1 (a difference, a harness failure, or a lost X connection), 2 (usage).
 */
#include <getopt.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <xcb/shape.h>

#include "x11-desk.h"

/* Reads of one quiet point at most, when the desktop keeps changing while it is read. */
#define MAX_READS 5
#define MAX_CLIENTS_OPTION (DESK_MAX_TOPS - DESK_MAX_CLIENTS - 4)

static void usage(FILE *f)
{
	fprintf(f, "usage: x11-desk [--display D] --seed S --steps N [--clients K] [--check CMD]\n"
		   "                [--compositor] [--send-events auto|always|never] [--no-bridge]\n"
		   "                [--working PID]... [-v]\n"
		   "  --display D   the X server (default: $DISPLAY)\n"
		   "  --seed S      the seed of the desktop and of the operations\n"
		   "  --steps N     how many operations\n"
		   "  --clients K   top-level windows of its own (default 6, at most %d)\n"
		   "  --check CMD   compare X's states with CMD's \"0x… STATE\" lines at every step\n"
		   "  --compositor  a compositing manager runs (waits for one): what clients were\n"
		   "                told must be visd's states; X's own differences are counted\n"
		   "  --send-events the bridge's mode: never, no synthetic event may come; always, one\n"
		   "                must follow every change of visd's state (default auto)\n"
		   "  --no-bridge   no handshake with visd-x11; print X's states at every step\n"
		   "  --working PID its waits (for the bridge, the clients, a manager) go on while\n"
		   "                the X server or PID (the bridge, visd, a manager) works;\n"
		   "                repeated for more\n"
		   "  -v            the operations as they happen, and the count of each kind\n",
		MAX_CLIENTS_OPTION);
}

static struct desk *dying; /* the desk desk_die cleans up once */

/* Kills the clients, frees everything and closes the connection. */
static void desk_finish(struct desk *d)
{
	build_kill_clients(d);
	record_finish(&d->rec);
	if (d->c != NULL)
		xcb_disconnect(d->c);
	d->c = NULL;
}

_Noreturn void desk_die(struct desk *d, int status, const char *fmt, ...)
{
	va_list ap;
	fflush(stdout);
	fprintf(stderr, "x11-desk: ");
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fprintf(stderr, "\n");
	if (dying == d) {
		dying = NULL;
		desk_finish(d);
	}
	exit(status);
}

void desk_check_connection(struct desk *d)
{
	if (xcb_connection_has_error(d->c))
		desk_die(d, 1, "the X server closed the connection");
}

/* Whether someone owns the selection *(xcb_atom_t *)arg. */
static bool owned(struct desk *d, void *arg)
{
	xcb_get_selection_owner_reply_t *o = xcb_get_selection_owner_reply(
		d->c, xcb_get_selection_owner(d->c, *(xcb_atom_t *)arg), NULL);
	bool yes = o != NULL && o->owner != XCB_NONE;
	free(o);
	desk_check_connection(d);
	return yes;
}

/* Waits for a manager to own the selection prefix + screen number (WM_S, _NET_WM_CM_S). */
static void wait_owner(struct desk *d, const char *prefix, int screen_no)
{
	char name[32], what[64];
	snprintf(name, sizeof name, "%s%d", prefix, screen_no);
	snprintf(what, sizeof what, "nobody owns %s", name);
	xcb_atom_t atom = record_intern(d, name);
	record_until(d, NULL, 0, owned, &atom, what);
}

static bool parse_ulong(const char *s, unsigned long *out)
{
	char *end;
	if (s[0] < '0' || s[0] > '9')
		return false;
	*out = strtoul(s, &end, 10);
	return *end == '\0';
}

int main(int argc, char **argv)
{
	static const struct option options[] = {
		{ "display", required_argument, NULL, 'd' }, { "seed", required_argument, NULL, 's' },
		{ "steps", required_argument, NULL, 'n' },   { "clients", required_argument, NULL, 'k' },
		{ "check", required_argument, NULL, 'c' },   { "no-bridge", no_argument, NULL, 'b' },
		{ "compositor", no_argument, NULL, 'C' },    { "send-events", required_argument, NULL, 'e' },
		{ "working", required_argument, NULL, 'w' }, { "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	const char *display = NULL, *cmd = NULL;
	unsigned long seed = 0, steps = 0, clients = 6;
	bool have_seed = false, have_steps = false, bridge = true, verbose = false, compositor = false;
	enum send_mode send_events = SEND_AUTO;
	pid_t working[PROGRESS_MAX_PIDS];
	size_t n_working = 1; /* [0]: the X server's, once connected */
	unsigned long pid;
	int opt;
	while ((opt = getopt_long(argc, argv, "v", options, NULL)) != -1) {
		switch (opt) {
		case 'd':
			display = optarg;
			break;
		case 's':
			have_seed = parse_ulong(optarg, &seed);
			if (!have_seed)
				goto bad;
			break;
		case 'n':
			have_steps = parse_ulong(optarg, &steps);
			if (!have_steps)
				goto bad;
			break;
		case 'k':
			if (!parse_ulong(optarg, &clients) || clients > MAX_CLIENTS_OPTION)
				goto bad;
			break;
		case 'c':
			cmd = optarg;
			break;
		case 'b':
			bridge = false;
			break;
		case 'C':
			compositor = true;
			break;
		case 'e':
			if (strcmp(optarg, "auto") == 0)
				send_events = SEND_AUTO;
			else if (strcmp(optarg, "always") == 0)
				send_events = SEND_ALWAYS;
			else if (strcmp(optarg, "never") == 0)
				send_events = SEND_NEVER;
			else
				goto bad;
			break;
		case 'w':
			if (!parse_ulong(optarg, &pid) || pid == 0 || pid > INT32_MAX ||
			    n_working == PROGRESS_MAX_PIDS - DESK_MAX_CLIENTS)
				goto bad;
			working[n_working++] = (pid_t)pid;
			break;
		case 'v':
			verbose = true;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			goto bad;
		}
	}
	if (optind != argc || !have_seed || !have_steps || (cmd != NULL && !bridge)) {
bad:
		usage(stderr);
		return 2;
	}

	struct desk d = { .rng = { seed }, .verbose = verbose, .display = display,
			  .compositor = compositor, .send_events = send_events };
	int screen_no;
	d.c = xcb_connect(display, &screen_no);
	if (xcb_connection_has_error(d.c)) {
		fprintf(stderr, "x11-desk: cannot connect to the X server %s\n",
			display ? display : getenv("DISPLAY") ? getenv("DISPLAY") : "(DISPLAY unset)");
		xcb_disconnect(d.c);
		return 1;
	}
	dying = &d;
	working[0] = progress_peer_pid(xcb_get_file_descriptor(d.c));
	memcpy(d.working, working, n_working * sizeof *working);
	d.n_working = n_working;
	if (display != NULL)
		setenv("DISPLAY", display, 1); /* for the clients */
	xcb_screen_iterator_t si = xcb_setup_roots_iterator(xcb_get_setup(d.c));
	for (int i = 0; i < screen_no && si.rem; i++)
		xcb_screen_next(&si);
	d.screen = si.data;
	d.root = d.screen->root;
	const xcb_query_extension_reply_t *shape = xcb_get_extension_data(d.c, &xcb_shape_id);
	d.shape = shape != NULL && shape->present;
	d.atoms[ATOM_WM_CHANGE_STATE] = record_intern(&d, "WM_CHANGE_STATE");
	d.atoms[ATOM_WM_STATE] = record_intern(&d, "WM_STATE");
	d.atoms[ATOM_NET_ACTIVE_WINDOW] = record_intern(&d, "_NET_ACTIVE_WINDOW");
	d.atoms[ATOM_NET_RESTACK_WINDOW] = record_intern(&d, "_NET_RESTACK_WINDOW");
	d.atom_opacity = record_intern(&d, "_NET_WM_WINDOW_OPACITY");
	d.atom_opaque_region = record_intern(&d, "_NET_WM_OPAQUE_REGION");

	uint32_t sync = record_start(&d);
	wait_owner(&d, "WM_S", screen_no);
	if (compositor)
		wait_owner(&d, "_NET_WM_CM_S", screen_no);
	build_desktop(&d, (int)clients);
	unsigned long checked = 0, diffs = 0, done = 0, rereads = 0;
	char what[160] = "the desktop built";
	for (unsigned long step = 0;; step++) {
		if (step > 0) {
			ops_step(&d, what, sizeof what);
			done = step;
			if (verbose)
				fprintf(stderr, "x11-desk: step %lu: %s\n", step, what);
		}
		struct check_read r = { 0 };
		for (int tries = 1;; tries++) {
			record_quiet(&d);
			unsigned long mark = d.rec.changes;
			if (bridge)
				record_sync(&d, ++sync);
			record_bystander(&d);
			if (cmd == NULL)
				break;
			check_read(&d, cmd, &r);
			/* The window manager may act after the quiet point (on a loaded machine):
			 * then what was read is not one desktop's, and is read again. */
			record_round_trip(&d);
			if (d.rec.changes == mark || tries == MAX_READS)
				break;
			check_read_free(&r);
			rereads++;
			if (verbose)
				fprintf(stderr, "x11-desk: step %lu: the desktop changed while it was "
						"read: read again\n", step);
		}
		if (cmd != NULL) {
			unsigned long n = check_compare(&d, &r, step, what, &checked);
			diffs += n;
			if (n > 0 || d.harness_failures > 0)
				break;
		} else if (!bridge) {
			check_print(&d, step);
		}
		if (step == steps)
			break;
	}
	unsigned long bystander = record_bystander(&d);
	bool synthetic_wrong = send_events == SEND_NEVER && d.rec.synthetic_events > 0;
	printf("x11-desk: %lu steps, %lu windows checked in all, %lu differences, X sent %lu "
	       "VisibilityNotify (%lu synthetic), %lu left out (X redirects them), %lu marked (a shape "
	       "past the border box: X alone says partially obscured), %lu quiet points read again (the "
	       "desktop moved meanwhile)\n",
	       done, checked, diffs, d.rec.visibility_events, d.rec.synthetic_events, d.redirected,
	       d.past_box, rereads);
	printf("x11-desk: %s, send-events %s: brute force %lu checked, X wrong %lu times, %lu "
	       "told nothing, visd changed %lu states (%lu not followed by a synthetic event), "
	       "bystander got %lu\n",
	       compositor ? "compositor" : "no compositor",
	       send_events == SEND_AUTO ? "auto" : send_events == SEND_ALWAYS ? "always" : "never",
	       d.brute_checked, d.x_wrong, d.untold, d.visd_changes, d.changes_untold, bystander);
	if (bystander > 0)
		printf("x11-desk: the bystander, which selected no VisibilityChange, got %lu "
		       "VisibilityNotify\n", bystander);
	if (synthetic_wrong)
		printf("x11-desk: the bridge runs with --send-events never, yet %lu synthetic "
		       "VisibilityNotify came\n", d.rec.synthetic_events);
	if (verbose) {
		fprintf(stderr, "x11-desk: operations:");
		for (int k = 0; ops_kind_names[k] != NULL; k++)
			fprintf(stderr, " %s %lu", ops_kind_names[k], d.op_counts[k]);
		fprintf(stderr, "\nx11-desk: %lu late windows, %lu covers, %lu states inferred, "
				"%lu X errors\n",
			d.rec.late_windows, d.rec.refreshes, d.rec.inferred, d.rec.x_errors);
	}
	int status = diffs > 0 || d.harness_failures > 0 || bystander > 0 || synthetic_wrong ? 1 : 0;
	free(d.prev_visd);
	dying = NULL;
	desk_finish(&d);
	return status;
}
