/*
 * Reads a `visctl stress --record` script for xorg-replay: its first line names the windows and
 * the screen, `create X Y W H --map` lines make the desktop bottom to top, one line an operation
 * follows (windows named @N), and `# @N STATE` comments at the end give the final states. Every
 * place and size a window takes is checked against X's 16-bit fields before anything is sent.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vis/visclient.h"
#include "xorg-replay.h"

#define MAX_WORDS 8
/* X's fields: INT16 coordinates (a window's edges are kept as such), CARD16 sizes. */
#define X_COORD_MIN (-32768)
#define X_COORD_MAX 32767
#define X_SIZE_MAX 65535

static const char *const kind_names[REPLAY_KINDS] = {
	[REPLAY_MOVE] = "move",   [REPLAY_RESIZE] = "resize",  [REPLAY_RAISE] = "raise",
	[REPLAY_LOWER] = "lower", [REPLAY_RESTACK] = "stack", [REPLAY_MAP] = "map",
	[REPLAY_UNMAP] = "unmap",
};

const char *replay_kind_name(enum replay_kind kind)
{
	return (unsigned)kind < REPLAY_KINDS ? kind_names[kind] : "?";
}

/* What the reader keeps between lines. */
struct reader {
	const char *path;
	size_t line;
	struct replay_script *s;
	size_t cap_ops;
	struct vis_rect *now;   /* each window's rectangle as the operations so far leave it */
	bool *mapped;
	uint32_t *below, *above; /* the stacking order, as a list of slots */
	uint32_t bottom, top;
	uint32_t created;
	bool header, any_state;
};
#define NONE UINT32_MAX

/* Says what is wrong at the current line; returns 2, the bad-input status. */
static int bad(struct reader *rd, const char *fmt, const char *arg)
{
	fprintf(stderr, "xorg-replay: %s:%zu: ", rd->path, rd->line);
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	return 2;
}

/* A plain decimal number (a leading '-' allowed) in [lo, hi]. 0, or -1. */
static int parse_int(const char *w, long long lo, long long hi, long long *out)
{
	const char *p = w + (*w == '-');
	long long v = 0;
	if (!*p)
		return -1;
	for (; *p; p++) {
		if (*p < '0' || *p > '9' || v > (INT64_MAX - 9) / 10)
			return -1;
		v = v * 10 + (*p - '0');
	}
	v = *w == '-' ? -v : v;
	if (v < lo || v > hi)
		return -1;
	*out = v;
	return 0;
}

/* "@N", a window the script has created: its slot. 0, or -1. */
static int parse_window(struct reader *rd, const char *w, uint32_t *slot)
{
	long long v;
	if (w[0] != '@' || parse_int(w + 1, 1, rd->created, &v) < 0)
		return -1;
	*slot = (uint32_t)(v - 1);
	return 0;
}

/* Whether X can hold the rectangle: edges within INT16, sizes within CARD16. */
static bool fits_x(struct vis_rect r)
{
	return r.x >= X_COORD_MIN && r.y >= X_COORD_MIN && r.w >= 1 && r.h >= 1 &&
	       r.w <= X_SIZE_MAX && r.h <= X_SIZE_MAX && (int64_t)r.x + r.w <= X_COORD_MAX &&
	       (int64_t)r.y + r.h <= X_COORD_MAX;
}

/* Refuses a window whose rectangle X cannot hold. 0, or 2. */
static int check_fits(struct reader *rd, uint32_t slot)
{
	struct vis_rect r = rd->now[slot];
	if (fits_x(r))
		return 0;
	fprintf(stderr,
		"xorg-replay: %s:%zu: window @%u at %d,%d size %dx%d does not fit X, which keeps a "
		"window's edges in 16 bits (%d..%d) and its size in 1..%d: record on a smaller "
		"screen\n", rd->path, rd->line, slot + 1, r.x, r.y, r.w, r.h, X_COORD_MIN,
		X_COORD_MAX, X_SIZE_MAX);
	return 2;
}

/* Takes slot k out of the stacking order. */
static void unlink_slot(struct reader *rd, uint32_t k)
{
	uint32_t b = rd->below[k], a = rd->above[k];
	if (b != NONE)
		rd->above[b] = a;
	else
		rd->bottom = a;
	if (a != NONE)
		rd->below[a] = b;
	else
		rd->top = b;
}

/* Puts slot k (unlinked) just above slot j; NONE: at the bottom. */
static void link_above(struct reader *rd, uint32_t k, uint32_t j)
{
	rd->below[k] = j;
	rd->above[k] = j == NONE ? rd->bottom : rd->above[j];
	if (rd->above[k] != NONE)
		rd->below[rd->above[k]] = k;
	else
		rd->top = k;
	if (j != NONE)
		rd->above[j] = k;
	else
		rd->bottom = k;
}

/* The first line: "# visctl stress: N windows on a WxH screen, seed S; …". 0, or 2. */
static int read_header(struct reader *rd, const char *text)
{
	unsigned n;
	int w, h;
	unsigned long long seed;
	if (sscanf(text, "# visctl stress: %u windows on a %dx%d screen, seed %llu", &n, &w, &h,
		   &seed) != 4)
		return bad(rd, "%s", "not a visctl stress record: the first line must be '# visctl "
				     "stress: N windows on a WxH screen, seed S …' (visctl stress "
				     "--record FILE writes it)");
	if (n < 1 || n > 1000000 || w < 1 || h < 1)
		return bad(rd, "%s", "the header's window count or screen is out of range");
	if (w > X_COORD_MAX || h > X_COORD_MAX)
		return bad(rd, "the screen is larger than X's %s pixels a side", "32767");
	struct replay_script *s = rd->s;
	s->n = n;
	s->screen_w = w;
	s->screen_h = h;
	s->seed = seed;
	if (!(s->rects = malloc(n * sizeof(*s->rects))) || !(rd->now = malloc(n * sizeof(*rd->now))) ||
	    !(rd->mapped = calloc(n, sizeof(*rd->mapped))) ||
	    !(rd->below = malloc(n * sizeof(*rd->below))) ||
	    !(rd->above = malloc(n * sizeof(*rd->above))) || !(s->want = malloc(n))) {
		fprintf(stderr, "xorg-replay: %s\n", strerror(ENOMEM));
		return 1;
	}
	memset(s->want, VIS_VISIBILITY_NONE, n);
	rd->header = true;
	return 0;
}

/* "# @N STATE": a final state. 0, or 2. */
static int read_comment(struct reader *rd, char **words, int nw)
{
	uint32_t slot;
	if (nw != 3 || parse_window(rd, words[1], &slot) < 0)
		return bad(rd, "'%s': a final state is '# @N STATE', N a window of the record",
			   words[1]);
	uint32_t st = 0;
	while (st < VIS_VISIBILITY_NONE && strcmp(words[2], vis_visibility_name(st)) != 0)
		st++;
	if (st == VIS_VISIBILITY_NONE)
		return bad(rd, "'%s' is not a state (unobscured, partially-obscured, fully-obscured)",
			   words[2]);
	if (rd->s->want[slot] != VIS_VISIBILITY_NONE)
		return bad(rd, "a second final state for %s", words[1]);
	rd->s->want[slot] = (uint8_t)st;
	rd->any_state = true;
	return 0;
}

/* "create X Y W H --map": the next window, on top. 0, or 2. */
static int read_create(struct reader *rd, char **words, int nw)
{
	struct replay_script *s = rd->s;
	long long v[4];
	if (s->n_ops || rd->any_state)
		return bad(rd, "%s after the operations", "create");
	if (nw != 6 || strcmp(words[5], "--map") != 0)
		return bad(rd, "%s", "a record's windows are 'create X Y W H --map'");
	if (rd->created == s->n)
		return bad(rd, "more windows than the first line's %s", "count");
	for (int i = 0; i < 4; i++)
		if (parse_int(words[i + 1], i < 2 ? INT32_MIN : 1, INT32_MAX, &v[i]) < 0)
			return bad(rd, "'%s' is not a coordinate or size", words[i + 1]);
	uint32_t k = rd->created++;
	s->rects[k] = rd->now[k] = (struct vis_rect){ (int32_t)v[0], (int32_t)v[1], (int32_t)v[2],
						       (int32_t)v[3] };
	rd->mapped[k] = true;
	link_above(rd, k, k ? k - 1 : NONE);
	return check_fits(rd, k);
}

/* Appends an operation. 0, or 1 (out of memory). */
static int push_op(struct reader *rd, const struct replay_op *op)
{
	struct replay_script *s = rd->s;
	if (s->n_ops == rd->cap_ops) {
		size_t cap = rd->cap_ops ? 2 * rd->cap_ops : 1024;
		struct replay_op *more = realloc(s->ops, cap * sizeof(*more));
		if (!more) {
			fprintf(stderr, "xorg-replay: %s\n", strerror(ENOMEM));
			return 1;
		}
		s->ops = more;
		rd->cap_ops = cap;
	}
	s->ops[s->n_ops++] = *op;
	return 0;
}

/* The number of words each operation's line has, its command included. */
static int op_words(enum replay_kind kind)
{
	switch (kind) {
	case REPLAY_MOVE:
	case REPLAY_RESIZE:
	case REPLAY_RESTACK:
		return 4;
	default:
		return 2;
	}
}

/* An operation's line, applied to the reader's copy of the stack. 0, 1 or 2. */
static int read_op(struct reader *rd, char **words, int nw)
{
	static const char *const not_replayed[] = { "batch-begin", "batch-commit", "border",
						    "shape", "opaque", "destroy" };
	for (size_t i = 0; i < sizeof(not_replayed) / sizeof(not_replayed[0]); i++)
		if (strcmp(words[0], not_replayed[i]) == 0)
			return bad(rd, "'%s' is not replayed on X: record with a --mix of move, resize, "
				       "raise, lower, restack and map only", words[0]);
	struct replay_op op = { .kind = REPLAY_KINDS };
	for (int k = 0; k < REPLAY_KINDS; k++)
		if (strcmp(words[0], kind_names[k]) == 0)
			op.kind = (enum replay_kind)k;
	if (op.kind == REPLAY_KINDS)
		return bad(rd, "unknown command '%s'", words[0]);
	if (rd->created != rd->s->n)
		return bad(rd, "'%s' before all the first line's windows are created", words[0]);
	if (rd->any_state)
		return bad(rd, "'%s' after the final states", words[0]);
	if (nw != op_words(op.kind))
		return bad(rd, "'%s' has the wrong number of arguments", words[0]);
	if (parse_window(rd, words[1], &op.slot) < 0)
		return bad(rd, "'%s' is not a window of the record (@1 … @N)", words[1]);
	long long a = 0, b = 0;
	struct vis_rect *r = &rd->now[op.slot];
	switch (op.kind) {
	case REPLAY_MOVE:
	case REPLAY_RESIZE: {
		long long lo = op.kind == REPLAY_MOVE ? INT32_MIN : 1;
		if (parse_int(words[2], lo, INT32_MAX, &a) < 0 ||
		    parse_int(words[3], lo, INT32_MAX, &b) < 0)
			return bad(rd, op.kind == REPLAY_MOVE ? "'%s' needs an x and a y"
							: "'%s' needs a width and a height of 1 or more",
				   words[0]);
		op.a = (int32_t)a;
		op.b = (int32_t)b;
		if (op.kind == REPLAY_MOVE)
			r->x = op.a, r->y = op.b;
		else
			r->w = op.a, r->h = op.b;
		int ret = check_fits(rd, op.slot);
		if (ret)
			return ret;
		break;
	}
	case REPLAY_RAISE:
		unlink_slot(rd, op.slot);
		link_above(rd, op.slot, rd->top);
		break;
	case REPLAY_LOWER:
		unlink_slot(rd, op.slot);
		link_above(rd, op.slot, NONE);
		break;
	case REPLAY_RESTACK:
		if (strcmp(words[2], "above") != 0 && strcmp(words[2], "below") != 0)
			return bad(rd, "'%s': stack @N above|below @M", words[2]);
		op.above = words[2][0] == 'a';
		if (parse_window(rd, words[3], &op.sibling) < 0 || op.sibling == op.slot)
			return bad(rd, "'%s' is not another window of the record", words[3]);
		unlink_slot(rd, op.slot);
		link_above(rd, op.slot, op.above ? op.sibling : rd->below[op.sibling]);
		break;
	case REPLAY_MAP:
	case REPLAY_UNMAP:
		rd->mapped[op.slot] = op.kind == REPLAY_MAP;
		break;
	}
	return push_op(rd, &op);
}

/* Splits a line into words in place. The number of words, or -1 past MAX_WORDS. */
static int split(char *text, char **words)
{
	int n = 0;
	for (char *p = text;;) {
		while (*p == ' ' || *p == '\t' || *p == '\r')
			p++;
		if (!*p)
			return n;
		if (n == MAX_WORDS)
			return -1;
		words[n++] = p;
		while (*p && *p != ' ' && *p != '\t' && *p != '\r')
			p++;
		if (*p)
			*p++ = '\0';
	}
}

/* One line. 0, 1 or 2. */
static int read_line(struct reader *rd, char *text)
{
	if (!rd->header)
		return read_header(rd, text);
	char *words[MAX_WORDS];
	text += strspn(text, " \t");
	if (text[0] == '#' && strncmp(text, "# @", 3) != 0)
		return 0; /* a comment, not a final state */
	int nw = split(text, words);
	if (nw < 0)
		return bad(rd, "%s", "too many words");
	if (nw == 0)
		return 0;
	if (words[0][0] == '#')
		return read_comment(rd, words, nw);
	if (strcmp(words[0], "create") == 0)
		return read_create(rd, words, nw);
	return read_op(rd, words, nw);
}

/* After the last line: every window created, and final states exactly for the mapped ones. */
static int read_end(struct reader *rd)
{
	struct replay_script *s = rd->s;
	if (!rd->header)
		return bad(rd, "%s", "empty: not a visctl stress record");
	if (rd->created != s->n)
		return bad(rd, "fewer windows than the first line's %s", "count");
	if (!rd->any_state)
		return bad(rd, "%s", "no final states ('# @N STATE' lines): the record is cut short");
	for (uint32_t k = 0; k < s->n; k++)
		if ((s->want[k] != VIS_VISIBILITY_NONE) != rd->mapped[k]) {
			fprintf(stderr, "xorg-replay: %s: window @%u is %s at the end, but %s a final "
					"state\n", rd->path, k + 1, rd->mapped[k] ? "mapped" : "unmapped",
				rd->mapped[k] ? "has no" : "has");
			return 2;
		}
	if (!(s->order = malloc(s->n * sizeof(*s->order)))) {
		fprintf(stderr, "xorg-replay: %s\n", strerror(ENOMEM));
		return 1;
	}
	uint32_t i = 0;
	for (uint32_t k = rd->bottom; k != NONE; k = rd->above[k])
		s->order[i++] = k;
	return 0;
}

int replay_script_read(const char *path, struct replay_script *s)
{
	memset(s, 0, sizeof(*s));
	FILE *f = fopen(path, "r");
	if (!f) {
		fprintf(stderr, "xorg-replay: %s: cannot read: %s\n", path, strerror(errno));
		return 1;
	}
	struct reader rd = { .path = path, .s = s, .bottom = NONE, .top = NONE };
	char *text = NULL;
	size_t cap = 0;
	ssize_t len;
	int ret = 0;
	while (!ret && (len = getline(&text, &cap, f)) >= 0) {
		rd.line++;
		if (memchr(text, '\0', (size_t)len)) {
			ret = bad(&rd, "%s", "a NUL byte: not a text file");
			break;
		}
		text[strcspn(text, "\n")] = '\0';
		ret = read_line(&rd, text);
	}
	if (!ret && ferror(f)) {
		fprintf(stderr, "xorg-replay: %s: cannot read: %s\n", path, strerror(errno));
		ret = 1;
	}
	if (!ret)
		ret = read_end(&rd);
	fclose(f);
	free(text);
	if (!ret) {
		s->end = rd.now;
		rd.now = NULL;
	}
	free(rd.now);
	free(rd.mapped);
	free(rd.below);
	free(rd.above);
	if (ret)
		replay_script_finish(s);
	return ret;
}

void replay_script_finish(struct replay_script *s)
{
	free(s->rects);
	free(s->ops);
	free(s->want);
	free(s->order);
	free(s->end);
	memset(s, 0, sizeof(*s));
}
