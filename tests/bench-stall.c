/*
 * Not a test: how long other clients wait while one client floods the daemon with queries, in a
 * batch or not. A client owns W unmapped windows; an attacker with no windows sends hello, then
 * N get-tree requests (each walks every window and answers an empty list) and a sync, inside one
 * batch or bare, and reads everything back; meanwhile a prober makes sync round trips. Prints the
 * prober's round-trip percentiles from the attack's first byte to its last reply, and how long
 * that took.
 *
 * usage: bench-stall VISD [--windows W] [--queries N]   (defaults 5,000 and 1,000,000)
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "vis/protocol.h"

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* One run: the attack, batched or not, with the prober's round trips; prints a table row. */
static void run(struct harness_daemon *d, uint32_t windows, uint32_t queries, bool batch)
{
	struct harness_conn attacker, prober;
	harness_open_as(&prober, d->sock, VIS_ROLE_CLIENT);
	harness_open_as(&attacker, d->sock, VIS_ROLE_CLIENT);
	uint8_t get_tree[VIS_MSG_HEADER];
	harness_put(get_tree, VIS_OP_GET_TREE);
	/* A child writes the attack while this process reads it back: a client that sent without
	 * reading would only stop itself once its replies fill the daemon's bound. */
	double start = harness_clock_ms();
	pid_t writer = fork();
	CHECK(writer >= 0, "fork: %s", strerror(errno));
	if (writer == 0) {
		if (batch)
			harness_req(&attacker, VIS_OP_BATCH_BEGIN);
		harness_send_copies(&attacker, get_tree, sizeof get_tree, queries);
		if (batch)
			harness_req(&attacker, VIS_OP_BATCH_COMMIT);
		harness_req(&attacker, VIS_OP_SYNC);
		_exit(0);
	}
	uint32_t last = attacker.seq + (batch ? 2 : 0) + queries + 1;
	size_t n = 0, cap = 1024;
	double *rtt = malloc(cap * sizeof *rtt);
	CHECK(rtt, "out of memory");
	for (bool done = false; !done;) {
		double t0 = harness_clock_ms();
		harness_sync(&prober, NULL);
		if (n == cap) {
			rtt = realloc(rtt, (cap *= 2) * sizeof *rtt);
			CHECK(rtt, "out of memory");
		}
		rtt[n++] = harness_clock_ms() - t0;
		struct vis_msg m;
		while (!done && harness_recv(&attacker, 0, &m) > 0)
			done = m.type->opcode == VIS_OP_SYNCED && m.args[0].u == last;
	}
	double total = harness_clock_ms() - start;
	int status;
	CHECK(waitpid(writer, &status, 0) == writer && WIFEXITED(status) && !WEXITSTATUS(status),
	      "the writer failed");
	qsort(rtt, n, sizeof *rtt, by_value);
	printf("| %s | %u | %u | %.0f | %zu | %.2f | %.2f | %.2f |\n", batch ? "batch" : "bare",
	       windows, queries, total, n, rtt[n / 2], rtt[n * 99 / 100], rtt[n - 1]);
	fflush(stdout);
	free(rtt);
	harness_close(&attacker);
	harness_close(&prober);
}

int main(int argc, char **argv)
{
	uint32_t windows = 5000, queries = 1000000;
	if (argc < 2 || argc % 2) {
		fprintf(stderr, "usage: bench-stall VISD [--windows W] [--queries N]\n");
		return 2;
	}
	for (int i = 2; i + 1 < argc; i += 2) {
		unsigned long v = strtoul(argv[i + 1], NULL, 10);
		if (!strcmp(argv[i], "--windows") && v >= 1 && v <= 262144)
			windows = (uint32_t)v;
		else if (!strcmp(argv[i], "--queries") && v >= 1 && v <= 2000000)
			queries = (uint32_t)v;
		else {
			fprintf(stderr, "bench-stall: bad option %s %s\n", argv[i], argv[i + 1]);
			return 2;
		}
	}
	struct harness_daemon d = { 0 };
	harness_start(&d, argv[1], NULL);
	struct harness_conn owner;
	harness_open_as(&owner, d.sock, VIS_ROLE_CLIENT);
	harness_create_many(&owner, windows, 0, 0);
	printf("another client's sync round trip (ms) while a client sends get-tree requests over "
	       "%u windows of a third\n\n",
	       windows);
	printf("| attack | windows | get-tree | attack ms | round trips | p50 | p99 | max |\n");
	printf("|---|---|---|---|---|---|---|---|\n");
	run(&d, windows, queries, true);
	run(&d, windows, queries, false);
	harness_close(&owner);
	harness_stop(&d);
	return 0;
}
