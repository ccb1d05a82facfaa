/*
 * The fault test: clients killed at random points in the middle of requests while a few others
 * keep working. Hostile clients run random sessions (windows, children, retained windows,
 * subscriptions, batches, queries, the odd malformed message) and never read their replies; a
 * quarter are forked processes sent SIGKILL after a random delay, the others connections this
 * process cuts at a random byte of their session, some after lingering unread. Meanwhile three
 * surviving clients create, move, resize, restack, map and unmap their windows, each keeping a
 * model of them, and an observer of every window reads only at quiet points: with the smallest
 * bound on pending output, it lags and overflows. Another such observer is cut at each quiet
 * point, lagging or overflowed, and renewed.
 *
 * At quiet points (every 500 hostile clients and at the end) every hostile client is gone and
 * the daemon must be back to its descriptors of the start; a manager reads the tree, which must
 * hold the survivors' windows exactly as their models say plus only retained, childless top-level
 * windows of the dead; every window's state must be the brute-force engine's on that stack, and
 * so must get-states, the survivors' last visibility notices and the stalled observer's once it
 * has caught up (its serials without gaps through overflows and resyncs). The retained leftovers
 * are then destroyed. At the end the daemon must exit with status 0 and no sanitizer report
 * (under ASan: no leak, no use-after-free).
 *
 * Usage: test-fault VISD [--clients N] [--seed S]  (CI: 1,000 clients; long form: 10,000)
 */
#include <errno.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "engine.h"
#include "harness.h"
#include "idmap.h"
#include "rng.h"
#include "vis/protocol.h"
#include "wire.h"

#define SCREEN_W         400
#define SCREEN_H         300
#define SURVIVORS        3
#define SURVIVOR_WINDOWS 8
#define AT_ONCE          24   /* hostile clients alive at a time */
#define QUIET_EVERY      500  /* hostile clients between two full checks */
#define SESSION_MAX      2048 /* bytes of an in-process hostile session */

static struct harness_daemon d;
static struct harness_conn mgr;
/* The latest window IDs seen (of survivors and at quiet points): hostile clients aim at them,
 * and next to them (IDs come in no order, so no other number is likely to be a window's). */
#define SEEN_IDS 64
static uint32_t seen_ids[SEEN_IDS];
static uint32_t n_seen;

static void note_seen(uint32_t id)
{
	seen_ids[n_seen++ % SEEN_IDS] = id;
}
static struct {
	int forked, cut, orphans, checks;
} stats;

/* A survivor's window in its model; the array is in stacking order among its own windows. */
struct model_window {
	uint32_t id;
	struct vis_rect r;
	bool mapped;
};

/* What a connection's notices told it: each window's last state, and the serials. */
struct told {
	/* By window ID (IDs are not small numbers): the state of the last visibility notice + 1;
	 * none before any. The zero map is an empty one. */
	struct vis_idmap state;
	uint64_t serial; /* the last notice's */
	int overflows;
};

struct survivor {
	struct harness_conn c;
	struct model_window w[SURVIVOR_WINDOWS];
	size_t n;
	int ops;
	struct told told;
};

static struct survivor surv[SURVIVORS];

/* An observer of every window that reads only at quiet points: it lags and overflows. */
static struct {
	struct harness_conn c;
	struct told told;
} stalled;

/* Another that never reads, cut at each quiet point while it lags or overflows, then renewed. */
static struct harness_conn doomed;

static void doomed_start(void)
{
	harness_open_as(&doomed, d.sock, VIS_ROLE_OBSERVER);
	harness_req(&doomed, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
}

/* A hostile client: an in-process connection with its session, or a forked process. */
struct hostile {
	bool used;
	struct vis_rng rng; /* its own: a client's choices do not depend on the others' timing */
	pid_t pid;          /* > 0: forked */
	long long deadline_us;
	int fd;
	uint8_t *session;
	size_t len, sent, cut;
	int linger; /* steps to stay, unread, once the session is cut */
};

static struct hostile hostiles[AT_ONCE];

static long long now_us(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (long long)t.tv_sec * 1000000 + t.tv_nsec / 1000;
}

/* What a hostile client knows: its role, whether it retains windows, the IDs it has seen. */
struct hostile_mind {
	struct vis_rng rng;
	bool retaining; /* uses RETAIN, on top-level windows only, and never parents anything */
	uint32_t ids[16];
	size_t n_ids;
};

/* A window ID to aim at: one of its own when it knows some, else a latest one or next to it. */
static uint32_t pick(struct hostile_mind *h)
{
	if (h->n_ids && vis_rng_below(&h->rng, 4))
		return h->ids[vis_rng_below(&h->rng, h->n_ids)];
	uint32_t n = n_seen < SEEN_IDS ? n_seen : SEEN_IDS;
	uint32_t id = n ? seen_ids[vis_rng_below(&h->rng, n)] : 1;
	return vis_rng_below(&h->rng, 4) ? id : id + (uint32_t)vis_rng_range(&h->rng, -2, 2);
}

/* Writes one random request (now and then a malformed one) to out; returns its size. */
static size_t random_request(struct hostile_mind *h, uint8_t *out)
{
	struct vis_rng *r = &h->rng;
	uint32_t x = (uint32_t)vis_rng_range(r, -50, SCREEN_W);
	uint32_t y = (uint32_t)vis_rng_range(r, -50, SCREEN_H);
	uint32_t w = 1 + (uint32_t)vis_rng_below(r, 200), ht = 1 + (uint32_t)vis_rng_below(r, 150);
	uint32_t k = (uint32_t)vis_rng_below(r, 100), coin = (uint32_t)vis_rng_below(r, 2);
	static const uint32_t simple[] = { VIS_OP_DESTROY,   VIS_OP_MAP,   VIS_OP_UNMAP,
					   VIS_OP_RAISE,     VIS_OP_LOWER, VIS_OP_GET_STATE,
					   VIS_OP_GET_REGION };
	static const uint32_t bare[] = { VIS_OP_BATCH_BEGIN, VIS_OP_BATCH_COMMIT, VIS_OP_GET_STATES,
					 VIS_OP_GET_TREE, VIS_OP_SYNC };
	if (k < 25) {
		uint32_t flags = (vis_rng_below(r, 5) ? VIS_CREATE_MAP : 0) |
				 (h->retaining && coin ? VIS_CREATE_RETAIN : 0);
		return harness_put(out, VIS_OP_CREATE, h->retaining || coin ? 0 : pick(h), x, y, w,
				   ht, flags, 0, 0, 0, 0);
	}
	if (k < 60)
		return harness_put(out, simple[vis_rng_below(r, 7)], pick(h));
	if (k < 66)
		return harness_put(out, VIS_OP_MOVE, pick(h), x, y);
	if (k < 72)
		return harness_put(out, VIS_OP_RESIZE, pick(h), w, ht);
	if (k < 75)
		return harness_put(out, VIS_OP_RESTACK, pick(h), coin, pick(h));
	if (k < 78)
		return harness_put(out, VIS_OP_REPARENT, pick(h), h->retaining ? 0 : pick(h), x, y);
	if (k < 83)
		return harness_put(out, VIS_OP_SUBSCRIBE, coin ? 0 : pick(h),
				   1 + (uint32_t)vis_rng_below(r, 7),
				   (uint32_t)vis_rng_below(r, 4));
	if (k < 85)
		return harness_put(out, VIS_OP_UNSUBSCRIBE, 0);
	if (k < 95)
		return harness_put(out, bare[vis_rng_below(r, 5)]);
	if (k < 99)
		return harness_put(out, VIS_OP_GET_REPAINT, x, y, w, ht);
	/* Malformed: a size under the header, or an unknown opcode. */
	size_t n = harness_put(out, coin ? 99 : VIS_OP_MAP);
	vis_wire_put_u32(out, vis_rng_below(r, 2) ? 4 : VIS_MSG_HEADER);
	return n;
}

/* The start of a session: hello as a client mostly, sometimes an observer or a would-be manager. */
static size_t random_hello(struct hostile_mind *h, uint8_t *out)
{
	uint32_t k = (uint32_t)vis_rng_below(&h->rng, 20);
	uint32_t role = k < 17 ? VIS_ROLE_CLIENT : k < 19 ? VIS_ROLE_OBSERVER : VIS_ROLE_MANAGER;
	h->retaining = role == VIS_ROLE_CLIENT && vis_rng_below(&h->rng, 3) == 0;
	return harness_put(out, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, role);
}

/* Reads what has come without waiting, and learns the IDs of its new windows. */
static void learn_ids(int fd, struct hostile_mind *h, struct vis_buf *in)
{
	uint8_t buf[4096];
	ssize_t got;
	while ((got = recv(fd, buf, sizeof buf, MSG_DONTWAIT)) > 0)
		if (vis_buf_append(in, buf, (size_t)got) < 0)
			_exit(0);
	if (got == 0)
		_exit(0);
	for (;;) {
		struct vis_msg m;
		char why[200];
		if (vis_msg_decode(in->data, in->len, VIS_PROTOCOL_MAX_MESSAGE, 0, &m, why,
				   sizeof why) != VIS_DECODE_OK)
			return;
		if (m.type->opcode == VIS_OP_CREATED)
			h->ids[h->n_ids < 16 ? h->n_ids++ : vis_rng_below(&h->rng, 16)] =
				m.args[1].u;
		vis_buf_consume(in, m.size);
	}
}

/*
 * A forked hostile client: random requests, each written in two pieces with a pause between,
 * reading its new windows' IDs now and then, until it is killed (or the daemon hangs up).
 */
static void __attribute__((noreturn)) hostile_process(uint64_t seed)
{
	closefrom(3);
	struct hostile_mind h = { .rng = { seed } };
	struct vis_buf in;
	vis_buf_init(&in);
	int fd = harness_connect(d.sock);
	if (fd < 0)
		_exit(0);
	uint8_t b[64];
	for (size_t n = random_hello(&h, b);; n = random_request(&h, b)) {
		size_t split = (size_t)vis_rng_below(&h.rng, n + 1);
		if (send(fd, b, split, MSG_NOSIGNAL) != (ssize_t)split)
			_exit(0);
		usleep((useconds_t)vis_rng_below(&h.rng, 300));
		if (send(fd, b + split, n - split, MSG_NOSIGNAL) != (ssize_t)(n - split))
			_exit(0);
		learn_ids(fd, &h, &in);
	}
}

/* Starts hostile client number i in slot s. */
static void hostile_start(struct hostile *s, uint64_t seed, int i)
{
	memset(s, 0, sizeof *s);
	s->used = true;
	s->rng.state = seed * 1000003u + (uint64_t)i;
	struct vis_rng *rng = &s->rng;
	uint64_t own_seed = vis_rng_next(rng);
	if (vis_rng_below(rng, 4) == 0) {
		fflush(NULL);
		s->pid = fork();
		CHECK(s->pid >= 0, "fork: %s", strerror(errno));
		if (s->pid == 0)
			hostile_process(own_seed);
		s->deadline_us = now_us() + (long long)vis_rng_below(rng, 20000);
		stats.forked++;
		return;
	}
	struct hostile_mind h = { .rng = { own_seed } };
	s->session = malloc(SESSION_MAX);
	CHECK(s->session, "out of memory");
	s->len = random_hello(&h, s->session);
	for (int k = (int)vis_rng_below(rng, 40); k > 0 && s->len + 64 <= SESSION_MAX; k--)
		s->len += random_request(&h, s->session + s->len);
	s->cut = (size_t)vis_rng_below(rng, s->len + 1);
	s->linger = vis_rng_below(rng, 4) ? 0 : (int)vis_rng_below(rng, 400);
	s->fd = harness_connect(d.sock);
	CHECK(s->fd >= 0, "connect: %s", strerror(errno));
	stats.cut++;
}

/* Ends a hostile client now: SIGKILL, or the connection cut where its session stands. */
static void hostile_end(struct hostile *s)
{
	if (s->pid > 0) {
		kill(s->pid, SIGKILL);
		CHECK(waitpid(s->pid, NULL, 0) == s->pid, "waitpid: %s", strerror(errno));
	} else {
		close(s->fd);
		free(s->session);
	}
	s->used = false;
}

/* Moves a hostile client on: the next piece of its session, or its end when it is due. */
static void hostile_step(struct hostile *s)
{
	if (s->pid > 0) {
		if (now_us() >= s->deadline_us)
			hostile_end(s);
		return;
	}
	size_t n = 1 + (size_t)vis_rng_below(&s->rng, 48);
	if (n > s->cut - s->sent)
		n = s->cut - s->sent;
	ssize_t w = n ? send(s->fd, s->session + s->sent, n, MSG_NOSIGNAL | MSG_DONTWAIT) : 0;
	if (w > 0)
		s->sent += (size_t)w;
	else if (w < 0 && errno != EAGAIN)
		s->sent = s->cut; /* the daemon hung up after a malformed message */
	if (s->sent == s->cut && s->linger-- <= 0)
		hostile_end(s);
}

/* Records a notice: serials without gaps, overflows counted, the last state of each window. */
static void on_notice(void *data, const struct vis_msg *m)
{
	struct told *t = data;
	CHECK(m->args[0].q == t->serial + 1, "notice serial %llu after %llu",
	      (unsigned long long)m->args[0].q, (unsigned long long)t->serial);
	t->serial++;
	t->overflows += m->type->opcode == VIS_OP_OVERFLOW;
	uint32_t id = m->args[1].u;
	if (m->type->opcode != VIS_OP_VISIBILITY)
		return;
	CHECK(vis_idmap_put(&t->state, id, (void *)(uintptr_t)(m->args[2].u + 1)) == 0,
	      "out of memory");
}

/* The state the last notice told of window id. */
static uint32_t told_state(const struct told *t, uint32_t id)
{
	uintptr_t v = (uintptr_t)vis_idmap_get(&t->state, id);
	return v ? (uint32_t)(v - 1) : VIS_VISIBILITY_NONE;
}

/* Moves model window k of s to index to (after removing it). */
static void move_in_model(struct survivor *s, size_t k, size_t to)
{
	struct model_window w = s->w[k];
	memmove(&s->w[k], &s->w[k + 1], (s->n - k - 1) * sizeof w);
	memmove(&s->w[to + 1], &s->w[to], (s->n - 1 - to) * sizeof w);
	s->w[to] = w;
}

/* One random change by a survivor to its own windows, applied to its model too. */
static void survivor_step(struct survivor *s, struct vis_rng *r)
{
	int32_t x = (int32_t)vis_rng_range(r, -30, SCREEN_W),
		y = (int32_t)vis_rng_range(r, -30, SCREEN_H);
	uint32_t w = 1 + (uint32_t)vis_rng_below(r, 250), h = 1 + (uint32_t)vis_rng_below(r, 200);
	int op = (int)vis_rng_below(r, 10);
	s->ops++;
	if (s->n < 2 || (op == 0 && s->n < SURVIVOR_WINDOWS)) {
		bool map = vis_rng_below(r, 5) != 0;
		uint32_t id = harness_create(&s->c, 0, x, y, w, h, map ? VIS_CREATE_MAP : 0);
		s->w[s->n++] = (struct model_window){ id, { x, y, (int32_t)w, (int32_t)h }, map };
		note_seen(id);
		return;
	}
	size_t k = (size_t)vis_rng_below(r, s->n), j = (size_t)vis_rng_below(r, s->n);
	struct model_window *m = &s->w[k];
	switch (op) {
	case 1:
		harness_req(&s->c, VIS_OP_DESTROY, m->id);
		memmove(m, m + 1, (s->n - k - 1) * sizeof *m);
		s->n--;
		break;
	case 2:
	case 3:
		harness_req(&s->c, op == 2 ? VIS_OP_MAP : VIS_OP_UNMAP, m->id);
		m->mapped = op == 2;
		break;
	case 4:
		harness_req(&s->c, VIS_OP_MOVE, m->id, (uint32_t)x, (uint32_t)y);
		m->r.x = x;
		m->r.y = y;
		break;
	case 5:
		harness_req(&s->c, VIS_OP_RESIZE, m->id, w, h);
		m->r.w = (int32_t)w;
		m->r.h = (int32_t)h;
		break;
	case 6:
		harness_req(&s->c, VIS_OP_RAISE, m->id);
		move_in_model(s, k, s->n - 1);
		break;
	case 7:
		harness_req(&s->c, VIS_OP_LOWER, m->id);
		move_in_model(s, k, 0);
		break;
	default:
		if (j == k)
			break;
		bool above = op == 8;
		harness_req(&s->c, VIS_OP_RESTACK, m->id,
			    above ? VIS_RESTACK_ABOVE : VIS_RESTACK_BELOW, s->w[j].id);
		/* Just above or below j among its own windows: j's index once k is out, +1 above.
		 */
		move_in_model(s, k, (j > k ? j - 1 : j) + above);
	}
	if (s->ops % 16 == 0)
		harness_sync(&s->c, NULL);
}

/* Which survivor owns window id (and its model index), or NULL. */
static struct survivor *owner_of(uint32_t id, size_t *index)
{
	for (size_t i = 0; i < SURVIVORS; i++)
		for (size_t k = 0; k < surv[i].n; k++)
			if (surv[i].w[k].id == id) {
				*index = k;
				return &surv[i];
			}
	return NULL;
}

/* The state get-tree gave window id. */
static uint32_t tree_state(const struct harness_node *t, size_t n, uint32_t id)
{
	for (size_t i = 0; i < n; i++)
		if (t[i].window == id)
			return t[i].state;
	harness_fail(__FILE__, __LINE__, "window %u is not in the tree", id);
}

/*
 * The full check, with every hostile client gone: the tree against the survivors' models, every
 * state against the brute force on the stack, get-states and last notices against the states;
 * then the retained leftovers of the dead are destroyed.
 */
static void quiet_check(int base_fds, int done)
{
	harness_context("quiet point after %d hostile clients", done);
	harness_close(&doomed);
	harness_wait_fds(&d, base_fds - 1);
	harness_check_alive(&d);
	for (size_t i = 0; i < SURVIVORS; i++)
		harness_sync(&surv[i].c, NULL);
	size_t n;
	struct harness_node *t = harness_get_tree(&mgr, &n);
	struct vis_rect *rects = malloc((n + 1) * sizeof *rects);
	uint8_t *want = malloc(n + 1);
	size_t *of = malloc((n + 1) * sizeof *of), mapped = 0, seen[SURVIVORS] = { 0 };
	CHECK(rects && want && of, "out of memory");
	for (size_t i = 0; i < n; i++) {
		size_t k;
		struct survivor *s = owner_of(t[i].window, &k);
		bool is_mapped = t[i].flags & VIS_WINDOW_MAPPED;
		CHECK(t[i].parent == VIS_WINDOW_ROOT,
		      "window %u is a child: a dead client's child was "
		      "left behind",
		      t[i].window);
		if (s) {
			const struct model_window *m = &s->w[k];
			CHECK(k == seen[s - surv]++, "survivor %zu's window %u is out of its order",
			      (size_t)(s - surv), m->id);
			CHECK(t[i].x == m->r.x && t[i].y == m->r.y &&
				      t[i].width == (uint32_t)m->r.w &&
				      t[i].height == (uint32_t)m->r.h && is_mapped == m->mapped,
			      "survivor %zu's window %u is not as its model says",
			      (size_t)(s - surv), m->id);
		} else {
			CHECK(t[i].flags & VIS_WINDOW_RETAINED,
			      "window %u of a dead client is still there and not retained",
			      t[i].window);
			stats.orphans++;
		}
		if (is_mapped) {
			rects[mapped] = (struct vis_rect){ t[i].x, t[i].y, (int32_t)t[i].width,
							   (int32_t)t[i].height };
			of[mapped++] = i;
		} else {
			CHECK(t[i].state == VIS_VISIBILITY_NONE, "unmapped window %u has state %u",
			      t[i].window, t[i].state);
		}
	}
	for (size_t i = 0; i < SURVIVORS; i++)
		CHECK(seen[i] == surv[i].n, "survivor %zu has %zu of its %zu windows", i, seen[i],
		      surv[i].n);
	struct vis_stack stack = { rects, mapped, true, SCREEN_W, SCREEN_H, NULL, NULL };
	CHECK(vis_compute(VIS_ENGINE_BRUTE, &stack, want) == 0, "brute force: %s", strerror(errno));
	for (size_t i = 0; i < mapped; i++)
		CHECK(t[of[i]].state == want[i], "window %u is %u, the brute force says %u",
		      t[of[i]].window, t[of[i]].state, want[i]);
	/* get-states, the manager's and each survivor's, and the survivors' last notices. */
	size_t ns;
	struct harness_state *st = harness_get_states(&mgr, &ns);
	size_t viewable = 0;
	for (size_t i = 0; i < n; i++)
		viewable += t[i].state != VIS_VISIBILITY_NONE;
	CHECK(ns == viewable, "get-states has %zu windows, get-tree %zu viewable", ns, viewable);
	for (size_t k = 0; k < ns; k++)
		CHECK(tree_state(t, n, st[k].window) == st[k].state,
		      "get-states disagrees with get-tree on window %u", st[k].window);
	free(st);
	for (size_t i = 0; i < SURVIVORS; i++) {
		st = harness_get_states(&surv[i].c, &ns);
		for (size_t j = 0; j < ns; j++) {
			size_t at;
			uint32_t id = st[j].window, want = tree_state(t, n, id);
			CHECK(owner_of(id, &at) == &surv[i], "survivor %zu sees window %u", i, id);
			CHECK(st[j].state == want && told_state(&surv[i].told, id) == want,
			      "survivor %zu: window %u is %u, the tree says %u, the last notice %u",
			      i, id, st[j].state, want, told_state(&surv[i].told, id));
		}
		free(st);
	}
	/* The stalled observer, behind since the last quiet point, catches up. */
	harness_sync(&stalled.c, NULL);
	for (size_t i = 0; i < n; i++)
		CHECK(t[i].state == VIS_VISIBILITY_NONE ||
			      told_state(&stalled.told, t[i].window) == t[i].state,
		      "the stalled observer was last told window %u is %u; it is %u", t[i].window,
		      told_state(&stalled.told, t[i].window), t[i].state);
	for (size_t i = 0; i < n; i++) {
		size_t at;
		if (!owner_of(t[i].window, &at))
			harness_req(&mgr, VIS_OP_DESTROY, t[i].window);
		note_seen(t[i].window);
	}
	harness_sync(&mgr, NULL);
	doomed_start();
	free(t);
	free(rects);
	free(want);
	free(of);
	stats.checks++;
}

/* Prints the daemon's resident memory, from /proc. */
static long rss_kib(void)
{
	char path[64], line[256];
	snprintf(path, sizeof path, "/proc/%d/status", (int)d.pid);
	FILE *f = fopen(path, "r");
	long kib = -1;
	while (f && fgets(line, sizeof line, f))
		if (sscanf(line, "VmRSS: %ld", &kib) == 1)
			break;
	if (f)
		fclose(f);
	return kib;
}

int main(int argc, char **argv)
{
	int clients = 1000;
	uint64_t seed = 1;
	for (int i = 2; i + 1 < argc; i += 2) {
		if (!strcmp(argv[i], "--clients"))
			clients = atoi(argv[i + 1]);
		else if (!strcmp(argv[i], "--seed"))
			seed = strtoull(argv[i + 1], NULL, 10);
	}
	if (argc < 2 || argc % 2 || clients < 1 || !seed) {
		fprintf(stderr, "usage: test-fault VISD [--clients N] [--seed S (not 0)]\n");
		return 2;
	}
	signal(SIGPIPE, SIG_IGN);
	harness_seed(seed);
	long long start = now_us();
	/* The smallest bound on pending output, so that the stalled observer overflows. */
	harness_start(
		&d, argv[1],
		(const char *const[]){ "--screen", "400x300", "--max-pending", "65536", NULL });
	harness_context("set-up");
	struct vis_rng rng = { seed };
	harness_open_as(&mgr, d.sock, VIS_ROLE_MANAGER);
	harness_open_as(&stalled.c, d.sock, VIS_ROLE_OBSERVER);
	stalled.c.on_notice = on_notice;
	stalled.c.notice_data = &stalled.told;
	harness_req(&stalled.c, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	for (size_t i = 0; i < SURVIVORS; i++) {
		harness_open_as(&surv[i].c, d.sock, VIS_ROLE_CLIENT);
		surv[i].c.on_notice = on_notice;
		surv[i].c.notice_data = &surv[i].told;
		harness_req(&surv[i].c, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0);
		for (int k = 0; k < 4; k++)
			survivor_step(&surv[i], &rng);
	}
	doomed_start();
	int base_fds = harness_count_fds(&d);
	long rss_start = rss_kib();
	int started = 0, alive = 0, next_quiet = QUIET_EVERY < clients ? QUIET_EVERY : clients;
	while (started < clients || alive) {
		harness_context("hostile clients %d of %d", started, clients);
		for (size_t i = 0; i < AT_ONCE && started < next_quiet; i++)
			if (!hostiles[i].used)
				hostile_start(&hostiles[i], seed, started++);
		alive = 0;
		for (size_t i = 0; i < AT_ONCE; i++)
			if (hostiles[i].used) {
				hostile_step(&hostiles[i]);
				alive += hostiles[i].used;
			}
		survivor_step(&surv[vis_rng_below(&rng, SURVIVORS)], &rng);
		if (!alive && started == next_quiet) {
			quiet_check(base_fds, started);
			next_quiet = next_quiet + QUIET_EVERY < clients ? next_quiet + QUIET_EVERY
									: clients;
		}
	}
	long rss_end = rss_kib();
	harness_context("shutdown");
	for (size_t i = 0; i < SURVIVORS; i++) {
		harness_close(&surv[i].c);
		vis_idmap_finish(&surv[i].told.state);
	}
	harness_close(&stalled.c);
	vis_idmap_finish(&stalled.told.state);
	harness_close(&doomed);
	harness_wait_fds(&d, base_fds - SURVIVORS - 2);
	size_t n;
	free(harness_get_tree(&mgr, &n));
	CHECK(n == 0, "%zu windows are left after every client went", n);
	harness_close(&mgr);
	struct harness_conn last;
	harness_open(&last, d.sock);
	harness_hello(&last, VIS_ROLE_CLIENT);
	harness_close(&last);
	harness_stop(&d);
	int survivor_ops = 0;
	for (size_t i = 0; i < SURVIVORS; i++)
		survivor_ops += surv[i].ops;
	printf("fault: seed %llu: %d hostile clients (%d killed processes, %d cut connections; "
	       "visd "
	       "accepted %u connections) died mid-session while %d survivors "
	       "made %d changes and an observer that read only at quiet points overflowed %d "
	       "times; "
	       "%d full checks of the states against the brute force, %d retained leftovers; "
	       "visd's "
	       "RSS %ld KiB before, %ld after; %.1f s\n",
	       (unsigned long long)seed, stats.forked + stats.cut, stats.forked, stats.cut, last.id,
	       SURVIVORS, survivor_ops, stalled.told.overflows, stats.checks,
	       stats.orphans, rss_start, rss_end, (double)(now_us() - start) / 1e6);
	return 0;
}
