/*
 * Not a test: how long other clients wait while one client makes the daemon work, and how long
 * the attack itself takes. Meanwhile a prober makes sync round trips; each attack prints the
 * prober's round-trip percentiles from the attack's first byte to its last reply.
 *
 * Queries: a client owns W unmapped windows; an attacker with no windows sends hello, then N
 * get-tree requests (each walks every window and answers an empty list) and a sync, inside one
 * batch or bare, and reads everything back.
 * Looks: an attacker makes L mapped windows, each with a shape and an opaque region of R/2
 * rectangles apiece (a grid of small squares; with --strips, 1-pixel strips, the shape's across
 * and the opaque region's down, whose crossings cut the window into about R²/2 pieces),
 * overlapping one another, then moves them M times, in batches of B moves.
 * Windows: an attacker makes W mapped windows over the screen and moves them, in batches.
 * Shaped parent: an attacker makes one window whose shape is R squares and W children under it,
 * which its shape clips, and moves the children, in batches.
 * Deep: an attacker makes a chain of windows 64 deep and W windows spread over its levels, and
 * moves them, in batches.
 * With --shaped-backdrop 1, the prober keeps a shaped window of the screen's size under them;
 * with --exposures 1, the attacker subscribes to its windows' states and exposures.
 *
 * With --fail-over MS it is the stall test too: it fails when a round trip took longer.
 *
 * usage: bench-stall VISD [--windows W] [--queries N] [--look-windows L] [--look-rects R]
 *                         [--moves M] [--batch B] [--attack A[,A…]] [--strips 0|1]
 *                         [--shaped-backdrop 0|1] [--exposures 0|1] [--fail-over MS]
 *        (defaults 5,000, 1,000,000, 40, 3,000, 704, 64, queries,looks; the attacks: queries,
 *        looks, windows, shaped-parent, deep)
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "harness.h"
#include "vis/protocol.h"

/* With --fail-over: the longest round trip allowed, in ms (0: any); past it, the run fails. */
static double fail_over;

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* The prober's round trips until the attacker's reply to request last; prints a table row. */
static void probe(struct harness_conn *prober, struct harness_conn *attacker, uint32_t last,
		  pid_t writer, double start, const char *row)
{
	size_t n = 0, cap = 1024;
	double *rtt = malloc(cap * sizeof *rtt);
	CHECK(rtt, "out of memory");
	for (bool done = false; !done;) {
		double t0 = harness_clock_ms();
		harness_sync(prober, NULL);
		if (n == cap) {
			rtt = realloc(rtt, (cap *= 2) * sizeof *rtt);
			CHECK(rtt, "out of memory");
		}
		rtt[n++] = harness_clock_ms() - t0;
		struct vis_msg m;
		while (!done && harness_recv(attacker, 0, &m) > 0) {
			CHECK(m.type->opcode != VIS_OP_ERROR, "the attack got an error: %.*s",
			      (int)m.args[3].s.len, m.args[3].s.p);
			done = m.type->opcode == VIS_OP_SYNCED && m.args[0].u == last;
		}
	}
	double total = harness_clock_ms() - start;
	int status;
	CHECK(waitpid(writer, &status, 0) == writer && WIFEXITED(status) && !WEXITSTATUS(status),
	      "the writer failed");
	qsort(rtt, n, sizeof *rtt, by_value);
	printf("| %s | %.0f | %zu | %.2f | %.2f | %.2f |\n", row, total, n, rtt[n / 2],
	       rtt[n * 99 / 100], rtt[n - 1]);
	fflush(stdout);
	CHECK(!fail_over || rtt[n - 1] <= fail_over,
	      "another client's sync waited %.0f ms, over the %.0f ms allowed", rtt[n - 1], fail_over);
	free(rtt);
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
	char row[100];
	snprintf(row, sizeof row, "%s %u get-tree over %u windows", batch ? "batch of" : "bare",
		 queries, windows);
	probe(&prober, &attacker, last, writer, start, row);
	harness_close(&attacker);
	harness_close(&prober);
}

/* With --shaped-backdrop 1: the prober keeps a shaped window under the attacker's. */
static bool shaped_backdrop;

/* With --exposures 1: the attacker subscribes to its windows' states and exposures. */
static bool exposures;

/* How a look's rectangles lie: squares in a grid, or strips across the window, horizontal for a
 * shape and vertical for an opaque region, so that their n × n crossings are as many pieces. */
static bool strips;

/* Sends a set-shape (opcode VIS_OP_SET_SHAPE) or set-opaque request of n rectangles: a grid of
 * side x side squares at a pitch of 2 * side + 1, starting at offset, 50 to a row; or strips. */
static void send_look(struct harness_conn *c, uint32_t opcode, uint32_t window, uint32_t n,
		      int32_t side, int32_t offset)
{
	uint32_t *rects = malloc(4 * (size_t)n * sizeof *rects);
	CHECK(rects, "out of memory");
	for (uint32_t k = 0; k < n; k++) {
		uint32_t *r = rects + 4 * k;
		r[0] = (uint32_t)(offset + (int32_t)(k % 50) * (2 * side + 1));
		r[1] = (uint32_t)(offset + (int32_t)(k / 50) * (2 * side + 1));
		r[2] = r[3] = (uint32_t)side;
		if (strips) {
			bool across = opcode == VIS_OP_SET_SHAPE;
			r[0] = across ? 0 : 2 * k;
			r[1] = across ? 2 * k : 0;
			r[2] = across ? 4096 : 1;
			r[3] = across ? 1 : 4096;
		}
	}
	/* shaped; opaque mode "the rects" */
	harness_look(c, opcode, window, opcode == VIS_OP_SET_SHAPE ? 1 : 2, rects, n);
	free(rects);
}

/* Creates n mapped windows of w × h under parent, spread over a width × height area, pipelined;
 * their IDs go to ids. */
static void create_spread(struct harness_conn *c, uint32_t parent, uint32_t n, uint32_t w,
			  uint32_t h, uint32_t width, uint32_t height, uint32_t *ids)
{
	enum { PER = 4096 };
	for (uint32_t done = 0; done < n;) {
		uint32_t k = n - done < PER ? n - done : PER;
		for (uint32_t i = done; i < done + k; i++)
			harness_req(c, VIS_OP_CREATE, parent, 7919 * i % (width - w),
				    104729 * i % (height - h), w, h, VIS_CREATE_MAP, 0, 0, 0, 0);
		for (uint32_t i = done; i < done + k; i++) {
			struct vis_msg m;
			harness_next_reply(c, &m, NULL);
			CHECK(m.type->opcode == VIS_OP_CREATED, "create %u: %s", i + 1, m.type->name);
			ids[i] = m.args[1].u;
		}
		done += k;
	}
}

/* Reads the replies up to a sync, counting the limit errors among them (looks refused). */
static uint32_t count_refused(struct harness_conn *c)
{
	uint32_t synced = harness_req(c, VIS_OP_SYNC), refused = 0;
	for (struct vis_msg m;;) {
		harness_next_reply(c, &m, NULL);
		if (m.type->opcode == VIS_OP_SYNCED && m.args[0].u == synced)
			return refused;
		CHECK(m.type->opcode == VIS_OP_ERROR && m.args[2].u == VIS_ERROR_LIMIT,
		      "the set-up got %s", m.type->name);
		refused++;
	}
}

/* The attacks that make the daemon recompute: what the attacker's windows are. */
enum scene { LOOKS, WINDOWS, SHAPED_PARENT, DEEP };

/*
 * A recompute attack: the attacker builds its scene (untimed), then moves its windows ids[0 …
 * n) moves times, in batches of batch, while the prober makes round trips; prints a table row.
 * LOOKS: n windows of 600 × 600 with looks of rects rectangles each, overlapping. WINDOWS: n
 * windows of 40 × 30 over the screen. SHAPED_PARENT: n windows of 20 × 20 under one of 1,600 ×
 * 1,000 whose shape is rects squares, which clips them all.
 */
static void run_moves(struct harness_daemon *d, enum scene scene, uint32_t n, uint32_t rects,
		      uint32_t moves, uint32_t batch)
{
	struct harness_conn attacker, prober;
	harness_open_as(&prober, d->sock, VIS_ROLE_CLIENT);
	harness_open_as(&attacker, d->sock, VIS_ROLE_CLIENT);
	if (shaped_backdrop) {
		/* The prober's window under everything, shaped: one square less than the screen. */
		uint32_t b = harness_create(&prober, 0, 0, 0, 3840, 2160, VIS_CREATE_MAP);
		send_look(&prober, VIS_OP_SET_SHAPE, b, 1, 3000, 0);
		harness_sync(&prober, NULL);
	}
	uint32_t *ids = malloc(n * sizeof *ids), refused = 0, parent = 0;
	CHECK(ids, "out of memory");
	char row[120];
	int32_t span_x = 3000, span_y = 1500;
	switch (scene) {
	case LOOKS:
		for (uint32_t i = 0; i < n; i++)
			ids[i] = harness_create(&attacker, 0, (int32_t)(37 * i % 1600),
						(int32_t)(23 * i % 900), 600, 600, VIS_CREATE_MAP);
		for (uint32_t i = 0; i < n; i++) {
			send_look(&attacker, VIS_OP_SET_SHAPE, ids[i], rects / 2, 4, 0);
			send_look(&attacker, VIS_OP_SET_OPAQUE, ids[i], rects - rects / 2, 2, 1);
		}
		refused = count_refused(&attacker);
		snprintf(row, sizeof row, "%u windows of %u look %s (%u looks refused)", n, n * rects,
			 strips ? "strips" : "squares", refused);
		break;
	case WINDOWS:
		create_spread(&attacker, 0, n, 40, 30, 3840, 2160, ids);
		snprintf(row, sizeof row, "%u windows", n);
		break;
	case SHAPED_PARENT:
		parent = harness_create(&attacker, 0, 100, 100, 1600, 1000, VIS_CREATE_MAP);
		send_look(&attacker, VIS_OP_SET_SHAPE, parent, rects, 4, 0);
		refused = count_refused(&attacker);
		create_spread(&attacker, parent, n, 20, 20, 1600, 1000, ids);
		span_x = 1580;
		span_y = 980;
		snprintf(row, sizeof row, "%u windows under one shaped with %u squares%s", n, rects,
			 refused ? " (refused)" : "");
		break;
	case DEEP: {
		/* A chain as deep as the daemon allows (64), each a pixel inside the last, the n
		 * windows spread over its levels. */
		uint32_t chain[63], depth = 63;
		chain[0] = harness_create(&attacker, 0, 100, 100, 1700, 1100, VIS_CREATE_MAP);
		for (uint32_t k = 1; k < depth; k++)
			chain[k] = harness_create(&attacker, chain[k - 1], 1, 1, 1700 - 2 * k,
						  1100 - 2 * k, VIS_CREATE_MAP);
		for (uint32_t done = 0, k = 0; k < depth; k++) {
			uint32_t some = n / depth + (k < n % depth);
			if (some)
				create_spread(&attacker, chain[k], some, 20, 20, 1500, 900, ids + done);
			done += some;
		}
		span_x = 1480;
		span_y = 880;
		snprintf(row, sizeof row, "%u windows over the levels of a chain 64 deep", n);
		break;
	}
	}
	if (exposures) {
		harness_req(&attacker, VIS_OP_SUBSCRIBE, 0,
			    VIS_NOTICE_VISIBILITY | VIS_NOTICE_EXPOSURE, 0);
		harness_sync(&attacker, NULL);
		strcat(row, ", exposures tracked");
	}
	size_t len = strlen(row);
	snprintf(row + len, sizeof row - len, ", %u moves in batches of %u", moves, batch);
	double start = harness_clock_ms();
	pid_t writer = fork();
	CHECK(writer >= 0, "fork: %s", strerror(errno));
	if (writer == 0) {
		for (uint32_t i = 0; i < moves; i++) {
			if (i % batch == 0)
				harness_req(&attacker, VIS_OP_BATCH_BEGIN);
			harness_req(&attacker, VIS_OP_MOVE, ids[i % n], (uint32_t)(97 * i % span_x),
				    (uint32_t)(61 * i % span_y));
			if (i % batch == batch - 1 || i + 1 == moves)
				harness_req(&attacker, VIS_OP_BATCH_COMMIT);
		}
		harness_req(&attacker, VIS_OP_SYNC);
		_exit(0);
	}
	uint32_t last = attacker.seq + moves + 2 * ((moves + batch - 1) / batch) + 1;
	probe(&prober, &attacker, last, writer, start, row);
	free(ids);
	harness_close(&attacker);
	harness_close(&prober);
}

int main(int argc, char **argv)
{
	uint32_t windows = 5000, queries = 1000000, look_windows = 40, look_rects = 3000;
	uint32_t moves = 704, batch = 64;
	const char *attack = "queries,looks";
	if (argc < 2 || argc % 2) {
		fprintf(stderr, "usage: bench-stall VISD [--windows W] [--queries N] "
				"[--look-windows L] [--look-rects R] [--moves M] [--batch B] "
				"[--attack A[,A…]] [--strips 0|1] [--shaped-backdrop 0|1]\n"
				"                   [--exposures 0|1] [--fail-over MS]\n"
				"  attacks: queries looks windows shaped-parent deep\n");
		return 2;
	}
	for (int i = 2; i + 1 < argc; i += 2) {
		unsigned long v = strtoul(argv[i + 1], NULL, 10);
		if (!strcmp(argv[i], "--windows") && v >= 1 && v <= 262144)
			windows = (uint32_t)v;
		else if (!strcmp(argv[i], "--queries") && v >= 1 && v <= 2000000)
			queries = (uint32_t)v;
		else if (!strcmp(argv[i], "--look-windows") && v >= 1 && v <= 4096)
			look_windows = (uint32_t)v;
		else if (!strcmp(argv[i], "--look-rects") && v >= 2 && v <= 8000)
			look_rects = (uint32_t)v;
		else if (!strcmp(argv[i], "--moves") && v >= 1 && v <= 1000000)
			moves = (uint32_t)v;
		else if (!strcmp(argv[i], "--batch") && v >= 1 && v <= 65536)
			batch = (uint32_t)v;
		else if (!strcmp(argv[i], "--fail-over") && v >= 1 && v <= 3600000)
			fail_over = (double)v;
		else if (!strcmp(argv[i], "--exposures") && v <= 1)
			exposures = v;
		else if (!strcmp(argv[i], "--shaped-backdrop") && v <= 1)
			shaped_backdrop = v;
		else if (!strcmp(argv[i], "--strips") && v <= 1)
			strips = v;
		else if (!strcmp(argv[i], "--attack"))
			attack = argv[i + 1];
		else {
			fprintf(stderr, "bench-stall: bad option %s %s\n", argv[i], argv[i + 1]);
			return 2;
		}
	}
	static const char *const names[] = { "queries", "looks", "windows", "shaped-parent",
					     "deep" };
	bool wanted[5] = { false };
	for (const char *a = attack; *a;) {
		size_t len = strcspn(a, ","), k = 0;
		while (k < 5 && (strlen(names[k]) != len || strncmp(a, names[k], len)))
			k++;
		if (k == 5) {
			fprintf(stderr, "bench-stall: unknown attack '%.*s'\n", (int)len, a);
			return 2;
		}
		wanted[k] = true;
		a += len + (a[len] == ',');
	}
	struct harness_daemon d = { 0 };
	harness_start(&d, argv[1], NULL);
	printf("another client's sync round trip (ms) while a client makes the daemon work\n\n");
	printf("| attack | attack ms | round trips | p50 | p99 | max |\n");
	printf("|---|---|---|---|---|---|\n");
	if (wanted[0]) {
		struct harness_conn owner;
		harness_open_as(&owner, d.sock, VIS_ROLE_CLIENT);
		harness_create_many(&owner, windows, 0, 0);
		run(&d, windows, queries, true);
		run(&d, windows, queries, false);
		harness_close(&owner);
	}
	if (wanted[1])
		run_moves(&d, LOOKS, look_windows, look_rects, moves, batch);
	if (wanted[2])
		run_moves(&d, WINDOWS, windows, 0, moves, batch);
	if (wanted[3])
		run_moves(&d, SHAPED_PARENT, windows, look_rects, moves, batch);
	if (wanted[4])
		run_moves(&d, DEEP, windows, 0, moves, batch);
	harness_stop(&d);
	return 0;
}
