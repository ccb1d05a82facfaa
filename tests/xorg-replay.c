/*
 * xorg-replay: the operations of a `visctl stress --record` script replayed on an X server, and
 * measured as visctl stress measures visd, so that the two can be set side by side
 * (tools/xorg-bench.sh does it).
 *
 * The record's windows become override-redirect, border-0, InputOutput top-level windows, made
 * in its order (each new one on top) on a server of its own without a window manager; S extra
 * connections, the subscribers, each select VisibilityChangeMask on every window; then the
 * windows are mapped. Each operation is one request: ConfigureWindow for a move, a resize, a
 * raise (Above), a lower (Below) and a restack (sibling and Above or Below), MapWindow or
 * UnmapWindow; batches, borders, shapes and opaque regions are refused. One at a time, each is
 * timed from its start to the arrival of the last VisibilityNotify it causes at any subscriber,
 * confirmed by a round trip on the manager's connection and then one on every subscriber's
 * (xorg-replay-x.c says why that is exact); an operation that causes none counts until the
 * manager's reply, as in visctl stress. The server's CPU time over the operations comes from
 * /proc/PID (--pid). At the end, every subscriber's last VisibilityNotify state of every viewable
 * window must be the record's final state for it (which visctl stress checked is visd's), and X's
 * stacking order, places, sizes and map states the record's.
 *
 *   xorg-replay [-c SUBSCRIBERS] [--display DISPLAY] [--pid PID] [--csv] [--quiet] RECORD
 *
 * Exit status: 0 the states matched, 1 a difference or a runtime error (no X server, an X error,
 * the server gone, a record that cannot be read), 2 usage or a record that is not one (or does
 * not fit X's 16-bit coordinates).
 */
#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "xorg-replay.h"

/* X.Org serves 256 clients by default (-maxclients); leave room for others. */
#define MAX_CLIENTS 250

static void usage(FILE *f)
{
	fprintf(f,
		"usage: xorg-replay [-c SUBSCRIBERS] [--display DISPLAY] [--pid PID] [--csv] [--quiet]\n"
		"                   RECORD\n"
		"  Replays a visctl stress --record script (move, resize, raise, lower, restack, map\n"
		"  only) on an X server of its own, measures each operation to the last\n"
		"  VisibilityNotify it causes, and checks that every subscriber's last states are\n"
		"  the record's final states.\n"
		"  -c SUBSCRIBERS   connections that select VisibilityChangeMask on every window,\n"
		"                   0..%d (default 10)\n"
		"  --display D      the X server (default: $DISPLAY)\n"
		"  --pid PID        the X server's process, for its CPU time\n"
		"  --csv            the results as a CSV header and one row\n"
		"  -q, --quiet      no progress line on stderr\n"
		"exit status: 0 passed, 1 a difference or a runtime error, 2 usage or a bad record\n",
		MAX_CLIENTS);
}

/* A plain decimal number in [lo, hi]. 0, or -1. */
static int parse_uint(const char *s, unsigned long lo, unsigned long hi, unsigned long *out)
{
	unsigned long v = 0;
	if (!*s)
		return -1;
	for (; *s; s++) {
		if (*s < '0' || *s > '9' || v > (hi - (unsigned long)(*s - '0')) / 10)
			return -1;
		v = v * 10 + (unsigned long)(*s - '0');
	}
	if (v < lo)
		return -1;
	*out = v;
	return 0;
}

/* Checks --pid: a running process whose name says it is an X server. 0, or -1. */
static int check_pid(pid_t pid)
{
	char path[64], name[64] = "";
	snprintf(path, sizeof(path), "/proc/%d/comm", (int)pid);
	FILE *f = fopen(path, "r");
	if (!f || !fgets(name, sizeof(name), f)) {
		fprintf(stderr, "xorg-replay: --pid %d: no such process\n", (int)pid);
		if (f)
			fclose(f);
		return -1;
	}
	fclose(f);
	name[strcspn(name, "\n")] = '\0';
	if (name[0] != 'X') {
		fprintf(stderr, "xorg-replay: --pid %d is '%s', not an X server\n", (int)pid, name);
		return -1;
	}
	return 0;
}

static double us(const struct histogram *h, double p)
{
	return (double)histogram_percentile(h, p) / 1e3;
}

/* The results as a CSV header and one row. */
static void print_csv(const struct replay_options *o, const struct replay_script *s,
		      const struct replay_result *r)
{
	double t = r->seconds > 0 ? r->seconds : 1e-9;
	const struct histogram *h = &r->latency;
	printf("windows,clients,seed,ops,seconds,ops_per_s,notices,notices_per_s,p50_us,p90_us,"
	       "p99_us,p999_us,max_us,mean_us,ops_without_notices,server_pid,server_cpu_s,"
	       "server_cpu_us_per_op,setup_s,mismatches,ok\n");
	printf("%u,%u,%llu,%llu,%.3f,%.0f,%llu,%.0f,%.1f,%.1f,%.1f,%.1f,%.1f,%.1f,%llu,", s->n,
	       o->clients, (unsigned long long)s->seed, (unsigned long long)r->ops, r->seconds,
	       (double)r->ops / t, (unsigned long long)r->notices, (double)r->notices / t,
	       us(h, 50), us(h, 90), us(h, 99), us(h, 99.9), (double)h->max / 1e3,
	       histogram_mean(h) / 1e3, (unsigned long long)r->ops_without_notices);
	if (o->pid)
		printf("%d,", (int)o->pid);
	else
		printf(",");
	if (r->server_cpu >= 0 && r->ops)
		printf("%.3f,%.1f,", r->server_cpu, r->server_cpu * 1e6 / (double)r->ops);
	else
		printf(",,");
	printf("%.3f,%llu,%d\n", r->setup_seconds, (unsigned long long)r->mismatches,
	       r->mismatches == 0);
}

/* One row of the latency table. */
static void print_row(const char *name, uint64_t ops, const struct histogram *h)
{
	printf("  %-9s %9llu %9.1f %9.1f %9.1f %9.1f %9.1f\n", name, (unsigned long long)ops,
	       us(h, 50), us(h, 90), us(h, 99), us(h, 99.9), (double)h->max / 1e3);
}

/* The results as a table for people, in visctl stress's layout. */
static void print_table(const struct replay_options *o, const struct replay_script *s,
			const struct replay_result *r)
{
	double t = r->seconds > 0 ? r->seconds : 1e-9;
	printf("xorg-replay: %u windows on %dx%d, %u subscribers, seed %llu, one operation at a "
	       "time\n\n", s->n, s->screen_w, s->screen_h, o->clients,
	       (unsigned long long)s->seed);
	printf("setup       %.3f s: windows made, selected by every subscriber, mapped\n",
	       r->setup_seconds);
	printf("throughput  %llu ops in %.3f s: %.0f ops/s\n", (unsigned long long)r->ops,
	       r->seconds, (double)r->ops / t);
	printf("notices     %llu VisibilityNotify: %.0f/s; %llu operations caused none\n",
	       (unsigned long long)r->notices, (double)r->notices / t,
	       (unsigned long long)r->ops_without_notices);
	printf("latency     µs from the operation to its last VisibilityNotify\n");
	printf("  %-9s %9s %9s %9s %9s %9s %9s\n", "kind", "ops", "p50", "p90", "p99", "p99.9",
	       "max");
	print_row("all", r->ops, &r->latency);
	for (int k = 0; k < REPLAY_KINDS; k++)
		if (r->kind_ops[k])
			print_row(replay_kind_name((enum replay_kind)k), r->kind_ops[k],
				  &r->kind_latency[k]);
	if (o->pid && r->server_cpu >= 0)
		printf("server      pid %d, cpu %.2f s (%.0f%% of the run), %.1f µs an operation\n",
		       (int)o->pid, r->server_cpu, 100 * r->server_cpu / t,
		       r->ops ? r->server_cpu * 1e6 / (double)r->ops : 0);
	if (r->mismatches)
		printf("check       FAILED: %llu differences (on stderr)\n",
		       (unsigned long long)r->mismatches);
	else
		printf("check       ok: every subscriber's last VisibilityNotify of every viewable "
		       "window is the record's final state; X's stack is the record's\n");
}

int main(int argc, char **argv)
{
	static const struct option longs[] = {
		{ "display", required_argument, NULL, 'd' }, { "pid", required_argument, NULL, 'p' },
		{ "csv", no_argument, NULL, 'v' },           { "quiet", no_argument, NULL, 'q' },
		{ "help", no_argument, NULL, 'h' },          { NULL, 0, NULL, 0 },
	};
	struct replay_options o = { .clients = 10, .progress = true };
	bool csv = false;
	unsigned long v;
	opterr = 0;
	for (int c; (c = getopt_long(argc, argv, ":c:qh", longs, NULL)) != -1;) {
		switch (c) {
		case 'c':
			if (parse_uint(optarg, 0, MAX_CLIENTS, &v) < 0) {
				fprintf(stderr, "xorg-replay: -c '%s' is not a number in 0..%d\n", optarg,
					MAX_CLIENTS);
				return 2;
			}
			o.clients = (uint32_t)v;
			break;
		case 'd':
			o.display = optarg;
			break;
		case 'p':
			if (parse_uint(optarg, 1, 0x7fffffff, &v) < 0) {
				fprintf(stderr, "xorg-replay: --pid '%s' is not a process ID\n", optarg);
				return 2;
			}
			o.pid = (pid_t)v;
			break;
		case 'v':
			csv = true;
			break;
		case 'q':
			o.progress = false;
			break;
		case 'h':
			usage(stdout);
			return 0;
		case ':':
			fprintf(stderr, "xorg-replay: %s needs a value\n", argv[optind - 1]);
			usage(stderr);
			return 2;
		default:
			fprintf(stderr, "xorg-replay: unknown option '%s'\n", argv[optind - 1]);
			usage(stderr);
			return 2;
		}
	}
	if (optind != argc - 1) {
		fprintf(stderr, "xorg-replay: %s\n", optind == argc ? "no RECORD given"
								 : "more than one RECORD given");
		usage(stderr);
		return 2;
	}
	if (o.pid && check_pid(o.pid) < 0)
		return 2;
	/* A server gone while a request is written must be an error, not a signal. */
	signal(SIGPIPE, SIG_IGN);
	struct replay_script s;
	int ret = replay_script_read(argv[optind], &s);
	if (ret)
		return ret;
	struct replay_result *r = malloc(sizeof(*r));
	if (!r) {
		fprintf(stderr, "xorg-replay: out of memory\n");
		replay_script_finish(&s);
		return 1;
	}
	ret = 1;
	if (replay_x_run(&o, &s, r) == 0) {
		if (csv)
			print_csv(&o, &s, r);
		else
			print_table(&o, &s, r);
		if (r->mismatches)
			fprintf(stderr, "xorg-replay: FAILED: %llu differences between X and the "
					"record\n", (unsigned long long)r->mismatches);
		else
			ret = 0;
	}
	free(r);
	replay_script_finish(&s);
	return fflush(stdout) == 0 ? ret : 1;
}
