/*
 * x11-order: what an unmodified X client sees of its window's visibility while visd-x11 runs:
 * where the bridge's synthetic VisibilityNotify (SendEvent) falls among X's own ConfigureNotify,
 * MapNotify, Expose and VisibilityNotify for the same change, how long after the change each
 * comes, and whether the last state the client was told is the true one.
 *
 * Two connections to the display. The client's creates its top-level W (InputOutput,
 * override-redirect) and selects VisibilityChange, Exposure and StructureNotify on it, as an
 * unmodified client does. The world's makes changes one at a time, a cycle of them --repeat
 * times: it covers W wholly by mapping a window over it and uncovers it, covers part of it and
 * uncovers that, grows and shrinks W under the cover, raises and lowers W, moves W under another
 * window and out, unmaps and maps W, and maps W under the cover. For each change: the time the
 * world's request is sent; a round trip on the world's connection (the change done); the
 * _VISD_X11_SYNC handshake with the bridge (the root's _VISD_X11_SYNC set to k, then
 * _VISD_X11_SYNCED awaited until it holds k: the bridge has applied the change and sent its
 * synthetic events, which it does before answering); a round trip on the client's connection
 * (every event generated so far is in); then events until none came for --quiet-ms ("late" ones,
 * which the handshake should have made impossible, are counted). The client's events are read
 * as they arrive, each timed from the world's request.
 *
 * W's true state comes from the geometry the world set, computed by the brute-force engine
 * (src/brute.c) on the stack of mapped windows. Whenever W is viewable, the last VisibilityNotify
 * its client got, X's own or synthetic, must be that state: otherwise the change counts as
 * "stale last" and is printed in full. With --check CMD, CMD's state of W (visctl -s SOCK states
 * --x11: "0x… STATE" lines of the viewable windows) must be that state too. --bursts N then makes
 * N runs of changes without waiting between them (bursts() says how), where only the last word
 * is checked.
 *
 * Prints a table per kind of change: how many; the world's round trip (p50); when X's first event
 * came and when the bridge's first synthetic event came (p50/p99, from the world's request), and
 * the synthetic event's distance from X's last own event before it; how often X's own last word
 * was not the true state; stale last words. Then the orders of events seen, with how often. Exit:
 * 0; 1 when a last word was stale, CMD differed, or the display, the bridge or CMD failed; 2
 * (usage). tools/x11-order.sh runs it on a private Xvfb with visd and the bridge (and xcompmgr).
 */
#include <getopt.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "engine.h"
#include "histogram.h"
#include "rng.h"
#include "x11-order.h"

#define MAX_ORDERS 8 /* orders of events kept a kind of change */

/* Where each starts: W at home, unmapped covers, the far window mapped. Fits 960×600. */
#define HOME { 100, 100, 200, 150 }
static const struct vis_rect start_rect[N_WINS] = {
	HOME, { 80, 80, 240, 190 }, { 50, 150, 150, 200 }, { 600, 100, 300, 250 },
};

enum op { OP_MAP, OP_UNMAP, OP_RAISE, OP_LOWER, OP_PLACE };

/* One change: what the world does to which window (OP_PLACE: to rect). */
struct step {
	const char *kind;
	enum op op;
	int win;
	struct vis_rect rect;
};

/*
 * The cycle: it leaves every window as it found it. W is at the bottom of the stack but between
 * raise and lower, so the cover, the part cover and the far window are above it whenever mapped.
 */
static const struct step cycle[] = {
	{ "cover", OP_MAP, WIN_COVER, { 0 } },
	{ "grow", OP_PLACE, WIN_W, { 100, 100, 400, 300 } },
	{ "shrink", OP_PLACE, WIN_W, HOME },
	{ "raise", OP_RAISE, WIN_W, { 0 } },
	{ "lower", OP_LOWER, WIN_W, { 0 } },
	{ "uncover", OP_UNMAP, WIN_COVER, { 0 } },
	{ "part-cover", OP_MAP, WIN_PART, { 0 } },
	{ "part-uncover", OP_UNMAP, WIN_PART, { 0 } },
	{ "move-under", OP_PLACE, WIN_W, { 620, 120, 200, 150 } },
	{ "move-out", OP_PLACE, WIN_W, HOME },
	{ "unmap", OP_UNMAP, WIN_W, { 0 } },
	{ "map", OP_MAP, WIN_W, { 0 } },
	{ "cover", OP_MAP, WIN_COVER, { 0 } },
	{ "unmap", OP_UNMAP, WIN_W, { 0 } },
	{ "map-covered", OP_MAP, WIN_W, { 0 } },
	{ "uncover", OP_UNMAP, WIN_COVER, { 0 } },
};
#define N_STEPS (sizeof(cycle) / sizeof(cycle[0]))

/* The figures of one kind of change; orders[] holds the first MAX_ORDERS orders seen. */
struct kind_stats {
	const char *name;
	unsigned long n, synthetic, x_wrong, stale, late, differ;
	struct histogram done, x_first, syn, gap;
	struct {
		char text[256];
		unsigned long n;
	} orders[MAX_ORDERS];
	unsigned n_orders;
	unsigned long other_orders;
};

static struct kind_stats kinds[N_STEPS];
static size_t n_kinds;

_Noreturn void order_die(const char *fmt, ...)
{
	va_list ap;
	fflush(stdout);
	fputs("x11-order: ", stderr);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	exit(1);
}

/* A state's short name in the tables. */
static const char *short_state(int state)
{
	static const char *const names[] = { "U", "PO", "FO", "none" };
	return state >= 0 && state < 4 ? names[state] : "?";
}

/* W's true state as the world set things: the brute force on the stack of mapped windows. */
static int truth(const struct order *o)
{
	if (!o->mapped[WIN_W])
		return VIS_NO_STATE;
	struct vis_rect rects[N_WINS];
	size_t n = 0, w = 0;
	for (int i = 0; i < N_WINS; i++) {
		int j = o->stack[i];
		if (!o->mapped[j])
			continue;
		if (j == WIN_W)
			w = n;
		rects[n++] = o->rect[j];
	}
	struct vis_stack s = { .rects = rects,
			       .n = n,
			       .has_screen = true,
			       .screen_w = o->screen->width_in_pixels,
			       .screen_h = o->screen->height_in_pixels };
	uint8_t states[N_WINS];
	if (vis_compute(VIS_ENGINE_BRUTE, &s, states) < 0)
		order_die("out of memory");
	return states[w];
}

/* Moves window i to the top or the bottom of the model's stack. */
static void restack(struct order *o, int i, bool top)
{
	int k = 0, rest[N_WINS];
	for (int j = 0; j < N_WINS; j++)
		if (o->stack[j] != i)
			rest[k++] = o->stack[j];
	if (top) {
		memcpy(o->stack, rest, (N_WINS - 1) * sizeof(int));
		o->stack[N_WINS - 1] = i;
	} else {
		memcpy(o->stack + 1, rest, (N_WINS - 1) * sizeof(int));
		o->stack[0] = i;
	}
}

/* Queues the world's request for a step and applies it to the model. */
static void world_request(struct order *o, const struct step *s)
{
	xcb_window_t id = o->win[s->win];
	uint32_t v[4];
	switch (s->op) {
	case OP_MAP:
		xcb_map_window(o->world, id);
		o->mapped[s->win] = true;
		break;
	case OP_UNMAP:
		xcb_unmap_window(o->world, id);
		o->mapped[s->win] = false;
		break;
	case OP_RAISE:
	case OP_LOWER:
		v[0] = s->op == OP_RAISE ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW;
		xcb_configure_window(o->world, id, XCB_CONFIG_WINDOW_STACK_MODE, v);
		restack(o, s->win, s->op == OP_RAISE);
		break;
	case OP_PLACE:
		v[0] = (uint32_t)s->rect.x;
		v[1] = (uint32_t)s->rect.y;
		v[2] = (uint32_t)s->rect.w;
		v[3] = (uint32_t)s->rect.h;
		xcb_configure_window(o->world, id,
				     XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y |
					     XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT,
				     v);
		o->rect[s->win] = s->rect;
		break;
	}
}

/* CMD's state of W: 0–2, or VIS_NO_STATE when CMD does not list it (not viewable). */
static int check_state(struct order *o)
{
	static const char *const names[] = { "unobscured", "partially-obscured", "fully-obscured" };
	FILE *f = popen(o->check, "r");
	if (f == NULL)
		order_die("cannot run %s", o->check);
	int state = VIS_NO_STATE;
	char *line = NULL, word[32];
	size_t cap = 0;
	unsigned xid;
	while (getline(&line, &cap, f) > 0)
		if (sscanf(line, "0x%x %31s", &xid, word) == 2 && xid == o->win[WIN_W])
			for (int s = 0; s < 3; s++)
				if (strcmp(word, names[s]) == 0)
					state = s;
	free(line);
	if (pclose(f) != 0)
		order_die("%s failed", o->check);
	return state;
}

/* The order of a change's events as text ("Configure, X:PO, Expose×2, syn:PO"). */
static void order_text(const struct order *o, char *buf, size_t size)
{
	static const char *const names[] = { "Configure", "Map", "Unmap", "Expose",
					     "X",         "syn", "other" };
	size_t len = 0;
	buf[0] = '\0';
	if (o->n_seen == 0)
		snprintf(buf, size, "(nothing)");
	for (size_t i = 0; i < o->n_seen && len < size; i++) {
		const struct seen *e = &o->seen[i];
		size_t run = 1;
		if (e->what == SEEN_EXPOSE)
			while (i + run < o->n_seen && o->seen[i + run].what == SEEN_EXPOSE)
				run++;
		int k = snprintf(buf + len, size - len, "%s%s", i ? ", " : "", names[e->what]);
		if (k > 0)
			len += (size_t)k;
		if (len >= size)
			break;
		if (e->what == SEEN_X_VIS || e->what == SEEN_SYN_VIS)
			k = snprintf(buf + len, size - len, ":%s", short_state(e->state));
		else if (e->what == SEEN_EXPOSE)
			k = snprintf(buf + len, size - len, "×%zu", run);
		else
			k = 0;
		if (k > 0)
			len += (size_t)k;
		i += run - 1;
	}
}

/* Prints a change's events with their times, for a stale last word or -v. */
static void print_seen(FILE *f, const struct order *o)
{
	static const char *const names[] = { "ConfigureNotify",  "MapNotify",
					     "UnmapNotify",      "Expose",
					     "VisibilityNotify", "synthetic VisibilityNotify",
					     "other event" };
	for (size_t i = 0; i < o->n_seen; i++) {
		const struct seen *e = &o->seen[i];
		fprintf(f, "    %8.1f µs  %s", (double)e->t / 1e3, names[e->what]);
		if (e->what == SEEN_X_VIS || e->what == SEEN_SYN_VIS)
			fprintf(f, " %s", vis_state_name(e->state));
		fputc('\n', f);
	}
}

/* The figures of the kind of change called name, made on its first change. */
static struct kind_stats *kind_of(const char *name)
{
	for (size_t i = 0; i < n_kinds; i++)
		if (strcmp(kinds[i].name, name) == 0)
			return &kinds[i];
	struct kind_stats *k = &kinds[n_kinds++];
	k->name = name;
	histogram_init(&k->done);
	histogram_init(&k->x_first);
	histogram_init(&k->syn);
	histogram_init(&k->gap);
	return k;
}

/* Files a change's figures under its kind, and says when its last word was stale. */
static void file_change(struct order *o, struct kind_stats *k, uint64_t done, unsigned long index,
			const struct step *s)
{
	k->n++;
	histogram_record(&k->done, done);
	bool x_seen = false, syn_seen = false;
	uint64_t last_x = 0;
	for (size_t i = 0; i < o->n_seen; i++) {
		const struct seen *e = &o->seen[i];
		if (e->what == SEEN_SYN_VIS) {
			if (!syn_seen) {
				histogram_record(&k->syn, e->t);
				if (x_seen)
					histogram_record(&k->gap, e->t - last_x);
				k->synthetic++;
			}
			syn_seen = true;
		} else if (!syn_seen) {
			if (!x_seen)
				histogram_record(&k->x_first, e->t);
			x_seen = true;
			last_x = e->t;
		}
	}
	char text[256];
	order_text(o, text, sizeof text);
	unsigned i = 0;
	while (i < k->n_orders && strcmp(k->orders[i].text, text) != 0)
		i++;
	if (i < k->n_orders) {
		k->orders[i].n++;
	} else if (k->n_orders < MAX_ORDERS) {
		snprintf(k->orders[k->n_orders].text, sizeof k->orders[0].text, "%s", text);
		k->orders[k->n_orders++].n = 1;
	} else {
		k->other_orders++;
	}
	int want = truth(o);
	bool stale = want != VIS_NO_STATE && o->told != want;
	if (want != VIS_NO_STATE && o->x_told != want)
		k->x_wrong++;
	if (o->verbose) {
		fprintf(stderr, "x11-order: change %lu, %s (true: %s):\n", index, s->kind,
			short_state(want));
		print_seen(stderr, o);
	}
	int visd = o->check != NULL ? check_state(o) : want;
	if (visd != want) {
		k->differ++;
		fprintf(stderr, "x11-order: change %lu, %s: %s says %s, the geometry %s\n", index,
			s->kind, o->check, short_state(visd), short_state(want));
	}
	if (stale) {
		k->stale++;
		fprintf(stderr,
			"x11-order: change %lu, %s: STALE: the client was told %s last, the "
			"true state is %s; it got:\n",
			index, s->kind, o->told < 0 ? "nothing" : vis_state_name((uint8_t)o->told),
			vis_state_name((uint8_t)want));
		print_seen(stderr, o);
	}
}

/* One change, measured (see the top). */
static void measure(struct order *o, const struct step *s, unsigned long index)
{
	struct kind_stats *k = kind_of(s->kind);
	conn_collect(o);
	o->n_seen = 0;
	o->collecting = true;
	world_request(o, s);
	xcb_get_input_focus_cookie_t ck = xcb_get_input_focus(o->world);
	o->t_req = conn_now_ns();
	xcb_flush(o->world);
	free(conn_await_reply(o, o->world, ck.sequence, "the world's round trip"));
	uint64_t done = conn_now_ns() - o->t_req;
	conn_handshake(o);
	conn_round_trip(o, o->client, "the client's round trip");
	size_t mark = o->n_seen;
	conn_quiet(o);
	o->collecting = false;
	k->late += o->n_seen - mark;
	if (o->n_seen == MAX_SEEN)
		order_die("change %lu (%s): more than %d events", index, s->kind, MAX_SEEN);
	file_change(o, k, done, index, s);
}

/*
 * Bursts: runs of 2 to 8 consecutive changes of the cycle, each sent 0 to 500 µs after the one
 * before without waiting for anything, so that X's events about a change cross the bridge's
 * synthetic events about the ones before; then the handshake, round trip and quiet as after one
 * change. Only the last word counts: it must be the true state. Returns the stale last words.
 */
static unsigned long bursts(struct order *o, unsigned long n, unsigned long *changes)
{
	struct vis_rng rng = { 1 };
	unsigned long stale = 0;
	size_t pos = 0; /* the cycle is done: its first step comes next */
	for (unsigned long i = 1; i <= n; i++) {
		int len = (int)vis_rng_range(&rng, 2, 8);
		conn_collect(o);
		o->n_seen = 0;
		o->collecting = true;
		o->t_req = conn_now_ns();
		for (int j = 0; j < len; j++) {
			world_request(o, &cycle[pos]);
			pos = (pos + 1) % N_STEPS;
			xcb_flush(o->world);
			long gap = (long)vis_rng_below(&rng, 501) * 1000;
			if (gap)
				nanosleep(&(struct timespec){ 0, gap }, NULL);
		}
		*changes += (unsigned long)len;
		conn_round_trip(o, o->world, "the world's round trip");
		conn_handshake(o);
		conn_round_trip(o, o->client, "the client's round trip");
		conn_quiet(o);
		o->collecting = false;
		int want = truth(o);
		if (o->verbose) {
			fprintf(stderr, "x11-order: burst %lu, %d changes up to %s (true: %s):\n",
				i, len, cycle[(pos + N_STEPS - 1) % N_STEPS].kind,
				short_state(want));
			print_seen(stderr, o);
		}
		if (o->check != NULL && check_state(o) != want) {
			stale++;
			fprintf(stderr, "x11-order: burst %lu: %s differs from the geometry (%s)\n",
				i, o->check, short_state(want));
		}
		if (want != VIS_NO_STATE && o->told != want) {
			stale++;
			fprintf(stderr,
				"x11-order: burst %lu, %d changes up to %s: STALE: the client "
				"was told %s last, the true state is %s; it got:\n",
				i, len, cycle[(pos + N_STEPS - 1) % N_STEPS].kind,
				o->told < 0 ? "nothing" : vis_state_name((uint8_t)o->told),
				vis_state_name((uint8_t)want));
			print_seen(stderr, o);
		}
	}
	return stale;
}

/* Creates the windows: W on the client's connection, the others on the world's, above it. */
static void setup(struct order *o)
{
	for (int i = 0; i < N_WINS; i++) {
		xcb_connection_t *c = i == WIN_W ? o->client : o->world;
		uint32_t mask = XCB_CW_BACK_PIXEL | XCB_CW_OVERRIDE_REDIRECT;
		uint32_t values[3] = {
			i == WIN_W ? o->screen->white_pixel : o->screen->black_pixel, 1, 0
		};
		if (i == WIN_W) {
			mask |= XCB_CW_EVENT_MASK;
			values[2] = XCB_EVENT_MASK_VISIBILITY_CHANGE | XCB_EVENT_MASK_EXPOSURE |
				    XCB_EVENT_MASK_STRUCTURE_NOTIFY;
		}
		const struct vis_rect *r = &start_rect[i];
		o->win[i] = xcb_generate_id(c);
		xcb_create_window(c, XCB_COPY_FROM_PARENT, o->win[i], o->screen->root,
				  (int16_t)r->x, (int16_t)r->y, (uint16_t)r->w, (uint16_t)r->h, 0,
				  XCB_WINDOW_CLASS_INPUT_OUTPUT, XCB_COPY_FROM_PARENT, mask,
				  values);
		o->rect[i] = *r;
		o->stack[i] = i;
		o->mapped[i] = i == WIN_W || i == WIN_FAR;
		if (o->mapped[i])
			xcb_map_window(c, o->win[i]);
		if (i == WIN_W)
			conn_round_trip(o, o->client, "creating W"); /* W first: the bottom */
	}
	conn_round_trip(o, o->world, "creating the windows");
	conn_handshake(o);
	conn_round_trip(o, o->client, "the client's round trip");
	conn_quiet(o);
}

/* Prints the table and the orders; returns the number of stale last words. */
static unsigned long report(const struct order *o, unsigned long repeat, bool cm)
{
	unsigned long stale = 0, differ = 0;
	printf("x11-order: %lu cycles of %zu changes; W's events by the client's connection, times "
	       "in µs after the world's request; %s\n",
	       repeat, N_STEPS, cm ? "a compositing manager runs" : "no compositing manager");
	printf("%-13s %6s %7s %15s %6s %15s %15s %7s %5s\n", "change", "count", "done", "X first",
	       "syn", "synthetic", "syn - X last", "X wrong", "stale");
	printf("%-13s %6s %7s %15s %6s %15s %15s %7s %5s\n", "", "", "p50", "p50/p99", "count",
	       "p50/p99", "p50/p99", "", "last");
	for (size_t i = 0; i < n_kinds; i++) {
		const struct kind_stats *k = &kinds[i];
		char x[32] = "-", s[32] = "-", g[32] = "-";
		if (k->x_first.n)
			snprintf(x, sizeof x, "%.0f/%.0f",
				 histogram_percentile(&k->x_first, 50) / 1e3,
				 histogram_percentile(&k->x_first, 99) / 1e3);
		if (k->syn.n)
			snprintf(s, sizeof s, "%.0f/%.0f", histogram_percentile(&k->syn, 50) / 1e3,
				 histogram_percentile(&k->syn, 99) / 1e3);
		if (k->gap.n)
			snprintf(g, sizeof g, "%.0f/%.0f", histogram_percentile(&k->gap, 50) / 1e3,
				 histogram_percentile(&k->gap, 99) / 1e3);
		printf("%-13s %6lu %7.0f %15s %6lu %15s %15s %7lu %5lu\n", k->name, k->n,
		       histogram_percentile(&k->done, 50) / 1e3, x, k->synthetic, s, g, k->x_wrong,
		       k->stale);
		stale += k->stale;
		differ += k->differ;
	}
	printf("orders seen (X:S X's own VisibilityNotify, syn:S the bridge's; U, PO, FO):\n");
	unsigned long late = 0;
	for (size_t i = 0; i < n_kinds; i++) {
		const struct kind_stats *k = &kinds[i];
		for (unsigned j = 0; j < k->n_orders; j++)
			printf("  %-13s %6lu  %s\n", j ? "" : k->name, k->orders[j].n,
			       k->orders[j].text);
		if (k->other_orders)
			printf("  %-13s %6lu  (other orders)\n", "", k->other_orders);
		late += k->late;
	}
	printf("x11-order: stale last: %lu; events after the handshake and round trip: %lu%s\n",
	       stale, late, o->check ? "" : "; visd not asked (no --check)");
	if (o->check)
		printf("x11-order: %s differed from the geometry %lu times\n", o->check, differ);
	return stale + differ;
}

static void usage(FILE *f)
{
	fputs("usage: x11-order [--display D] [--repeat N] [--bursts N] [--quiet-ms MS]\n"
	      "                 [--check CMD] [--compositor] [--working PID]... [-v]\n"
	      "  --display D    the X server, where visd-x11 runs (default: $DISPLAY)\n"
	      "  --repeat N     cycles of changes (default 100)\n"
	      "  --bursts N     then N bursts of changes without waiting (default 0)\n"
	      "  --quiet-ms MS  after each change, read events until none for MS (default 50)\n"
	      "  --check CMD    also compare CMD's state of W (visctl -s SOCK states --x11)\n"
	      "  --compositor   wait for a compositing manager to own _NET_WM_CM_S0\n"
	      "  --working PID  waits for an answer go on while the X server or PID (the\n"
	      "                 bridge, visd, the compositor) works; repeated for more\n"
	      "  -v             every change's events, timed\n",
	      f);
}

int main(int argc, char **argv)
{
	static const struct option options[] = {
		{ "display", required_argument, NULL, 'd' },
		{ "repeat", required_argument, NULL, 'r' },
		{ "quiet-ms", required_argument, NULL, 'q' },
		{ "check", required_argument, NULL, 'c' },
		{ "compositor", no_argument, NULL, 'C' },
		{ "bursts", required_argument, NULL, 'b' },
		{ "working", required_argument, NULL, 'w' },
		{ "help", no_argument, NULL, 'h' },
		{ NULL, 0, NULL, 0 },
	};
	struct order o = { .quiet_ms = 50, .told = -1, .x_told = -1, .n_working = 1 };
	const char *display = NULL;
	unsigned long repeat = 100, n_bursts = 0;
	bool compositor = false;
	char *end;
	int opt;
	while ((opt = getopt_long(argc, argv, "v", options, NULL)) != -1) {
		switch (opt) {
		case 'd':
			display = optarg;
			break;
		case 'r':
			repeat = strtoul(optarg, &end, 10);
			if (*end || repeat == 0)
				goto bad;
			break;
		case 'q':
			o.quiet_ms = (int)strtol(optarg, &end, 10);
			if (*end || o.quiet_ms < 1 || o.quiet_ms > 1000)
				goto bad;
			break;
		case 'b':
			n_bursts = strtoul(optarg, &end, 10);
			if (*end)
				goto bad;
			break;
		case 'c':
			o.check = optarg;
			break;
		case 'w': {
			long pid = strtol(optarg, &end, 10);
			if (*end || pid <= 0 || pid > INT32_MAX || o.n_working == PROGRESS_MAX_PIDS)
				goto bad;
			o.working[o.n_working++] = (pid_t)pid;
			break;
		}
		case 'C':
			compositor = true;
			break;
		case 'v':
			o.verbose = true;
			break;
		case 'h':
			usage(stdout);
			return 0;
		default:
			goto bad;
		}
	}
	if (optind != argc) {
bad:
		usage(stderr);
		return 2;
	}
	const char *name = display ? display : getenv("DISPLAY");
	if (name == NULL || name[0] == '\0')
		name = "(no $DISPLAY)";
	int screen_no;
	o.client = xcb_connect(display, &screen_no);
	o.world = xcb_connect(display, NULL);
	if (xcb_connection_has_error(o.client) || xcb_connection_has_error(o.world))
		order_die("cannot connect to the X display %s", name);
	o.working[0] = progress_peer_pid(xcb_get_file_descriptor(o.world)); /* the X server */
	xcb_screen_iterator_t it = xcb_setup_roots_iterator(xcb_get_setup(o.client));
	for (int i = 0; i < screen_no && it.rem; i++)
		xcb_screen_next(&it);
	o.screen = it.data;
	if (o.screen->width_in_pixels < 960 || o.screen->height_in_pixels < 600)
		order_die("the screen of %s is %ux%u: it needs 960x600 at least", name,
			  o.screen->width_in_pixels, o.screen->height_in_pixels);
	char cm[32];
	snprintf(cm, sizeof cm, "_NET_WM_CM_S%d", screen_no);
	bool cm_running = conn_owned(&o, cm, compositor);
	o.sync = conn_intern(&o, "_VISD_X11_SYNC");
	o.synced = conn_intern(&o, "_VISD_X11_SYNCED");
	uint32_t mask = XCB_EVENT_MASK_PROPERTY_CHANGE;
	xcb_change_window_attributes(o.world, o.screen->root, XCB_CW_EVENT_MASK, &mask);
	o.k = conn_read_counter(&o, o.sync); /* a previous run's: the handshake goes on from it */
	setup(&o);
	unsigned long index = 0;
	for (unsigned long r = 0; r < repeat; r++)
		for (size_t i = 0; i < N_STEPS; i++)
			measure(&o, &cycle[i], ++index);
	unsigned long bad = report(&o, repeat, cm_running), changes = 0;
	if (n_bursts) {
		unsigned long stale = bursts(&o, n_bursts, &changes);
		printf("x11-order: %lu bursts of 2 to 8 changes 0 to 500 µs apart (%lu changes): "
		       "stale last or visd different: %lu\n",
		       n_bursts, changes, stale);
		bad += stale;
	}
	xcb_disconnect(o.client);
	xcb_disconnect(o.world);
	return bad ? 1 : 0;
}
