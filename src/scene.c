/*
 * Scenes and their text format.
 *
 * The parser is strict so that a typo in a scene file is reported rather than silently turned into
 * a different scene: numbers are plain decimal (an optional '-' for X and Y, never '+', never hex,
 * never trailing junk) and every range is checked without relying on strtol's clamping. It makes
 * one pass over the text; duplicate IDs are found afterwards by sorting (id, position) pairs, so a
 * million windows parse in a fraction of a second.
 */
#include <errno.h>
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "radix.h"
#include "scene.h"

/* The most fields a record can have; one more is kept so "got N" can count the excess. */
#define MAX_FIELDS 6

/* The longest stretch of a bad field quoted in a message, so reasons fit in vis_scene_error. */
#define QUOTE_MAX 24

/* The records that give the window above them a look: border, shape, opaque, input-only. */
enum { LOOK_BORDER, LOOK_SHAPE, LOOK_OPAQUE, LOOK_INPUT_ONLY, LOOK_RECORDS };

static const char *const look_records[LOOK_RECORDS] = { "border", "shape", "opaque",
							 "input-only" };

struct field {
	const char *s;
	size_t len;
};

/* Per-parse state that does not belong in the scene: where each window was defined. */
struct parser {
	struct vis_scene *scene;
	struct vis_scene_error *err;
	size_t line;
	size_t screen_line;    /* 0 when no screen was given */
	size_t *lines;         /* lines[i]: the line of window i */
	size_t lines_cap;
	size_t look_lines[LOOK_RECORDS]; /* the last window's look records' lines (0: none yet) */
};

/* Starts a scene with no arrays, so finish and push work on it without special cases. */
void vis_scene_init(struct vis_scene *scene)
{
	memset(scene, 0, sizeof(*scene));
}

/* Releases the arrays; leaves the scene reusable, so finishing twice is harmless. */
void vis_scene_finish(struct vis_scene *scene)
{
	for (size_t i = 0; scene->looks != NULL && i < scene->n; i++) {
		free(scene->looks[i].shape);
		free(scene->looks[i].opaque_rects);
	}
	free(scene->looks);
	free(scene->ids);
	free(scene->rects);
	vis_scene_init(scene);
}

/* Grows both arrays for at least one more window, failing cleanly if the size would overflow. */
static int scene_grow(struct vis_scene *scene)
{
	size_t cap = scene->cap ? scene->cap : 16;

	if (scene->cap != 0) {
		if (cap > SIZE_MAX / 2) {
			errno = ENOMEM;
			return -1;
		}
		cap *= 2;
	}
	if (cap > SIZE_MAX / sizeof(struct vis_rect)) {
		errno = ENOMEM;
		return -1;
	}

	/* Keep whichever array did grow: its extra room is harmless while cap stays the old one. */
	uint32_t *ids = realloc(scene->ids, cap * sizeof(*ids));
	if (ids == NULL)
		return -1;
	scene->ids = ids;
	struct vis_rect *rects = realloc(scene->rects, cap * sizeof(*rects));
	if (rects == NULL)
		return -1;
	scene->rects = rects;
	if (scene->looks != NULL) {
		struct vis_look *looks = realloc(scene->looks, cap * sizeof(*looks));
		if (looks == NULL)
			return -1;
		scene->looks = looks;
	}
	scene->cap = cap;
	return 0;
}

struct vis_look *vis_scene_look(struct vis_scene *scene, size_t i)
{
	if (scene->looks == NULL) {
		scene->looks = calloc(scene->cap ? scene->cap : 1, sizeof(*scene->looks));
		if (scene->looks == NULL) {
			errno = ENOMEM;
			return NULL;
		}
	}
	return &scene->looks[i];
}

/* Adds a window on top, growing by doubling so building a scene stays linear. */
int vis_scene_push(struct vis_scene *scene, uint32_t id, struct vis_rect rect)
{
	if (scene->n == scene->cap && scene_grow(scene) < 0)
		return -1;
	scene->ids[scene->n] = id;
	scene->rects[scene->n] = rect;
	if (scene->looks != NULL)
		memset(&scene->looks[scene->n], 0, sizeof(*scene->looks));
	scene->n++;
	return 0;
}

/* Lends the engines the scene's rectangles without copying them. */
struct vis_stack vis_scene_stack(const struct vis_scene *scene)
{
	struct vis_stack stack = {
		.rects = scene->rects,
		.n = scene->n,
		.has_screen = scene->has_screen,
		.screen_w = scene->screen_w,
		.screen_h = scene->screen_h,
		.looks = scene->looks,
	};
	return stack;
}

/* Records a reason for the current line; always returns -1 so callers can `return fail(...)`. */
static int fail(struct parser *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int fail(struct parser *p, const char *fmt, ...)
{
	va_list ap;

	p->err->line = p->line;
	va_start(ap, fmt);
	vsnprintf(p->err->reason, sizeof(p->err->reason), fmt, ap);
	va_end(ap);
	errno = EINVAL;
	return -1;
}

/* Copies a field into buf for quoting, shortened and with unprintable bytes replaced, so a binary
 * file cannot garble the terminal or overflow the reason. */
static const char *quote(struct field f, char *buf, size_t size)
{
	size_t n = f.len < size - 4 ? f.len : size - 4;

	if (n > QUOTE_MAX)
		n = QUOTE_MAX;
	for (size_t i = 0; i < n; i++) {
		unsigned char c = (unsigned char)f.s[i];
		buf[i] = c >= 0x20 && c < 0x7f ? (char)c : '?';
	}
	if (n < f.len) {
		memcpy(buf + n, "...", 3);
		n += 3;
	}
	buf[n] = '\0';
	return buf;
}

/*
 * Reads a decimal integer in [lo, hi]. Returns 0, -1 when the field is not a number, or -2 when
 * it is one but out of range. Accumulates with saturation rather than strtol so overflow can never
 * wrap and no locale or base prefix is involved.
 */
static int parse_int(struct field f, int64_t lo, int64_t hi, int64_t *out)
{
	const char *s = f.s, *end = f.s + f.len;
	bool neg = false;
	uint64_t v = 0;
	bool big = false;

	if (s < end && *s == '-') {
		neg = true;
		s++;
	}
	if (s == end)
		return -1;
	for (; s < end; s++) {
		if (*s < '0' || *s > '9')
			return -1;
		if (v > (UINT64_MAX - 9) / 10)
			big = true;
		else
			v = v * 10 + (uint64_t)(*s - '0');
	}
	if (big || v > (uint64_t)INT64_MAX)
		return -2;
	int64_t x = neg ? -(int64_t)v : (int64_t)v;
	if (x < lo || x > hi)
		return -2;
	*out = x;
	return 0;
}

/* Parses one numeric field of a record, explaining a failure in the record's terms. */
static int parse_field(struct parser *p, const char *record, const char *name, struct field f,
		       int64_t lo, int64_t hi, int64_t *out)
{
	char q[QUOTE_MAX + 4];

	switch (parse_int(f, lo, hi, out)) {
	case 0:
		return 0;
	case -1:
		return fail(p, "%s: %s '%s' is not a number", record, name, quote(f, q, sizeof(q)));
	default:
		return fail(p, "%s: %s %s out of range %lld..%lld", record, name,
			    quote(f, q, sizeof(q)), (long long)lo, (long long)hi);
	}
}

/* Remembers the line of window n so a duplicate ID can be blamed on the right lines later. */
static int parser_note_line(struct parser *p, size_t n)
{
	if (n == p->lines_cap) {
		size_t cap = p->lines_cap ? p->lines_cap : 16;
		if (p->lines_cap != 0) {
			if (cap > SIZE_MAX / 2 / sizeof(size_t)) {
				errno = ENOMEM;
				return -1;
			}
			cap *= 2;
		}
		size_t *lines = realloc(p->lines, cap * sizeof(*lines));
		if (lines == NULL)
			return -1;
		p->lines = lines;
		p->lines_cap = cap;
	}
	p->lines[n] = p->line;
	return 0;
}

/* Handles `screen W H`. */
static int parse_screen(struct parser *p, const struct field *fields, size_t nfields)
{
	int64_t w, h;

	if (nfields != 3)
		return fail(p, "screen: expected 2 fields (W H), got %zu", nfields - 1);
	if (p->screen_line != 0)
		return fail(p, "screen given twice (first on line %zu)", p->screen_line);
	if (p->scene->n != 0)
		return fail(p, "screen after a window");
	if (parse_field(p, "screen", "W", fields[1], 1, INT32_MAX, &w) < 0 ||
	    parse_field(p, "screen", "H", fields[2], 1, INT32_MAX, &h) < 0)
		return -1;
	p->scene->has_screen = true;
	p->scene->screen_w = (int32_t)w;
	p->scene->screen_h = (int32_t)h;
	p->screen_line = p->line;
	return 0;
}

/* Handles `window ID X Y W H`. */
static int parse_window(struct parser *p, const struct field *fields, size_t nfields)
{
	int64_t id, x, y, w, h;

	if (nfields != 6)
		return fail(p, "window: expected 5 fields (ID X Y W H), got %zu", nfields - 1);
	if (parse_field(p, "window", "ID", fields[1], 0, UINT32_MAX, &id) < 0 ||
	    parse_field(p, "window", "X", fields[2], INT32_MIN, INT32_MAX, &x) < 0 ||
	    parse_field(p, "window", "Y", fields[3], INT32_MIN, INT32_MAX, &y) < 0 ||
	    parse_field(p, "window", "W", fields[4], 1, INT32_MAX, &w) < 0 ||
	    parse_field(p, "window", "H", fields[5], 1, INT32_MAX, &h) < 0)
		return -1;

	struct vis_rect r = { (int32_t)x, (int32_t)y, (int32_t)w, (int32_t)h };
	if (parser_note_line(p, p->scene->n) < 0 || vis_scene_push(p->scene, (uint32_t)id, r) < 0)
		return -1;
	memset(p->look_lines, 0, sizeof(p->look_lines));
	return 0;
}

/*
 * The next field of s[*i … len), separated by spaces and tabs, into *f, moving *i past it.
 * Returns false at the end of the line.
 */
static bool next_field(const char *s, size_t len, size_t *i, struct field *f)
{
	while (*i < len && (s[*i] == ' ' || s[*i] == '\t'))
		++*i;
	if (*i == len)
		return false;
	size_t start = *i;
	while (*i < len && s[*i] != ' ' && s[*i] != '\t')
		++*i;
	*f = (struct field){ s + start, *i - start };
	return true;
}

/*
 * Reads the rectangles "X,Y,W,H" of a shape or opaque record from s (the line after the keyword)
 * into a new array. Returns 0, or -1 with the reason.
 */
static int parse_rects(struct parser *p, const char *record, const char *s, size_t len,
		       struct vis_rect **out, uint32_t *count)
{
	static const char *const names[4] = { "X", "Y", "W", "H" };
	struct vis_rect *rects = NULL;
	size_t n = 0, cap = 0, i = 0;
	struct field rf;

	while (next_field(s, len, &i, &rf)) {
		size_t start = (size_t)(rf.s - s);
		if (n == cap) {
			cap = cap ? 2 * cap : 8;
			struct vis_rect *more = cap > UINT32_MAX ? NULL
						: realloc(rects, cap * sizeof(*rects));
			if (more == NULL) {
				free(rects);
				errno = ENOMEM;
				return -1;
			}
			rects = more;
		}
		/* Four comma-separated numbers, no spaces inside. */
		struct field f[4];
		size_t k = 0, j = start;
		for (; k < 4; k++) {
			size_t b = j;
			while (j < i && s[j] != ',')
				j++;
			f[k] = (struct field){ s + b, j - b };
			if (j == i)
				break;
			j++;
		}
		char q[QUOTE_MAX + 4], what[64];
		if (k != 3 || j != i) {
			free(rects);
			return fail(p, "%s: rectangle %zu '%s' is not X,Y,W,H", record, n + 1,
				    quote(rf, q, sizeof(q)));
		}
		int64_t v[4];
		snprintf(what, sizeof(what), "%s rectangle %zu", record, n + 1);
		for (k = 0; k < 4; k++) {
			int64_t lo = k < 2 ? INT32_MIN : 1;
			if (parse_field(p, what, names[k], f[k], lo, INT32_MAX, &v[k]) < 0) {
				free(rects);
				return -1;
			}
		}
		rects[n++] = (struct vis_rect){ (int32_t)v[0], (int32_t)v[1], (int32_t)v[2],
						(int32_t)v[3] };
	}
	*out = rects;
	*count = (uint32_t)n;
	return 0;
}

/*
 * Handles the look records (border, shape, opaque, input-only) of the window on the line above,
 * s and len being the whole line and fields its first fields.
 */
static int parse_look(struct parser *p, int which, const struct field *fields, size_t nfields,
		      const char *s, size_t len)
{
	const char *record = look_records[which];
	struct vis_scene *scene = p->scene;

	if (scene->n == 0)
		return fail(p, "%s before any window (it applies to the window above it)", record);
	if (p->look_lines[which] != 0)
		return fail(p, "%s given twice for window %" PRIu32 " (first on line %zu)", record,
			    scene->ids[scene->n - 1], p->look_lines[which]);
	struct vis_look *look = vis_scene_look(scene, scene->n - 1);
	if (look == NULL)
		return -1;
	struct vis_look was = *look;
	const char *rest = fields[0].s + fields[0].len;
	size_t rest_len = len - (size_t)(rest - s);
	int64_t b;

	switch (which) {
	case LOOK_BORDER:
		if (nfields != 2)
			return fail(p, "border: expected 1 field (B), got %zu", nfields - 1);
		if (parse_field(p, "border", "B", fields[1], 0, INT32_MAX, &b) < 0)
			return -1;
		look->border = (int32_t)b;
		break;
	case LOOK_SHAPE:
		if (parse_rects(p, "shape", rest, rest_len, &look->shape, &look->n_shape) < 0)
			return -1;
		look->shaped = true;
		break;
	case LOOK_OPAQUE:
		if (nfields == 2 && fields[1].len == 4 && memcmp(fields[1].s, "none", 4) == 0) {
			look->opaque = VIS_OPAQUE_NONE;
		} else if (nfields == 2 && fields[1].len == 3 && memcmp(fields[1].s, "all", 3) == 0) {
			look->opaque = VIS_OPAQUE_ALL;
		} else if (nfields == 1) {
			return fail(p, "opaque: expected none, all or rectangles X,Y,W,H");
		} else {
			if (parse_rects(p, "opaque", rest, rest_len, &look->opaque_rects,
					&look->n_opaque) < 0)
				return -1;
			look->opaque = VIS_OPAQUE_RECTS;
		}
		break;
	default:
		if (nfields != 1)
			return fail(p, "input-only: expected no fields, got %zu", nfields - 1);
		look->input_only = true;
		break;
	}
	const char *why = vis_look_check(scene->rects[scene->n - 1], look);
	if (why != NULL) {
		/* Undo, so the scene holds only what was accepted. */
		if (look->shape != was.shape)
			free(look->shape);
		if (look->opaque_rects != was.opaque_rects)
			free(look->opaque_rects);
		*look = was;
		return fail(p, "%s: window %" PRIu32 ": %s", record, scene->ids[scene->n - 1], why);
	}
	p->look_lines[which] = p->line;
	return 0;
}

/* Splits one line (comment already removed) into fields and parses the record, if any. */
static int parse_line(struct parser *p, const char *s, size_t len)
{
	struct field fields[MAX_FIELDS + 1], f;
	size_t nfields = 0;
	size_t i = 0;

	while (next_field(s, len, &i, &f)) {
		if (nfields <= MAX_FIELDS)
			fields[nfields] = f;
		nfields++;
	}
	if (nfields == 0)
		return 0;

	struct field rec = fields[0];
	if (rec.len == 6 && memcmp(rec.s, "window", 6) == 0)
		return parse_window(p, fields, nfields);
	if (rec.len == 6 && memcmp(rec.s, "screen", 6) == 0)
		return parse_screen(p, fields, nfields);
	for (int k = 0; k < LOOK_RECORDS; k++) {
		if (rec.len == strlen(look_records[k]) && memcmp(rec.s, look_records[k], rec.len) == 0)
			return parse_look(p, k, fields, nfields, s, len);
	}
	char q[QUOTE_MAX + 4];
	return fail(p, "unknown record '%s'", quote(rec, q, sizeof(q)));
}

/*
 * Reports the first duplicate ID in reading order among the first n windows: the one whose second
 * definition comes earliest. Returns 0 when there is none, 1 after filling err, or -1 (ENOMEM).
 */
static int find_duplicate(struct parser *p, size_t n)
{
	if (n < 2)
		return 0;
	if (n > UINT32_MAX) { /* positions are 32-bit */
		errno = ENOMEM;
		return -1;
	}
	uint64_t *id = malloc(n * sizeof(*id));
	uint32_t *pos = malloc(n * sizeof(*pos));
	if (id == NULL || pos == NULL) {
		free(id);
		free(pos);
		errno = ENOMEM;
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		id[i] = p->scene->ids[i];
		pos[i] = (uint32_t)i;
	}
	/* Stable: equal IDs stay in stack order. */
	if (vis_radix_sort(id, pos, n) < 0) {
		free(id);
		free(pos);
		return -1;
	}

	size_t best = SIZE_MAX, first = 0;
	for (size_t i = 1; i < n; i++) {
		/* Within a run of equal IDs, only the second entry can be the earliest redefinition. */
		if (id[i] == id[i - 1] && (i < 2 || id[i - 2] != id[i]) && pos[i] < best) {
			best = pos[i];
			first = pos[i - 1];
		}
	}
	free(id);
	free(pos);
	if (best == SIZE_MAX)
		return 0;
	p->line = p->lines[best];
	fail(p, "duplicate window ID %" PRIu32 " (first on line %zu)", p->scene->ids[best],
	     p->lines[first]);
	return 1;
}

/* Reads a scene line by line, stopping at the first error a reader of the file would meet. */
int vis_scene_parse(struct vis_scene *scene, const char *text, size_t len,
		    struct vis_scene_error *err)
{
	struct parser p = { .scene = scene, .err = err };
	const char *s = text, *end = text + len;
	int ret = 0;

	err->line = 0;
	err->reason[0] = '\0';
	while (s < end) {
		const char *nl = memchr(s, '\n', (size_t)(end - s));
		const char *eol = nl ? nl : end;
		size_t n = (size_t)(eol - s);

		p.line++;
		if (memchr(s, '\0', n) != NULL) {
			ret = fail(&p, "NUL byte in input");
			break;
		}
		if (n > 0 && s[n - 1] == '\r')
			n--;
		const char *hash = memchr(s, '#', n);
		if (hash != NULL)
			n = (size_t)(hash - s);
		if (parse_line(&p, s, n) < 0) {
			ret = -1;
			break;
		}
		s = nl ? nl + 1 : end;
	}

	if (ret < 0 && err->line != 0) {
		/* A duplicate on an earlier line is the first error a reader would meet. */
		struct vis_scene_error syntax = *err;
		int dup = find_duplicate(&p, scene->n);
		if (dup == 0)
			*err = syntax;
		else if (dup < 0)
			goto nomem;
	} else if (ret == 0) {
		int dup = find_duplicate(&p, scene->n);
		if (dup < 0)
			goto nomem;
		if (dup > 0)
			ret = -1;
	} else {
		goto nomem;
	}
	free(p.lines);
	if (ret < 0) {
		vis_scene_finish(scene);
		errno = EINVAL;
	}
	return ret;

nomem:
	free(p.lines);
	vis_scene_finish(scene);
	err->line = 0;
	snprintf(err->reason, sizeof(err->reason), "out of memory");
	errno = ENOMEM;
	return -1;
}

/* Writes v in decimal at p and returns the end: printf is the bottleneck at a million lines. */
static char *put_u64(char *p, uint64_t v)
{
	char tmp[20];
	size_t n = 0;

	do {
		tmp[n++] = (char)('0' + v % 10);
		v /= 10;
	} while (v != 0);
	while (n > 0)
		*p++ = tmp[--n];
	return p;
}

/* Writes a signed 32-bit value in decimal at p and returns the end. */
static char *put_i32(char *p, int32_t v)
{
	if (v < 0) {
		*p++ = '-';
		return put_u64(p, (uint64_t)-(int64_t)v);
	}
	return put_u64(p, (uint64_t)v);
}

/* The longest line: "window " plus five numbers of at most 11 characters and their separators. */
#define LINE_MAX_LEN 64

/* The longest "X,Y,W,H" with its space. */
#define RECT_MAX_LEN 48

/* Writes " X,Y,W,H" for each rectangle. */
static char *put_rects(char *p, const struct vis_rect *r, size_t n)
{
	for (size_t i = 0; i < n; i++) {
		*p++ = ' ';
		p = put_i32(p, r[i].x);
		*p++ = ',';
		p = put_i32(p, r[i].y);
		*p++ = ',';
		p = put_i32(p, r[i].w);
		*p++ = ',';
		p = put_i32(p, r[i].h);
	}
	return p;
}

/* Writes the look records of a window that has a look. */
static char *put_look(char *p, const struct vis_look *look)
{
	if (look->border != 0) {
		p = stpcpy(p, "border ");
		p = put_i32(p, look->border);
		*p++ = '\n';
	}
	if (look->input_only)
		p = stpcpy(p, "input-only\n");
	if (look->shaped) {
		p = put_rects(stpcpy(p, "shape"), look->shape, look->n_shape);
		*p++ = '\n';
	}
	if (look->opaque == VIS_OPAQUE_NONE)
		p = stpcpy(p, "opaque none\n");
	if (look->opaque == VIS_OPAQUE_RECTS) {
		p = put_rects(stpcpy(p, "opaque"), look->opaque_rects, look->n_opaque);
		*p++ = '\n';
	}
	return p;
}

/* Writes the text form into one buffer sized for the longest possible lines, shrunk at the end. */
int vis_scene_format(const struct vis_scene *scene, char **out, size_t *len)
{
	if (scene->n > (SIZE_MAX - 2 * LINE_MAX_LEN) / LINE_MAX_LEN / 5) {
		errno = ENOMEM;
		return -1;
	}
	size_t size = (scene->n + 1) * LINE_MAX_LEN + 1;
	for (size_t i = 0; scene->looks != NULL && i < scene->n; i++) {
		/* Four more lines at most, and the rectangles (each at most 2^32 − 1). */
		uint64_t rects = (uint64_t)scene->looks[i].n_shape + scene->looks[i].n_opaque;
		if (rects > (SIZE_MAX - size) / RECT_MAX_LEN - 4 * LINE_MAX_LEN) {
			errno = ENOMEM;
			return -1;
		}
		size += 4 * LINE_MAX_LEN + (size_t)rects * RECT_MAX_LEN;
	}
	char *buf = malloc(size);
	if (buf == NULL)
		return -1;

	char *p = buf;
	if (scene->has_screen) {
		p = stpcpy(p, "screen ");
		p = put_i32(p, scene->screen_w);
		*p++ = ' ';
		p = put_i32(p, scene->screen_h);
		*p++ = '\n';
	}
	for (size_t i = 0; i < scene->n; i++) {
		const struct vis_rect *r = &scene->rects[i];
		p = stpcpy(p, "window ");
		p = put_u64(p, scene->ids[i]);
		*p++ = ' ';
		p = put_i32(p, r->x);
		*p++ = ' ';
		p = put_i32(p, r->y);
		*p++ = ' ';
		p = put_i32(p, r->w);
		*p++ = ' ';
		p = put_i32(p, r->h);
		*p++ = '\n';
		if (scene->looks != NULL && !vis_look_plain(&scene->looks[i]))
			p = put_look(p, &scene->looks[i]);
	}
	*p = '\0';

	/* Give back the slack of the worst-case estimate; failing to shrink is harmless. */
	size_t used = (size_t)(p - buf);
	char *shrunk = realloc(buf, used + 1);
	*out = shrunk ? shrunk : buf;
	*len = used;
	return 0;
}
