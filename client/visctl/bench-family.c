/*
 * visctl bench --family: engines timed on scenes drawn at random from the scene family
 * (src/family.h), each against the fastest engine on the same scene. Each engine runs in a child
 * process, so that one that runs away on a scene (the region method is cubic on some) is stopped
 * at a bound and counted as slower than it, instead of stopping the run.
 */
#include <errno.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "bench.h"
#include "family.h"
#include "visctl.h"

/* An engine stopped past this many times the fastest so far, and at least STOP_MIN_MS. */
#define STOP_RATIO 32
#define STOP_MIN_MS 2000

/* What a child reports: the fastest run's time and a hash of the states. */
struct timing {
	double ms;
	uint64_t hash;
	int err; /* errno of a failed run, else 0 */
};

static double now_s(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

/* In the child: the engine's fastest of at least 3 runs and of target_s spent, and the states. */
static struct timing run_engine(enum vis_engine engine, const struct vis_stack *stack,
				double target_s)
{
	struct timing t = { INFINITY, 0xcbf29ce484222325ull, 0 };
	uint8_t *states = malloc(stack->n ? stack->n : 1);
	if (!states) {
		t.err = ENOMEM;
		return t;
	}
	double spent = 0;
	for (unsigned reps = 0; reps < 3 || spent < target_s; reps++) {
		double t0 = now_s();
		if (vis_compute(engine, stack, states) < 0) {
			t.err = errno;
			break;
		}
		double d = now_s() - t0;
		spent += d;
		t.ms = d * 1e3 < t.ms ? d * 1e3 : t.ms;
	}
	for (size_t i = 0; i < stack->n; i++)
		t.hash = (t.hash ^ states[i]) * 0x100000001b3ull;
	free(states);
	return t;
}

/*
 * Times engine on stack in a child, stopped after stop_ms: 0 with *t, 1 when stopped, -1 when
 * the child could not be made or failed.
 */
static int time_in_child(enum vis_engine engine, const struct vis_stack *stack, double target_s,
			 double stop_ms, struct timing *t)
{
	int fds[2];
	if (pipe(fds) < 0)
		return -1;
	fflush(NULL);
	pid_t pid = fork();
	if (pid < 0) {
		close(fds[0]);
		close(fds[1]);
		return -1;
	}
	if (pid == 0) {
		close(fds[0]);
		struct timing r = run_engine(engine, stack, target_s);
		_exit(write(fds[1], &r, sizeof r) == (ssize_t)sizeof r ? 0 : 1);
	}
	close(fds[1]);
	struct pollfd p = { fds[0], POLLIN, 0 };
	double deadline = now_s() + stop_ms / 1e3;
	int rc = 1, ready = 0;
	for (double left; (left = deadline - now_s()) > 0;) {
		ready = poll(&p, 1, (int)(left * 1e3) + 1);
		if (ready != 0 && !(ready < 0 && errno == EINTR))
			break;
	}
	if (ready > 0)
		rc = read(fds[0], t, sizeof *t) == (ssize_t)sizeof *t && !t->err ? 0 : -1;
	if (rc == 1)
		kill(pid, SIGKILL);
	close(fds[0]);
	int status;
	while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
		;
	return rc;
}

static int by_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

/* A ratio with its bound marked: stopped engines count as slower than their stop. */
static void print_ratio(double r, bool stopped)
{
	printf(" | %s%.2f", stopped ? ">" : "", r);
}

int bench_family(const struct bench *b, uint64_t count, size_t min_n, size_t max_n, FILE *csv)
{
	size_t ne = b->nengines;
	/* The sweep first: O(n log n) on every scene, it bounds the others' stops. */
	enum vis_engine order[VIS_ENGINE_COUNT];
	size_t no = 0;
	for (size_t c = 0; c < ne; c++)
		if (b->engines[c] == VIS_ENGINE_GMV_HEAP)
			order[no++] = VIS_ENGINE_GMV_HEAP;
	for (size_t c = 0; c < ne; c++)
		if (b->engines[c] != VIS_ENGINE_GMV_HEAP)
			order[no++] = b->engines[c];
	double *ratio = calloc(count * ne, sizeof *ratio);
	bool *stopped = calloc(count * ne, sizeof *stopped);
	struct vis_family *members = calloc(count, sizeof *members);
	size_t *fastest = calloc(ne, sizeof *fastest);
	if (!ratio || !stopped || !members || !fastest) {
		fprintf(stderr, "visctl bench: out of memory\n");
		free(ratio), free(stopped), free(members), free(fastest);
		return -1;
	}
	if (csv) {
		fprintf(csv, "scene,params");
		for (size_t c = 0; c < no; c++)
			fprintf(csv, ",%s_ms", vis_engine_name(order[c]));
		fprintf(csv, "\n");
	}
	struct vis_rng draw = { b->seed };
	int ret = -1;
	char text[256];
	for (uint64_t s = 0; s < count; s++) {
		struct vis_family *f = &members[s];
		vis_family_draw(&draw, min_n, max_n, f);
		struct vis_scene scene;
		vis_scene_init(&scene);
		if (vis_family_gen(&scene, f, b->seed ^ (s * 0x9e3779b97f4a7c15ull)) < 0) {
			fprintf(stderr, "visctl bench: scene %llu: out of memory\n",
				(unsigned long long)s);
			vis_scene_finish(&scene);
			goto out;
		}
		struct vis_stack stack = vis_scene_stack(&scene);
		double ms[VIS_ENGINE_COUNT], best = INFINITY;
		bool stop[VIS_ENGINE_COUNT];
		uint64_t hash = 0;
		bool have_hash = false;
		for (size_t c = 0; c < no; c++) {
			double limit = isinf(best) ? 3600e3 : fmax(STOP_MIN_MS, STOP_RATIO * best);
			struct timing t;
			int rc = time_in_child(order[c], &stack, b->target_s, limit, &t);
			if (rc < 0) {
				vis_family_describe(f, text, sizeof text);
				fprintf(stderr, "visctl bench: %s failed on scene %llu (%s)\n",
					vis_engine_name(order[c]), (unsigned long long)s, text);
				vis_scene_finish(&scene);
				goto out;
			}
			stop[c] = rc == 1;
			ms[c] = stop[c] ? limit : t.ms;
			if (!stop[c]) {
				if (have_hash && t.hash != hash) {
					vis_family_describe(f, text, sizeof text);
					fprintf(stderr, "visctl bench: engines disagree on scene %llu (%s)\n",
						(unsigned long long)s, text);
					vis_scene_finish(&scene);
					goto out;
				}
				hash = t.hash;
				have_hash = true;
				best = fmin(best, t.ms);
			}
		}
		vis_scene_finish(&scene);
		size_t win = 0;
		for (size_t c = 0; c < no; c++) {
			ratio[s * ne + c] = ms[c] / best;
			stopped[s * ne + c] = stop[c];
			if (ms[c] < ms[win])
				win = c;
		}
		fastest[win]++;
		if (csv) {
			vis_family_describe(f, text, sizeof text);
			fprintf(csv, "%llu,\"%s\"", (unsigned long long)s, text);
			for (size_t c = 0; c < no; c++)
				fprintf(csv, ",%s%.4f", stop[c] ? ">" : "", ms[c]);
			fprintf(csv, "\n");
		}
		if ((s + 1) % 100 == 0)
			fprintf(stderr, "bench: %llu of %llu scenes\n", (unsigned long long)(s + 1),
				(unsigned long long)count);
	}
	printf("\nfamily: %llu scenes (seed %llu, n %zu to %zu): each engine's time / the fastest's "
	       "on the same scene (> : stopped at that bound)\n",
	       (unsigned long long)count, (unsigned long long)b->seed, min_n, max_n);
	printf("| engine | median | p95 | worst | fastest on |\n|---|---|---|---|---|\n");
	double *sorted = malloc(count * sizeof *sorted);
	if (!sorted) {
		fprintf(stderr, "visctl bench: out of memory\n");
		goto out;
	}
	size_t worst_of[VIS_ENGINE_COUNT];
	for (size_t c = 0; c < no; c++) {
		worst_of[c] = 0;
		for (uint64_t s = 0; s < count; s++) {
			sorted[s] = ratio[s * ne + c];
			if (ratio[s * ne + c] > ratio[worst_of[c] * ne + c])
				worst_of[c] = s;
		}
		qsort(sorted, count, sizeof *sorted, by_double);
		size_t w = worst_of[c];
		printf("| %s", vis_engine_name(order[c]));
		print_ratio(sorted[count / 2], false);
		print_ratio(sorted[(count * 95) / 100 < count ? (count * 95) / 100 : count - 1], false);
		print_ratio(ratio[w * ne + c], stopped[w * ne + c]);
		printf(" | %zu |\n", fastest[c]);
	}
	printf("\nworst scene of each engine:\n");
	for (size_t c = 0; c < no; c++) {
		vis_family_describe(&members[worst_of[c]], text, sizeof text);
		printf("  %s: scene %zu, %s%.2fx: %s\n", vis_engine_name(order[c]), worst_of[c],
		       stopped[worst_of[c] * ne + c] ? ">" : "", ratio[worst_of[c] * ne + c], text);
	}
	fflush(stdout);
	free(sorted);
	ret = 0;
out:
	free(ratio), free(stopped), free(members), free(fastest);
	return ret;
}
