/*
 * `visctl watch`: subscribes to notices and prints one line per notice, flushed at once so that
 * a pipe reader sees each as it happens. SIGINT and SIGTERM end it cleanly: they are blocked
 * except inside ppoll, so one arriving between two checks is never lost.
 *
 * With --x11, windows are named by the X window they mirror: the XIDs come from the lookups of
 * the XIDs given, from the tree (parents and siblings too) and from stack notices, which carry
 * every window's external ID. The tree is read after subscribing, so that a window watched either
 * is in it or has stack notices; the notices that come before it are held until it has come.
 */
#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "idmap.h"
#include "live.h"
#include "visctl.h"

/* A notice held until the tree has come (--x11), with its own copy of its rectangles. */
struct held_notice {
	struct vis_notice n;
	struct vis_rect32 *rects;
};

struct watch {
	bool json;
	uint64_t count; /* 0: no limit */
	uint64_t seen;
	bool x11;                /* name windows by their XIDs */
	struct vis_idmap xid_of; /* window → index in xids, plus 1 */
	uint64_t *xids;
	size_t n_xids, cap_xids;
	bool holding; /* notices wait in held until the tree has come */
	struct held_notice *held;
	size_t n_held, cap_held;
	bool failed; /* out of memory while holding or learning: the watch ends */
};

/* Remembers that window mirrors X window xid. */
static void learn(struct watch *w, uint32_t window, uint64_t xid)
{
	uintptr_t i = (uintptr_t)vis_idmap_get(&w->xid_of, window);
	if (i) {
		w->xids[i - 1] = xid;
		return;
	}
	if (w->n_xids == w->cap_xids) {
		size_t cap = w->cap_xids ? 2 * w->cap_xids : 64;
		uint64_t *more = realloc(w->xids, cap * sizeof(*more));
		if (!more) {
			w->failed = true;
			return;
		}
		w->xids = more;
		w->cap_xids = cap;
	}
	w->xids[w->n_xids] = xid;
	if (vis_idmap_put(&w->xid_of, window, (void *)(uintptr_t)(w->n_xids + 1)) < 0)
		w->failed = true;
	else
		w->n_xids++;
}

/* Prints a window: "0xXID" when watching X windows and it mirrors one, else its ID. */
static void print_window(const struct watch *w, uint32_t window)
{
	uintptr_t i = w->x11 && window ? (uintptr_t)vis_idmap_get(&w->xid_of, window) : 0;
	if (i)
		printf("0x%" PRIx64, w->xids[i - 1]);
	else
		printf("%u", window);
}

static volatile sig_atomic_t stop_signal;

/* Notes the signal; the loop sees it when ppoll returns. */
static void on_signal(int sig)
{
	stop_signal = sig;
}

/* The name of a stack change, as watch prints it. */
static const char *change_name(uint32_t change)
{
	static const char *const names[] = { "create",    "destroy", "map",      "unmap",
					     "configure", "restack", "reparent", "resync", "look" };
	return change < sizeof(names) / sizeof(names[0]) ? names[change] : "?";
}

/* Prints a notice as a text line. */
static void print_text(const struct watch *w, const struct vis_notice *n)
{
	printf("%" PRIu64 " ", n->serial);
	switch (n->kind) {
	case VIS_NOTICE_KIND_VISIBILITY:
		printf("visibility ");
		print_window(w, n->window);
		printf(" %s %s", vis_visibility_name(n->visibility.state),
		       vis_visibility_name(n->visibility.previous));
		if (n->visibility.coalesced)
			printf(" coalesced %u", n->visibility.coalesced);
		break;
	case VIS_NOTICE_KIND_EXPOSURE:
		printf("exposure ");
		print_window(w, n->window);
		for (uint32_t i = 0; i < n->exposure.n_rects; i++) {
			const struct vis_rect32 *r = &n->exposure.rects[i];
			printf(" %d,%d,%u,%u", r->x, r->y, r->width, r->height);
		}
		if (n->exposure.flags & VIS_EXPOSURE_COLLAPSED)
			printf(" collapsed");
		if (n->exposure.coalesced)
			printf(" coalesced %u", n->exposure.coalesced);
		break;
	case VIS_NOTICE_KIND_STACK:
		printf("stack %s ", change_name(n->stack.change));
		print_window(w, n->window);
		putchar(' ');
		print_window(w, n->stack.parent);
		printf(" %d,%d,%u,%u ", n->stack.x, n->stack.y, n->stack.width, n->stack.height);
		print_window(w, n->stack.sibling);
		/* Only what a plain window lacks, so that plain desktops print as before. */
		if (n->stack.border)
			printf(" border %u", n->stack.border);
		if (n->stack.flags & VIS_WINDOW_SHAPED)
			printf(" shaped");
		if (n->stack.flags & VIS_WINDOW_TRANSLUCENT)
			printf(" translucent");
		if (n->stack.flags & VIS_WINDOW_INPUT_ONLY)
			printf(" input-only");
		break;
	case VIS_NOTICE_KIND_OVERFLOW:
		printf("overflow %u %u", n->overflow.dropped, n->overflow.resync);
		break;
	}
	putchar('\n');
}

/* Prints a notice as one JSON object (every string is one of ours: nothing to escape). */
static void print_json(const struct watch *w, const struct vis_notice *n)
{
	printf("{\"serial\":%" PRIu64 ",", n->serial);
	/* Watching X windows: the window's XID first, where it has one. */
	uintptr_t x = w->x11 && n->window ? (uintptr_t)vis_idmap_get(&w->xid_of, n->window) : 0;
	if (x)
		printf("\"x11\":\"0x%" PRIx64 "\",", w->xids[x - 1]);
	switch (n->kind) {
	case VIS_NOTICE_KIND_VISIBILITY:
		printf("\"notice\":\"visibility\",\"window\":%u,\"state\":\"%s\",\"previous\":\"%s\","
		       "\"coalesced\":%u}",
		       n->window, vis_visibility_name(n->visibility.state),
		       vis_visibility_name(n->visibility.previous), n->visibility.coalesced);
		break;
	case VIS_NOTICE_KIND_EXPOSURE:
		printf("\"notice\":\"exposure\",\"window\":%u,\"collapsed\":%s,\"coalesced\":%u,"
		       "\"rects\":[",
		       n->window, n->exposure.flags & VIS_EXPOSURE_COLLAPSED ? "true" : "false",
		       n->exposure.coalesced);
		for (uint32_t i = 0; i < n->exposure.n_rects; i++) {
			const struct vis_rect32 *r = &n->exposure.rects[i];
			printf("%s[%d,%d,%u,%u]", i ? "," : "", r->x, r->y, r->width, r->height);
		}
		printf("]}");
		break;
	case VIS_NOTICE_KIND_STACK:
		printf("\"notice\":\"stack\",\"change\":\"%s\",\"window\":%u,\"parent\":%u,\"x\":%d,"
		       "\"y\":%d,\"width\":%u,\"height\":%u,\"sibling\":%u,\"border\":%u,"
		       "\"shaped\":%s,\"translucent\":%s,\"input_only\":%s}",
		       change_name(n->stack.change), n->window, n->stack.parent, n->stack.x,
		       n->stack.y, n->stack.width, n->stack.height, n->stack.sibling, n->stack.border,
		       n->stack.flags & VIS_WINDOW_SHAPED ? "true" : "false",
		       n->stack.flags & VIS_WINDOW_TRANSLUCENT ? "true" : "false",
		       n->stack.flags & VIS_WINDOW_INPUT_ONLY ? "true" : "false");
		break;
	case VIS_NOTICE_KIND_OVERFLOW:
		printf("\"notice\":\"overflow\",\"dropped\":%u,\"resync\":%u}", n->overflow.dropped,
		       n->overflow.resync);
		break;
	}
	putchar('\n');
}

/* Learns a stack notice's X window, if it mirrors one. */
static void learn_notice(struct watch *w, const struct vis_notice *n)
{
	if (n->kind == VIS_NOTICE_KIND_STACK && n->stack.ext_namespace == VIS_EXTERNAL_X11)
		learn(w, n->window, n->stack.external);
}

/* Prints a notice, up to the count; later ones (read in the same dispatch) are dropped. */
static void print_notice(struct watch *w, const struct vis_notice *n)
{
	if (w->count && w->seen >= w->count)
		return;
	w->seen++;
	if (w->json)
		print_json(w, n);
	else
		print_text(w, n);
	fflush(stdout);
}

/* Keeps a copy of a notice until the tree has come. */
static void hold(struct watch *w, const struct vis_notice *n)
{
	if (w->n_held == w->cap_held) {
		size_t cap = w->cap_held ? 2 * w->cap_held : 64;
		struct held_notice *more = realloc(w->held, cap * sizeof(*more));
		if (!more) {
			w->failed = true;
			return;
		}
		w->held = more;
		w->cap_held = cap;
	}
	struct held_notice *h = &w->held[w->n_held];
	h->n = *n;
	h->rects = NULL;
	if (n->kind == VIS_NOTICE_KIND_EXPOSURE && n->exposure.n_rects) {
		h->rects = malloc(n->exposure.n_rects * sizeof(*h->rects));
		if (!h->rects) {
			w->failed = true;
			return;
		}
		memcpy(h->rects, n->exposure.rects, n->exposure.n_rects * sizeof(*h->rects));
		h->n.exposure.rects = h->rects;
	}
	w->n_held++;
}

static void on_notice(void *data, const struct vis_notice *n)
{
	struct watch *w = data;
	if (w->failed)
		return;
	if (w->holding) {
		hold(w, n);
		return;
	}
	if (w->x11)
		learn_notice(w, n);
	print_notice(w, n);
}

/*
 * Watching by XID: reads the tree (every window that existed when the subscriptions began and
 * exists still), learns the held stack notices (the others), then prints what was held.
 */
static int release_held(struct live *l, struct watch *w)
{
	struct vis_window_info *t;
	size_t n;
	int ret = VISCTL_EXIT_OK;
	if (vis_client_get_tree(l->client, &t, &n) < 0) {
		ret = live_failed(l, "watch: get-tree");
	} else {
		for (size_t i = 0; i < n; i++)
			if (t[i].ext_namespace == VIS_EXTERNAL_X11)
				learn(w, t[i].window, t[i].external);
		free(t);
	}
	w->holding = false;
	for (size_t i = 0; i < w->n_held; i++)
		learn_notice(w, &w->held[i].n);
	for (size_t i = 0; i < w->n_held; i++) {
		if (ret == VISCTL_EXIT_OK && !w->failed)
			print_notice(w, &w->held[i].n);
		free(w->held[i].rects);
	}
	w->n_held = 0;
	if (ret == VISCTL_EXIT_OK && w->failed)
		ret = live_error(l, "watch: %s", strerror(ENOMEM));
	return ret;
}

/*
 * Looks up the windows of the XIDs given (each a valid XID: checked while parsing), remembering
 * their XIDs, and replaces each argument by the window's ID. Returns 0, or the status to exit with.
 */
static int lookup_xids(struct live *l, struct watch *w, char **ids, int n, char (*found)[16])
{
	for (int i = 0; i < n; i++) {
		uint64_t xid;
		uint32_t window;
		live_parse_u64(ids[i], &xid);
		if (vis_client_lookup(l->client, VIS_EXTERNAL_X11, xid, &window) < 0) {
			char what[64];
			snprintf(what, sizeof(what), "watch: lookup --x11 %s", ids[i]);
			return live_failed(l, what);
		}
		learn(w, window, xid);
		snprintf(found[i], sizeof(found[i]), "%u", window);
		ids[i] = found[i];
	}
	return w->failed ? live_error(l, "watch: %s", strerror(ENOMEM)) : VISCTL_EXIT_OK;
}

/* Subscribes to each window of ids (or to every window when n is 0), then a round trip. */
static int subscribe(struct live *l, char **ids, int n)
{
	uint32_t first = 0;
	for (int i = 0; i < (n ? n : 1); i++) {
		uint32_t id = VIS_WINDOW_ALL;
		if (n)
			live_parse_u32(ids[i], &id);
		uint32_t seq = vis_client_subscribe(l->client, id, VIS_NOTICE_ALL, 0);
		if (!seq)
			return live_failed(l, "watch: subscribe");
		if (!first)
			first = seq;
	}
	struct vis_error e;
	if (vis_client_roundtrip(l->client) < 0)
		return live_failed(l, "watch");
	if (vis_client_last_error(l->client, &e) && e.seq >= first) {
		/* Name the window whose subscription failed: requests were numbered in order. */
		char what[64];
		snprintf(what, sizeof(what), "watch: subscribe %s",
			 n ? ids[e.seq - first] : "all");
		return live_failed(l, what);
	}
	return VISCTL_EXIT_OK;
}

/* Reads notices until the count is reached, a signal comes or the connection fails. */
static int watch_loop(struct live *l, struct watch *w, const sigset_t *wait_mask)
{
	struct pollfd pfd = { .fd = vis_client_fd(l->client), .events = POLLIN };
	while (!stop_signal && !w->failed && !(w->count && w->seen >= w->count)) {
		if (ppoll(&pfd, 1, NULL, wait_mask) < 0) {
			if (errno == EINTR)
				continue;
			return live_error(l, "watch: %s", strerror(errno));
		}
		if (vis_client_dispatch(l->client) < 0)
			return live_failed(l, "watch");
	}
	return VISCTL_EXIT_OK;
}

int cmd_watch(struct live *l, int argc, char **argv)
{
	struct watch w = { 0 };
	char **ids = calloc((size_t)argc, sizeof(*ids));
	char(*found)[16] = calloc((size_t)argc, sizeof(*found));
	int n = 0, ret;
	if (!ids || !found) {
		free(ids);
		free(found);
		return live_error(l, "watch: %s", strerror(ENOMEM));
	}
	/* The IDs are XIDs with --x11, wherever it stands. */
	for (int i = 1; i < argc; i++)
		w.x11 |= strcmp(argv[i], "--x11") == 0;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		uint32_t id;
		uint64_t xid;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			free(ids);
			free(found);
			printf("usage: visctl watch [--json] [--count N] [ID...] | --x11 [XID...]\n"
			       "  Prints the notices about the windows (every window the connection\n"
			       "  may see when none is given) until N have come, or until interrupted.\n"
			       "  A client (no --role) sees only the windows its connection created:\n"
			       "  with none and no ID, watch refuses with exit status 2; use\n"
			       "  --role observer (or manager) to watch every window.\n"
			       "  --x11: the arguments are X window IDs (hex 0x... or decimal), each\n"
			       "  looked up; the lines name every window that mirrors an X window by\n"
			       "  its XID, 0x and lowercase hex, where they would say its ID\n"
			       "  ('5 visibility 0x1e00003 unobscured initial'; the window, parent and\n"
			       "  sibling of stack lines), and --json objects get \"x11\":\"0x...\" first.\n"
			       "  Without --role, --x11 takes the observer role.\n");
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		}
		const char *count = NULL;
		if (strcmp(a, "--x11") == 0) {
			/* Seen above. */
		} else if (strcmp(a, "--json") == 0) {
			w.json = true;
		} else if (strncmp(a, "--count=", 8) == 0) {
			count = a + 8;
		} else if (strcmp(a, "--count") == 0) {
			if (i + 1 == argc) {
				free(ids);
				free(found);
				return live_usage(l, argv[0], "--count needs a number");
			}
			count = argv[++i];
		} else if (a[0] == '-') {
			free(ids);
			free(found);
			return live_usage(l, argv[0], "unknown option '%s'", a);
		} else if (w.x11 && live_xid_arg(l, argv[0], a, &xid, &ret) < 0) {
			free(ids);
			free(found);
			return ret;
		} else if (!w.x11 && (live_parse_u32(a, &id) < 0 || id == VIS_WINDOW_ALL)) {
			free(ids);
			free(found);
			return live_usage(l, argv[0], "ID '%s' is not a number from 1 to 4294967295",
					  a);
		} else {
			ids[n++] = argv[i];
		}
		uint32_t c;
		if (count && (live_parse_u32(count, &c) < 0 || c == 0)) {
			free(ids);
			free(found);
			return live_usage(l, argv[0], "N '%s' is not a number from 1 to 4294967295",
					  count);
		}
		if (count)
			w.count = c;
	}

	/* Blocked from here on, so that a signal before ppoll still ends the loop. */
	sigset_t block, saved;
	struct sigaction sa = { .sa_handler = on_signal }, old_int, old_term;
	sigemptyset(&block);
	sigaddset(&block, SIGINT);
	sigaddset(&block, SIGTERM);
	sigprocmask(SIG_BLOCK, &block, &saved);
	sigemptyset(&sa.sa_mask);
	sigaction(SIGINT, &sa, &old_int);
	sigaction(SIGTERM, &sa, &old_term);
	stop_signal = 0;

	ret = VISCTL_EXIT_FAILURE;
	vis_idmap_init(&w.xid_of);
	if (w.x11)
		live_x11_role(l);
	if (live_connect(l) && !n && live_sees_nothing(l)) {
		/* Every window it may see is none, for good: it would wait forever, silently. */
		ret = live_usage(l, argv[0],
				 "this connection owns no windows, and a client sees only its own: "
				 "nothing to watch (use --role observer to watch every window)");
	} else if (l->client) {
		vis_client_set_notice_handler(l->client, on_notice, &w);
		ret = w.x11 && n ? lookup_xids(l, &w, ids, n, found) : VISCTL_EXIT_OK;
		w.holding = w.x11;
		if (ret == VISCTL_EXIT_OK)
			ret = subscribe(l, ids, n);
		if (ret == VISCTL_EXIT_OK && w.holding)
			ret = release_held(l, &w);
		if (ret == VISCTL_EXIT_OK)
			ret = watch_loop(l, &w, &saved);
		if (ret == VISCTL_EXIT_OK && w.failed)
			ret = live_error(l, "watch: %s", strerror(ENOMEM));
		vis_client_set_notice_handler(l->client, NULL, NULL);
	}
	for (size_t i = 0; i < w.n_held; i++)
		free(w.held[i].rects);
	free(w.held);
	free(w.xids);
	vis_idmap_finish(&w.xid_of);
	free(found);
	sigaction(SIGINT, &old_int, NULL);
	sigaction(SIGTERM, &old_term, NULL);
	sigprocmask(SIG_SETMASK, &saved, NULL);
	free(ids);
	return ret;
}
