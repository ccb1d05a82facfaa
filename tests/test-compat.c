/*
 * Old clients against today's daemon: sessions recorded between a client and the daemon of an
 * older protocol version, replayed against today's visd, whose answers must be the recorded ones
 * byte for byte (PROTOCOL.md, "Versions": a daemon serves every version from 3 on).
 *
 *   test-compat VISD DIR NAME...      replays DIR/NAME.{client,daemon,steps} against VISD
 *   test-compat VISD --side-by-side   observers of versions 3 and 4 get the same notices
 *   test-compat --record LISTEN DAEMON PREFIX
 *                                     records one connection made to socket LISTEN, passed on
 *                                     to socket DAEMON, into PREFIX.{client,daemon,steps}
 *
 * A recording is the client's bytes (NAME.client), the daemon's (NAME.daemon), and how they
 * interleaved (NAME.steps, text: "send N" for N bytes the client wrote, "recv N" for N bytes it
 * had been sent before it wrote again; "end" once the client closed its end, after which the
 * daemon's last bytes came). The replay sends the client's bytes in the same steps, waiting before
 * each for the daemon's bytes the client had seen, so the daemon runs the requests in the same
 * turns; then it closes its end and expects the daemon's remaining bytes and the end of the
 * connection. The daemon runs with --id-key 0x5eed and --screen 1920x1080, as the recording's did
 * (tests/compat/README.md), so nothing varies but what PROTOCOL.md lets vary between daemons: the
 * text of an error message, for people, is not compared.
 */
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "harness.h"
#include "vis/protocol.h"

/* The options of the daemons that recorded the sessions (tests/compat/README.md). */
#define ID_KEY "0x5eed"
#define SCREEN "1920x1080"

/* A whole file, malloc'd; *len its size. Fails the test when it cannot be read. */
static uint8_t *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	CHECK(f, "%s: %s", path, strerror(errno));
	uint8_t *data = NULL;
	size_t n = 0, cap = 0, got;
	do {
		if (n == cap) {
			cap = cap ? 2 * cap : 65536;
			data = realloc(data, cap);
			CHECK(data, "out of memory");
		}
		got = fread(data + n, 1, cap - n, f);
		n += got;
	} while (got > 0);
	CHECK(!ferror(f), "%s: read error", path);
	fclose(f);
	*len = n;
	return data;
}

/* Prints a message's bytes as words, for a failure's report. */
static void dump(const char *who, const uint8_t *p, size_t n)
{
	fprintf(stderr, "  %s:", who);
	for (size_t i = 0; i < n; i++)
		fprintf(stderr, "%s%02x", i % 4 ? "" : " ", p[i]);
	fprintf(stderr, "\n");
}

/*
 * Fails unless message m (raw, its bytes) is the recording's message at offset at; returns that
 * one's size. The text of an error is for people and may change (PROTOCOL.md, "Versions"): two
 * errors agree when their sequence number, opcode and code do.
 */
static uint32_t compare(const struct vis_msg *m, const uint8_t *raw, const uint8_t *want,
			size_t wlen, size_t at, size_t index)
{
	struct vis_msg r;
	char why[128];
	if (at < wlen && vis_msg_decode(want + at, wlen - at, VIS_PROTOCOL_MAX_MESSAGE, 0, &r, why,
					sizeof why) == VIS_DECODE_OK) {
		if (r.size == m->size && memcmp(raw, want + at, m->size) == 0)
			return r.size;
		if (r.type == m->type && m->type->opcode == VIS_OP_ERROR &&
		    memcmp(raw + VIS_MSG_HEADER, want + at + VIS_MSG_HEADER, 12) == 0)
			return r.size;
	}
	fprintf(stderr, "message %zu from visd (%s, %u bytes, at byte %zu) is not the recording's\n",
		index, m->type->name, m->size, at);
	dump("visd  ", raw, m->size);
	dump("wanted", want + at, at < wlen ? (wlen - at < m->size + 64 ? wlen - at : m->size + 64)
					    : 0);
	harness_fail(__FILE__, __LINE__, "replay differs");
}

/* Replays one recording against the daemon d. */
static void replay(struct harness_daemon *d, const char *dir, const char *name)
{
	char path[512];
	size_t clen, dlen, slen;
	snprintf(path, sizeof path, "%s/%s.client", dir, name);
	uint8_t *client = slurp(path, &clen);
	snprintf(path, sizeof path, "%s/%s.daemon", dir, name);
	uint8_t *daemon = slurp(path, &dlen);
	snprintf(path, sizeof path, "%s/%s.steps", dir, name);
	char *steps = (char *)slurp(path, &slen);
	steps = realloc(steps, slen + 1);
	CHECK(steps, "out of memory");
	steps[slen] = '\0';

	harness_context("%s", name);
	struct harness_conn c;
	harness_open(&c, d->sock);
	size_t sent = 0, got = 0, messages = 0;
	bool ended = false;
	for (char *line = strtok(steps, "\n"); line; line = strtok(NULL, "\n")) {
		size_t n = 0;
		if (strcmp(line, "end") == 0) {
			CHECK(shutdown(c.fd, SHUT_WR) == 0, "shutdown: %s", strerror(errno));
			ended = true;
		} else if (sscanf(line, "send %zu", &n) == 1) {
			CHECK(!ended && sent + n <= clen, "%s.steps: send past the client's bytes",
			      name);
			CHECK(harness_send(&c, client + sent, n) == 0, "send: %s", strerror(errno));
			sent += n;
		} else if (sscanf(line, "recv %zu", &n) == 1) {
			for (size_t want = got + n; got < want; messages++) {
				struct vis_msg m;
				CHECK(harness_recv(&c, HARNESS_WORKING, &m) == 1,
				      "visd ended the connection after %zu of %zu bytes", got, dlen);
				got += compare(&m, c.in.data, daemon, dlen, got, messages);
			}
		} else {
			CHECK(0, "%s.steps: cannot read '%s'", name, line);
		}
	}
	CHECK(sent == clen && got == dlen, "%s.steps covers %zu of %zu client bytes, %zu of %zu",
	      name, sent, clen, got, dlen);
	struct vis_msg m;
	int r = harness_recv(&c, HARNESS_WORKING, &m);
	if (r == 1)
		compare(&m, c.in.data, daemon, dlen, got, messages);
	CHECK(r == 0, "visd sent more than the recording");
	harness_close(&c);
	printf("%s: %zu bytes of requests replayed, %zu messages (%zu bytes) as recorded\n", name,
	       clen, messages, dlen);
	free(client);
	free(daemon);
	free(steps);
}

/* What an observer was sent: its notices' bytes, one after another. */
struct stream {
	struct harness_conn c;
	struct vis_buf bytes;
	size_t notices, coalesced, overflows, exposures;
};

static void on_notice(void *data, const struct vis_msg *m)
{
	struct stream *s = data;
	CHECK(vis_buf_append(&s->bytes, s->c.in.data, m->size) == 0, "out of memory");
	s->notices++;
	if (m->type->opcode == VIS_OP_EXPOSURE) {
		s->exposures++;
		s->coalesced += m->args[3].u > 0;
	}
	s->overflows += m->type->opcode == VIS_OP_OVERFLOW;
}

/* Opens an observer speaking version, subscribed to every window for mask. */
static void open_observer(struct stream *s, const char *sock, uint32_t version, uint32_t mask)
{
	memset(s, 0, sizeof *s);
	harness_open(&s->c, sock);
	struct vis_msg m;
	uint32_t seq = harness_req(&s->c, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, version,
				   VIS_ROLE_OBSERVER);
	harness_expect(&s->c, seq, VIS_OP_HELLO_REPLY, &m);
	CHECK(m.args[1].u == version, "hello %u: hello-reply says version %u", version,
	      m.args[1].u);
	s->c.on_notice = on_notice;
	s->c.notice_data = s;
	harness_req(&s->c, VIS_OP_SUBSCRIBE, 0, mask, 0);
	harness_sync(&s->c, NULL);
}

/*
 * Two observers, of versions 3 and 4, stop reading while a manager sweeps a bordered cover across
 * a grid of bordered windows, until they lag (their notices held and merged) or, with stack
 * notices too, overflow (dropped, then a resync). Read at last, the two streams must be the same
 * bytes but for the rectangles of exposures, version 3's shifted by the window's border: every
 * path an exposure takes out of the daemon converts it.
 */
static void side_by_side(const char *visd, uint32_t mask, int sweeps)
{
	struct harness_daemon d = { 0 };
	harness_start(&d, visd, (const char *[]){ "--max-pending", "65536", NULL });
	struct harness_conn m;
	harness_open(&m, d.sock);
	harness_hello(&m, VIS_ROLE_MANAGER);
	struct stream o[2];
	open_observer(&o[0], d.sock, 3, mask);
	open_observer(&o[1], d.sock, VIS_PROTOCOL_VERSION, mask);
	enum { SIDE = 10, N = SIDE * SIDE + 1 };
	uint32_t ids[N], borders[N];
	for (uint32_t i = 0; i < N; i++) {
		uint32_t cover = i == N - 1;
		borders[i] = cover ? 4 : 1 + i % 3;
		uint32_t seq = harness_req(&m, VIS_OP_CREATE, 0, cover ? 0 : 24 * (i % SIDE),
					   cover ? 0 : 24 * (i / SIDE), cover ? 70 : 18,
					   cover ? 70 : 18, VIS_CREATE_MAP, borders[i], 0, 0, 0);
		struct vis_msg r;
		harness_expect(&m, seq, VIS_OP_CREATED, &r);
		ids[i] = r.args[1].u;
	}
	for (int s = 0; s < sweeps; s++)
		for (int k = 0; k < 40; k++) {
			harness_req(&m, VIS_OP_MOVE, ids[N - 1], (uint32_t)(6 * k - 20),
				    (uint32_t)(5 * k + s % 7));
			harness_sync(&m, NULL); /* one recompute a move */
		}
	harness_check_alive(&d);
	for (int i = 0; i < 2; i++)
		harness_sync(&o[i].c, NULL);
	printf("mask %u: %zu notices (%zu exposures, %zu of them coalesced), %zu overflows\n", mask,
	       o[0].notices, o[0].exposures, o[0].coalesced, o[0].overflows);
	if (mask & VIS_NOTICE_STACK)
		CHECK(o[0].overflows > 0, "the observers never overflowed");
	else
		CHECK(o[0].coalesced > 0, "the observers never lagged");
	CHECK(o[0].bytes.len == o[1].bytes.len && o[0].notices == o[1].notices,
	      "version 3 was sent %zu notices (%zu bytes), version 4 %zu (%zu)", o[0].notices,
	      o[0].bytes.len, o[1].notices, o[1].bytes.len);
	size_t shifted = 0;
	for (size_t at = 0; at < o[0].bytes.len;) {
		struct vis_msg a, b;
		char why[128];
		CHECK(vis_msg_decode(o[0].bytes.data + at, o[0].bytes.len - at,
				     VIS_PROTOCOL_MAX_MESSAGE, 0, &a, why, sizeof why) ==
			      VIS_DECODE_OK &&
			      vis_msg_decode(o[1].bytes.data + at, o[1].bytes.len - at,
					     VIS_PROTOCOL_MAX_MESSAGE, 0, &b, why, sizeof why) ==
				      VIS_DECODE_OK,
		      "byte %zu: %s", at, why);
		CHECK(a.type == b.type && a.size == b.size, "byte %zu: version 3 got %s, 4 got %s",
		      at, a.type->name, b.type->name);
		if (a.type->opcode != VIS_OP_EXPOSURE) {
			CHECK(memcmp(o[0].bytes.data + at, o[1].bytes.data + at, a.size) == 0,
			      "byte %zu: the %s notices differ", at, a.type->name);
			at += a.size;
			continue;
		}
		uint32_t b4 = UINT32_MAX;
		for (uint32_t i = 0; i < N; i++)
			if (ids[i] == a.args[1].u)
				b4 = borders[i];
		CHECK(b4 != UINT32_MAX && a.args[1].u == b.args[1].u && a.args[2].u == b.args[2].u &&
			      a.args[3].u == b.args[3].u && a.args[4].a.n == b.args[4].a.n,
		      "byte %zu: the exposures differ beyond their rectangles", at);
		for (uint32_t r = 0; r < a.args[4].a.n; r++)
			for (uint32_t k = 0; k < 4; k++) {
				uint32_t v3 = vis_arg_word(&a.args[4], 'R', r, k);
				uint32_t v4 = vis_arg_word(&b.args[4], 'R', r, k);
				CHECK(v3 == (k < 2 ? v4 + b4 : v4),
				      "byte %zu, window %u (border %u), rectangle %u word %u: "
				      "version 3 got %d, 4 got %d",
				      at, a.args[1].u, b4, r, k, (int32_t)v3, (int32_t)v4);
			}
		shifted += a.args[4].a.n;
		at += a.size;
	}
	printf("mask %u: the streams agree, %zu rectangles shifted by their window's border\n",
	       mask, shifted);
	for (int i = 0; i < 2; i++) {
		harness_close(&o[i].c);
		vis_buf_finish(&o[i].bytes);
	}
	harness_close(&m);
	harness_stop(&d);
}

/* A socket listening at path, or one connected to it. */
static int unix_socket(const char *path, bool listening)
{
	struct sockaddr_un a = { .sun_family = AF_UNIX };
	CHECK(strlen(path) < sizeof a.sun_path, "%s: path too long", path);
	strcpy(a.sun_path, path);
	int fd = socket(AF_UNIX, SOCK_STREAM, 0);
	CHECK(fd >= 0, "socket: %s", strerror(errno));
	if (listening) {
		CHECK(bind(fd, (struct sockaddr *)&a, sizeof a) == 0 && listen(fd, 1) == 0,
		      "%s: %s", path, strerror(errno));
	} else {
		CHECK(connect(fd, (struct sockaddr *)&a, sizeof a) == 0, "%s: %s", path,
		      strerror(errno));
	}
	return fd;
}

/* Writes all of n bytes to fd (a file or a socket). */
static void put(int fd, const uint8_t *p, size_t n)
{
	while (n) {
		ssize_t k = write(fd, p, n);
		if (k < 0 && errno == EINTR)
			continue;
		CHECK(k > 0, "write: %s", strerror(errno));
		p += k;
		n -= (size_t)k;
	}
}

/*
 * Passes one connection on from listen_path to daemon_path, recording both ways; steps are
 * written as the client sends, each send preceded by what it had been sent since its last one.
 */
static int record(const char *listen_path, const char *daemon_path, const char *prefix)
{
	char path[512];
	int out[2];
	const char *ext[2] = { "client", "daemon" };
	for (int i = 0; i < 2; i++) {
		snprintf(path, sizeof path, "%s.%s", prefix, ext[i]);
		out[i] = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
		CHECK(out[i] >= 0, "%s: %s", path, strerror(errno));
	}
	snprintf(path, sizeof path, "%s.steps", prefix);
	FILE *steps = fopen(path, "w");
	CHECK(steps, "%s: %s", path, strerror(errno));

	int l = unix_socket(listen_path, true);
	int cl = accept(l, NULL, NULL);
	CHECK(cl >= 0, "accept: %s", strerror(errno));
	close(l);
	unlink(listen_path);
	int dm = unix_socket(daemon_path, false);
	size_t unseen = 0; /* the daemon's bytes passed on since the client last sent */
	bool client_open = true;
	uint8_t buf[65536];
	for (;;) {
		struct pollfd p[2] = { { cl, client_open ? POLLIN : 0, 0 }, { dm, POLLIN, 0 } };
		if (poll(p, 2, -1) < 0) {
			CHECK(errno == EINTR, "poll: %s", strerror(errno));
			continue;
		}
		if (p[1].revents) {
			ssize_t k = read(dm, buf, sizeof buf);
			if (k <= 0)
				break; /* the daemon closed the connection */
			put(out[1], buf, (size_t)k);
			if (client_open)
				(void)!write(cl, buf, (size_t)k); /* it may have gone */
			unseen += (size_t)k;
		}
		if (client_open && p[0].revents) {
			ssize_t k = read(cl, buf, sizeof buf);
			if (unseen)
				fprintf(steps, "recv %zu\n", unseen);
			unseen = 0;
			if (k <= 0) {
				fprintf(steps, "end\n");
				shutdown(dm, SHUT_WR);
				client_open = false;
				continue;
			}
			fprintf(steps, "send %zd\n", k);
			put(out[0], buf, (size_t)k);
			put(dm, buf, (size_t)k);
		}
	}
	if (unseen)
		fprintf(steps, "recv %zu\n", unseen);
	CHECK(!client_open, "the daemon closed the connection before the client");
	fclose(steps);
	close(out[0]);
	close(out[1]);
	close(cl);
	close(dm);
	return 0;
}

int main(int argc, char **argv)
{
	if (argc == 5 && strcmp(argv[1], "--record") == 0)
		return record(argv[2], argv[3], argv[4]);
	if (argc == 3 && strcmp(argv[2], "--side-by-side") == 0) {
		harness_context("side by side: coalescing");
		side_by_side(argv[1], VIS_NOTICE_VISIBILITY | VIS_NOTICE_EXPOSURE, 30);
		harness_context("side by side: overflow");
		side_by_side(argv[1], VIS_NOTICE_ALL, 30);
		printf("2 passed, 0 failed\n");
		return 0;
	}
	if (argc < 4) {
		fprintf(stderr, "usage: test-compat VISD DIR NAME...\n"
				"       test-compat VISD --side-by-side\n"
				"       test-compat --record LISTEN DAEMON PREFIX\n");
		return 2;
	}
	for (int i = 3; i < argc; i++) {
		struct harness_daemon d = { 0 };
		harness_start(&d, argv[1],
			      (const char *const[]){ "--id-key", ID_KEY, "--screen", SCREEN, NULL });
		replay(&d, argv[2], argv[i]);
		harness_stop(&d);
	}
	printf("%d passed, 0 failed\n", argc - 3);
	return 0;
}
