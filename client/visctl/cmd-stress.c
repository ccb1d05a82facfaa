/*
 * `visctl stress`, in the mould of redis-benchmark and wrk2: its options, and the report of the
 * run (stress-run.c does it) as a table, JSON or CSV. Scripts parse the JSON and CSV: their
 * field names are an interface, documented in docs/SERVICE.md (visctl stress).
 */
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "stress.h"
#include "visctl.h"

#define MAX_CLIENTS 1000
#define MAX_WINDOWS 1000000
#define MAX_PIPELINE 1000000
#define MAX_BATCH 10000
#define MAX_WEIGHT 1000000
#define DEFAULT_COUNT 10000

static const uint32_t default_mix[STRESS_KINDS] = {
	[STRESS_MOVE] = 40, [STRESS_RESIZE] = 15,  [STRESS_RAISE] = 15, [STRESS_LOWER] = 10,
	[STRESS_RESTACK] = 5, [STRESS_MAP] = 10, [STRESS_BATCH] = 5,
};

enum format { FORMAT_TABLE, FORMAT_JSON, FORMAT_CSV };

/* The usage, to stdout for --help and to stderr after a mistake. */
static void usage(FILE *f)
{
	fprintf(f,
		"usage: visctl stress [-c CLIENTS] [-n WINDOWS] [--count N] [--duration SECONDS]\n"
		"                     [-R OPS] [--pipeline K] [--mix KIND=WEIGHT,...] [--batch-size B]\n"
		"                     [--exposure] [--scene KIND] [--seed S] [--record FILE]\n"
		"                     [--pid PID] [--json | --csv] [--quiet]\n"
		"  A manager changes a desktop of WINDOWS windows (as visctl gen makes them)\n"
		"  while CLIENTS observers subscribed to every window count the notices. An\n"
		"  operation's latency runs from its start to the arrival of the last notice it\n"
		"  causes, confirmed by a sync on every subscriber. At the end the daemon's tree and\n"
		"  states, and each subscriber's last notices, must equal the run's model of the stack\n"
		"  (its states computed as visctl compute does), and no notice may be missing.\n"
		"  -c CLIENTS          subscribers, 0..%d (default 10)\n"
		"  -n WINDOWS          windows, 1..%d (default 1000)\n"
		"  --count N           operations (default %d unless --duration is given)\n"
		"  --duration SECONDS  start no operation after this long\n"
		"  -R OPS              start operations at this fixed rate a second; one held back by\n"
		"                      a full pipeline counts from when it was due (default: closed\n"
		"                      loop, each as soon as the pipeline has room)\n"
		"  --pipeline K        operations in flight at most (default 1: one at a time)\n"
		"  --mix LIST          KIND=WEIGHT,... of move resize raise lower restack map batch\n"
		"                      border shape opaque (default move=40,resize=15,raise=15,\n"
		"                      lower=10,restack=5,map=10,batch=5); map unmaps a window or maps\n"
		"                      one back; border sets a width of 0-3, shape gives rounded\n"
		"                      corners, an L, no pixels or the border box, opaque all, none or\n"
		"                      a shadow margin's inside\n"
		"  --batch-size B      changes in a batch operation (default 8)\n"
		"  --exposure          the subscribers ask for exposure notices too\n"
		"  --scene KIND        the desktop: random, uniform, grid, cascade, tiles or nested\n"
		"                      (default random)\n"
		"  --seed S            the desktop and the operations (default 1)\n"
		"  --record FILE       writes the operations as a script for visctl script\n"
		"  --pid PID           visd's process, for CPU and memory (default: the socket's peer);\n"
		"                      refused unless it is a visd, and the one serving the socket\n"
		"  --json, --csv       the results as JSON or CSV instead of a table\n"
		"  -q, --quiet         no progress line (on stderr: overwritten in place on a\n"
		"                      terminal, else one line a second)\n"
		"  visd must have no windows but the run's. It ignores --role: the run takes the\n"
		"  manager role (its changes) and the observer role (its subscribers), which visd\n"
		"  grants only to its own user.\n"
		"exit status: 0 passed, 1 a mismatch or a runtime error, 2 usage\n",
		MAX_CLIENTS, MAX_WINDOWS, DEFAULT_COUNT);
}

/* Reports a usage mistake; returns the usage exit status. */
static int bad_usage(const char *fmt, const char *arg)
{
	fputs("visctl stress: ", stderr);
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	usage(stderr);
	return VISCTL_EXIT_USAGE;
}

/* Parses a plain decimal number in [lo, hi]. 0, or -1. */
static int parse_uint(const char *s, uint64_t lo, uint64_t hi, uint64_t *out)
{
	uint64_t v = 0;
	if (!*s)
		return -1;
	for (; *s; s++) {
		uint64_t d = (uint64_t)(*s - '0');
		if (*s < '0' || *s > '9' || v > (UINT64_MAX - d) / 10)
			return -1;
		v = v * 10 + d;
	}
	if (v < lo || v > hi)
		return -1;
	*out = v;
	return 0;
}

/* Parses a positive, finite number of seconds or operations a second. 0, or -1. */
static int parse_positive(const char *s, double *out)
{
	char *end;
	errno = 0;
	double v = strtod(s, &end);
	if (errno || end == s || *end || !isfinite(v) || v <= 0 || v > 1e9)
		return -1;
	*out = v;
	return 0;
}

/* Parses --mix: KIND=WEIGHT or KIND (weight 1), comma-separated; kinds not named weigh 0. */
static int parse_mix(const char *list, uint32_t *mix)
{
	char buf[256];
	if (strlen(list) >= sizeof(buf))
		return bad_usage("--mix '%s' is too long", list);
	strcpy(buf, list);
	memset(mix, 0, STRESS_KINDS * sizeof(*mix));
	uint64_t total = 0;
	for (char *save, *item = strtok_r(buf, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
		char *eq = strchr(item, '=');
		uint64_t weight = 1;
		if (eq) {
			*eq = '\0';
			if (parse_uint(eq + 1, 0, MAX_WEIGHT, &weight) < 0)
				return bad_usage("--mix: weight '%s' is not a number in 0..1000000",
						 eq + 1);
		}
		int k = 0;
		while (k < STRESS_KINDS && strcmp(item, stress_kind_name((enum stress_kind)k)) != 0)
			k++;
		if (k == STRESS_KINDS)
			return bad_usage("--mix: unknown kind '%s' (move, resize, raise, lower, restack, "
					 "map, batch, border, shape, opaque)", item);
		mix[k] = (uint32_t)weight;
		total += weight;
	}
	if (total == 0)
		return bad_usage("--mix '%s' gives every kind weight 0", list);
	return 0;
}

/* Reads the options into o and *format. 0 to run, -1 after --help, or the exit status to return
 * after a mistake. */
static int parse_options(int argc, char **argv, struct stress_options *o, enum format *format,
			 const char **record)
{
	static const struct option longs[] = {
		{ "count", required_argument, NULL, 'N' },  { "duration", required_argument, NULL, 'D' },
		{ "pipeline", required_argument, NULL, 'P' }, { "mix", required_argument, NULL, 'M' },
		{ "batch-size", required_argument, NULL, 'B' }, { "exposure", no_argument, NULL, 'E' },
		{ "seed", required_argument, NULL, 'S' },   { "record", required_argument, NULL, 'W' },
		{ "scene", required_argument, NULL, 'K' },
		{ "pid", required_argument, NULL, 'p' },    { "json", no_argument, NULL, 'j' },
		{ "csv", no_argument, NULL, 'v' },          { "quiet", no_argument, NULL, 'q' },
		{ "help", no_argument, NULL, 'h' },         { NULL, 0, NULL, 0 },
	};
	uint64_t v;
	bool quiet = false;
	optind = 0;
	opterr = 0;
	for (int c; (c = getopt_long(argc, argv, ":c:n:R:qh", longs, NULL)) != -1;) {
		const char *a = optarg;
		switch (c) {
		case 'c':
			if (parse_uint(a, 0, MAX_CLIENTS, &v) < 0)
				return bad_usage("-c '%s' is not a number in 0..1000", a);
			o->clients = (uint32_t)v;
			break;
		case 'n':
			if (parse_uint(a, 1, MAX_WINDOWS, &v) < 0)
				return bad_usage("-n '%s' is not a number in 1..1000000", a);
			o->windows = (uint32_t)v;
			break;
		case 'N':
			if (parse_uint(a, 1, UINT64_MAX, &o->count) < 0)
				return bad_usage("--count '%s' is not a positive number", a);
			break;
		case 'D':
			if (parse_positive(a, &o->duration) < 0)
				return bad_usage("--duration '%s' is not a positive number of seconds", a);
			break;
		case 'R':
			if (parse_positive(a, &o->rate) < 0)
				return bad_usage("-R '%s' is not a positive rate", a);
			break;
		case 'P':
			if (parse_uint(a, 1, MAX_PIPELINE, &v) < 0)
				return bad_usage("--pipeline '%s' is not a number in 1..1000000", a);
			o->pipeline = (uint32_t)v;
			break;
		case 'M': {
			int r = parse_mix(a, o->mix);
			if (r)
				return r;
			break;
		}
		case 'B':
			if (parse_uint(a, 1, MAX_BATCH, &v) < 0)
				return bad_usage("--batch-size '%s' is not a number in 1..10000", a);
			o->batch_size = (uint32_t)v;
			break;
		case 'E':
			o->exposure = true;
			break;
		case 'S':
			if (parse_uint(a, 0, UINT64_MAX, &o->seed) < 0)
				return bad_usage("--seed '%s' is not a number", a);
			break;
		case 'K':
			/* Looks come from --mix: a change each, as the model tracks them. */
			if (vis_gen_kind_from_name(a, &o->scene) < 0 || o->scene == VIS_GEN_SHAPED ||
			    o->scene == VIS_GEN_TRANSLUCENT)
				return bad_usage("--scene '%s' is not random, uniform, grid, cascade, "
						 "tiles or nested", a);
			break;
		case 'W':
			*record = a;
			break;
		case 'p':
			if (parse_uint(a, 1, INT32_MAX, &v) < 0)
				return bad_usage("--pid '%s' is not a process ID", a);
			o->pid = (pid_t)v;
			break;
		case 'j':
		case 'v':
			if (*format != FORMAT_TABLE && *format != (c == 'j' ? FORMAT_JSON : FORMAT_CSV))
				return bad_usage("%s", "--json and --csv exclude each other");
			*format = c == 'j' ? FORMAT_JSON : FORMAT_CSV;
			break;
		case 'q':
			quiet = true;
			break;
		case 'h':
			usage(stdout);
			return -1;
		case ':':
			return bad_usage("%s needs a value", argv[optind - 1]);
		default:
			return bad_usage("unknown option '%s'", argv[optind - 1]);
		}
	}
	if (optind < argc)
		return bad_usage("unexpected argument '%s'", argv[optind]);
	if (!o->count && o->duration == 0)
		o->count = DEFAULT_COUNT;
	o->progress = !quiet;
	o->progress_tty = isatty(STDERR_FILENO);
	return 0;
}

/* One number of the results, for JSON and CSV alike; absent ones are null (JSON), empty (CSV).
 * Counts are printed from integer, so that a 64-bit seed survives; measures with decimals. */
struct field {
	const char *name;
	const char *text; /* a word, not a number, when not NULL */
	bool present;
	int decimals; /* < 0: the count */
	uint64_t count;
	double value;
};

/* The flat results, in the order JSON and CSV give them. Returns how many. */
static size_t fields(const struct stress_options *o, const struct stress_result *r,
		     struct field *f)
{
	const struct histogram *h = &r->latency;
	double t = r->seconds > 0 ? r->seconds : 1e-9;
	bool cpu = r->daemon_cpu >= 0;
	size_t n = 0;
#define COUNT(name_, count_, present_) \
	f[n++] = (struct field){ name_, NULL, present_, -1, (uint64_t)(count_), 0 }
#define VALUE(name_, value_, present_, decimals_) \
	f[n++] = (struct field){ name_, NULL, present_, decimals_, 0, (double)(value_) }
	COUNT("windows", o->windows, true);
	COUNT("clients", o->clients, true);
	COUNT("seed", o->seed, true);
	COUNT("pipeline", o->pipeline, true);
	VALUE("rate", o->rate, o->rate > 0, 1);
	COUNT("ops", r->ops, true);
	COUNT("changes", r->changes, true);
	VALUE("seconds", r->seconds, true, 3);
	VALUE("ops_per_s", (double)r->ops / t, true, 0);
	VALUE("changes_per_s", (double)r->changes / t, true, 0);
	COUNT("notices", r->notices, true);
	VALUE("notices_per_s", (double)r->notices / t, true, 0);
	VALUE("p50_us", (double)histogram_percentile(h, 50) / 1e3, true, 1);
	VALUE("p90_us", (double)histogram_percentile(h, 90) / 1e3, true, 1);
	VALUE("p99_us", (double)histogram_percentile(h, 99) / 1e3, true, 1);
	VALUE("p999_us", (double)histogram_percentile(h, 99.9) / 1e3, true, 1);
	VALUE("max_us", (double)h->max / 1e3, true, 1);
	VALUE("mean_us", histogram_mean(h) / 1e3, true, 1);
	COUNT("daemon_pid", r->daemon_pid, r->daemon_pid > 0);
	VALUE("daemon_cpu_s", r->daemon_cpu, cpu, 2);
	VALUE("daemon_cpu_pct", 100 * r->daemon_cpu / t, cpu, 1);
	COUNT("daemon_rss_kb", r->daemon_rss_kb, r->daemon_rss_kb >= 0);
	COUNT("daemon_hwm_kb", r->daemon_hwm_kb, r->daemon_hwm_kb >= 0);
	VALUE("visctl_cpu_s", r->self_cpu, true, 2);
	COUNT("mismatches", r->mismatches, true);
	f[n++] = (struct field){ "scene", vis_gen_kind_name(o->scene), true, -1, 0, 0 };
#undef COUNT
#undef VALUE
	return n;
}

#define MAX_FIELDS 32

/* Prints a field's value as JSON and CSV want it; a word in quotes for JSON. */
static void print_value(const struct field *f, const char *absent, bool json)
{
	if (f->text)
		printf(json ? "\"%s\"" : "%s", f->text);
	else if (f->present && f->decimals < 0)
		printf("%llu", (unsigned long long)f->count);
	else if (f->present)
		printf("%.*f", f->decimals, f->value);
	else
		fputs(absent, stdout);
}

/* The results as one JSON object; "kinds" has each kind's operations and latencies. */
static void print_json(const struct stress_options *o, const struct stress_result *r)
{
	struct field f[MAX_FIELDS];
	size_t n = fields(o, r, f);
	putchar('{');
	for (size_t i = 0; i < n; i++) {
		printf("\"%s\":", f[i].name);
		print_value(&f[i], "null", true);
		putchar(',');
	}
	printf("\"ok\":%s,\"kinds\":{", r->mismatches ? "false" : "true");
	for (int k = 0, first = 1; k < STRESS_KINDS; k++) {
		const struct histogram *h = &r->kind_latency[k];
		if (!r->kind_ops[k])
			continue;
		printf("%s\"%s\":{\"ops\":%llu,\"p50_us\":%.1f,\"p99_us\":%.1f,\"max_us\":%.1f}",
		       first ? "" : ",", stress_kind_name((enum stress_kind)k),
		       (unsigned long long)r->kind_ops[k], (double)histogram_percentile(h, 50) / 1e3,
		       (double)histogram_percentile(h, 99) / 1e3, (double)h->max / 1e3);
		first = 0;
	}
	printf("}}\n");
}

/* The results as a CSV header and one row. */
static void print_csv(const struct stress_options *o, const struct stress_result *r)
{
	struct field f[MAX_FIELDS];
	size_t n = fields(o, r, f);
	for (size_t i = 0; i < n; i++)
		printf("%s,", f[i].name);
	printf("ok\n");
	for (size_t i = 0; i < n; i++) {
		print_value(&f[i], "", false);
		putchar(',');
	}
	printf("%d\n", r->mismatches ? 0 : 1);
}

/* One row of the latency table: operations and percentiles in microseconds. */
static void print_latency_row(const char *name, uint64_t ops, const struct histogram *h)
{
	printf("  %-9s %9llu", name, (unsigned long long)ops);
	static const double ps[] = { 50, 90, 99, 99.9 };
	for (size_t i = 0; i < sizeof(ps) / sizeof(ps[0]); i++)
		printf(" %9.1f", (double)histogram_percentile(h, ps[i]) / 1e3);
	printf(" %9.1f\n", (double)h->max / 1e3);
}

/* The results as a table for people. */
static void print_table(const struct stress_options *o, const struct stress_result *r)
{
	double t = r->seconds > 0 ? r->seconds : 1e-9;
	printf("visctl stress: %u windows (%s) on %dx%d, %u subscribers%s, seed %llu, pipeline "
	       "%u, ", o->windows, vis_gen_kind_name(o->scene), r->screen_w, r->screen_h, o->clients,
	       o->exposure ? " (+exposure)" : "", (unsigned long long)o->seed, o->pipeline);
	if (o->rate > 0)
		printf("rate %.0f/s\n", o->rate);
	else
		printf("rate unlimited\n");
	printf("mix:");
	for (int k = 0, first = 1; k < STRESS_KINDS; k++)
		if (o->mix[k]) {
			printf("%s %s %u", first ? "" : ",", stress_kind_name((enum stress_kind)k),
			       o->mix[k]);
			first = 0;
		}
	if (o->mix[STRESS_BATCH])
		printf(" (%u changes a batch)", o->batch_size);
	printf("\n\n");
	printf("throughput  %llu ops in %.3f s: %.0f ops/s, %.0f changes/s\n",
	       (unsigned long long)r->ops, r->seconds, (double)r->ops / t, (double)r->changes / t);
	printf("notices     %llu: %.0f/s\n", (unsigned long long)r->notices, (double)r->notices / t);
	printf("latency     µs from the operation to its last notice\n");
	printf("  %-9s %9s %9s %9s %9s %9s %9s\n", "kind", "ops", "p50", "p90", "p99", "p99.9",
	       "max");
	print_latency_row("all", r->ops, &r->latency);
	for (int k = 0; k < STRESS_KINDS; k++)
		if (r->kind_ops[k])
			print_latency_row(stress_kind_name((enum stress_kind)k), r->kind_ops[k],
					  &r->kind_latency[k]);
	printf("visd        ");
	if (r->daemon_pid > 0)
		printf("pid %d", (int)r->daemon_pid);
	if (r->daemon_cpu >= 0)
		printf(", cpu %.2f s (%.0f%% of the run)", r->daemon_cpu, 100 * r->daemon_cpu / t);
	if (r->daemon_rss_kb >= 0)
		printf(", rss %.1f MiB, peak %.1f MiB", (double)r->daemon_rss_kb / 1024,
		       (double)r->daemon_hwm_kb / 1024);
	printf("\nvisctl      cpu %.2f s (%.0f%% of the run)\n", r->self_cpu, 100 * r->self_cpu / t);
	if (r->mismatches)
		printf("check       FAILED: %llu differences (on stderr)\n",
		       (unsigned long long)r->mismatches);
	else
		printf("check       ok: visd's tree and states, and every subscriber's last notices, "
		       "equal the model's; no notice missing\n");
}

int cmd_stress(struct live *l, int argc, char **argv)
{
	struct stress_options o = { .socket = l->socket, .clients = 10, .windows = 1000,
				    .pipeline = 1, .batch_size = 8, .seed = 1 };
	memcpy(o.mix, default_mix, sizeof(o.mix));
	enum format format = FORMAT_TABLE;
	const char *record = NULL;
	int r = parse_options(argc, argv, &o, &format, &record);
	if (r < 0)
		return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
	if (r)
		return r;
	const char *corrupt = getenv("VISCTL_STRESS_CORRUPT_MODEL");
	o.corrupt_model = corrupt && *corrupt && strcmp(corrupt, "0") != 0;
	if (record && !(o.record = fopen(record, "w"))) {
		fprintf(stderr, "visctl stress: %s: cannot write: %s\n", record, strerror(errno));
		return VISCTL_EXIT_USAGE;
	}
	struct stress_result *res = malloc(sizeof(*res));
	int ret = VISCTL_EXIT_FAILURE;
	if (!res)
		fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
	else if (stress_run(&o, res) == 0) {
		if (format == FORMAT_JSON)
			print_json(&o, res);
		else if (format == FORMAT_CSV)
			print_csv(&o, res);
		else
			print_table(&o, res);
		double achieved = res->seconds > 0 ? (double)res->ops / res->seconds : 0;
		if (o.rate > 0 && achieved < 0.95 * o.rate)
			fprintf(stderr, "visctl stress: %.0f operations a second of the %.0f asked: the "
					"latencies count the wait; a larger --pipeline may keep up\n",
				achieved, o.rate);
		if (res->mismatches)
			fprintf(stderr, "visctl stress: FAILED: %llu differences between visd and "
					"the model; --seed %llu reproduces the run\n",
				(unsigned long long)res->mismatches, (unsigned long long)o.seed);
		else
			ret = VISCTL_EXIT_OK;
	}
	if (o.record && (fclose(o.record) != 0) && ret == VISCTL_EXIT_OK) {
		fprintf(stderr, "visctl stress: %s: write error: %s\n", record, strerror(errno));
		ret = VISCTL_EXIT_FAILURE;
	}
	free(res);
	return ret;
}
