/*
 * libFuzzer target: the scene parser on arbitrary text. A scene that parses must keep the
 * format's promises (unique IDs, sizes of at least 1, a screen only when one was given) and read
 * back equal from its own formatted text; a refusal must name a line of the input and give a
 * printable reason, and leave the scene empty.
 */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int compare_ids(const void *a, const void *b)
{
	uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
	return (x > y) - (x < y);
}

/* How many times needle occurs in text[0, len). */
static size_t count(const char *text, size_t len, const char *needle)
{
	size_t n = 0, k = strlen(needle);
	for (const char *p = text; (p = memmem(p, len - (size_t)(p - text), needle, k)); p += k)
		n++;
	return n;
}

/* Checks a scene that parsed from text[0, len). */
static void check_scene(const struct vis_scene *s, const char *text, size_t len)
{
	assert(s->n <= count(text, len, "window"));
	assert(s->n <= s->cap && (s->n == 0 || (s->ids && s->rects)));
	assert(!s->has_screen || (count(text, len, "screen") && s->screen_w >= 1 && s->screen_h >= 1));
	assert(s->has_screen || (s->screen_w == 0 && s->screen_h == 0));
	for (size_t i = 0; i < s->n; i++)
		assert(s->rects[i].w >= 1 && s->rects[i].h >= 1);
	if (s->n) {
		uint32_t *ids = malloc(s->n * sizeof(*ids));
		assert(ids);
		memcpy(ids, s->ids, s->n * sizeof(*ids));
		qsort(ids, s->n, sizeof(*ids), compare_ids);
		for (size_t i = 1; i < s->n; i++)
			assert(ids[i - 1] != ids[i]);
		free(ids);
	}

	/* Formatted, the scene reads back the same. */
	char *out;
	size_t out_len;
	assert(vis_scene_format(s, &out, &out_len) == 0 && strlen(out) == out_len);
	struct vis_scene back;
	struct vis_scene_error err;
	vis_scene_init(&back);
	assert(vis_scene_parse(&back, out, out_len, &err) == 0);
	assert(back.n == s->n && back.has_screen == s->has_screen);
	assert(back.screen_w == s->screen_w && back.screen_h == s->screen_h);
	assert(s->n == 0 || (memcmp(back.ids, s->ids, s->n * sizeof(*s->ids)) == 0 &&
			     memcmp(back.rects, s->rects, s->n * sizeof(*s->rects)) == 0));
	vis_scene_finish(&back);
	free(out);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	/* An exact copy: the parser gets no NUL after the text, so ASan sees reads past the end. */
	char *text = malloc(size ? size : 1);
	assert(text);
	memcpy(text, data, size);

	struct vis_scene s;
	struct vis_scene_error err;
	vis_scene_init(&s);
	memset(&err, 0x55, sizeof(err));
	if (vis_scene_parse(&s, text, size, &err) == 0) {
		check_scene(&s, text, size);
	} else {
		size_t lines = 1 + count(text, size, "\n");
		size_t len = strnlen(err.reason, sizeof(err.reason));
		assert(len > 0 && len < sizeof(err.reason));
		for (size_t i = 0; i < len; i++)
			assert(err.reason[i] >= 0x20 && err.reason[i] < 0x7f);
		assert(err.line >= 1 || errno == ENOMEM);
		assert(err.line <= lines);
		assert(s.n == 0 && !s.ids && !s.rects && !s.has_screen);
	}
	vis_scene_finish(&s);
	free(text);
	return 0;
}
