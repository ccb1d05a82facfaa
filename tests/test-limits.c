/*
 * visd's limits, slow readers and fairness, against a real daemon: every configurable limit
 * refuses with a `limit` error and the connection carries on; a descriptor shortage and a
 * connection flood are refused cleanly and the daemon recovers; a subscriber that stops reading
 * gets coalesced notices, or an overflow notice and a resync, with gapless serials and the right
 * final states; a client flooding requests does not starve an interactive one.
 *
 * usage: test-limits VISD
 */
#undef NDEBUG
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "limits.h"
#include "vis/protocol.h"

const char *limits_visd;

bool limits_try_hello(struct harness_conn *c, const char *sock, const char *reason)
{
	uint8_t hello[VIS_MSG_HEADER + 12];
	size_t len = harness_build(hello, VIS_OP_HELLO,
				   (const uint32_t[]){ VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, 0 }, 3);
	harness_open(c, sock);
	harness_send(c, hello, len);
	c->seq = 1;
	struct vis_msg r;
	harness_next_reply(c, &r, NULL);
	if (r.type->opcode == VIS_OP_HELLO_REPLY)
		return true;
	CHECK(r.type->opcode == VIS_OP_ERROR && r.args[0].u == 1 && r.args[1].u == VIS_OP_HELLO &&
		      r.args[2].u == VIS_ERROR_LIMIT,
	      "wanted hello-reply or a limit error, got %s", r.type->name);
	CHECK(!reason || memmem(r.args[3].s.p, r.args[3].s.len, reason, strlen(reason)),
	      "refused with '%.*s', not for %s", (int)r.args[3].s.len, r.args[3].s.p, reason);
	CHECK(harness_recv(c, HARNESS_WORKING, &r) == 0, "a refused connection stayed open");
	harness_close(c);
	return false;
}

const char *limits_read_log(const struct harness_daemon *d)
{
	static char text[1 << 16];
	FILE *f = fopen(d->log, "r");
	CHECK(f, "cannot read %s", d->log);
	text[fread(text, 1, sizeof text - 1, f)] = 0;
	fclose(f);
	return text;
}

void limits_expect_limit(struct harness_conn *c, uint32_t seq, uint32_t op, const char *option)
{
	harness_expect_error(c, seq, op, VIS_ERROR_LIMIT, option, false);
	harness_sync(c, NULL);
}

static void test_configured_limits(void)
{
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd,
		      (const char *[]){ "--max-clients", "4", "--max-windows", "4", "--max-depth",
					"2", "--max-subscriptions", "2", "--max-look-rects", "10",
					NULL });
	struct harness_conn m, c;
	harness_open(&m, d.sock);
	harness_hello(&m, VIS_ROLE_MANAGER);
	harness_open(&c, d.sock);
	harness_hello(&c, VIS_ROLE_CLIENT);

	harness_context("windows per connection");
	uint32_t w[4];
	for (int i = 0; i < 4; i++)
		w[i] = harness_create(&c, 0, 10 * i, 0, 5, 5, VIS_CREATE_MAP);
	uint32_t seq = harness_req(&c, VIS_OP_CREATE, 0, 0, 0, 5, 5, 0, 0, 0, 0, 0);
	limits_expect_limit(&c, seq, VIS_OP_CREATE, "--max-windows");
	harness_req(&c, VIS_OP_DESTROY, w[3]);
	w[3] = harness_create(&c, 0, 0, 0, 5, 5, 0); /* room again */

	harness_context("look rectangles per connection");
	{
		/* set-shape w, shaped 1, k rectangles of 1x1; set-opaque w, mode 2, k of them. */
		uint32_t words[3 + 4 * 8];
		for (uint32_t k = 0; k < 8; k++) {
			words[3 + 4 * k] = k;
			words[4 + 4 * k] = 0;
			words[5 + 4 * k] = words[6 + 4 * k] = 1;
		}
		uint8_t b[VIS_MSG_HEADER + sizeof words];
#define LOOK(op, win, mode, k)                                                                   \
	(words[0] = (win), words[1] = (mode), words[2] = (k),                                   \
	 harness_request_raw(&c, b, harness_build(b, (op), words, 3 + 4 * (size_t)(k))))
		LOOK(VIS_OP_SET_SHAPE, w[0], 1, 6);
		seq = LOOK(VIS_OP_SET_SHAPE, w[1], 1, 6);
		limits_expect_limit(&c, seq, VIS_OP_SET_SHAPE, "--max-look-rects");
		LOOK(VIS_OP_SET_OPAQUE, w[1], 2, 4); /* 6 + 4: the limit exactly */
		seq = LOOK(VIS_OP_SET_OPAQUE, w[2], 2, 1);
		limits_expect_limit(&c, seq, VIS_OP_SET_OPAQUE, "--max-look-rects");
		LOOK(VIS_OP_SET_SHAPE, w[0], 1, 2); /* replacing 6 by 2 frees 4 */
		LOOK(VIS_OP_SET_SHAPE, w[2], 1, 4);
		seq = LOOK(VIS_OP_SET_SHAPE, w[3], 1, 1);
		limits_expect_limit(&c, seq, VIS_OP_SET_SHAPE, "--max-look-rects");
		/* The manager, changing the client's window, is held to the client's count. */
		words[0] = w[3], words[1] = 1, words[2] = 1;
		seq = harness_request_raw(&m, b, harness_build(b, VIS_OP_SET_SHAPE, words, 7));
		limits_expect_limit(&m, seq, VIS_OP_SET_SHAPE, "--max-look-rects");
		harness_req(&c, VIS_OP_DESTROY, w[2]); /* frees its 4 */
		LOOK(VIS_OP_SET_SHAPE, w[3], 1, 4);
		harness_sync(&c, NULL);
		w[2] = harness_create(&c, 0, 20, 0, 5, 5, 0);
#undef LOOK
	}

	harness_context("tree depth");
	uint32_t a = harness_create(&m, 0, 0, 0, 50, 50, VIS_CREATE_MAP);
	uint32_t b = harness_create(&m, a, 1, 1, 10, 10, VIS_CREATE_MAP);
	uint32_t x = harness_create(&m, 0, 60, 0, 50, 50, VIS_CREATE_MAP);
	seq = harness_req(&m, VIS_OP_CREATE, b, 0, 0, 2, 2, 0, 0, 0, 0, 0);
	limits_expect_limit(&m, seq, VIS_OP_CREATE, "--max-depth");
	seq = harness_req(&m, VIS_OP_REPARENT, a, x, 0, 0);
	limits_expect_limit(&m, seq, VIS_OP_REPARENT, "--max-depth");
	harness_req(&m, VIS_OP_REPARENT, b, x, 0, 0); /* b alone fits under x */
	harness_sync(&m, NULL);
	size_t n;
	struct harness_node *tree = harness_get_tree(&m, &n);
	bool moved = false;
	for (size_t i = 0; i < n; i++)
		moved |= tree[i].window == b && tree[i].parent == x;
	CHECK(moved, "window %u was not reparented under %u", b, x);
	free(tree);

	harness_context("subscriptions");
	harness_req(&c, VIS_OP_SUBSCRIBE, w[0], VIS_NOTICE_VISIBILITY, 0);
	harness_req(&c, VIS_OP_SUBSCRIBE, w[1], VIS_NOTICE_VISIBILITY, 0);
	harness_req(&c, VIS_OP_SUBSCRIBE, w[1], VIS_NOTICE_ALL, 0); /* replaces: no new one */
	seq = harness_req(&c, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_VISIBILITY, 0);
	limits_expect_limit(&c, seq, VIS_OP_SUBSCRIBE, "--max-subscriptions");

	harness_context("clients");
	struct harness_conn more[2], extra;
	for (int i = 0; i < 2; i++) {
		harness_open(&more[i], d.sock);
		harness_hello(&more[i], VIS_ROLE_CLIENT);
	}
	CHECK(!limits_try_hello(&extra, d.sock, "--max-clients"), "a fifth client was accepted");
	CHECK(strstr(limits_read_log(&d), "--max-clients"), "the refusal is not logged");
	harness_close(&more[1]);
	/* The daemon frees the slot when it sees the hang-up: retry until it has. */
	for (struct progress p = harness_working(&d);
	     !limits_try_hello(&extra, d.sock, "--max-clients");)
		harness_still_working(&p, "a freed client slot was never reused");
	harness_sync(&extra, NULL);
	harness_sync(&c, NULL);
	harness_close(&extra);
	harness_close(&more[0]);
	harness_close(&c);
	harness_close(&m);
	harness_stop(&d);
}

/* --max-look-pieces counts what looks cut into, at the windows' sizes: few rectangles that cross
 * are many pieces, and a resize can make more. */
static void test_look_pieces(void)
{
	harness_context("look pieces per connection");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, (const char *[]){ "--max-look-pieces", "10", NULL });
	struct harness_conn c;
	harness_open_as(&c, d.sock, VIS_ROLE_CLIENT);
	uint32_t w0 = harness_create(&c, 0, 0, 0, 100, 100, VIS_CREATE_MAP);
	uint32_t w1 = harness_create(&c, 0, 50, 50, 100, 100, VIS_CREATE_MAP);
	static const uint32_t across[] = { 0, 0, 100, 1, 0, 2, 100, 1 };
	static const uint32_t down[] = { 0, 0, 1, 100, 2, 0, 1, 100 };
	static const uint32_t squares[] = { 0, 0, 1, 1, 2, 0, 1, 1, 4, 0, 1, 1, 6, 0, 1, 1,
					    8, 0, 1, 1, 10, 0, 1, 1, 12, 0, 1, 1, 14, 0, 1, 1 };
	harness_look(&c, VIS_OP_SET_SHAPE, w0, 1, across, 2);   /* 2 pieces */
	harness_look(&c, VIS_OP_SET_SHAPE, w1, 1, squares, 8);  /* 8: 10 in all, the limit */
	/* Two strips down cut the two across into 4 opaque crossings and 4 see-through pieces. */
	uint32_t seq = harness_look(&c, VIS_OP_SET_OPAQUE, w0, 2, down, 2);
	limits_expect_limit(&c, seq, VIS_OP_SET_OPAQUE, "--max-look-pieces");
	harness_req(&c, VIS_OP_DESTROY, w1); /* frees its 8 */
	harness_look(&c, VIS_OP_SET_OPAQUE, w0, 2, down, 2); /* 8 */
	harness_sync(&c, NULL);

	harness_context("look pieces per connection: a resize cuts again");
	uint32_t w2 = harness_create(&c, 0, 200, 0, 10, 1, VIS_CREATE_MAP);
	harness_look(&c, VIS_OP_SET_OPAQUE, w2, 2, squares, 1); /* 1 opaque, 1 see-through: 10 */
	seq = harness_req(&c, VIS_OP_RESIZE, w2, 10, 10);      /* 1 + 2: 11 */
	limits_expect_limit(&c, seq, VIS_OP_RESIZE, "--max-look-pieces");
	seq = harness_req(&c, VIS_OP_CONFIGURE, w2, 200, 0, 10, 1, 1); /* a border: 1 + 4 */
	limits_expect_limit(&c, seq, VIS_OP_CONFIGURE, "--max-look-pieces");
	size_t n;
	struct harness_node *tree = harness_get_tree(&c, &n);
	for (size_t i = 0; i < n; i++)
		if (tree[i].window == w2)
			CHECK(tree[i].width == 10 && tree[i].height == 1 && tree[i].border == 0,
			      "a refused resize changed window %u to %ux%u, border %u", w2,
			      tree[i].width, tree[i].height, tree[i].border);
	free(tree);
	harness_req(&c, VIS_OP_SET_OPAQUE, w0, 0, 0); /* w0's strips all opaque: 2 */
	harness_req(&c, VIS_OP_RESIZE, w2, 10, 10);
	harness_sync(&c, NULL);

	harness_context("look pieces per connection: a batch's looks cut again");
	{
		/* A shape of 4,000 squares, all past the border box: no pieces, but each resize
		 * cuts it again, 128,032 windows' worth of a batch's 4,194,304. */
		enum { N = 4000 };
		static uint32_t far[4 * N];
		for (uint32_t k = 0; k < N; k++) {
			uint32_t *r = far + 4 * k;
			r[0] = 1000 + 2 * k, r[1] = 0, r[2] = r[3] = 1;
		}
		harness_look(&c, VIS_OP_SET_SHAPE, w2, 1, far, N);
		harness_sync(&c, NULL);
		harness_req(&c, VIS_OP_BATCH_BEGIN);
		for (uint32_t k = 0; k < 40; k++)
			harness_req(&c, VIS_OP_RESIZE, w2, 11 + k, 10);
		uint32_t commit = harness_req(&c, VIS_OP_BATCH_COMMIT);
		uint32_t synced = harness_req(&c, VIS_OP_SYNC);
		uint32_t refused = 0, first = 0;
		for (struct vis_msg m;;) {
			harness_next_reply(&c, &m, NULL);
			if (m.type->opcode == VIS_OP_ERROR) {
				CHECK(m.args[2].u == VIS_ERROR_LIMIT && strstr(m.args[3].s.p, "another batch"),
				      "a resize got error %u: %.*s", m.args[2].u, (int)m.args[3].s.len,
				      m.args[3].s.p);
				first = first ? first : m.args[0].u;
				refused++;
				continue;
			}
			if (m.type->opcode == VIS_OP_SYNCED && m.args[0].u == synced)
				break;
			CHECK(false, "unexpected %s", m.type->name);
		}
		CHECK(refused == 8 && first == commit - 8, "%u resizes refused, from request %u "
		      "(commit %u): the batch's 4,194,304 windows' worth are 32 such cuts", refused, first,
		      commit);
	}
	harness_close(&c);
	harness_stop(&d);
}

/* A daemon with few descriptors: a flood is refused cleanly, and it serves again afterwards. */
static void test_descriptor_shortage(void)
{
	harness_context("descriptor shortage");
	struct harness_daemon d = { .nofile = 48 };
	harness_start(&d, limits_visd, NULL);
	enum { FLOOD = 100 };
	static struct harness_conn conn[FLOOD];
	static bool accepted[FLOOD];
	int served = 0;
	for (int i = 0; i < FLOOD; i++)
		served += accepted[i] = limits_try_hello(&conn[i], d.sock, NULL);
	CHECK(served == 16, "48 descriptors should serve 16 clients; served %d", served);
	CHECK(strstr(limits_read_log(&d), "keeping 8 of them for the daemon's uid, not 32"),
	      "the owner's reserve was not cut to half of the 16 slots");
	harness_check_alive(&d);
	for (int i = 0; i < FLOOD; i++)
		if (accepted[i])
			harness_close(&conn[i]);
	struct harness_conn c;
	for (struct progress p = harness_working(&d); !limits_try_hello(&c, d.sock, NULL);)
		harness_still_working(&p, "the daemon did not recover after the flood");
	harness_create(&c, 0, 0, 0, 10, 10, VIS_CREATE_MAP);
	harness_close(&c);
	harness_stop(&d);
}

/* What a subscriber makes of its notices: the last state of each window, and what it saw. */
struct view {
	uint32_t *ids;   /* the windows heard of, hashed by ID (0: a free slot) */
	uint32_t *state; /* by slot; 3 unknown or not viewable */
	bool *exists;    /* by slot, from stack notices */
	size_t cap;      /* a power of two */
	uint64_t serial;
	uint32_t coalesced, overflows, resync_left, dropped;
};

static void view_init(struct view *v, size_t cap)
{
	*v = (struct view){ .cap = cap };
	v->ids = calloc(cap, sizeof *v->ids);
	v->state = malloc(cap * sizeof *v->state);
	v->exists = calloc(cap, sizeof *v->exists);
	CHECK(v->ids && v->state && v->exists, "out of memory");
	for (size_t i = 0; i < cap; i++)
		v->state[i] = VIS_VISIBILITY_NONE;
}

/* The slot of window id (not 0) in the view, taken for it if new. IDs are not small numbers. */
static size_t slot(struct view *v, uint32_t id)
{
	size_t k = (size_t)((id * 0x9e3779b97f4a7c15ull) >> 32) & (v->cap - 1);
	for (size_t probes = 0; v->ids[k] && v->ids[k] != id; probes++) {
		CHECK(probes < v->cap, "more than %zu windows in the view", v->cap);
		k = (k + 1) & (v->cap - 1);
	}
	v->ids[k] = id;
	return k;
}

/* Applies one message if it is a notice; false for replies. */
static bool view_apply(struct view *v, const struct vis_msg *m)
{
	if (m->type->dir != VIS_DIR_NOTICE)
		return false;
	const union vis_arg *a = m->args;
	CHECK(a[0].q == v->serial + 1, "notice %s with serial %llu after %llu", m->type->name,
	      (unsigned long long)a[0].q, (unsigned long long)v->serial);
	v->serial = a[0].q;
	if (v->resync_left)
		v->resync_left--;
	switch (m->type->opcode) {
	case VIS_OP_VISIBILITY:
		v->state[slot(v, a[1].u)] = a[2].u;
		v->coalesced += a[4].u;
		break;
	case VIS_OP_EXPOSURE:
		v->coalesced += a[3].u;
		break;
	case VIS_OP_STACK:
		v->exists[slot(v, a[2].u)] = a[1].u != VIS_STACK_DESTROY;
		if (!(a[9].u & VIS_WINDOW_VIEWABLE))
			v->state[slot(v, a[2].u)] = VIS_VISIBILITY_NONE;
		break;
	case VIS_OP_OVERFLOW:
		CHECK(!v->resync_left, "an overflow notice inside a resync");
		v->overflows++;
		v->dropped += a[1].u;
		v->resync_left = a[2].u;
		/* Everything is restated: forget what we knew. */
		for (size_t i = 0; i < v->cap; i++) {
			v->state[i] = VIS_VISIBILITY_NONE;
			v->exists[i] = false;
		}
		break;
	}
	return true;
}

/* Reads everything up to the reply of a sync, then checks the view against the daemon. */
static void view_check(struct view *v, struct harness_conn *o, bool stack)
{
	uint32_t seq = harness_req(o, VIS_OP_SYNC);
	struct vis_msg m;
	for (;;) {
		CHECK(harness_recv(o, HARNESS_WORKING, &m) > 0,
		      "no synced from the slow reader's sync");
		if (!view_apply(v, &m)) {
			CHECK(m.type->opcode == VIS_OP_SYNCED && m.args[0].u == seq, "got %s",
			      m.type->name);
			break;
		}
	}
	CHECK(!v->resync_left, "%u resync notices missing", v->resync_left);
	size_t n;
	struct harness_state *s = harness_get_states(o, &n);
	size_t viewable = 0;
	for (size_t i = 0; i < v->cap; i++)
		viewable += v->state[i] != VIS_VISIBILITY_NONE;
	CHECK(viewable == n, "the subscriber knows %zu viewable windows, the daemon %zu", viewable,
	      n);
	for (size_t i = 0; i < n; i++)
		CHECK(v->state[slot(v, s[i].window)] == s[i].state,
		      "window %u: the subscriber says %u, the daemon %u", s[i].window,
		      v->state[slot(v, s[i].window)], s[i].state);
	free(s);
	if (stack) {
		struct harness_node *t = harness_get_tree(o, &n);
		size_t known = 0;
		for (size_t i = 0; i < v->cap; i++)
			known += v->exists[i];
		CHECK(known == n, "the subscriber knows %zu windows, the daemon %zu", known, n);
		for (size_t i = 0; i < n; i++)
			CHECK(v->exists[slot(v, t[i].window)],
			      "window %u unknown to the subscriber", t[i].window);
		free(t);
	}
}

/*
 * A subscriber stops reading while a manager sweeps a cover across a grid of windows: every
 * sweep changes most states. Then it reads everything and must agree with the daemon.
 */
static void run_slow_reader(uint32_t mask, int sweeps, const char *pending, struct view *v)
{
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd,
		      pending ? (const char *[]){ "--max-pending", pending, NULL } : NULL);
	struct harness_conn m, o;
	harness_open(&m, d.sock);
	harness_hello(&m, VIS_ROLE_MANAGER);
	harness_open(&o, d.sock);
	harness_hello(&o, VIS_ROLE_OBSERVER);
	harness_req(&o, VIS_OP_SUBSCRIBE, 0, mask, 0);
	harness_sync(&o, NULL);
	enum { SIDE = 12 };
	for (int i = 0; i < SIDE * SIDE; i++)
		harness_create(&m, 0, 20 * (i % SIDE), 20 * (i / SIDE), 20, 20, VIS_CREATE_MAP);
	uint32_t cover = harness_create(&m, 0, 0, 0, 70, 70, VIS_CREATE_MAP);
	view_init(v, 1024);
	for (int s = 0; s < sweeps; s++)
		for (int k = 0; k < 40; k++) {
			harness_req(&m, VIS_OP_MOVE, cover, (uint32_t)(6 * k - 20),
				    (uint32_t)(5 * k + s % 7));
			harness_sync(&m, NULL); /* one recompute a move */
		}
	harness_check_alive(&d);
	view_check(v, &o, mask & VIS_NOTICE_STACK);
	harness_close(&o);
	harness_close(&m);
	harness_stop(&d);
}

static void test_slow_readers(void)
{
	struct view v;
	harness_context("slow reader: coalescing");
	run_slow_reader(VIS_NOTICE_VISIBILITY | VIS_NOTICE_EXPOSURE, 60, "65536", &v);
	CHECK(v.coalesced > 0 && !v.overflows,
	      "a lagging subscriber of states: %u coalesced, %u overflows", v.coalesced,
	      v.overflows);
	printf("slow reader of states: %llu notices, standing for %u more\n",
	       (unsigned long long)v.serial, v.coalesced);
	free(v.ids);
	free(v.state);
	free(v.exists);

	harness_context("slow reader: overflow");
	run_slow_reader(VIS_NOTICE_ALL, 60, "65536", &v);
	CHECK(v.overflows > 0 && v.dropped > 0, "a stalled stack subscriber never overflowed");
	printf("slow reader of everything: %llu notices, %u overflows dropping %u\n",
	       (unsigned long long)v.serial, v.overflows, v.dropped);
	free(v.ids);
	free(v.state);
	free(v.exists);

	/* The default bound: half of 4 MiB must wait before notices coalesce, and they do. */
	harness_context("slow reader: coalescing under the default --max-pending");
	run_slow_reader(VIS_NOTICE_VISIBILITY | VIS_NOTICE_EXPOSURE, 400, NULL, &v);
	CHECK(v.coalesced > 0 && !v.overflows,
	      "a lagging subscriber of states, default bound: %u coalesced, %u overflows",
	      v.coalesced, v.overflows);
	printf("slow reader of states, default bound: %llu notices, standing for %u more\n",
	       (unsigned long long)v.serial, v.coalesced);
	free(v.ids);
	free(v.state);
	free(v.exists);
}

/*
 * A subscriber of stack notices that falls behind, but not past the bound, has them held, then
 * sent in order, each as complete as one sent at once (border, external ID). 50,000 moves make
 * 3.4 MB of notices: past the socket's buffer and half the default bound, not past the bound.
 */
static void test_held_stack(void)
{
	harness_context("slow reader: held stack notices");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, NULL);
	struct harness_conn m, o;
	harness_open(&m, d.sock);
	harness_hello(&m, VIS_ROLE_MANAGER);
	harness_open(&o, d.sock);
	harness_hello(&o, VIS_ROLE_OBSERVER);
	harness_req(&o, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_STACK, 0);
	harness_sync(&o, NULL);
	struct vis_msg msg;
	uint32_t seq = harness_req(&m, VIS_OP_CREATE, 0, 10, 10, 50, 50, VIS_CREATE_MAP, 3, 1,
				   0x1234, 0);
	harness_expect(&m, seq, VIS_OP_CREATED, &msg);
	uint32_t w = msg.args[1].u;
	enum { MOVES = 50000 };
	for (uint32_t k = 0; k < MOVES; k++) {
		harness_req(&m, VIS_OP_MOVE, w, k % 500, 10);
		if (k % 1000 == 999)
			harness_sync(&m, NULL);
	}
	seq = harness_req(&o, VIS_OP_SYNC);
	uint32_t n = 0;
	for (;;) {
		CHECK(harness_recv(&o, HARNESS_WORKING, &msg) > 0,
		      "no synced after %u stack notices", n);
		if (msg.type->opcode == VIS_OP_SYNCED && msg.args[0].u == seq)
			break;
		CHECK(msg.type->opcode == VIS_OP_STACK, "got %s", msg.type->name);
		const union vis_arg *a = msg.args;
		CHECK(a[10].u == 3 && a[11].u == 1 && a[12].q == 0x1234,
		      "stack notice %u, of window %u: border %u, external ID %u:%#llx", n, a[2].u,
		      a[10].u, a[11].u, (unsigned long long)a[12].q);
		n++;
	}
	CHECK(n == MOVES + 2, "%u stack notices for a create, a map and %u moves", n, MOVES);
	printf("slow reader of stack notices: %u, held and sent complete\n", n);
	harness_check_alive(&d);
	harness_close(&o);
	harness_close(&m);
	harness_stop(&d);
}

static double now_us(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return t.tv_sec * 1e6 + t.tv_nsec / 1e3;
}

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/*
 * The median time from an interactive client's move to the visibility notice it causes: its window
 * goes back and forth between 5, 5 and off the screen (fully obscured), changing state each time.
 */
static double interactive_median(struct harness_conn *c, uint32_t w, int rounds)
{
	double *t = malloc(rounds * sizeof *t);
	CHECK(t, "out of memory");
	for (int i = 0; i < rounds; i++) {
		double start = now_us();
		harness_req(c, VIS_OP_MOVE, w, (uint32_t)(i % 2 ? 5 : -5000), 5);
		struct vis_msg m;
		do
			CHECK(harness_recv(c, HARNESS_WORKING, &m) > 0, "no visibility notice");
		while (m.type->opcode != VIS_OP_VISIBILITY);
		t[i] = now_us() - start;
	}
	qsort(t, rounds, sizeof *t, by_value);
	double median = t[rounds / 2];
	free(t);
	return median;
}

/* A client pipelines changes to its 1,000 windows as fast as it can write, until killed. */
static pid_t start_flooder(const char *sock)
{
	fflush(NULL);
	pid_t pid = fork();
	CHECK(pid >= 0, "fork: %s", strerror(errno));
	if (pid)
		return pid;
	prctl(PR_SET_PDEATHSIG, SIGKILL); /* a failing test must not leave it behind */
	struct harness_conn f;
	harness_open(&f, sock);
	harness_hello(&f, VIS_ROLE_CLIENT);
	enum { N = 1000 };
	uint32_t first = harness_create(&f, 0, 0, 0, 100, 100, VIS_CREATE_MAP);
	for (int i = 1; i < N; i++)
		harness_create(&f, 0, i * 37 % 3000, i * 53 % 1800, 300, 200, VIS_CREATE_MAP);
	/* Moves, and a sync now and then as a script would: each sync forces a recompute. */
	uint8_t burst[16 * 20];
	for (unsigned k = 0;; k++) {
		size_t len = 0;
		for (int i = 0; i < 15; i++, k++)
			len += harness_build(burst + len, VIS_OP_MOVE,
					     (const uint32_t[]){ first + k % N, k * 7 % 3500,
								 k * 11 % 2000 },
					     3);
		len += harness_build(burst + len, VIS_OP_SYNC, NULL, 0);
		if (write(f.fd, burst, len) < 0)
			_exit(0);
		/* Its replies are read, or its output fills and the daemon stops reading it. */
		char drain[4096];
		while (recv(f.fd, drain, sizeof drain, MSG_DONTWAIT) > 0)
			;
	}
}

static void test_fairness(void)
{
	harness_context("fairness");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, NULL);
	pid_t flooder = start_flooder(d.sock);
	struct harness_conn c;
	harness_open(&c, d.sock);
	harness_hello(&c, VIS_ROLE_CLIENT);
	/* Wait for the flooder's windows, so that both measurements recompute the same stack. */
	struct harness_conn o;
	harness_open(&o, d.sock);
	harness_hello(&o, VIS_ROLE_OBSERVER);
	for (struct progress p = harness_working(&d);;) {
		size_t n;
		free(harness_get_tree(&o, &n));
		if (n >= 1000)
			break;
		harness_still_working(&p, "the flooder never created its windows");
	}
	harness_close(&o);
	kill(flooder, SIGSTOP);
	usleep(100000); /* what it had sent is done */
	/*
	 * The daemon recomputes only what a change can affect: a small window's move would cost far
	 * less than the flooder's turns, whose scattered moves recompute about everything. So the
	 * interactive window spans the screen below the flooder's windows, and its moves on and off
	 * the screen recompute everything too. Partially obscured on it: no window of the flooder's
	 * reaches x = 3800.
	 */
	uint32_t w = harness_create(&c, 0, 5, 5, 3830, 2150, VIS_CREATE_MAP);
	harness_req(&c, VIS_OP_LOWER, w);
	harness_req(&c, VIS_OP_SUBSCRIBE, w, VIS_NOTICE_VISIBILITY, 0);
	harness_sync(&c, NULL);
	double alone = interactive_median(&c, w, 200);
	kill(flooder, SIGCONT);
	usleep(100000);
	double flooded = interactive_median(&c, w, 200);
	kill(flooder, SIGKILL);
	waitpid(flooder, NULL, 0);
	printf("interactive move -> notice, median: %.0f us alone, %.0f us beside a flooder\n",
	       alone, flooded);
	/* 2x, plus 200 us for the scheduling of two processes on two cores. */
	CHECK(flooded <= 2 * alone + 200, "the flooder slowed an interactive client from %.0f to "
					  "%.0f us",
	      alone, flooded);
	harness_check_alive(&d);
	harness_close(&c);
	harness_stop(&d);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: test-limits VISD\n");
		return 2;
	}
	limits_visd = argv[1];
	signal(SIGPIPE, SIG_IGN);
	test_configured_limits();
	test_look_pieces();
	limits_quota_lockout();
	limits_quota_connections();
	limits_quota_hello_timeout();
	limits_quota_retained();
	limits_quota_look_pieces();
	test_descriptor_shortage();
	test_slow_readers();
	test_held_stack();
	test_fairness();
	printf("limits: every limit refuses cleanly; slow readers catch up right; the flooder "
	       "starves no one\n");
	return 0;
}
