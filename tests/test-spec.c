/*
 * What the protocol's spec (proto/PROTOCOL.md) says, against a real visd through raw
 * connections, where the daemon once said otherwise: one viewable flag everywhere, the
 * translucent flag from the pixels, a batch charged its requests' bytes, window coordinates from
 * the inside's corner for regions and exposures, the two stack notices of create with MAP, and
 * window IDs that say nothing about other clients' windows.
 *
 * usage: test-spec VISD
 */
#undef NDEBUG
#include <signal.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "harness.h"
#include "vis/protocol.h"
#include "wire.h"

static const char *visd;

/* The notices a connection received, as the harness skipped them. */
struct notice {
	uint32_t opcode;
	union vis_arg args[VIS_MSG_MAX_ARGS];
	uint32_t rects[64][4]; /* an exposure's first 64 rectangles: x, y, width, height */
};

struct notices {
	struct notice v[64];
	size_t n;
};

static void record(void *data, const struct vis_msg *m)
{
	struct notices *log = data;
	CHECK(log->n < 64, "more than 64 notices");
	struct notice *r = &log->v[log->n++];
	r->opcode = m->type->opcode;
	memcpy(r->args, m->args, sizeof r->args);
	if (r->opcode == VIS_OP_EXPOSURE)
		for (uint32_t i = 0; i < m->args[4].a.n && i < 64; i++)
			for (uint32_t k = 0; k < 4; k++)
				r->rects[i][k] = vis_arg_word(&m->args[4], 'R', i, k);
}

/* Opens a connection for role whose notices go to log. */
static void open_logged(struct harness_conn *c, const struct harness_daemon *d, uint32_t role,
			struct notices *log)
{
	harness_open_as(c, d->sock, (int)role);
	log->n = 0;
	c->on_notice = record;
	c->notice_data = log;
}

/* The tree record of window id. */
static struct harness_node node_of(struct harness_conn *c, uint32_t id)
{
	size_t n;
	struct harness_node *v = harness_get_tree(c, &n), r = { 0 };
	for (size_t i = 0; i < n; i++)
		if (v[i].window == id)
			r = v[i];
	free(v);
	CHECK(r.window == id, "window %u is not in get-tree", id);
	return r;
}

/* The flags of the last stack notice about id in log. */
static uint32_t stack_flags(const struct notices *log, uint32_t id)
{
	for (size_t i = log->n; i-- > 0;)
		if (log->v[i].opcode == VIS_OP_STACK && log->v[i].args[2].u == id)
			return log->v[i].args[9].u;
	harness_fail(__FILE__, __LINE__, "no stack notice about window %u", id);
}

/*
 * A mapped input-only window is viewable (it and its ancestors are mapped) in get-tree as in its
 * stack notices; under an unmapped parent it is not, in either.
 */
static void test_viewable(const struct harness_daemon *d)
{
	harness_context("viewable input-only windows");
	struct harness_conn c;
	struct notices log;
	open_logged(&c, d, VIS_ROLE_CLIENT, &log);
	harness_req(&c, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_STACK, 0);
	uint32_t io = harness_create(&c, 0, 10, 10, 50, 50, VIS_CREATE_MAP | VIS_CREATE_INPUT_ONLY);
	uint32_t p = harness_create(&c, 0, 100, 100, 50, 50, 0);
	uint32_t child = harness_create(&c, p, 0, 0, 5, 5, VIS_CREATE_MAP | VIS_CREATE_INPUT_ONLY);
	harness_sync(&c, NULL);
	const uint32_t want = VIS_WINDOW_MAPPED | VIS_WINDOW_VIEWABLE | VIS_WINDOW_INPUT_ONLY;
	struct harness_node t = node_of(&c, io);
	CHECK(t.flags == want && stack_flags(&log, io) == want && t.state == VIS_VISIBILITY_NONE,
	      "mapped input-only window: get-tree flags %#x (state %u), map notice %#x; wanted %#x",
	      t.flags, t.state, stack_flags(&log, io), want);
	const uint32_t hidden = VIS_WINDOW_MAPPED | VIS_WINDOW_INPUT_ONLY;
	t = node_of(&c, child);
	CHECK(t.flags == hidden && stack_flags(&log, child) == hidden,
	      "input-only window under an unmapped parent: get-tree %#x, notice %#x; wanted %#x",
	      t.flags, stack_flags(&log, child), hidden);
	harness_req(&c, VIS_OP_MAP, p);
	harness_sync(&c, NULL);
	t = node_of(&c, child);
	CHECK(t.flags == want, "input-only window once its parent is mapped: get-tree %#x", t.flags);
	harness_close(&c);
}

/* Sends set-shape (shaped 1) or set-opaque (mode) with n rectangles of x, y, width, height. */
static void set_look(struct harness_conn *c, uint32_t op, uint32_t id, uint32_t mode,
		     const int32_t (*r)[4], uint32_t n)
{
	harness_look(c, op, id, mode, (const uint32_t *)r, n);
}

/* Whether get-tree and the last stack notice about id both have the translucent flag as want. */
static void expect_translucent(struct harness_conn *c, const struct notices *log, uint32_t id,
			       bool want, const char *what)
{
	harness_sync(c, NULL);
	uint32_t tree = node_of(c, id).flags, notice = stack_flags(log, id);
	CHECK(!!(tree & VIS_WINDOW_TRANSLUCENT) == want &&
		      !!(notice & VIS_WINDOW_TRANSLUCENT) == want,
	      "%s: get-tree flags %#x, stack notice %#x; translucent should be %s", what, tree,
	      notice, want ? "set" : "clear");
}

/*
 * The translucent flag says whether some pixel of the window (its shape clipped to its border
 * box) hides nothing, whatever the opaque mode says: opaque rectangles that cover every pixel
 * (abutting or overlapping) leave it clear, one pixel left free sets it; a resize or a border
 * that uncovers pixels sets it, as in get-tree as in stack notices; a window without pixels is
 * never translucent, nor an input-only one.
 */
static void test_translucent(const struct harness_daemon *d)
{
	harness_context("the translucent flag from the pixels");
	struct harness_conn c;
	struct notices log;
	open_logged(&c, d, VIS_ROLE_CLIENT, &log);
	harness_req(&c, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_STACK, 0);
	uint32_t w = harness_create(&c, 0, 10, 10, 10, 10, VIS_CREATE_MAP);
	const int32_t halves[2][4] = { { 0, 0, 5, 10 }, { 5, 0, 5, 10 } };
	const int32_t overlap[2][4] = { { 0, 0, 7, 10 }, { 3, 0, 7, 10 } };
	const int32_t but_one[2][4] = { { 0, 0, 10, 9 }, { 0, 9, 9, 1 } };
	const int32_t framed[1][4] = { { -1, -1, 12, 12 } };
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, halves, 2);
	expect_translucent(&c, &log, w, false, "abutting opaque rectangles covering the window");
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, overlap, 2);
	expect_translucent(&c, &log, w, false, "overlapping opaque rectangles covering the window");
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, but_one, 2);
	expect_translucent(&c, &log, w, true, "one pixel left out of the opaque rectangles");
	harness_req(&c, VIS_OP_RESIZE, w, 10, 9);
	expect_translucent(&c, &log, w, false, "resized so that the free pixel is gone");
	harness_req(&c, VIS_OP_RESIZE, w, 11, 9);
	expect_translucent(&c, &log, w, true, "resized wider than the opaque rectangles");
	harness_req(&c, VIS_OP_CONFIGURE, w, 10, 10, 10, 10, 1);
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, halves, 2);
	expect_translucent(&c, &log, w, true, "a border outside the opaque rectangles");
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, framed, 1);
	expect_translucent(&c, &log, w, false, "opaque rectangles covering the border too");
	harness_req(&c, VIS_OP_CONFIGURE, w, 10, 10, 10, 10, 2);
	expect_translucent(&c, &log, w, true, "a border grown past the opaque rectangles");
	set_look(&c, VIS_OP_SET_SHAPE, w, 1, framed, 1);
	expect_translucent(&c, &log, w, false, "shaped to the opaque rectangle");
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_RECTS, halves, 2);
	expect_translucent(&c, &log, w, true, "shaped into the border, opaque only inside it");
	harness_req(&c, VIS_OP_CONFIGURE, w, 10, 10, 10, 10, 0);
	expect_translucent(&c, &log, w, false, "the same without a border: its inside, opaque");
	set_look(&c, VIS_OP_SET_SHAPE, w, 1, NULL, 0);
	set_look(&c, VIS_OP_SET_OPAQUE, w, VIS_OPAQUE_MODE_NONE, NULL, 0);
	expect_translucent(&c, &log, w, false, "no pixels at all (mode none)");
	set_look(&c, VIS_OP_SET_SHAPE, w, 0, NULL, 0);
	expect_translucent(&c, &log, w, true, "its border box again (mode none)");
	uint32_t io = harness_create(&c, 0, 0, 0, 5, 5, VIS_CREATE_MAP | VIS_CREATE_INPUT_ONLY);
	expect_translucent(&c, &log, io, false, "an input-only window");
	harness_close(&c);
}

/* Reads n synced replies, answering the requests from first on, straight from the socket. */
static void read_synced(struct harness_conn *c, uint32_t first, uint32_t n)
{
	enum { SYNCED = VIS_MSG_HEADER + 4 };
	CHECK(c->in.len == c->taken, "bytes left over before the synced replies");
	static uint8_t b[SYNCED << 12];
	size_t have = 0;
	for (uint32_t got = 0; got < n;) {
		ssize_t k = read(c->fd, b + have, sizeof b - have);
		CHECK(k > 0, "the connection ended after %u of %u synced replies", got, n);
		have += (size_t)k;
		size_t at = 0;
		for (; have - at >= SYNCED && got < n; at += SYNCED, got++)
			CHECK(vis_wire_get_u32(b + at) == SYNCED &&
				      vis_wire_get_u32(b + at + 4) == VIS_OP_SYNCED &&
				      vis_wire_get_u32(b + at + 8) == first + got,
			      "reply %u of %u is not synced for request %u", got + 1, n, first + got);
		memmove(b, b + at, have - at);
		have -= at;
	}
	CHECK(have == 0, "more than the synced replies");
}

/*
 * A batch is charged its requests' bytes: 2,097,152 syncs of 8 bytes are 16 MiB, which it holds
 * (and then answers every one); one sync more is the limit error that names the bound and ends
 * the connection.
 */
static void test_batch_bytes(const struct harness_daemon *d)
{
	harness_context("a batch charged its requests' bytes");
	const uint32_t fit = (16u << 20) / VIS_MSG_HEADER;
	uint8_t sync[VIS_MSG_HEADER];
	harness_put(sync, VIS_OP_SYNC);
	struct harness_conn c;
	harness_open_as(&c, d->sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	uint32_t first = c.seq + 1;
	harness_send_copies(&c, sync, sizeof sync, fit);
	harness_req(&c, VIS_OP_BATCH_COMMIT);
	read_synced(&c, first, fit);
	harness_sync(&c, NULL);
	harness_close(&c);

	harness_open_as(&c, d->sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	harness_send_copies(&c, sync, sizeof sync, fit + 1);
	harness_expect_error(&c, 2 + fit + 1, VIS_OP_SYNC, VIS_ERROR_LIMIT, "16777216 bytes", true);
	harness_close(&c);
}

/*
 * create with MAP is reported as create then map: two stack notices, the first with the flags of
 * an unmapped window (0), the second with mapped and viewable, both before the created reply.
 */
static void test_create_mapped(const struct harness_daemon *d)
{
	harness_context("create with MAP: two stack notices");
	struct harness_conn c;
	struct notices log;
	open_logged(&c, d, VIS_ROLE_CLIENT, &log);
	harness_req(&c, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_STACK, 0);
	harness_sync(&c, NULL);
	uint32_t w = harness_create(&c, 0, 5, 5, 20, 20, VIS_CREATE_MAP);
	CHECK(log.n == 2, "create with MAP sent %zu stack notices before its reply, not 2", log.n);
	const union vis_arg *a = log.v[0].args, *b = log.v[1].args;
	CHECK(log.v[0].opcode == VIS_OP_STACK && a[1].u == VIS_STACK_CREATE && a[2].u == w &&
		      a[9].u == 0,
	      "the first notice: change %u of window %u, flags %#x; wanted create of %u, flags 0",
	      a[1].u, a[2].u, a[9].u, w);
	CHECK(log.v[1].opcode == VIS_OP_STACK && b[1].u == VIS_STACK_MAP && b[2].u == w &&
		      b[9].u == (VIS_WINDOW_MAPPED | VIS_WINDOW_VIEWABLE),
	      "the second notice: change %u of window %u, flags %#x; wanted map of %u, flags 3",
	      b[1].u, b[2].u, b[9].u, w);
	CHECK(a[0].q + 1 == b[0].q, "serials %llu and %llu are not consecutive",
	      (unsigned long long)a[0].q, (unsigned long long)b[0].q);
	harness_sync(&c, NULL);
	CHECK(log.n == 2, "%zu more notices after the reply", log.n - 2);
	harness_close(&c);
}

/* Rectangles x, y, width, height (window coordinates). */
struct rects {
	int32_t r[64][4];
	uint32_t n;
};

static struct rects region_of(struct harness_conn *c, uint32_t id)
{
	struct vis_msg m;
	harness_expect(c, harness_req(c, VIS_OP_GET_REGION, id), VIS_OP_REGION, &m);
	struct rects out = { .n = m.args[3].a.n };
	CHECK(m.args[2].u == 0 && out.n <= 64, "a region of %u rectangles", out.n);
	for (uint32_t i = 0; i < out.n; i++)
		for (uint32_t k = 0; k < 4; k++)
			out.r[i][k] = (int32_t)vis_arg_word(&m.args[3], 'R', i, k);
	return out;
}

/* The rectangles of the last exposure notice about id in log. */
static struct rects exposure_of(const struct notices *log, uint32_t id)
{
	for (size_t i = log->n; i-- > 0;)
		if (log->v[i].opcode == VIS_OP_EXPOSURE && log->v[i].args[1].u == id) {
			struct rects out = { .n = log->v[i].args[4].a.n };
			CHECK(out.n <= 64, "an exposure of %u rectangles", out.n);
			memcpy(out.r, log->v[i].rects, out.n * sizeof out.r[0]);
			return out;
		}
	harness_fail(__FILE__, __LINE__, "no exposure notice about window %u", id);
}

static bool holds(const struct rects *r, int32_t x, int32_t y)
{
	for (uint32_t i = 0; i < r->n; i++)
		if (x >= r->r[i][0] && x < r->r[i][0] + r->r[i][2] && y >= r->r[i][1] &&
		    y < r->r[i][1] + r->r[i][3])
			return true;
	return false;
}

/* A bordered window seen in part, as the test places it: its pixels, in window coordinates. */
struct scene {
	int32_t width, height, border;
	const struct rects *shape; /* NULL: the border box */
	int32_t cover[4];          /* a window above it, in its window coordinates (w 0: none) */
};

/* Checks rectangles against the scene, pixel by pixel around the border box. */
static void check_pixels(const struct rects *got, const struct scene *s, const char *what)
{
	int32_t b = s->border;
	for (int32_t y = -b - 2; y < s->height + b + 2; y++)
		for (int32_t x = -b - 2; x < s->width + b + 2; x++) {
			bool mine = x >= -b && x < s->width + b && y >= -b && y < s->height + b &&
				    (!s->shape || holds(s->shape, x, y));
			bool covered = x >= s->cover[0] && x < s->cover[0] + s->cover[2] &&
				       y >= s->cover[1] && y < s->cover[1] + s->cover[3];
			CHECK(holds(got, x, y) == (mine && !covered),
			      "%s: pixel %d,%d (window coordinates) is %s in the %u rectangles "
			      "(first %d,%d %dx%d)",
			      what, x, y, holds(got, x, y) ? "in" : "not", got->n, got->r[0][0],
			      got->r[0][1], got->r[0][2], got->r[0][3]);
		}
}

/*
 * Regions and exposures are in window coordinates, from the inside's corner, as shapes are: a
 * bordered window's border lies at negative coordinates in get-region and in exposure notices,
 * and a shape reaching into the border is seen where its pixels are.
 */
static void test_coordinates(const struct harness_daemon *d)
{
	harness_context("window coordinates of regions and exposures");
	struct harness_conn c;
	struct notices log;
	open_logged(&c, d, VIS_ROLE_CLIENT, &log);
	uint32_t w = harness_create(&c, 0, 10, 10, 20, 10, 0);
	harness_req(&c, VIS_OP_CONFIGURE, w, 10, 10, 20, 10, 3);
	harness_req(&c, VIS_OP_SUBSCRIBE, w, VIS_NOTICE_EXPOSURE, 0);
	harness_req(&c, VIS_OP_MAP, w);
	harness_sync(&c, NULL);
	struct scene s = { 20, 10, 3, NULL, { 0 } };
	struct rects r = region_of(&c, w);
	CHECK(r.n == 1 && r.r[0][0] == -3 && r.r[0][1] == -3 && r.r[0][2] == 26 && r.r[0][3] == 16,
	      "the whole bordered window: get-region %u rectangles, first %d,%d %dx%d; wanted "
	      "-3,-3 26x16",
	      r.n, r.r[0][0], r.r[0][1], r.r[0][2], r.r[0][3]);
	struct rects e = exposure_of(&log, w);
	check_pixels(&e, &s, "exposure on map");
	/* A window over its top-left corner, at the border box's corner: window coordinates -3, -3. */
	uint32_t cover = harness_create(&c, 0, 10, 10, 5, 5, VIS_CREATE_MAP);
	s.cover[0] = s.cover[1] = -3;
	s.cover[2] = s.cover[3] = 5;
	harness_sync(&c, NULL);
	r = region_of(&c, w);
	check_pixels(&r, &s, "get-region under a window");
	harness_req(&c, VIS_OP_MOVE, cover, 200, 200);
	harness_sync(&c, NULL);
	e = exposure_of(&log, w);
	CHECK(e.n == 1 && e.r[0][0] == -3 && e.r[0][1] == -3 && e.r[0][2] == 5 && e.r[0][3] == 5,
	      "uncovered: exposure %u rectangles, first %d,%d %dx%d; wanted -3,-3 5x5", e.n,
	      e.r[0][0], e.r[0][1], e.r[0][2], e.r[0][3]);
	/* A shape reaching into the border, and past the border box. */
	const int32_t shape[3][4] = { { -2, -2, 5, 5 }, { 10, 0, 5, 5 }, { 18, 8, 10, 10 } };
	set_look(&c, VIS_OP_SET_SHAPE, w, 1, shape, 3);
	struct rects sh = { .n = 3 };
	memcpy(sh.r, shape, sizeof shape);
	s.shape = &sh;
	s.cover[2] = 0;
	harness_sync(&c, NULL);
	r = region_of(&c, w);
	check_pixels(&r, &s, "get-region of a shape reaching into the border");
	harness_close(&c);
}

static int cmp_u32(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return (x > y) - (x < y);
}

/*
 * Window IDs say nothing about other clients' windows: two clients creating in turn do not get
 * IDs one apart, nor IDs that grow, so neither can count the other's windows between two of its
 * own; and the IDs of one daemon are all distinct (never 0) over many creations.
 */
static void test_ids(const struct harness_daemon *d)
{
	harness_context("window IDs");
	enum { TURNS = 64, MANY = 20000 };
	struct harness_conn a, b;
	harness_open_as(&a, d->sock, VIS_ROLE_CLIENT);
	harness_open_as(&b, d->sock, VIS_ROLE_CLIENT);
	uint32_t *ids = malloc((2 * TURNS + MANY) * sizeof *ids);
	CHECK(ids, "out of memory");
	size_t n = 0, adjacent = 0, growing = 0;
	for (int i = 0; i < TURNS; i++) {
		ids[n++] = harness_create(&a, 0, 0, 0, 5, 5, 0);
		ids[n++] = harness_create(&b, 0, 0, 0, 5, 5, 0);
	}
	for (int i = 2; i < 2 * TURNS; i += 2) { /* a's consecutive IDs: b created one between */
		adjacent += ids[i] - ids[i - 2] == 2 || ids[i] - ids[i - 1] == 1;
		growing += ids[i] > ids[i - 2];
	}
	CHECK(adjacent <= 2 && growing < TURNS - 8,
	      "a client's IDs tell the other's windows: %zu of %d steps are 2 apart, %zu grow",
	      adjacent, TURNS - 1, growing);
	/* Many more, in batches of creates destroyed again: none is 0, none comes back. */
	uint8_t create[VIS_MSG_HEADER + 40], destroy[VIS_MSG_HEADER + 4];
	harness_put(create, VIS_OP_CREATE, 0, 0, 0, 5, 5, 0, 0, 0, 0, 0);
	for (int round = 0; round < MANY / 1000; round++) {
		harness_send_copies(&a, create, sizeof create, 1000);
		for (int i = 0; i < 1000; i++) {
			struct vis_msg m;
			harness_next_reply(&a, &m, NULL);
			CHECK(m.type->opcode == VIS_OP_CREATED, "create: %s", m.type->name);
			ids[n++] = m.args[1].u;
		}
		for (size_t i = n - 1000; i < n; i++) {
			harness_put(destroy, VIS_OP_DESTROY, ids[i]);
			harness_request_raw(&a, destroy, sizeof destroy);
		}
		harness_sync(&a, NULL);
	}
	qsort(ids, n, sizeof *ids, cmp_u32);
	CHECK(ids[0] != 0, "window ID 0");
	for (size_t i = 1; i < n; i++)
		CHECK(ids[i] != ids[i - 1], "window ID %u handed out twice", ids[i]);
	free(ids);
	harness_close(&a);
	harness_close(&b);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: test-spec VISD\n");
		return 2;
	}
	visd = argv[1];
	signal(SIGPIPE, SIG_IGN);
	struct harness_daemon d = { 0 };
	harness_start(&d, visd, NULL);
	test_viewable(&d);
	test_translucent(&d);
	test_batch_bytes(&d);
	test_create_mapped(&d);
	test_ids(&d);
	test_coordinates(&d);
	harness_stop(&d);
	printf("spec: the daemon does what PROTOCOL.md says\n");
	return 0;
}
