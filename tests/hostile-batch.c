/*
 * Batches against the hostile suite's visd: one too large to hold, one whose replies would run
 * away with the daemon's memory, and one that holds a flood of queries, which must not stall the
 * other clients while its answers run.
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

/* A batch that would hold more than 16 MiB: a limit error that ends the connection. */
static void test_batch_limit(void)
{
	harness_context("a batch over its limit");
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	/* Each held create is charged its 48 bytes. */
	enum { HELD = 48 };
	uint32_t full = (16u << 20) / HELD;
	uint8_t req[48];
	harness_put(req, VIS_OP_CREATE, 0, 300, 200, 1, 1, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	harness_send_copies(&c, req, sizeof req, full + 1);
	harness_expect_error(&c, 2 + full + 1, VIS_OP_CREATE, VIS_ERROR_LIMIT,
			     "would take over 16777216 bytes", true);
	harness_close(&c);
	hostile_check_unaffected(); /* nothing held was run: no retained window is left */
}

/*
 * A batch of 2,000 get-tree requests, 32 KB of reply each: 64 MB in all, far past the bound on
 * what may wait for one connection. The held queries run after the batch's changes at the pace
 * the client reads, so while it does not read, others are served, and once it reads, every reply
 * comes, in order.
 */
static void test_batch_queries(void)
{
	harness_context("a batch of queries whose replies pass the bound");
	enum { WINDOWS = 1000, QUERIES = 2000 };
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_create_many(&c, WINDOWS, 300, 200);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	uint32_t first = c.seq + 1;
	uint8_t req[VIS_MSG_HEADER];
	harness_put(req, VIS_OP_GET_TREE);
	harness_send_copies(&c, req, sizeof req, QUERIES);
	harness_req(&c, VIS_OP_BATCH_COMMIT);
	uint32_t last = harness_req(&c, VIS_OP_SYNC);
	/* The client reads nothing yet: the others go on. */
	for (int i = 0; i < 20; i++)
		harness_sync(&hostile_innocent, NULL);
	struct vis_msg m;
	uint32_t trees = 0;
	int r;
	while ((r = harness_recv(&c, HARNESS_WORKING, &m)) > 0 &&
	       m.type->opcode == VIS_OP_TREE) {
		CHECK(m.args[0].u == first + trees && m.args[2].a.n == WINDOWS,
		      "tree reply %u answers request %u", trees, m.args[0].u);
		trees++;
	}
	CHECK(r > 0 && trees == QUERIES && m.type->opcode == VIS_OP_SYNCED && m.args[0].u == last,
	      "after %u of %u tree replies, %s", trees, QUERIES,
	      r > 0 ? m.type->name : "the connection ended");
	harness_close(&c);
	hostile_check_unaffected();
}

/*
 * Replies of a batch's changes are held until the replies before them have gone; past the bound
 * (pending output plus a batch's 16 MiB) the held request gets a limit error that ends the
 * connection, after every reply before it, in order.
 */
static void test_batch_reply_bound(void)
{
	harness_context("a batch whose changes' errors pass the bound");
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	uint32_t first = c.seq + 1;
	/* Each a window error of about 48 bytes: 20 MiB of them pass the bound. */
	enum { MOVES = 500000 };
	uint8_t req[VIS_MSG_HEADER + 12];
	harness_put(req, VIS_OP_MOVE, 999999, 0, 0);
	harness_send_copies(&c, req, sizeof req, MOVES);
	harness_req(&c, VIS_OP_BATCH_COMMIT);
	struct vis_msg m;
	uint32_t errors = 0;
	int r;
	while ((r = harness_recv(&c, HARNESS_WORKING, &m)) > 0 && m.type->opcode == VIS_OP_ERROR &&
	       m.args[2].u == VIS_ERROR_WINDOW) {
		CHECK(m.args[0].u == first + errors, "error %u answers request %u", errors,
		      m.args[0].u);
		errors++;
	}
	CHECK(r > 0 && m.type->opcode == VIS_OP_ERROR && m.args[0].u == first + errors &&
		      m.args[2].u == VIS_ERROR_LIMIT &&
		      memmem(m.args[3].s.p, m.args[3].s.len, "the batch's replies", 19),
	      "after %u window errors, no limit error for request %u", errors, first + errors);
	CHECK(errors > 100000 && errors < MOVES, "%u window errors before the limit", errors);
	CHECK(harness_recv(&c, HARNESS_WORKING, &m) == 0,
	      "the connection went on after the limit error");
	harness_close(&c);
	hostile_check_unaffected();
}

/*
 * The stall an adversary found: a client with no windows commits a batch of get-tree requests,
 * each walking 5,000 windows of another client. The batch's answers must take turns with the
 * others: an innocent client's round trip while they run stays a small part of their time
 * (measured against it, so that the check holds on any machine and under sanitizers).
 */
static void test_batch_stall(void)
{
	harness_context("a batch of queries that would stall the daemon");
	enum { WINDOWS = 5000, QUERIES = 40000 };
	struct harness_conn owner, c;
	harness_open_as(&owner, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_create_many(&owner, WINDOWS, 300, 200);
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	uint32_t first = c.seq + 1;
	uint8_t req[VIS_MSG_HEADER];
	harness_put(req, VIS_OP_GET_TREE);
	harness_send_copies(&c, req, sizeof req, QUERIES);
	double start = harness_clock_ms();
	harness_req(&c, VIS_OP_BATCH_COMMIT);
	uint32_t last = harness_req(&c, VIS_OP_SYNC);
	uint32_t trees = 0, syncs = 0;
	double worst = 0;
	for (bool done = false; !done;) {
		double t0 = harness_clock_ms();
		harness_sync(&hostile_innocent, NULL);
		double t = harness_clock_ms() - t0;
		worst = t > worst ? t : worst;
		syncs++;
		struct vis_msg m;
		while (!done && harness_recv(&c, 0, &m) > 0) {
			if (m.type->opcode == VIS_OP_SYNCED) {
				CHECK(m.args[0].u == last && trees == QUERIES,
				      "synced %u after %u of %u tree replies", m.args[0].u, trees,
				      QUERIES);
				done = true;
			} else {
				CHECK(m.type->opcode == VIS_OP_TREE && m.args[0].u == first + trees &&
					      m.args[2].a.n == 0,
				      "tree reply %u: %s for request %u", trees, m.type->name,
				      m.args[0].u);
				trees++;
			}
		}
	}
	double total = harness_clock_ms() - start;
	printf("hostile: a batch of %d get-tree over %d windows ran for %.0f ms; the innocent's "
	       "worst round trip meanwhile: %.1f ms (%u round trips)\n",
	       QUERIES, WINDOWS, total, worst, syncs);
	CHECK(worst < total / 4, "the innocent waited %.1f ms of the batch's %.0f ms", worst, total);
	harness_close(&c);
	harness_close(&owner);
	hostile_check_unaffected();
}

/*
 * A client that sends requests and never reads: once its replies fill the bound, the daemon stops
 * reading it and must sit idle, not spin on its unread input (it did: 100% of a core).
 */
static void test_flood_unread(void)
{
	harness_context("a client that sends requests and never reads");
	enum { WINDOWS = 1000 };
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_create_many(&c, WINDOWS, 300, 200);
	/* 32 KB a reply: the bound fills after about 130; the rest wait unread, and the socket. */
	uint8_t req[VIS_MSG_HEADER * 1024];
	for (int i = 0; i < 1024; i++)
		harness_put(req + VIS_MSG_HEADER * i, VIS_OP_GET_TREE);
	size_t sent = 0;
	for (int idle = 0; idle < 20;) {
		ssize_t k = send(c.fd, req, sizeof req, MSG_DONTWAIT | MSG_NOSIGNAL);
		if (k > 0)
			sent += (size_t)k;
		else if (errno == EAGAIN)
			idle++, usleep(10000);
		else
			CHECK(0, "send: %s", strerror(errno));
	}
	/* It may still be answering what it read (slow under a sanitizer on a busy machine): it
	 * must come to rest, a second with under 200 ms of CPU time, before the stall interval. */
	double cpu = 0;
	for (double start = harness_clock_ms();;) {
		double before = progress_cpu_ms(&hostile_visd.pid, 1);
		usleep(1000000);
		cpu = progress_cpu_ms(&hostile_visd.pid, 1) - before;
		harness_check_alive(&hostile_visd);
		if (cpu < 200)
			break;
		CHECK(harness_clock_ms() - start < PROGRESS_STALL_MS,
		      "the daemon used %.0f ms of CPU a second for %d s while a client did not read",
		      cpu, PROGRESS_STALL_MS / 1000);
	}
	printf("hostile: %zu bytes of get-tree unread; the daemon then used %.0f ms of CPU in 1 s\n",
	       sent, cpu);
	harness_sync(&hostile_innocent, NULL);
	harness_close(&c);
	hostile_check_unaffected();
}

void hostile_batch(void)
{
	test_batch_limit();
	test_batch_queries();
	test_batch_reply_bound();
	test_batch_stall();
	test_flood_unread();
}
