/*
 * visd-x11: gives visd an X screen's windows, so that visd's subscribers (and, with
 * --send-events, unmodified X clients) learn true visibility where X's VisibilityNotify fails:
 * under a compositing manager, and around windows X redirects by itself.
 */
#include <errno.h>
#include <getopt.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <xcb/shape.h>
#include <xcb/xfixes.h>

#include "bridge.h"
#include "histogram.h"

/* From a turn's first X event read to the turn's end: every turn, and those that told clients. */
static struct histogram turn_times, told_times;

static volatile sig_atomic_t stop_signal, check_asked;

static void on_signal(int sig)
{
	if (sig == SIGUSR1)
		check_asked = 1;
	else
		stop_signal = sig;
}

/*
 * The end of a turn's reads: where the windows in limbo went, and the children lists to read
 * again; then whether the mirror drifted, said and counted. Returns whether it did (the caller
 * reads the whole tree).
 */
static bool settle(struct bridge *b)
{
	if (b->n_limbo || b->reread.n)
		xread_pending(b);
	if (!b->resync_needed)
		return false;
	bridge_log(b, 0, "resynchronizing from a fresh read of the tree: %s", b->resync_reason);
	b->resync_needed = false;
	b->resyncs++;
	return true;
}

/*
 * SIGUSR1: reads the whole tree again and applies it. The mirror was exact when that changes
 * nothing, since every mirror function sends visd only differences. Under one server grab, every
 * event X generated before it is applied first, then the tree is read: nothing can change in
 * between, so a correction is a drift, never an event still on its way (a desktop need not be
 * quiet to be checked). Then visd's tree is compared with the mirror (twin.c).
 */
static void check_mirror(struct bridge *b)
{
	check_asked = 0;
	xcb_grab_server(b->x);
	b->grabbed = true;
	free(xcb_get_input_focus_reply(b->x, xcb_get_input_focus(b->x), NULL));
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_queued_event(b->x)) != NULL) {
		events_handle(b, ev);
		free(ev);
	}
	settle(b); /* the whole tree is read next, resynchronization or not */
	uint64_t before = 0;
	int rc = visd_end_turn(b);
	if (rc == 0) {
		before = b->requests;
		rc = xread_screen(b);
	}
	b->grabbed = false;
	xcb_ungrab_server(b->x);
	xcb_flush(b->x);
	if (rc < 0 || visd_end_turn(b) < 0)
		return;
	/* One line a check, once both are done: the tests wait for it. */
	uint64_t corrections = b->requests - before;
	char why[160];
	rc = twin_check(b, why, sizeof(why));
	if (rc < 0)
		return;
	char x_word[96];
	if (corrections)
		snprintf(x_word, sizeof(x_word), "the mirror had drifted from X's tree (%llu "
			 "corrections sent)", (unsigned long long)corrections);
	else
		snprintf(x_word, sizeof(x_word), "the mirror of %u windows equals X's tree",
			 b->n_windows);
	if (rc == 0) {
		bridge_log(b, 0, "checked: %s, and visd's tree the mirror", x_word);
	} else {
		bridge_log(b, 0, "checked: %s, but visd's tree had drifted from the mirror (%s): its "
				 "windows are made again", x_word, why);
		b->resyncs++;
		if (twin_rebuild(b) < 0)
			return;
	}
	notify_flush(b);
	xcb_flush(b->x);
}

void bridge_refused(struct bridge *b, const struct vis_error *err, xcb_window_t xid)
{
	b->visd_refused = true;
	if (b->refusals++)
		return; /* the first says why; the count comes at the end */
	char what[32] = "";
	if (xid)
		snprintf(what, sizeof(what), " of window 0x%x", xid);
	bridge_log(b, 0, "visd refused %s%s (%s): %s", vis_request_name(err->opcode), what,
		   vis_error_code_name(err->code), err->message);
}

static void on_visd_error(void *data, const struct vis_error *err)
{
	bridge_refused(data, err, 0);
}

void bridge_log(const struct bridge *b, int level, const char *fmt, ...)
{
	if (b && level > b->verbose)
		return;
	va_list ap;
	va_start(ap, fmt);
	fputs("visd-x11: ", stderr);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
}

static void usage(FILE *f)
{
	fputs("usage: visd-x11 [--display DISPLAY] [-s SOCKET] [--send-events auto|always|never]\n"
	      "                [--translucency auto|on|off] [-v]...\n"
	      "       visd-x11 --help | --version\n"
	      "Mirrors the X screen's window tree into visd (as its manager), so that visd's\n"
	      "subscribers learn every X window's true visibility; its windows carry their X IDs\n"
	      "(visctl watch --x11 XID, visctl states --x11).\n"
	      "  --display DISPLAY   the X server (default $DISPLAY)\n"
	      "  -s, --socket PATH   visd's socket (default $VISD_SOCKET, else $XDG_RUNTIME_DIR/visd-0)\n"
	      "  --send-events MODE  synthetic VisibilityNotify to X clients that selected it:\n"
	      "                      auto (default) where X's own word differs from the truth,\n"
	      "                      always on every change as well, never\n"
	      "  --translucency MODE whether ARGB windows and windows below 100% opacity hide only\n"
	      "                      their _NET_WM_OPAQUE_REGION: auto (default) while a compositing\n"
	      "                      manager runs, on, off\n"
	      "  -v                  say more (twice: every window created, every event sent;\n"
	      "                      three times: every event read)\n"
	      "SIGUSR1 checks the mirror against a fresh read of X's tree, and visd's tree against the\n"
	      "mirror, and says whether either had drifted.\n"
	      "exit status: 0 stopped by a signal, 1 the X server or visd went away or refused, 2 usage\n",
	      f);
}

static xcb_atom_t intern(xcb_connection_t *x, const char *name)
{
	xcb_intern_atom_reply_t *r =
		xcb_intern_atom_reply(x, xcb_intern_atom(x, 0, (uint16_t)strlen(name), name), NULL);
	xcb_atom_t a = r ? r->atom : XCB_NONE;
	free(r);
	return a;
}

static uint64_t now_ns(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000000000u + (uint64_t)t.tv_nsec;
}

/* Connects to X and finds the screen, its extensions and atoms. */
static int setup_x(struct bridge *b, const char *display)
{
	b->x = xcb_connect(display, &b->screen_number);
	if (xcb_connection_has_error(b->x)) {
		bridge_log(NULL, 0, "cannot connect to the X display %s",
			   display ? display : getenv("DISPLAY") ? getenv("DISPLAY") : "(no $DISPLAY)");
		return -1;
	}
	xcb_screen_iterator_t it = xcb_setup_roots_iterator(xcb_get_setup(b->x));
	for (int i = 0; i < b->screen_number && it.rem; i++)
		xcb_screen_next(&it);
	b->screen = it.data;
	b->client_bits = ~xcb_get_setup(b->x)->resource_id_mask;
	const xcb_query_extension_reply_t *e = xcb_get_extension_data(b->x, &xcb_shape_id);
	if (e && e->present) {
		b->shape_ext = true;
		b->shape_event = e->first_event;
	} else {
		bridge_log(b, 0, "the X server has no SHAPE extension: every window is rectangular");
	}
	e = xcb_get_extension_data(b->x, &xcb_xfixes_id);
	if (e && e->present) {
		xcb_xfixes_query_version_reply_t *v = xcb_xfixes_query_version_reply(
			b->x, xcb_xfixes_query_version(b->x, 5, 0), NULL);
		if (v) {
			b->xfixes_ext = true;
			b->xfixes_event = e->first_event;
		}
		free(v);
	}
	char cm[32];
	snprintf(cm, sizeof(cm), "_NET_WM_CM_S%d", b->screen_number);
	b->atom_cm = intern(b->x, cm);
	b->atom_opacity = intern(b->x, "_NET_WM_WINDOW_OPACITY");
	b->atom_opaque_region = intern(b->x, "_NET_WM_OPAQUE_REGION");
	b->atom_sync = intern(b->x, "_VISD_X11_SYNC");
	b->atom_synced = intern(b->x, "_VISD_X11_SYNCED");
	if (b->xfixes_ext)
		xcb_xfixes_select_selection_input(
			b->x, b->screen->root, b->atom_cm,
			XCB_XFIXES_SELECTION_EVENT_MASK_SET_SELECTION_OWNER |
				XCB_XFIXES_SELECTION_EVENT_MASK_SELECTION_WINDOW_DESTROY |
				XCB_XFIXES_SELECTION_EVENT_MASK_SELECTION_CLIENT_CLOSE);
	else if (b->translucency == TRANSLUCENCY_AUTO)
		bridge_log(b, 0, "the X server has no XFIXES: a compositing manager is looked for "
				 "at start-up only");
	return xcb_connection_has_error(b->x) ? -1 : 0;
}

static int setup_visd(struct bridge *b, const char *socket)
{
	b->vc = vis_client_connect(socket, VIS_ROLE_MANAGER);
	if (!b->vc) {
		bridge_log(NULL, 0, "out of memory");
		return -1;
	}
	if (vis_client_error(b->vc)) {
		/* A refused handshake's message is the daemon's already: say it once. */
		struct vis_error e;
		const char *msg = vis_client_error_message(b->vc);
		bool more = vis_client_last_error(b->vc, &e) && !strstr(msg, e.message);
		bridge_log(NULL, 0, "cannot connect to visd as its manager: %s%s%s%s", msg,
			   more ? ": " : "", more ? e.message : "",
			   vis_client_error(b->vc) == EBUSY
				   ? " (another visd-x11, or another manager, is connected to this "
				     "visd: one bridge a visd)"
				   : "");
		return -1;
	}
	uint32_t w, h;
	vis_client_screen(b->vc, &w, &h);
	if (w != b->screen->width_in_pixels || h != b->screen->height_in_pixels)
		bridge_log(b, 0, "visd's screen is %ux%u, X's %ux%u: windows crossing the edges "
				 "may get other states than X's; start visd with --screen %ux%u",
			   w, h, b->screen->width_in_pixels, b->screen->height_in_pixels,
			   b->screen->width_in_pixels, b->screen->height_in_pixels);
	vis_client_set_notice_handler(b->vc, notify_on_visd, b);
	vis_client_set_error_handler(b->vc, on_visd_error, b);
	vis_client_subscribe(b->vc, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0);
	return vis_client_roundtrip(b->vc);
}

/* Answers the quiet-point handshake: _VISD_X11_SYNCED takes _VISD_X11_SYNC's value. */
static void answer_sync(struct bridge *b)
{
	xcb_get_property_reply_t *r = xcb_get_property_reply(
		b->x, xcb_get_property(b->x, 0, b->root->id, b->atom_sync, XCB_ATOM_CARDINAL, 0, 1),
		NULL);
	if (r && r->format == 32 && xcb_get_property_value_length(r) >= 4)
		xcb_change_property(b->x, XCB_PROP_MODE_REPLACE, b->root->id, b->atom_synced,
				    XCB_ATOM_CARDINAL, 32, 1, xcb_get_property_value(r));
	free(r);
	b->sync_asked = false;
}


/* One turn: ev and every event already read, one visd batch, the answers. */
/* Applies ev and every event X has sent since; 0, or -1 when X failed or memory ran out. */
static int apply_events(struct bridge *b, xcb_generic_event_t *ev)
{
	while (ev) {
		/* Everything read so far, then the new windows' subtrees at once, then in order. */
		size_t n = 0, n_new = 0;
		for (; ev; ev = xcb_poll_for_event(b->x)) {
			if (n == b->cap_events) {
				size_t cap = b->cap_events ? 2 * b->cap_events : 256;
				xcb_generic_event_t **e = realloc(b->events_read, cap * sizeof(*e));
				xcb_window_t *w = realloc(b->new_windows, cap * sizeof(*w));
				if (e)
					b->events_read = e;
				if (w)
					b->new_windows = w;
				if (!e || !w) {
					bridge_log(b, 0, "out of memory");
					free(ev);
					b->x_failed = true;
					return -1;
				}
				b->cap_events = cap;
			}
			b->events_read[n++] = ev;
			if (ev->response_type == XCB_CREATE_NOTIFY)
				b->new_windows[n_new++] = ((xcb_create_notify_event_t *)ev)->window;
		}
		if (n_new)
			xread_prefetch(b, b->new_windows, (uint32_t)n_new);
		for (size_t i = 0; i < n; i++) {
			events_handle(b, b->events_read[i]);
			free(b->events_read[i]);
		}
		xread_prefetch_done(b);
		ev = xcb_poll_for_event(b->x);
	}
	if (xcb_connection_has_error(b->x)) {
		b->x_failed = true;
		return -1;
	}
	if (settle(b))
		xread_screen(b);
	return 0;
}

static void turn(struct bridge *b, xcb_generic_event_t *ev, uint64_t arrival)
{
	uint64_t told_before = b->synthetic_sent;
	b->turns++;
	for (int pass = 0;; pass++) {
		if (apply_events(b, ev) < 0)
			return;
		/*
		 * X writes a change's first event to an idle client at once and the rest when the
		 * requester's time slice ends: the bridge often wakes on a window's ConfigureNotify
		 * alone, before X's own VisibilityNotify of the same change, which says what its
		 * clients were told. A round trip to X alongside visd's brings every event X made
		 * before it, so that auto does not repeat X's right word (always tells every change
		 * anyway); one more pass only, so that a busy X cannot hold the synthetic events back.
		 */
		bool fence = pass == 0 && b->send_events == SEND_AUTO && (b->batch_open || b->visd_sent);
		xcb_get_input_focus_cookie_t cookie;
		if (fence) {
			cookie = xcb_get_input_focus(b->x);
			xcb_flush(b->x);
		}
		if (visd_end_turn(b) < 0)
			return;
		if (fence)
			free(xcb_get_input_focus_reply(b->x, cookie, NULL));
		if (!fence || !(ev = xcb_poll_for_event(b->x)))
			break;
	}
	/* The synthetic events first: a client that sees the answer has them already. */
	notify_flush(b);
	if (b->sync_asked)
		answer_sync(b);
	xcb_flush(b->x);
	uint64_t took = now_ns() - arrival;
	histogram_record(&turn_times, took);
	if (b->synthetic_sent != told_before)
		histogram_record(&told_times, took);
}

static void report_times(const struct bridge *b, const char *what, const struct histogram *h)
{
	if (h->n)
		bridge_log(b, 1, "%s: %llu, from the first X event read to the turn's end: p50 %.0f "
				 "µs, p99 %.0f µs, max %.0f µs",
			   what, (unsigned long long)h->n, histogram_percentile(h, 50) / 1e3,
			   histogram_percentile(h, 99) / 1e3, (double)h->max / 1e3);
}

/* The bridge cannot mirror the screen in this visd: says what to change, for exit status 1. */
static int refused(const struct bridge *b)
{
	bridge_log(b, 0, "visd refused %u request%s: its tree can no longer mirror X's; stopping "
			 "(see visd's --max-windows and --max-depth)",
		   b->refusals, b->refusals == 1 ? "" : "s");
	return 1;
}

static int run(struct bridge *b)
{
	int xfd = xcb_get_file_descriptor(b->x), vfd = vis_client_fd(b->vc);
	while (!stop_signal && !b->x_failed && !b->visd_failed && !b->visd_refused) {
		if (check_asked)
			check_mirror(b);
		xcb_generic_event_t *ev = xcb_poll_for_queued_event(b->x);
		uint64_t arrival = now_ns();
		if (!ev) {
			struct pollfd p[2] = { { xfd, POLLIN, 0 }, { vfd, POLLIN, 0 } };
			if (vis_client_flush(b->vc) == 1)
				p[1].events |= POLLOUT;
			if (poll(p, 2, -1) < 0) {
				if (errno == EINTR)
					continue;
				bridge_log(b, 0, "poll: %s", strerror(errno));
				return 1;
			}
			if (p[1].revents && vis_client_dispatch(b->vc) < 0) {
				b->visd_failed = true;
				break;
			}
			arrival = now_ns();
			ev = xcb_poll_for_event(b->x);
			if (!ev && xcb_connection_has_error(b->x)) {
				b->x_failed = true;
				break;
			}
			if (!ev) {
				notify_flush(b);
				xcb_flush(b->x);
				continue;
			}
		}
		turn(b, ev, arrival);
	}
	if (b->x_failed) {
		bridge_log(b, 0, "the X server closed the connection");
		return 1;
	}
	if (b->visd_failed || vis_client_error(b->vc)) {
		bridge_log(b, 0, "visd closed the connection: %s", vis_client_error_message(b->vc));
		return 1;
	}
	if (b->visd_refused)
		return refused(b);
	return 0;
}

static int parse_mode(const char *arg, const char *const *names, int *out)
{
	for (int i = 0; names[i]; i++)
		if (!strcmp(arg, names[i])) {
			*out = i;
			return 0;
		}
	return -1;
}

int main(int argc, char **argv)
{
	static const struct option longs[] = {
		{ "display", required_argument, NULL, 'd' },
		{ "socket", required_argument, NULL, 's' },
		{ "send-events", required_argument, NULL, 'e' },
		{ "translucency", required_argument, NULL, 't' },
		{ "verbose", no_argument, NULL, 'v' },
		{ "help", no_argument, NULL, 'h' },
		{ "version", no_argument, NULL, 'V' },
		{ NULL, 0, NULL, 0 },
	};
	static const char *const send_names[] = { "auto", "always", "never", NULL };
	static const char *const trans_names[] = { "auto", "on", "off", NULL };
	struct bridge b = { 0 };
	const char *display = NULL, *socket = NULL;
	int opt, mode;
	while ((opt = getopt_long(argc, argv, "s:vh", longs, NULL)) != -1) {
		switch (opt) {
		case 'd':
			display = optarg;
			break;
		case 's':
			socket = optarg;
			break;
		case 'e':
			if (parse_mode(optarg, send_names, &mode) < 0) {
				fprintf(stderr, "visd-x11: --send-events takes auto, always or never, "
						"not '%s'\n", optarg);
				return 2;
			}
			b.send_events = (enum send_events)mode;
			break;
		case 't':
			if (parse_mode(optarg, trans_names, &mode) < 0) {
				fprintf(stderr, "visd-x11: --translucency takes auto, on or off, not "
						"'%s'\n", optarg);
				return 2;
			}
			b.translucency = (enum translucency)mode;
			break;
		case 'v':
			b.verbose++;
			break;
		case 'h':
			usage(stdout);
			return 0;
		case 'V':
			printf("visd-x11 %s (protocol %u)\n", VIS_VERSION, VIS_PROTOCOL_VERSION);
			return 0;
		default:
			usage(stderr);
			return 2;
		}
	}
	if (optind < argc) {
		fprintf(stderr, "visd-x11: unexpected argument '%s'\n", argv[optind]);
		usage(stderr);
		return 2;
	}
	struct sigaction sa = { .sa_handler = on_signal };
	sigaction(SIGINT, &sa, NULL);
	sigaction(SIGTERM, &sa, NULL);
	sigaction(SIGUSR1, &sa, NULL);
	signal(SIGPIPE, SIG_IGN);

	histogram_init(&turn_times);
	histogram_init(&told_times);
	int rc = 1;
	if (setup_x(&b, display) < 0 || setup_visd(&b, socket) < 0)
		goto out;
	if (mirror_init(&b) < 0) {
		bridge_log(&b, 0, "out of memory");
		goto out;
	}
	uint64_t t0 = now_ns();
	xread_cm(&b);
	if (xread_screen(&b) < 0 || visd_end_turn(&b) < 0) {
		bridge_log(&b, 0, "%s while reading the tree",
			   xcb_connection_has_error(b.x) ? "the X server closed the connection"
							 : "visd closed the connection");
		goto out;
	}
	if (b.visd_refused) {
		rc = refused(&b);
		goto out;
	}
	notify_flush(&b);
	xcb_flush(b.x);
	bridge_log(&b, 1, "mirrored %u windows in %.1f ms%s", b.n_windows, (double)(now_ns() - t0) / 1e6,
		   b.cm_running ? "; a compositing manager runs" : "");
	rc = run(&b);
	if (stop_signal)
		bridge_log(&b, 1, "stopped by signal %d", (int)stop_signal);
	bridge_log(&b, 1, "%llu X events in %llu turns, %llu resynchronizations, %llu synthetic "
			  "events sent",
		   (unsigned long long)b.events, (unsigned long long)b.turns,
		   (unsigned long long)b.resyncs, (unsigned long long)b.synthetic_sent);
	report_times(&b, "turns", &turn_times);
	report_times(&b, "turns that sent synthetic events", &told_times);
out:
	mirror_finish(&b);
	free(b.events_read);
	free(b.new_windows);
	vis_client_destroy(b.vc);
	if (b.x)
		xcb_disconnect(b.x);
	return rc;
}
