/*
 * libFuzzer target: libvisclient's handling of what the daemon sends. A connection is made around
 * one end of a socketpair (vis_client_adopt), with hello and requests of every kind waiting
 * (fuzz-client.h); the input is written to the other end, the daemon's, in chunks, read through
 * vis_client_dispatch, then the daemon hangs up. Whatever the bytes, the library must end with a
 * sticky error and never crash; it must call each callback at most once, in request order, never
 * once the connection has failed, and hand handlers only values that exist.
 */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "fuzz-client.h"
#include "visclient-private.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* A request waiting for its reply: the callbacks' data. */
struct request {
	uint32_t seq;
	int called;
};

static struct {
	struct vis_client *c;
	int reenter, depth;
	uint32_t last_answered; /* the request whose callback ran last */
	uint64_t serial;        /* the last notice's */
	struct request req[FUZZ_SEQ_SYNC + FUZZ_SYNCS];
} f;

/* Handlers' dispatch, one level deep: a synchronous call inside a handler does the same. */
static void reenter(void)
{
	if (f.reenter && f.depth == 0) {
		f.depth++;
		vis_client_dispatch(f.c);
		f.depth--;
	}
}

/* Checks a callback's call: the first for its request, in order, on a good connection. */
static void answer(void *data, const struct vis_error *err)
{
	struct request *r = data;
	assert(!vis_client_error(f.c) && !r->called && r->seq > f.last_answered);
	r->called = 1;
	f.last_answered = r->seq;
	if (err)
		assert(err->seq == r->seq && memchr(err->message, 0, sizeof(err->message)));
}

static void on_created(void *data, const struct vis_error *err, uint32_t window)
{
	answer(data, err);
	assert(err ? window == 0 : window != VIS_WINDOW_ROOT);
}

static void on_state(void *data, const struct vis_error *err, uint32_t window, uint32_t state)
{
	answer(data, err);
	assert(err ? window == 0 && state == 0
		   : window == FUZZ_WINDOW && state <= VIS_VISIBILITY_NONE);
}

/* Where arrays are read to: a volatile sum, which the compiler cannot drop. */
static volatile uint8_t sink;

/* Reads an array whole, so that ASan sees a short or stale one. */
static void touch(const void *items, size_t n, size_t size)
{
	for (size_t i = 0; i < n * size; i++)
		sink += ((const uint8_t *)items)[i];
}

/* Checks a callback's call with an array, which is empty when the request failed. */
static void answer_array(void *data, const struct vis_error *err, const void *items, size_t n,
			 size_t size)
{
	answer(data, err);
	assert(!err || (!items && !n));
	touch(items, n, size);
}

static void on_states(void *data, const struct vis_error *err,
		      const struct vis_window_state *states, size_t n)
{
	answer_array(data, err, states, n, sizeof(*states));
	for (size_t i = 0; i < n; i++)
		assert(states[i].state <= VIS_VISIBILITY_FULLY_OBSCURED);
}

static void on_tree(void *data, const struct vis_error *err, const struct vis_window_info *windows,
		    size_t n)
{
	answer_array(data, err, windows, n, sizeof(*windows));
	for (size_t i = 0; i < n; i++)
		assert(windows[i].state <= VIS_VISIBILITY_NONE &&
		       (windows[i].ext_namespace || !windows[i].external));
}

static void on_rects(void *data, const struct vis_error *err, const struct vis_rect32 *rects,
		     size_t n)
{
	answer_array(data, err, rects, n, sizeof(*rects));
}

static void on_windows(void *data, const struct vis_error *err, const uint32_t *windows, size_t n)
{
	answer_array(data, err, windows, n, sizeof(*windows));
}

/* Sends the next sync, if there may be one more: a queue that keeps growing while it is read. */
static void send_sync(void);

static void on_synced(void *data, const struct vis_error *err)
{
	answer(data, err);
	send_sync();
}

static void send_sync(void)
{
	uint32_t seq = f.c->next_seq;
	if (seq >= sizeof(f.req) / sizeof(f.req[0]))
		return;
	f.req[seq] = (struct request){ seq, 0 };
	assert(vis_client_sync_async(f.c, on_synced, &f.req[seq]) == seq);
}

static void on_notice(void *data, const struct vis_notice *n)
{
	(void)data;
	assert(!vis_client_error(f.c) && n->serial == ++f.serial);
	switch (n->kind) {
	case VIS_NOTICE_KIND_VISIBILITY:
		assert(n->visibility.state <= VIS_VISIBILITY_NONE);
		assert(n->visibility.previous <= VIS_VISIBILITY_INITIAL);
		break;
	case VIS_NOTICE_KIND_EXPOSURE:
		assert(n->exposure.flags <= VIS_EXPOSURE_COLLAPSED);
		assert(!n->exposure.n_rects == !n->exposure.rects);
		touch(n->exposure.rects, n->exposure.n_rects, sizeof(*n->exposure.rects));
		break;
	case VIS_NOTICE_KIND_STACK:
		assert(n->stack.change <= VIS_STACK_LOOK);
		assert(n->stack.ext_namespace || !n->stack.external);
		break;
	case VIS_NOTICE_KIND_OVERFLOW:
		assert(!n->window);
		break;
	default:
		assert(!"a notice of no kind");
	}
	reenter();
}

static void on_error(void *data, const struct vis_error *e)
{
	(void)data;
	assert(!vis_client_error(f.c) && e->seq < f.c->next_seq);
	assert(memchr(e->message, 0, sizeof(e->message)));
	reenter();
}

/* The request of number seq, as the callbacks' data. */
static struct request *request(uint32_t seq)
{
	f.req[seq] = (struct request){ seq, 0 };
	return &f.req[seq];
}

/* Plays the daemon answering hello as visd would: client FUZZ_CLIENT_ID, role client. */
static void answer_hello(int fd)
{
	union vis_arg a[7] = { { .u = 1 },   { .u = VIS_PROTOCOL_VERSION },
			       { .u = FUZZ_CLIENT_ID }, { .u = VIS_ROLE_CLIENT },
			       { .u = 100 }, { .u = 200 }, { .u = 65536 } };
	struct vis_buf b;
	vis_buf_init(&b);
	assert(vis_msg_encode(&b, VIS_OP_HELLO_REPLY, a) == 0);
	assert(send(fd, b.data, b.len, MSG_NOSIGNAL) == (ssize_t)b.len);
	vis_buf_finish(&b);
	assert(vis_client_dispatch(f.c) == 1 && vis_client_id(f.c) == FUZZ_CLIENT_ID);
}

/* Sends hello and the requests of fuzz-client.h, checking that they get the numbers it says. */
static void send_requests(struct vis_client *c, int handshake, int fd)
{
	struct vis_rect32 damage = { -10, -10, 100, 100 };
	uint32_t seq;
	assert(vis_client_hello(c, VIS_ROLE_CLIENT) == 1);
	if (!handshake)
		answer_hello(fd);
	seq = vis_client_create_async(c, 0, 1, 2, 3, 4, 0, on_created, request(FUZZ_SEQ_CREATE));
	assert(seq == FUZZ_SEQ_CREATE);
	assert(vis_client_map(c, FUZZ_WINDOW) == FUZZ_SEQ_MAP);
	seq = vis_client_get_state_async(c, FUZZ_WINDOW, on_state, request(FUZZ_SEQ_GET_STATE));
	assert(seq == FUZZ_SEQ_GET_STATE);
	seq = vis_client_get_states_async(c, on_states, request(FUZZ_SEQ_GET_STATES));
	assert(seq == FUZZ_SEQ_GET_STATES);
	seq = vis_client_get_tree_async(c, on_tree, request(FUZZ_SEQ_GET_TREE));
	assert(seq == FUZZ_SEQ_GET_TREE);
	seq = vis_client_get_region_async(c, FUZZ_WINDOW, on_rects, request(FUZZ_SEQ_GET_REGION));
	assert(seq == FUZZ_SEQ_GET_REGION);
	seq = vis_client_get_repaint_async(c, damage, on_windows, request(FUZZ_SEQ_GET_REPAINT));
	assert(seq == FUZZ_SEQ_GET_REPAINT);
	send_sync();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	int sv[2];
	assert(socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) == 0);
	assert(fcntl(sv[1], F_SETFL, O_NONBLOCK) == 0);
	memset(&f, 0, sizeof(f));
	f.c = vis_client_adopt(sv[0]);
	assert(f.c);
	f.reenter = (data[0] & FUZZ_REENTER) != 0;
	int handshake = (data[0] & FUZZ_HANDSHAKE) != 0;
	vis_client_set_notice_handler(f.c, on_notice, NULL);
	vis_client_set_error_handler(f.c, on_error, NULL);
	send_requests(f.c, handshake, sv[1]);

	/* The daemon's side: its bytes in chunks, the client reading between them. */
	size_t chunk = fuzz_client_chunks[data[0] & 7];
	const uint8_t *p = data + 1;
	size_t left = size - 1;
	while (left && !vis_client_error(f.c)) {
		ssize_t w = send(sv[1], p, left < chunk ? left : chunk, MSG_NOSIGNAL);
		if (w > 0) {
			p += w;
			left -= (size_t)w;
		} else {
			assert(w < 0 && (errno == EAGAIN || errno == EWOULDBLOCK));
		}
		vis_client_dispatch(f.c);
	}
	/* Then it hangs up: whatever came, the connection ends in a sticky error. */
	assert(shutdown(sv[1], SHUT_WR) == 0);
	for (size_t i = 0; vis_client_dispatch(f.c) >= 0; i++)
		assert(i <= size);
	/* A refused handshake says how; anything else is a hang-up or a broken protocol. */
	int e = vis_client_error(f.c);
	assert(e == EPROTO || e == ECONNRESET ||
	       (handshake && (e == EACCES || e == EBUSY || e == EPROTONOSUPPORT ||
			      e == EAGAIN || e == ECONNREFUSED)));
	assert(vis_client_role(f.c) <= VIS_ROLE_MANAGER);
	assert(vis_client_error_message(f.c)[0]);
	assert(vis_client_dispatch(f.c) == -1 && vis_client_map(f.c, 1) == 0);
	assert(vis_client_sync_async(f.c, on_synced, NULL) == 0);
	vis_client_destroy(f.c);
	close(sv[1]);
	return 0;
}
