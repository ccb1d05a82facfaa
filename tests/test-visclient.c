/*
 * Unit tests of libvisclient against a fake daemon: a forked process on a private Unix socket
 * that answers the handshake, then plays a script of good or broken messages. The library must
 * put chunked replies back together, give notices to the handler with their fields, and answer
 * every broken message with a sticky connection error, never a crash or a hang.
 */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include "codec.h"
#include "vis/visclient.h"
#include "wire.h"

/* The fake daemon's side of one connection. */
struct fake {
	int fd;
	uint8_t buf[4096];
	size_t len;
	uint32_t serial; /* the next notice's */
};

/* Stops the fake daemon with a failure the parent sees in its exit status. */
static void fake_die(const char *what)
{
	fprintf(stderr, "fake daemon: %s\n", what);
	_exit(3);
}

/* Reads the next request; exits quietly when the client has gone. */
static void fake_read(struct fake *f, uint32_t opcode)
{
	for (;;) {
		struct vis_msg m;
		char why[200];
		enum vis_decode r = vis_msg_decode(f->buf, f->len, 4096, 1, &m, why, sizeof(why));
		if (r == VIS_DECODE_MALFORMED)
			fake_die(why);
		if (r == VIS_DECODE_OK) {
			if (m.type->opcode != opcode)
				fake_die("unexpected request");
			memmove(f->buf, f->buf + m.size, f->len - m.size);
			f->len -= m.size;
			return;
		}
		ssize_t n = read(f->fd, f->buf + f->len, sizeof(f->buf) - f->len);
		if (n <= 0)
			_exit(0);
		f->len += (size_t)n;
	}
}

static void fake_raw(struct fake *f, const void *p, size_t len)
{
	if (write(f->fd, p, len) != (ssize_t)len)
		fake_die("write");
}

/* Sends one message, encoded by the codec; up to 12 u/i arguments, then arrays and strings. */
static void fake_send(struct fake *f, uint32_t opcode, const union vis_arg *args)
{
	struct vis_buf b;
	vis_buf_init(&b);
	if (vis_msg_encode(&b, opcode, args) < 0)
		fake_die("encode");
	fake_raw(f, b.data, b.len);
	vis_buf_finish(&b);
}

#define U(v) { .u = (v) }

static void fake_synced(struct fake *f, uint32_t seq)
{
	union vis_arg a[1] = { U(seq) };
	fake_send(f, VIS_OP_SYNCED, a);
}

static void fake_error(struct fake *f, uint32_t seq, uint32_t opcode, uint32_t code,
		       const char *msg)
{
	union vis_arg a[4] = { U(seq), U(opcode), U(code), { .s = { msg, (uint32_t)strlen(msg) } } };
	fake_send(f, VIS_OP_ERROR, a);
}

static void fake_visibility(struct fake *f, uint32_t window, uint32_t state, uint32_t previous)
{
	union vis_arg a[5] = { { .q = f->serial++ }, U(window), U(state), U(previous), U(0) };
	fake_send(f, VIS_OP_VISIBILITY, a);
}

/* Answers hello like visd: client 7, role as asked, a 100x200 screen. */
static void fake_hello(struct fake *f)
{
	fake_read(f, VIS_OP_HELLO);
	union vis_arg a[7] = { U(1), U(VIS_PROTOCOL_VERSION), U(7), U(0), U(100), U(200),
			       U(65536) };
	fake_send(f, VIS_OP_HELLO_REPLY, a);
}

/* Waits for the client to hang up, so that what was sent is read before EOF. */
static void fake_linger(struct fake *f)
{
	char c;
	while (read(f->fd, &c, 1) > 0)
		;
}

/* The good session: every reply kind, chunks, notices in between, an error. */
static void serve_good(struct fake *f)
{
	fake_hello(f);
	fake_read(f, VIS_OP_CREATE); /* 2 */
	fake_visibility(f, 5, VIS_VISIBILITY_UNOBSCURED, VIS_VISIBILITY_NONE);
	fake_send(f, VIS_OP_CREATED, (union vis_arg[]){ U(2), U(5) });

	fake_read(f, VIS_OP_GET_STATES); /* 3 */
	static const uint32_t s1[] = { 5, 0 }, s2[] = { 6, 2, 8, 1 };
	fake_send(f, VIS_OP_STATES, (union vis_arg[]){ U(3), U(1), { .a = { NULL, s1, 1 } } });
	static const uint32_t rects[] = { 0, 0, 10, 5, (uint32_t)-3, 5, 20, 1 };
	fake_send(f, VIS_OP_EXPOSURE, (union vis_arg[]){ { .q = f->serial++ }, U(5), U(1), U(3),
							  { .a = { NULL, rects, 2 } } });
	fake_send(f, VIS_OP_STATES, (union vis_arg[]){ U(3), U(0), { .a = { NULL, s2, 2 } } });

	fake_read(f, VIS_OP_MAP);  /* 4 */
	fake_read(f, VIS_OP_SYNC); /* 5 */
	fake_error(f, 4, VIS_OP_MAP, VIS_ERROR_WINDOW, "no such window 9");
	fake_send(f, VIS_OP_STACK, (union vis_arg[]){ { .q = f->serial++ }, U(VIS_STACK_RESTACK),
						       U(5), U(0), { .i = -4 }, U(6), U(7), U(8),
						       U(6), U(3), U(2), U(VIS_EXTERNAL_X11),
						       { .q = 0x1e00003 } });
	fake_synced(f, 5);

	fake_read(f, VIS_OP_GET_REGION); /* 6 */
	fake_send(f, VIS_OP_REGION, (union vis_arg[]){ U(6), U(5), U(1), { .a = { NULL, rects, 1 } } });
	fake_send(f, VIS_OP_REGION,
		  (union vis_arg[]){ U(6), U(5), U(0), { .a = { NULL, rects + 4, 1 } } });

	fake_read(f, VIS_OP_GET_TREE); /* 7 */
	/* Its external ID's tag, 0x100000002, as two words, low first. */
	static const uint32_t node[] = { 5, 0, (uint32_t)-1, 2, 30, 40, 0, 3, 1, 77, 2, 1 };
	fake_send(f, VIS_OP_TREE, (union vis_arg[]){ U(7), U(0), { .a = { NULL, node, 1 } } });

	fake_read(f, VIS_OP_GET_REPAINT); /* 8 */
	static const uint32_t ids[] = { 5, 6 };
	fake_send(f, VIS_OP_REPAINT, (union vis_arg[]){ U(8), U(0), { .a = { NULL, ids, 2 } } });

	fake_read(f, VIS_OP_GET_STATE); /* 9 */
	fake_send(f, VIS_OP_STATE, (union vis_arg[]){ U(9), U(5), U(1) });

	fake_read(f, VIS_OP_SYNC); /* 10 */
	fake_synced(f, 10);

	fake_read(f, VIS_OP_LOOKUP); /* 11 */
	fake_send(f, VIS_OP_FOUND, (union vis_arg[]){ U(11), U(5) });

	/* A batch's round trip comes in one write: begin, map, sync, commit (8 + 12 + 8 + 8). */
	if (f->len != 0)
		fake_die("bytes before the batch");
	ssize_t got = read(f->fd, f->buf, sizeof(f->buf));
	if (got != 36)
		fake_die("the batch's round trip did not come in one write");
	f->len = (size_t)got;
	fake_read(f, VIS_OP_BATCH_BEGIN); /* 12 */
	fake_read(f, VIS_OP_MAP);         /* 13 */
	fake_read(f, VIS_OP_SYNC);        /* 14 */
	fake_read(f, VIS_OP_BATCH_COMMIT); /* 15 */
	fake_synced(f, 14);
	/* Then the daemon goes away: a clean EOF. */
}

static struct vis_notice notices[8];
static struct vis_rect32 exposure_rects[4];
static int n_notices;

static void on_notice(void *data, const struct vis_notice *n)
{
	(void)data;
	assert(n_notices < 8);
	notices[n_notices] = *n;
	if (n->kind == VIS_NOTICE_KIND_EXPOSURE) {
		assert(n->exposure.n_rects <= 4);
		memcpy(exposure_rects, n->exposure.rects, n->exposure.n_rects * sizeof(*n->exposure.rects));
		notices[n_notices].exposure.rects = exposure_rects;
	}
	n_notices++;
}

static void client_good(struct vis_client *c)
{
	assert(vis_client_error(c) == 0);
	assert(vis_client_id(c) == 7 && vis_client_role(c) == VIS_ROLE_CLIENT);
	uint32_t w, h;
	vis_client_screen(c, &w, &h);
	assert(w == 100 && h == 200);
	vis_client_set_notice_handler(c, on_notice, NULL);

	uint32_t window = 0;
	assert(vis_client_create(c, 0, 1, 2, 3, 4, VIS_CREATE_MAP, &window) == 0 && window == 5);
	assert(n_notices == 1 && notices[0].kind == VIS_NOTICE_KIND_VISIBILITY);
	assert(notices[0].serial == 1 && notices[0].window == 5);
	assert(notices[0].visibility.state == 0 && notices[0].visibility.previous == 3);

	struct vis_window_state *states;
	size_t n;
	assert(vis_client_get_states(c, &states, &n) == 0 && n == 3);
	assert(states[0].window == 5 && states[1].window == 6 && states[1].state == 2);
	assert(states[2].window == 8 && states[2].state == 1);
	free(states);
	assert(n_notices == 2 && notices[1].kind == VIS_NOTICE_KIND_EXPOSURE);
	assert(notices[1].serial == 2 && notices[1].exposure.flags == VIS_EXPOSURE_COLLAPSED);
	assert(notices[1].exposure.n_rects == 2 && exposure_rects[1].x == -3);
	assert(notices[1].exposure.coalesced == 3);
	assert(exposure_rects[1].width == 20 && exposure_rects[0].height == 5);

	assert(vis_client_map(c, 9) == 4);
	assert(vis_client_sync(c) == -1 && vis_client_error(c) == 0);
	struct vis_error e;
	assert(vis_client_last_error(c, &e) == 1 && e.seq == 4 && e.opcode == VIS_OP_MAP);
	assert(e.code == VIS_ERROR_WINDOW && strcmp(e.message, "no such window 9") == 0);
	assert(n_notices == 3 && notices[2].kind == VIS_NOTICE_KIND_STACK);
	assert(notices[2].stack.change == VIS_STACK_RESTACK && notices[2].stack.x == -4);
	assert(notices[2].stack.sibling == 6 && notices[2].stack.flags == 3);
	assert(notices[2].stack.border == 2);
	assert(notices[2].stack.ext_namespace == VIS_EXTERNAL_X11 &&
	       notices[2].stack.external == 0x1e00003);

	struct vis_rect32 *r;
	assert(vis_client_get_region(c, 5, &r, &n) == 0 && n == 2);
	assert(r[0].width == 10 && r[1].x == -3 && r[1].height == 1);
	free(r);

	struct vis_window_info *t;
	assert(vis_client_get_tree(c, &t, &n) == 0 && n == 1);
	assert(t[0].window == 5 && t[0].x == -1 && t[0].height == 40 && t[0].flags == 3);
	assert(t[0].border == 0 && t[0].state == 1);
	assert(t[0].ext_namespace == 77 && t[0].external == 0x100000002ull);
	free(t);

	uint32_t *ids;
	struct vis_rect32 damage = { 0, 0, 10, 10 };
	assert(vis_client_get_repaint(c, damage, &ids, &n) == 0 && n == 2 && ids[1] == 6);
	free(ids);

	uint32_t state;
	assert(vis_client_get_state(c, 5, &state) == 0 && state == 1);
	assert(vis_client_sync(c) == 0);
	assert(vis_client_lookup(c, VIS_EXTERNAL_X11, 0x1e00003, &window) == 0 && window == 5);
	/* Held until the commit: a batch-begin written at once would reach the fake, which waits
	 * in read, alone during the pause. */
	assert(vis_client_batch_begin(c) == 12);
	usleep(20000);
	assert(vis_client_map(c, 5) == 13 && vis_client_batch_roundtrip(c) == 0);

	/* The daemon hung up: sticky, and everything after fails at once. */
	while (vis_client_dispatch(c) >= 0)
		;
	assert(vis_client_error(c) == ECONNRESET && vis_client_error_message(c)[0]);
	assert(vis_client_map(c, 1) == 0 && vis_client_roundtrip(c) == -1);
	assert(vis_client_flush(c) == -1);
}

/* A broken message: raw bytes sent in answer to the client's sync (request 2). */
struct broken {
	const char *name;
	uint8_t bytes[96];
	size_t len;
	int close_after; /* hang up at once rather than wait for the client */
	int expect;      /* the sticky errno */
};

static const struct broken *current;

/* Writes a header into b. */
static size_t header(uint8_t *b, uint32_t size, uint16_t opcode)
{
	vis_wire_put_u32(b, size);
	vis_wire_put_u16(b + 4, opcode);
	vis_wire_put_u16(b + 6, 0);
	return 8;
}

static void serve_broken(struct fake *f)
{
	fake_hello(f);
	fake_read(f, VIS_OP_SYNC);
	fake_raw(f, current->bytes, current->len);
	if (!current->close_after)
		fake_linger(f);
}

static void client_broken(struct vis_client *c)
{
	assert(vis_client_error(c) == 0);
	vis_client_set_notice_handler(c, on_notice, NULL);
	if (vis_client_roundtrip(c) == 0) {
		/* The sync was answered before the broken part: read on until it comes. */
		while (vis_client_dispatch(c) >= 0)
			;
	}
	if (vis_client_error(c) != current->expect) {
		fprintf(stderr, "%s: error %d (%s), expected %d\n", current->name,
			vis_client_error(c), vis_client_error_message(c), current->expect);
		abort();
	}
	assert(vis_client_error_message(c)[0]);
	assert(vis_client_dispatch(c) == -1 && vis_client_sync_async(c, NULL, NULL) == 0);
}

/* Forks a fake daemon running serve, connects to it, runs check; both must succeed. */
static void run(const char *dir, void (*serve)(struct fake *), void (*check)(struct vis_client *),
		uint32_t role)
{
	static int count;
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	snprintf(addr.sun_path, sizeof(addr.sun_path), "%s/s%d", dir, count++);
	int lfd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	assert(lfd >= 0);
	assert(bind(lfd, (struct sockaddr *)&addr, sizeof(addr)) == 0 && listen(lfd, 1) == 0);
	pid_t pid = fork();
	assert(pid >= 0);
	if (pid == 0) {
		struct fake f = { .fd = accept(lfd, NULL, NULL), .serial = 1 };
		if (f.fd < 0)
			fake_die("accept");
		serve(&f);
		_exit(0);
	}
	close(lfd);
	n_notices = 0;
	struct vis_client *c = vis_client_connect(addr.sun_path, role);
	assert(c);
	check(c);
	vis_client_destroy(c);
	int status;
	assert(waitpid(pid, &status, 0) == pid);
	assert(WIFEXITED(status) && WEXITSTATUS(status) == 0);
	unlink(addr.sun_path);
}

/* A refused handshake: connect returns a connection in error, with the daemon's reason. */
static void serve_refused(struct fake *f)
{
	fake_read(f, VIS_OP_HELLO);
	fake_error(f, 1, VIS_OP_HELLO, VIS_ERROR_ACCESS, "role manager not allowed");
}

static void client_refused(struct vis_client *c)
{
	struct vis_error e;
	assert(vis_client_error(c) == EACCES);
	assert(strstr(vis_client_error_message(c), "role manager not allowed"));
	assert(vis_client_last_error(c, &e) == 1 && e.code == VIS_ERROR_ACCESS && e.seq == 1);
}

/* The hello-reply serve_bad_hello sends: one that no daemon sends. */
static const uint32_t *bad_hello;

static void serve_bad_hello(struct fake *f)
{
	union vis_arg a[7];
	for (int i = 0; i < 7; i++)
		a[i].u = bad_hello[i];
	fake_read(f, VIS_OP_HELLO);
	fake_send(f, VIS_OP_HELLO_REPLY, a);
	fake_linger(f);
}

static void client_eproto(struct vis_client *c)
{
	assert(vis_client_error(c) == EPROTO);
}

/*
 * Look replies for get-look of window 5: a good one (two shape rectangles, opaque mode 2 with one),
 * then, per bad_look, one whose values no daemon sends.
 */
static int bad_look; /* 0: the good reply; 1 shaped 2; 2 mode 3; 3 rectangles with shaped 0;
			 4 another window */

static void serve_look(struct fake *f)
{
	static const uint32_t shape[] = { 0, 0, 10, 5, (uint32_t)-2, 5, 3, 4 };
	static const uint32_t opaque[] = { 1, 1, 8, 3 };
	uint32_t shaped = bad_look == 1 ? 2 : bad_look == 3 ? 0 : 1;
	uint32_t mode = bad_look == 2 ? 3 : VIS_OPAQUE_MODE_RECTS;
	fake_hello(f);
	fake_read(f, VIS_OP_GET_LOOK);
	fake_send(f, VIS_OP_LOOK,
		  (union vis_arg[]){ U(2), U(bad_look == 4 ? 6 : 5), U(shaped), U(mode),
				     { .a = { NULL, shape, 2 } }, { .a = { NULL, opaque, 1 } } });
	fake_linger(f);
}

static void client_look(struct vis_client *c)
{
	struct vis_look_info l;
	int rc = vis_client_get_look(c, 5, &l);
	if (bad_look) {
		assert(rc == -1 && vis_client_error(c) == EPROTO);
		return;
	}
	assert(rc == 0 && l.window == 5 && l.shaped == 1 && l.n_shape == 2 &&
	       l.mode == VIS_OPAQUE_MODE_RECTS && l.n_opaque == 1);
	assert(l.shape[1].x == -2 && l.shape[1].height == 4 && l.opaque[0].width == 8);
	free(l.shape);
	free(l.opaque);
}

/* A daemon that hangs up at once. */
static void serve_hangup(struct fake *f)
{
	fake_hello(f);
}

/* Writing to a daemon that went away: an error, never SIGPIPE (which would kill the test). */
static void client_hangup(struct vis_client *c)
{
	assert(vis_client_error(c) == 0);
	usleep(100 * 1000);
	for (int i = 0; i < 100000 && vis_client_map(c, 1); i++)
		;
	int r = vis_client_flush(c);
	assert(r == -1 || vis_client_roundtrip(c) == -1);
	assert(vis_client_error(c) == EPIPE || vis_client_error(c) == ECONNRESET);
}

/* A missing socket: the error names the path. */
static void test_no_socket(const char *dir)
{
	char path[200];
	snprintf(path, sizeof(path), "%s/missing", dir);
	struct vis_client *c = vis_client_connect(path, VIS_ROLE_CLIENT);
	assert(c && vis_client_error(c) == ENOENT);
	assert(strstr(vis_client_error_message(c), path));
	assert(vis_client_map(c, 1) == 0 && vis_client_dispatch(c) == -1);
	vis_client_destroy(c);
	vis_client_destroy(NULL);
}

static void test_names(void)
{
	assert(strcmp(vis_visibility_name(2), "fully-obscured") == 0);
	assert(strcmp(vis_visibility_name(3), "none") == 0);
	assert(strcmp(vis_visibility_name(4), "initial") == 0);
	assert(strcmp(vis_visibility_name(5), "?") == 0);
	assert(strcmp(vis_error_code_name(VIS_ERROR_WINDOW), "window") == 0);
	assert(strcmp(vis_error_code_name(0), "?") == 0);
	assert(strcmp(vis_request_name(VIS_OP_GET_STATES), "get-states") == 0);
	assert(strcmp(vis_request_name(VIS_OP_SYNCED), "?") == 0);

	char buf[64];
	setenv("VISD_SOCKET", "/x/y", 1);
	assert(vis_client_default_socket(buf, sizeof(buf)) == 0 && strcmp(buf, "/x/y") == 0);
	unsetenv("VISD_SOCKET");
	setenv("XDG_RUNTIME_DIR", "/run/u", 1);
	assert(vis_client_default_socket(buf, sizeof(buf)) == 0 && strcmp(buf, "/run/u/visd-0") == 0);
	assert(vis_client_default_socket(buf, 5) == -1);
	unsetenv("XDG_RUNTIME_DIR");
	assert(vis_client_default_socket(buf, sizeof(buf)) == -1);
}

/*
 * The version macros and vis_client_version() agree with each other and with meson's project
 * version (given by the test's argument), as the generated vis/version.h should make them.
 */
static void test_version(const char *project_version)
{
	char parts[64];
	snprintf(parts, sizeof(parts), "%d.%d.%d", VIS_CLIENT_VERSION_MAJOR,
		 VIS_CLIENT_VERSION_MINOR, VIS_CLIENT_VERSION_MICRO);
	assert(strcmp(parts, VIS_CLIENT_VERSION) == 0);
	assert(strcmp(vis_client_version(), VIS_CLIENT_VERSION) == 0);
	if (strcmp(VIS_CLIENT_VERSION, project_version) != 0) {
		fprintf(stderr, "VIS_CLIENT_VERSION is %s, meson's project version %s\n",
			VIS_CLIENT_VERSION, project_version);
		exit(1);
	}
}

/* Fills the broken cases, each a message (or bytes) the library must refuse. */
static size_t make_broken(struct broken *b)
{
	size_t n = 0, o;
	/* A synced reply for a request never sent. */
	b[n] = (struct broken){ .name = "wrong seq", .expect = EPROTO };
	o = header(b[n].bytes, 12, VIS_OP_SYNCED);
	vis_wire_put_u32(b[n].bytes + o, 99);
	b[n++].len = 12;
	/* A created reply where synced is due. */
	b[n] = (struct broken){ .name = "wrong reply type", .expect = EPROTO };
	o = header(b[n].bytes, 16, VIS_OP_CREATED);
	vis_wire_put_u32(b[n].bytes + o, 2);
	vis_wire_put_u32(b[n].bytes + o + 4, 9);
	b[n++].len = 16;
	/* An opcode no message has, and a request's opcode. */
	b[n] = (struct broken){ .name = "unknown opcode", .expect = EPROTO };
	b[n].len = header(b[n].bytes, 8, 200);
	n++;
	b[n] = (struct broken){ .name = "request opcode", .expect = EPROTO };
	header(b[n].bytes, 12, VIS_OP_MAP);
	b[n++].len = 12;
	/* A size over the protocol's maximum: refused from the header, before any allocation. */
	b[n] = (struct broken){ .name = "oversized", .expect = EPROTO };
	b[n].len = header(b[n].bytes, 0x7ffffff0u, VIS_OP_SYNCED);
	n++;
	/* A states reply claiming 1000 records with room for one. */
	b[n] = (struct broken){ .name = "count over payload", .expect = EPROTO };
	o = header(b[n].bytes, 28, VIS_OP_STATES);
	vis_wire_put_u32(b[n].bytes + o, 2);
	vis_wire_put_u32(b[n].bytes + o + 4, 0);
	vis_wire_put_u32(b[n].bytes + o + 8, 1000);
	b[n++].len = 28;
	/* Part of a message, then EOF. */
	b[n] = (struct broken){ .name = "truncated", .expect = EPROTO, .close_after = 1 };
	header(b[n].bytes, 32, VIS_OP_SYNCED);
	b[n++].len = 12;
	/* Nothing at all, then EOF: a clean hang-up. */
	b[n++] = (struct broken){ .name = "eof", .expect = ECONNRESET, .close_after = 1 };
	/* The sync answered, then a reply to nothing. */
	b[n] = (struct broken){ .name = "reply without request", .expect = EPROTO };
	o = header(b[n].bytes, 12, VIS_OP_SYNCED);
	vis_wire_put_u32(b[n].bytes + o, 2);
	header(b[n].bytes + 12, 12, VIS_OP_SYNCED);
	vis_wire_put_u32(b[n].bytes + 20, 3);
	b[n++].len = 24;
	/* An error for a request never sent. */
	b[n] = (struct broken){ .name = "error without request", .expect = EPROTO };
	o = header(b[n].bytes, 24, VIS_OP_ERROR);
	vis_wire_put_u32(b[n].bytes + o, 50);
	vis_wire_put_u32(b[n].bytes + o + 4, VIS_OP_MAP);
	vis_wire_put_u32(b[n].bytes + o + 8, VIS_ERROR_WINDOW);
	b[n++].len = 24;
	/* A notice whose serial skips one. */
	b[n] = (struct broken){ .name = "serial gap", .expect = EPROTO };
	o = header(b[n].bytes, 32, VIS_OP_VISIBILITY);
	vis_wire_put_u64(b[n].bytes + o, 2);
	b[n++].len = 32;
	/* A notice with a state that does not exist. */
	b[n] = (struct broken){ .name = "unknown state", .expect = EPROTO };
	o = header(b[n].bytes, 32, VIS_OP_VISIBILITY);
	vis_wire_put_u64(b[n].bytes + o, 1);
	vis_wire_put_u32(b[n].bytes + o + 12, 7);
	b[n++].len = 32;
	/* "initial" is a previous state only. */
	b[n] = (struct broken){ .name = "initial as a state", .expect = EPROTO };
	o = header(b[n].bytes, 32, VIS_OP_VISIBILITY);
	vis_wire_put_u64(b[n].bytes + o, 1);
	vis_wire_put_u32(b[n].bytes + o + 12, VIS_VISIBILITY_INITIAL);
	b[n++].len = 32;
	b[n] = (struct broken){ .name = "previous past initial", .expect = EPROTO };
	o = header(b[n].bytes, 32, VIS_OP_VISIBILITY);
	vis_wire_put_u64(b[n].bytes + o, 1);
	vis_wire_put_u32(b[n].bytes + o + 16, VIS_VISIBILITY_INITIAL + 1);
	b[n++].len = 32;
	/* An external ID without a namespace, in a stack notice. */
	b[n] = (struct broken){ .name = "external without namespace", .expect = EPROTO };
	o = header(b[n].bytes, 68, VIS_OP_STACK);
	vis_wire_put_u64(b[n].bytes + o, 1);
	vis_wire_put_u32(b[n].bytes + o + 12, 5);
	vis_wire_put_u32(b[n].bytes + o + 28, 1);
	vis_wire_put_u32(b[n].bytes + o + 32, 1);
	vis_wire_put_u64(b[n].bytes + o + 52, 0x1e00003);
	b[n++].len = 68;
	/* A chunked reply with more = 2. */
	b[n] = (struct broken){ .name = "more not 0 or 1", .expect = EPROTO };
	o = header(b[n].bytes, 20, VIS_OP_STATES);
	vis_wire_put_u32(b[n].bytes + o, 2);
	vis_wire_put_u32(b[n].bytes + o + 4, 2);
	b[n++].len = 20;
	/* A fatal error: kept as the last error, and the connection is over. */
	b[n] = (struct broken){ .name = "fatal error", .expect = EPROTO };
	o = header(b[n].bytes, 28, VIS_OP_ERROR);
	vis_wire_put_u32(b[n].bytes + o + 4, VIS_OP_SYNC);
	vis_wire_put_u32(b[n].bytes + o + 8, VIS_ERROR_MALFORMED);
	vis_wire_put_u32(b[n].bytes + o + 12, 3);
	memcpy(b[n].bytes + o + 16, "bad", 3);
	b[n++].len = 28;
	return n;
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: test-visclient PROJECT-VERSION\n");
		return 2;
	}
	alarm(60); /* a hang is a failure too */
	char dir[] = "/tmp/test-visclient.XXXXXX";
	assert(mkdtemp(dir));

	test_names();
	test_version(argv[1]);
	test_no_socket(dir);
	run(dir, serve_good, client_good, VIS_ROLE_CLIENT);
	run(dir, serve_refused, client_refused, VIS_ROLE_MANAGER);
	/* Hello-replies with another version, a role that does not exist, a request limit under
	 * the protocol's least (every request would fail with EMSGSIZE), none at all, one over the
	 * largest message: the handshake fails. */
	static const uint32_t bad_hellos[][7] = {
		{ 1, VIS_PROTOCOL_VERSION + 1, 7, 0, 100, 200, 65536 },
		{ 1, VIS_PROTOCOL_VERSION, 7, 3, 100, 200, 65536 },
		{ 1, VIS_PROTOCOL_VERSION, 7, 0, 100, 200, 3 },
		{ 1, VIS_PROTOCOL_VERSION, 7, 0, 100, 200, 0 },
		{ 1, VIS_PROTOCOL_VERSION, 7, 0, 100, 200, VIS_PROTOCOL_MAX_MESSAGE + 4 },
	};
	for (size_t i = 0; i < sizeof(bad_hellos) / sizeof(bad_hellos[0]); i++) {
		bad_hello = bad_hellos[i];
		run(dir, serve_bad_hello, client_eproto, VIS_ROLE_CLIENT);
	}
	run(dir, serve_hangup, client_hangup, VIS_ROLE_CLIENT);
	for (bad_look = 0; bad_look <= 4; bad_look++)
		run(dir, serve_look, client_look, VIS_ROLE_CLIENT);

	struct broken cases[20];
	size_t n = make_broken(cases);
	for (size_t i = 0; i < n; i++) {
		current = &cases[i];
		run(dir, serve_broken, client_broken, VIS_ROLE_CLIENT);
	}
	rmdir(dir);
	printf("visclient: %zu broken messages refused\n", n);
	return 0;
}
