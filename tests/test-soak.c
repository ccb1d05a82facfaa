/*
 * The soak: one observer subscribed to everything that never reads, beside active clients that
 * each move their window and wait for the visibility notice it causes, over a 1,000-window stack.
 * The daemon's RSS is sampled as it runs and must level off; the active clients' latencies are
 * reported (p50, p99, max) and must stay bounded.
 *
 * usage: test-soak VISD [--changes N] [--clients N] [--max-pending BYTES]
 * Its length is a number of changes, not of seconds, so that a slow machine does the same work
 * (the stalled observer's queue filled early, then as many changes again). CI runs a short form
 * with a small bound, so that the stalled observer reaches it in the first few hundred changes.
 */
#undef NDEBUG
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "vis/protocol.h"

enum { BACKGROUND = 1000, MAX_CLIENTS = 50, MAX_SAMPLES = 4096 };

/*
 * How much the daemon's RSS may grow in the second half of the run over the first half's peak,
 * in KiB. Under ASan, freed memory waits in a quarantine (QUARANTINE_MB, below) before it is
 * reused, and what waits there counts in the RSS: when the daemon starts to free blocks of
 * another kind late in the run (a recompute through the tree among live ones, a realloc'd
 * array), the RSS rises by up to that much once, then levels off (over 200,000 changes it
 * stayed within 32-34 MiB, while a short run saw 29.4 MiB, then 32.3).
 */
#define QUARANTINE_MB 4
#if defined(__SANITIZE_ADDRESS__) /* GCC */
#define GROWTH_KIB (2048 + QUARANTINE_MB * 1024)
#elif defined(__has_feature) /* clang */
#if __has_feature(address_sanitizer)
#define GROWTH_KIB (2048 + QUARANTINE_MB * 1024)
#endif
#endif
#ifndef GROWTH_KIB
#define GROWTH_KIB 2048
#endif

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + t.tv_nsec / 1e9;
}

/* The daemon's resident set in KiB, from /proc. */
static long rss_kib(pid_t pid)
{
	char path[64], line[256];
	snprintf(path, sizeof path, "/proc/%d/status", (int)pid);
	FILE *f = fopen(path, "r");
	CHECK(f, "cannot read %s", path);
	long kib = -1;
	while (fgets(line, sizeof line, f))
		if (sscanf(line, "VmRSS: %ld", &kib) == 1)
			break;
	fclose(f);
	CHECK(kib > 0, "no VmRSS in %s", path);
	return kib;
}

static int by_value(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* An active client: its window, where it is, and when its last move went. */
struct active {
	struct harness_conn conn;
	uint32_t window, y;
	bool left;
	double sent;
};

static void send_move(struct active *a)
{
	a->left = !a->left;
	/* Half off the screen, or on it: the state flips between partially obscured and not. */
	harness_req(&a->conn, VIS_OP_MOVE, a->window, (uint32_t)(a->left ? -5 : 5), a->y);
	a->sent = now_s();
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: test-soak VISD [--changes N] [--clients N] "
				"[--max-pending BYTES]\n");
		return 2;
	}
	long changes = 20000;
	int clients = 8;
	const char *max_pending = "4194304";
	for (int i = 2; i + 1 < argc; i += 2) {
		if (strcmp(argv[i], "--changes") == 0)
			changes = atol(argv[i + 1]);
		else if (strcmp(argv[i], "--clients") == 0)
			clients = atoi(argv[i + 1]);
		else if (strcmp(argv[i], "--max-pending") == 0)
			max_pending = argv[i + 1];
	}
	CHECK(changes >= 40 && clients >= 1 && clients <= MAX_CLIENTS,
	      "want --changes 40 or more and --clients 1 to %d", MAX_CLIENTS);
	signal(SIGPIPE, SIG_IGN);
	/*
	 * Under ASan, freed memory waits in a quarantine of up to 256 MB, and the daemon's RSS grows
	 * into it as fast as the daemon frees memory: one that frees little per change takes longer
	 * than the soak to fill it, which would look like growth. With 4 MB, the RSS mostly levels
	 * off within the first samples (with 16 MB it still crept by 1–2.6 MB over what was CI's 4 s
	 * on a busy machine), and GROWTH_KIB allows for the rest. (Without ASan, nothing reads the
	 * variable.)
	 */
	const char *asan = getenv("ASAN_OPTIONS");
	char asan_options[1024];
	snprintf(asan_options, sizeof asan_options, "%s%squarantine_size_mb=%d", asan ? asan : "",
		 asan && *asan ? ":" : "", QUARANTINE_MB);
	setenv("ASAN_OPTIONS", asan_options, 1);
	struct harness_daemon d = { 0 };
	harness_start(&d, argv[1], (const char *[]){ "--max-pending", max_pending, NULL });

	harness_context("set-up");
	struct harness_conn m, stalled;
	harness_open(&m, d.sock);
	harness_hello(&m, VIS_ROLE_MANAGER);
	for (int i = 0; i < BACKGROUND; i++)
		harness_create(&m, 0, i * 37 % 3600, i * 53 % 2000, 240, 160, VIS_CREATE_MAP);
	harness_open(&stalled, d.sock);
	harness_hello(&stalled, VIS_ROLE_OBSERVER);
	harness_req(&stalled, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_ALL, 0);
	static struct active act[MAX_CLIENTS];
	for (int i = 0; i < clients; i++) {
		struct active *a = &act[i];
		harness_open(&a->conn, d.sock);
		harness_hello(&a->conn, VIS_ROLE_CLIENT);
		/* Apart from each other, so that every move changes the mover's state. */
		a->y = 40 * (uint32_t)i;
		a->window = harness_create(&a->conn, 0, 5, (int32_t)a->y, 400, 30, VIS_CREATE_MAP);
		harness_req(&a->conn, VIS_OP_SUBSCRIBE, a->window, VIS_NOTICE_VISIBILITY, 0);
		harness_sync(&a->conn, NULL);
	}

	harness_context("soak");
	size_t cap = 1 << 16, n = 0;
	double *lat = malloc(cap * sizeof *lat);
	long rss[MAX_SAMPLES];
	int samples = 0;
	CHECK(lat, "out of memory");
	for (int i = 0; i < clients; i++)
		send_move(&act[i]);
	double start = now_s();
	size_t next_sample = 0;
	/* A notice is awaited as long as the daemon works (progress.h). */
	struct progress work;
	bool waiting = false;
	while (n < (size_t)changes) {
		if (n >= next_sample && samples < MAX_SAMPLES) {
			rss[samples++] = rss_kib(d.pid);
			next_sample += (size_t)changes / 40;
		}
		struct pollfd p[MAX_CLIENTS];
		for (int i = 0; i < clients; i++)
			p[i] = (struct pollfd){ act[i].conn.fd, POLLIN, 0 };
		int ready = poll(p, (nfds_t)clients, 100);
		CHECK(ready >= 0, "poll");
		if (ready == 0) {
			if (!waiting)
				work = harness_working(&d);
			waiting = true;
			harness_still_working(&work, "no visibility notice");
			continue;
		}
		waiting = false;
		for (int i = 0; i < clients; i++) {
			struct active *a = &act[i];
			struct vis_msg msg;
			if (!(p[i].revents & POLLIN))
				continue;
			while (harness_recv(&a->conn, 0, &msg) > 0) {
				CHECK(msg.type->opcode == VIS_OP_VISIBILITY && msg.args[1].u == a->window,
				      "client %d: unexpected %s", i, msg.type->name);
				if (n == cap) {
					cap *= 2;
					lat = realloc(lat, cap * sizeof *lat);
					CHECK(lat, "out of memory");
				}
				lat[n++] = (now_s() - a->sent) * 1e6;
				send_move(a);
			}
		}
	}
	harness_check_alive(&d);
	qsort(lat, n, sizeof *lat, by_value);
	CHECK(n > 0, "no notice arrived");
	double elapsed = now_s() - start;
	printf("soak: %zu changes in %.1f s, %d active clients and one that never reads, %d background windows, "
	       "--max-pending %s\n",
	       n, elapsed, clients, BACKGROUND, max_pending);
	printf("  %.0f changes a second; latency move -> notice: p50 %.0f us, p99 %.0f us, "
	       "max %.0f us\n",
	       n / elapsed, lat[n / 2], lat[n * 99 / 100], lat[n - 1]);
	printf("  daemon RSS (KiB) over time:");
	for (int i = 0; i < samples; i += samples / 10 > 0 ? samples / 10 : 1)
		printf(" %ld", rss[i]);
	printf(" ... %ld\n", rss[samples - 1]);
	/* Levelled off: the second half grows no more than GROWTH_KIB beyond the first half's peak. */
	long first = 0, second = 0;
	for (int i = 0; i < samples; i++) {
		long *peak = i < samples / 2 ? &first : &second;
		if (rss[i] > *peak)
			*peak = rss[i];
	}
	CHECK(second <= first + GROWTH_KIB, "the daemon's RSS keeps growing: %ld KiB, then %ld KiB",
	      first, second);
	CHECK(lat[n * 99 / 100] < 1e6, "p99 latency %.0f us: the active clients starve", lat[n * 99 / 100]);
	free(lat);
	for (int i = 0; i < clients; i++)
		harness_close(&act[i].conn);
	harness_close(&stalled);
	harness_close(&m);
	harness_stop(&d);
	return 0;
}
