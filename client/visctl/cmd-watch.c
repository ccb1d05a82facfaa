/*
 * `visctl watch`: subscribes to notices and prints one line per notice, flushed at once so that
 * a pipe reader sees each as it happens. SIGINT and SIGTERM end it cleanly: they are blocked
 * except inside ppoll, so one arriving between two checks is never lost.
 */
#include <errno.h>
#include <inttypes.h>
#include <poll.h>
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "visctl.h"

struct watch {
	bool json;
	uint64_t count; /* 0: no limit */
	uint64_t seen;
};

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
static void print_text(const struct vis_notice *n)
{
	printf("%" PRIu64 " ", n->serial);
	switch (n->kind) {
	case VIS_NOTICE_KIND_VISIBILITY:
		printf("visibility %u %s %s", n->window, vis_visibility_name(n->visibility.state),
		       vis_visibility_name(n->visibility.previous));
		if (n->visibility.coalesced)
			printf(" coalesced %u", n->visibility.coalesced);
		break;
	case VIS_NOTICE_KIND_EXPOSURE:
		printf("exposure %u", n->window);
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
		printf("stack %s %u %u %d,%d,%u,%u %u", change_name(n->stack.change), n->window,
		       n->stack.parent, n->stack.x, n->stack.y, n->stack.width, n->stack.height,
		       n->stack.sibling);
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
static void print_json(const struct vis_notice *n)
{
	printf("{\"serial\":%" PRIu64 ",", n->serial);
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

/* Prints each notice up to the count; later ones (read in the same dispatch) are dropped. */
static void on_notice(void *data, const struct vis_notice *n)
{
	struct watch *w = data;
	if (w->count && w->seen >= w->count)
		return;
	w->seen++;
	if (w->json)
		print_json(n);
	else
		print_text(n);
	fflush(stdout);
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
	while (!stop_signal && !(w->count && w->seen >= w->count)) {
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
	int n = 0, ret;
	if (!ids)
		return live_error(l, "watch: %s", strerror(ENOMEM));
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		uint32_t id;
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			free(ids);
			printf("usage: visctl watch [--json] [--count N] [ID...]\n"
			       "  Prints the notices about the windows (every window the connection\n"
			       "  may see when none is given) until N have come, or until interrupted.\n"
			       "  A client (no --role) sees only the windows its connection created:\n"
			       "  with none and no ID, watch refuses with exit status 2; use\n"
			       "  --role observer (or manager) to watch every window.\n");
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		}
		const char *count = NULL;
		if (strcmp(a, "--json") == 0) {
			w.json = true;
		} else if (strncmp(a, "--count=", 8) == 0) {
			count = a + 8;
		} else if (strcmp(a, "--count") == 0) {
			if (i + 1 == argc) {
				free(ids);
				return live_usage(l, argv[0], "--count needs a number");
			}
			count = argv[++i];
		} else if (a[0] == '-') {
			free(ids);
			return live_usage(l, argv[0], "unknown option '%s'", a);
		} else if (live_parse_u32(a, &id) < 0 || id == VIS_WINDOW_ALL) {
			free(ids);
			return live_usage(l, argv[0], "ID '%s' is not a number from 1 to 4294967295",
					  a);
		} else {
			ids[n++] = argv[i];
		}
		uint32_t c;
		if (count && (live_parse_u32(count, &c) < 0 || c == 0)) {
			free(ids);
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
	if (live_connect(l) && !n && live_sees_nothing(l)) {
		/* Every window it may see is none, for good: it would wait forever, silently. */
		ret = live_usage(l, argv[0],
				 "this connection owns no windows, and a client sees only its own: "
				 "nothing to watch (use --role observer to watch every window)");
	} else if (l->client) {
		vis_client_set_notice_handler(l->client, on_notice, &w);
		ret = subscribe(l, ids, n);
		if (ret == VISCTL_EXIT_OK)
			ret = watch_loop(l, &w, &saved);
		vis_client_set_notice_handler(l->client, NULL, NULL);
	}
	sigaction(SIGINT, &old_int, NULL);
	sigaction(SIGTERM, &old_term, NULL);
	sigprocmask(SIG_SETMASK, &saved, NULL);
	free(ids);
	return ret;
}
