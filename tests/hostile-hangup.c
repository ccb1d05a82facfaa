/*
 * Clients that hang up with requests in flight: every complete request received before the
 * hang-up runs, in order, as if the connection had stayed; after a half-close every reply is
 * delivered before the connection ends; a partial request, or a batch left open, is dropped and
 * logged.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "hostile.h"
#include "vis/protocol.h"
#include "wire.h"

/* Top-level windows whose owner is gone (retained leftovers), as the manager sees them. */
static size_t count_orphans(void)
{
	struct harness_conn mgr;
	harness_open_as(&mgr, hostile_visd.sock, VIS_ROLE_MANAGER);
	size_t n, orphans = 0;
	struct harness_node *t = harness_get_tree(&mgr, &n);
	for (size_t i = 0; i < n; i++) {
		bool innocent = false;
		for (size_t k = 0; k < HOSTILE_WINDOWS; k++)
			innocent |= t[i].window == hostile_win[k];
		orphans += !innocent && (t[i].flags & VIS_WINDOW_RETAINED);
	}
	free(t);
	harness_close(&mgr);
	return orphans;
}

/* Whether the daemon's log holds text. */
static bool logged(const char *text)
{
	static char log[1 << 20];
	FILE *f = fopen(hostile_visd.log, "r");
	CHECK(f, "cannot read %s", hostile_visd.log);
	log[fread(log, 1, sizeof log - 1, f)] = 0;
	fclose(f);
	return strstr(log, text);
}

/* hello and n retained creates, as one run of bytes (malloc'd; *len bytes). */
static uint8_t *hello_and_creates(uint32_t n, size_t *len)
{
	uint8_t *b = malloc(VIS_MSG_HEADER + 12 + (size_t)n * 48 + 64);
	CHECK(b, "out of memory");
	size_t at = harness_put(b, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION,
				VIS_ROLE_CLIENT);
	for (uint32_t i = 0; i < n; i++)
		at += harness_put(b + at, VIS_OP_CREATE, 0, 300 + (int32_t)(i % 50), 200, 5, 5,
				  VIS_CREATE_RETAIN, 0, 0, 0, 0);
	*len = at;
	return b;
}

/* Waits until the manager sees want retained leftovers (the daemon runs them after the close). */
static void expect_orphans(size_t want, const char *what)
{
	size_t have = 0;
	char why[200];
	for (struct progress p = harness_working(&hostile_visd); (have = count_orphans()) < want;) {
		snprintf(why, sizeof why, "%s: %zu retained windows exist, not %zu", what, have,
			 want);
		harness_still_working(&p, why);
	}
	CHECK(have == want, "%s: %zu retained windows exist, not %zu", what, have, want);
	hostile_destroy_leftovers();
	hostile_check_unaffected();
}

/* hello, 200 retained creates, close() at once without reading a byte: all 200 exist. */
static void test_close_after_creates(void)
{
	harness_context("close() right after 200 retained creates");
	size_t len;
	uint8_t *b = hello_and_creates(200, &len);
	for (int run = 0; run < 5; run++) {
		struct harness_conn c;
		harness_open(&c, hostile_visd.sock);
		CHECK(harness_send(&c, b, len) == 0, "send: %s", strerror(errno));
		harness_close(&c);
		expect_orphans(200, "after close()");
	}
	free(b);
}

/*
 * shutdown(SHUT_WR) after the requests: every reply comes, in order, then the end of the
 * connection; the windows exist.
 */
static void test_half_close(void)
{
	harness_context("shutdown(SHUT_WR) after 200 retained creates and 64 syncs");
	size_t len;
	uint8_t *b = hello_and_creates(200, &len);
	b = realloc(b, len + 64 * VIS_MSG_HEADER);
	CHECK(b, "out of memory");
	for (int i = 0; i < 64; i++)
		len += harness_put(b + len, VIS_OP_SYNC);
	for (int run = 0; run < 3; run++) {
		struct harness_conn c;
		harness_open(&c, hostile_visd.sock);
		CHECK(harness_send(&c, b, len) == 0 && shutdown(c.fd, SHUT_WR) == 0, "send: %s",
		      strerror(errno));
		struct vis_msg m;
		uint32_t seq = 1;
		CHECK(harness_recv(&c, HARNESS_WORKING, &m) > 0 &&
			      m.type->opcode == VIS_OP_HELLO_REPLY,
		      "no hello-reply");
		while (seq < 1 + 200 + 64) {
			int r = harness_recv(&c, HARNESS_WORKING, &m);
			CHECK(r > 0, "the connection ended after %u replies of %d", seq, 1 + 200 + 64);
			if (m.type->dir == VIS_DIR_NOTICE)
				continue;
			seq++;
			CHECK(m.args[0].u == seq &&
				      m.type->opcode == (seq <= 201 ? VIS_OP_CREATED : VIS_OP_SYNCED),
			      "reply %s answers request %u, not %u", m.type->name, m.args[0].u, seq);
		}
		CHECK(harness_recv(&c, HARNESS_WORKING, &m) == 0,
		      "the connection went on after its requests");
		harness_close(&c);
		expect_orphans(200, "after a half-close");
	}
	free(b);
}

/*
 * What cannot run at a hang-up: a partial request, a batch never committed. A committed batch's
 * changes run, and its queries cost nothing once nobody can read them.
 */
static void test_hangup_leftovers(void)
{
	harness_context("a hang-up with a partial request and an open batch");
	uint8_t b[4096];
	size_t n = harness_put(b, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION,
			       VIS_ROLE_CLIENT);
	n += harness_put(b + n, VIS_OP_BATCH_BEGIN);
	for (int i = 0; i < 10; i++)
		n += harness_put(b + n, VIS_OP_CREATE, 0, 300, 200, 5, 5, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	for (int i = 0; i < 50; i++)
		n += harness_put(b + n, VIS_OP_GET_TREE);
	n += harness_put(b + n, VIS_OP_BATCH_COMMIT);
	n += harness_put(b + n, VIS_OP_CREATE, 0, 300, 200, 5, 5, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	n += harness_put(b + n, VIS_OP_BATCH_BEGIN);
	n += harness_put(b + n, VIS_OP_CREATE, 0, 300, 200, 5, 5, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	size_t cut = n + harness_put(b + n, VIS_OP_CREATE, 0, 300, 200, 5, 5, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	n = cut - 7; /* the last create, cut short */
	struct harness_conn c;
	harness_open(&c, hostile_visd.sock);
	CHECK(harness_send(&c, b, n) == 0, "send: %s", strerror(errno));
	harness_close(&c);
	expect_orphans(11, "the committed batch and the create after it");
	CHECK(logged("hung up in the middle of a request: 41 bytes dropped") &&
		      logged("hung up inside a batch: 52 bytes of held requests dropped"),
	      "the dropped requests were not logged");
}

void hostile_hangup(void)
{
	test_close_after_creates();
	test_half_close();
	test_hangup_leftovers();
}
