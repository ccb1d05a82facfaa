/*
 * The scene subcommands: `visctl compute` (a scene file in, one state per window out) and
 * `visctl gen` (a generated scene out). Both must keep up with a million windows, so output goes
 * through one large buffer and a hand-rolled integer formatter rather than printf per line.
 */
#include <errno.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "engine.h"
#include "look.h"
#include "radix.h"
#include "gen.h"
#include "scene.h"
#include "stack-svg.h"
#include "visctl.h"

#define OUT_SIZE (1 << 16)

/* Buffered output to a file descriptor; the first write error sticks and stops further writes. */
struct out {
	int fd;
	size_t len;
	int error; /* an errno value, 0 while all is well */
	char buf[OUT_SIZE];
};

/* A buffered writer to stdout; NULL (after saying so on stderr) when memory is short. */
static struct out *out_create(const char *who)
{
	struct out *o = malloc(sizeof(*o));
	if (o == NULL) {
		fprintf(stderr, "%s: %s\n", who, strerror(ENOMEM));
		return NULL;
	}
	o->fd = STDOUT_FILENO;
	o->len = 0;
	o->error = 0;
	return o;
}

/* Writes out the buffered bytes, retrying short writes and EINTR. */
static void out_flush(struct out *o)
{
	size_t done = 0;

	while (done < o->len && o->error == 0) {
		ssize_t r = write(o->fd, o->buf + done, o->len - done);
		if (r < 0 && errno != EINTR)
			o->error = errno;
		else if (r > 0)
			done += (size_t)r;
	}
	o->len = 0;
}

/* Appends bytes, flushing when the buffer is full. */
static void out_put(struct out *o, const char *s, size_t len)
{
	while (len > 0) {
		if (o->len == OUT_SIZE)
			out_flush(o);
		size_t n = OUT_SIZE - o->len < len ? OUT_SIZE - o->len : len;
		memcpy(o->buf + o->len, s, n);
		o->len += n;
		s += n;
		len -= n;
	}
}

/* Appends an unsigned number in decimal. */
static void out_u32(struct out *o, uint32_t v)
{
	char tmp[10];
	size_t n = sizeof(tmp);

	do {
		tmp[--n] = (char)('0' + v % 10);
		v /= 10;
	} while (v != 0);
	out_put(o, tmp + n, sizeof(tmp) - n);
}

/* Flushes and reports a write error the way every subcommand does; returns the exit status. */
static int out_finish(struct out *o)
{
	out_flush(o);
	if (o->error != 0) {
		fprintf(stderr, "visctl: write error: %s\n", strerror(o->error));
		return VISCTL_EXIT_FAILURE;
	}
	return VISCTL_EXIT_OK;
}

/* The stack positions in ascending ID order; scenes already in order (generated ones) skip the sort. */
static uint32_t *order_by_id(const struct vis_scene *scene)
{
	size_t n = scene->n;
	uint32_t *order = malloc((n ? n : 1) * sizeof(*order));
	uint64_t *key = NULL;
	bool sorted = true;

	if (order == NULL)
		return NULL;
	for (size_t i = 0; i < n; i++) {
		order[i] = (uint32_t)i;
		if (i > 0 && scene->ids[i] < scene->ids[i - 1])
			sorted = false;
	}
	if (sorted)
		return order;
	key = malloc(n * sizeof(*key));
	if (key == NULL) {
		free(order);
		return NULL;
	}
	for (size_t i = 0; i < n; i++)
		key[i] = scene->ids[i];
	if (vis_radix_sort(key, order, n) < 0) {
		free(order);
		order = NULL;
	}
	free(key);
	return order;
}

/* The compute usage, to stdout for --help and to stderr after a mistake. */
static void compute_usage(FILE *f)
{
	fprintf(f, "usage: visctl compute [--engine=auto|gmv|gmv-heap|region|brute] [--visible] "
		   "[--json]\n"
		   "                      [--time] [--svg FILE] SCENE\n"
		   "  Prints 'ID STATE' for every window in ascending ID order (with --visible, only\n"
		   "  the IDs of windows that are not fully obscured). SCENE is a path or '-' for\n"
		   "  stdin. --json prints each as one JSON object a line, {\"window\":ID,\"state\":\n"
		   "  STATE} ({\"window\":ID} with --visible). --time prints compute_ms=... on stderr.\n"
		   "  --svg also draws the scene into FILE: every window in its state's colour, its\n"
		   "  visible parts filled.\n");
}

/* Reports a usage mistake and returns the usage exit status. */
static int compute_bad_usage(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static int compute_bad_usage(const char *fmt, ...)
{
	va_list ap;

	fputs("visctl compute: ", stderr);
	va_start(ap, fmt);
	vfprintf(stderr, fmt, ap);
	va_end(ap);
	fputc('\n', stderr);
	compute_usage(stderr);
	return VISCTL_EXIT_USAGE;
}

/*
 * Draws the scene with its states into svg, which it closes. Returns the exit status, having
 * said what went wrong.
 */
static int compute_svg(const struct vis_scene *scene, const uint8_t *states, const char *shown,
		       FILE *svg, const char *svg_path)
{
	struct vis_stack windows = vis_scene_stack(scene);
	struct vis_pieces pieces = { 0 };
	struct stack_svg p;
	char title[512];
	size_t input_only = 0;
	uint32_t *window_of = NULL;
	int r = 0;

	snprintf(title, sizeof(title), "visctl compute %s", shown);
	stack_svg_init(&p, title);
	p.has_screen = scene->has_screen;
	p.screen_w = scene->screen_w;
	p.screen_h = scene->screen_h;
	/* Windows with a look are drawn from their pieces: their pixels, opaque or translucent. */
	if (scene->looks != NULL) {
		r = vis_pieces_init(&pieces, &windows);
		window_of = r == 0 ? malloc((pieces.stack.n + 1) * sizeof(*window_of)) : NULL;
		if (window_of == NULL)
			r = -1;
	}
	size_t k = 0;
	for (size_t i = 0; i < scene->n && r == 0; i++) {
		const struct vis_look *look = scene->looks ? &scene->looks[i] : NULL;
		struct vis_box box = vis_rect_box(scene->rects[i]);
		if (look != NULL && look->input_only) {
			input_only++; /* no pixels to draw */
			continue;
		}
		if (look != NULL && look->border != 0) {
			box.x2 += 2 * (int64_t)look->border;
			box.y2 += 2 * (int64_t)look->border;
		}
		r = stack_svg_add(&p, scene->ids[i], 0, box, states[i]);
		if (r == 0 && look != NULL && look->border != 0)
			p.windows[p.n - 1].inside = (struct vis_box){ box.x1 + look->border,
								      box.y1 + look->border,
								      box.x2 - look->border,
								      box.y2 - look->border };
		bool drawn_whole = look == NULL || (!look->shaped && look->opaque == VIS_OPAQUE_ALL);
		for (; r == 0 && scene->looks != NULL && k < pieces.stack.n && pieces.window[k] == i;
		     k++) {
			window_of[k] = (uint32_t)(p.n - 1);
			if (!drawn_whole)
				r = stack_svg_add_pixels(&p, vis_rect_box(pieces.rects[k]),
							 pieces.see_through[k] != 0);
		}
	}
	if (input_only)
		stack_svg_note(&p, "Not drawn: %zu input-only window%s.", input_only,
		       input_only == 1 ? "" : "s");
	if (r == 0)
		r = stack_svg_find_parts(&p, scene->looks ? &pieces.stack : &windows, window_of);
	vis_pieces_finish(&pieces);
	free(window_of);
	if (r < 0) {
		fprintf(stderr, "visctl compute: %s: %s\n", svg_path, strerror(errno));
		stack_svg_finish(&p);
		fclose(svg);
		return VISCTL_EXIT_FAILURE;
	}
	r = stack_svg_write(&p, svg);
	stack_svg_finish(&p);
	/* A failed write of buffered data (a full disk) shows up only at fclose. */
	if (fclose(svg) != 0 || r < 0) {
		fprintf(stderr, "visctl compute: %s: write error: %s\n", svg_path, strerror(errno));
		return VISCTL_EXIT_FAILURE;
	}
	return VISCTL_EXIT_OK;
}

/*
 * Computes the scene's states and writes them out, then the picture when svg is not NULL; the
 * scene has been parsed already.
 */
static int compute_run(const struct vis_scene *scene, enum vis_engine engine, bool visible,
		       bool json, bool timing, const char *shown, FILE *svg, const char *svg_path)
{
	struct vis_stack stack = vis_scene_stack(scene);
	uint8_t *states = malloc(scene->n ? scene->n : 1);
	uint32_t *order = order_by_id(scene);
	struct timespec t0, t1;
	int ret = VISCTL_EXIT_FAILURE;

	if (states == NULL || order == NULL) {
		fprintf(stderr, "visctl compute: %s\n", strerror(ENOMEM));
		goto out;
	}
	clock_gettime(CLOCK_MONOTONIC, &t0);
	int r = vis_compute(engine, &stack, states);
	clock_gettime(CLOCK_MONOTONIC, &t1);
	if (r < 0) {
		fprintf(stderr, "visctl compute: engine %s: %s\n", vis_engine_name(engine),
			strerror(errno));
		goto out;
	}
	if (timing)
		fprintf(stderr, "compute_ms=%.3f\n",
			(double)(t1.tv_sec - t0.tv_sec) * 1e3 + (double)(t1.tv_nsec - t0.tv_nsec) / 1e6);

	/* What follows an ID for each state (" state\n", or JSON's rest of the object), made once
	 * so the loop is only copies. */
	char suffix[3][48];
	size_t suffix_len[3];
	for (int s = 0; s < 3; s++)
		suffix_len[s] = (size_t)snprintf(suffix[s], sizeof(suffix[s]),
						 visible ? (json ? "}\n" : "\n")
							 : (json ? ",\"state\":\"%s\"}\n" : " %s\n"),
						 vis_state_name((enum vis_state)s));

	struct out *o = out_create("visctl compute");
	if (o == NULL)
		goto out;
	for (size_t i = 0; i < scene->n && o->error == 0; i++) {
		uint32_t k = order[i];
		uint8_t s = states[k];
		/* An input-only window has no state, as an unviewable one has none in `states`. */
		if (s > VIS_FULLY_OBSCURED || (visible && s == VIS_FULLY_OBSCURED))
			continue;
		if (json)
			out_put(o, "{\"window\":", 10);
		out_u32(o, scene->ids[k]);
		out_put(o, suffix[s], suffix_len[s]);
	}
	ret = out_finish(o);
	free(o);
	if (svg != NULL) {
		int r = compute_svg(scene, states, shown, svg, svg_path);
		svg = NULL;
		ret = ret != VISCTL_EXIT_OK ? ret : r;
	}
out:
	if (svg != NULL)
		fclose(svg);
	free(states);
	free(order);
	return ret;
}

/*
 * Matches argv[*i] against an option with a value, given as "--NAME=VALUE" or "--NAME VALUE"
 * (then *i moves past the value). Returns 1 with *value set, 0 when it is not that option, -1
 * when the value is missing.
 */
static int option_value(int argc, char **argv, int *i, const char *name, const char **value)
{
	size_t len = strlen(name);

	if (strncmp(argv[*i], name, len) == 0 && argv[*i][len] == '=') {
		*value = argv[*i] + len + 1;
		return 1;
	}
	if (strcmp(argv[*i], name) != 0)
		return 0;
	if (*i + 1 == argc)
		return -1;
	*value = argv[++*i];
	return 1;
}

/* `visctl compute`: bad usage and bad scenes exit 2 with nothing on stdout, runtime failures 1. */
int cmd_compute(int argc, char **argv)
{
	enum vis_engine engine = VIS_ENGINE_AUTO;
	bool visible = false, json = false, timing = false, options_done = false;
	const char *path = NULL, *svg_path = NULL;

	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const char *name = NULL;
		int r;

		if (options_done || a[0] != '-' || strcmp(a, "-") == 0) {
			if (path != NULL)
				return compute_bad_usage("unexpected argument '%s'", a);
			path = a;
		} else if (strcmp(a, "--") == 0) {
			options_done = true;
		} else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			compute_usage(stdout);
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		} else if (strcmp(a, "--visible") == 0) {
			visible = true;
		} else if (strcmp(a, "--json") == 0) {
			json = true;
		} else if (strcmp(a, "--time") == 0) {
			timing = true;
		} else if ((r = option_value(argc, argv, &i, "--svg", &svg_path)) != 0) {
			if (r < 0)
				return compute_bad_usage("%s needs a FILE", a);
		} else if ((r = option_value(argc, argv, &i, "--engine", &name)) != 0) {
			if (r < 0)
				return compute_bad_usage("%s needs an engine name", a);
		} else {
			return compute_bad_usage("unknown option '%s'", a);
		}
		if (name != NULL && vis_engine_from_name(name, &engine) < 0)
			return compute_bad_usage("unknown engine '%s' "
						 "(auto, gmv, gmv-heap, region, brute)", name);
	}
	if (path == NULL)
		return compute_bad_usage("%s", "missing SCENE");
	if (svg_path != NULL && svg_path[0] == '\0')
		return compute_bad_usage("%s", "empty --svg FILE");

	const char *shown = strcmp(path, "-") == 0 ? "<stdin>" : path;
	char *text;
	size_t len;
	if (visctl_read_all(path, &text, &len) < 0) {
		/* A missing or unreadable file is a runtime error (1), not bad usage. */
		fprintf(stderr, "visctl: %s: cannot read: %s\n", shown, strerror(errno));
		return VISCTL_EXIT_FAILURE;
	}

	struct vis_scene scene;
	struct vis_scene_error err;
	vis_scene_init(&scene);
	int r = vis_scene_parse(&scene, text, len, &err);
	free(text);
	if (r < 0) {
		if (err.line == 0) {
			fprintf(stderr, "%s: %s\n", shown, err.reason);
			return VISCTL_EXIT_FAILURE;
		}
		fprintf(stderr, "%s:%zu: %s\n", shown, err.line, err.reason);
		return VISCTL_EXIT_USAGE;
	}
	/* Open the picture before computing: a bad path fails with nothing on stdout. */
	FILE *svg = NULL;
	if (svg_path != NULL && (svg = fopen(svg_path, "w")) == NULL) {
		fprintf(stderr, "visctl compute: %s: cannot write: %s\n", svg_path, strerror(errno));
		vis_scene_finish(&scene);
		return VISCTL_EXIT_FAILURE;
	}
	int ret = compute_run(&scene, engine, visible, json, timing, shown, svg, svg_path);
	vis_scene_finish(&scene);
	return ret;
}

/* The gen usage, to stdout for --help and to stderr after a mistake. */
static void gen_usage(FILE *f)
{
	fprintf(f, "usage: visctl gen KIND N SEED [W H]\n"
		   "  Writes a scene of N windows (0..100000000) to stdout; the same KIND, N, SEED\n"
		   "  and screen give the same scene. KIND is one of:");
	for (int k = 0; k < VIS_GEN_KIND_COUNT; k++)
		fprintf(f, " %s", vis_gen_kind_name((enum vis_gen_kind)k));
	fprintf(f, ".\n  W H size the screen (default %dx%d; grid sizes its own).\n",
		VIS_GEN_SCREEN_W, VIS_GEN_SCREEN_H);
}

/* Parses plain decimal (no sign, no junk) up to max. Returns 0, or -1. */
static int parse_u64(const char *s, uint64_t max, uint64_t *out)
{
	uint64_t v = 0;

	if (*s == '\0')
		return -1;
	for (; *s != '\0'; s++) {
		if (*s < '0' || *s > '9')
			return -1;
		unsigned d = (unsigned)(*s - '0');
		if (v > (max - d) / 10)
			return -1;
		v = v * 10 + d;
	}
	*out = v;
	return 0;
}

/* Reports a bad gen argument and returns the usage exit status. */
static int gen_bad_usage(const char *what, const char *arg, const char *range)
{
	fprintf(stderr, "visctl gen: %s '%s' is not a number in %s\n", what, arg, range);
	gen_usage(stderr);
	return VISCTL_EXIT_USAGE;
}

#define GEN_MAX_N 100000000u
#define GEN_CHUNK 65536

/* `visctl gen`: checks every argument before generating, so bad usage never writes a partial scene. */
int cmd_gen(int argc, char **argv)
{
	enum vis_gen_kind kind;
	uint64_t n, seed, w = 0, h = 0;

	if (argc == 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
		gen_usage(stdout);
		return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
	}
	if (argc != 4 && argc != 6) {
		fprintf(stderr, "visctl gen: expected KIND N SEED [W H], got %d arguments\n",
			argc - 1);
		gen_usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	if (vis_gen_kind_from_name(argv[1], &kind) < 0) {
		fprintf(stderr, "visctl gen: unknown kind '%s'\n", argv[1]);
		gen_usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	if (parse_u64(argv[2], GEN_MAX_N, &n) < 0)
		return gen_bad_usage("N", argv[2], "0..100000000");
	if (parse_u64(argv[3], UINT64_MAX, &seed) < 0)
		return gen_bad_usage("SEED", argv[3], "0..18446744073709551615");
	if (argc == 6 && (parse_u64(argv[4], INT32_MAX, &w) < 0 || w == 0))
		return gen_bad_usage("W", argv[4], "1..2147483647");
	if (argc == 6 && (parse_u64(argv[5], INT32_MAX, &h) < 0 || h == 0))
		return gen_bad_usage("H", argv[5], "1..2147483647");

	struct vis_scene scene;
	vis_scene_init(&scene);
	if (vis_gen(&scene, kind, (size_t)n, seed, (int32_t)w, (int32_t)h) < 0) {
		fprintf(stderr, "visctl gen: %s\n", strerror(errno));
		return errno == EINVAL ? VISCTL_EXIT_USAGE : VISCTL_EXIT_FAILURE;
	}

	/*
	 * Format in chunks through views of the scene, so a huge scene never needs its whole text
	 * in memory; only the first chunk carries the screen line.
	 */
	struct out *o = out_create("visctl gen");
	int ret = VISCTL_EXIT_FAILURE;
	if (o == NULL)
		goto out;
	size_t i = 0;
	do {
		struct vis_scene part = scene;
		size_t m = scene.n - i < GEN_CHUNK ? scene.n - i : GEN_CHUNK;
		char *text;
		size_t len;

		part.has_screen = scene.has_screen && i == 0;
		part.ids = m ? scene.ids + i : NULL;
		part.rects = m ? scene.rects + i : NULL;
		part.n = part.cap = m;
		if (vis_scene_format(&part, &text, &len) < 0) {
			fprintf(stderr, "visctl gen: %s\n", strerror(errno));
			free(o);
			goto out;
		}
		out_put(o, text, len);
		free(text);
		i += m;
	} while (i < scene.n && o->error == 0);
	ret = out_finish(o);
	free(o);
out:
	vis_scene_finish(&scene);
	return ret;
}
