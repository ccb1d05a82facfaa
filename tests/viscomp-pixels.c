/*
 * The pixel checks of test-viscomp-pixels.sh, in C because a shell takes minutes over the 300,000
 * pixels of a shot that this reads in milliseconds.
 *
 *   viscomp-pixels check SHOT.ppm BACKGROUND
 * reads the windows, top first, from standard input, one a line: ID X Y W H RRGGBB STATE (the
 * window's box in the shot, x, y inclusive, x + w, y + h exclusive; its solid colour; the state
 * viscomp's libvis gave it). Every pixel of the shot must be the colour of the topmost window
 * whose box holds it, or BACKGROUND (RRGGBB) where none does; a window with no pixel on top
 * must show none of its colour; and each window's state must be what its pixels on top make it:
 * fully-obscured for none, unobscured for all of its box, partially-obscured in between. What
 * no output shows is a window too, as in viscomp's model, with "-" for its colour: on top of
 * all, it covers what lies below it, and its pixels (grim's fill between outputs) are not checked;
 * the shot's own edges are the outputs' outer ones.
 *
 *   viscomp-pixels same A.ppm B.ppm
 * The two shots must be equal, pixel for pixel.
 *
 * Both print what they found, up to a few wrong pixels, and exit 0 when it holds, 1 when it does
 * not, 2 for bad input. SHOT is what grim writes: binary PPM (P6), maxval 255.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_SIDE 16384
#define MAX_WINDOWS 64
#define MAX_SHOWN 5 /* wrong pixels printed */

struct shot {
	int width, height;
	unsigned char *rgb; /* width * height * 3 bytes, rows top to bottom */
};

struct window {
	long id;
	int x, y, width, height;
	unsigned int color; /* 0xRRGGBB */
	bool outside; /* what no output shows: colour "-", its pixels unchecked */
	char state[32];
	long on_top, shown; /* pixels it is the topmost window at; pixels of its colour */
};

/* Reads one decimal field of a PPM header, skipping white space and comments; -1 on error. */
static long header_field(FILE *f)
{
	int c;
	for (;;) {
		c = getc(f);
		if (c == '#') {
			while (c != '\n' && c != EOF)
				c = getc(f);
		} else if (c != ' ' && c != '\t' && c != '\n' && c != '\r') {
			break;
		}
	}
	long v = 0;
	if (c < '0' || c > '9')
		return -1;
	for (; c >= '0' && c <= '9'; c = getc(f)) {
		v = v * 10 + (c - '0');
		if (v > MAX_SIDE)
			return -1;
	}
	return c == ' ' || c == '\t' || c == '\n' || c == '\r' ? v : -1; /* one white space ends it */
}

/* Reads a P6 PPM; 0, or -1 with the reason printed. */
static int shot_read(struct shot *shot, const char *path)
{
	FILE *f = fopen(path, "rb");
	if (f == NULL) {
		fprintf(stderr, "viscomp-pixels: %s: %s\n", path, strerror(errno));
		return -1;
	}
	long w = -1, h = -1, max = -1;
	if (getc(f) == 'P' && getc(f) == '6') {
		w = header_field(f);
		h = header_field(f);
		max = header_field(f);
	}
	if (w <= 0 || h <= 0 || max != 255) {
		fprintf(stderr, "viscomp-pixels: %s: not a P6 PPM of 8-bit samples\n", path);
		fclose(f);
		return -1;
	}
	/* w, h ≤ MAX_SIDE: the size fits a size_t with room to spare. */
	size_t size = (size_t)w * (size_t)h * 3;
	shot->rgb = malloc(size);
	if (shot->rgb == NULL || fread(shot->rgb, 1, size, f) != size) {
		fprintf(stderr, "viscomp-pixels: %s: short or unreadable\n", path);
		free(shot->rgb);
		fclose(f);
		return -1;
	}
	fclose(f);
	shot->width = (int)w, shot->height = (int)h;
	return 0;
}

static uint32_t pixel_at(const struct shot *shot, int x, int y)
{
	const unsigned char *p = shot->rgb + ((size_t)y * (size_t)shot->width + (size_t)x) * 3;
	return (uint32_t)p[0] << 16 | (uint32_t)p[1] << 8 | p[2];
}

/* Reads the window lines from stdin; their count, or -1 with the reason printed. */
static int read_windows(struct window *windows)
{
	char line[256];
	int n = 0;
	while (fgets(line, sizeof(line), stdin) != NULL) {
		if (n == MAX_WINDOWS) {
			fprintf(stderr, "viscomp-pixels: more than %d windows\n", MAX_WINDOWS);
			return -1;
		}
		struct window *w = &windows[n];
		memset(w, 0, sizeof(*w));
		char color[8];
		if (sscanf(line, "%ld %d %d %d %d %7s %31s", &w->id, &w->x, &w->y, &w->width,
			   &w->height, color, w->state) != 7 ||
		    w->width <= 0 || w->height <= 0) {
			fprintf(stderr, "viscomp-pixels: bad window line: %s", line);
			return -1;
		}
		char *end;
		w->outside = strcmp(color, "-") == 0;
		w->color = (unsigned int)strtoul(color, &end, 16);
		if (!w->outside && (strlen(color) != 6 || *end != '\0')) {
			fprintf(stderr, "viscomp-pixels: bad window line: %s", line);
			return -1;
		}
		for (int i = 0; i < n && !w->outside; i++) {
			if (!windows[i].outside && windows[i].color == w->color) {
				fprintf(stderr, "viscomp-pixels: windows %ld and %ld share %06x\n",
					windows[i].id, w->id, w->color);
				return -1;
			}
		}
		n++;
	}
	return n;
}

/* The state a window's pixels on top give it, in visctl's names. */
static const char *state_of(const struct window *w)
{
	if (w->on_top == 0)
		return "fully-obscured";
	if (w->on_top == (long)w->width * w->height)
		return "unobscured";
	return "partially-obscured";
}

/* check: every pixel against the windows' boxes and stacking, and the states against both. */
static int check(const struct shot *shot, uint32_t background)
{
	static struct window windows[MAX_WINDOWS];
	int n = read_windows(windows);
	if (n < 0)
		return 2;
	long wrong = 0;
	for (int y = 0; y < shot->height; y++) {
		for (int x = 0; x < shot->width; x++) {
			struct window *top = NULL;
			for (int i = 0; i < n && top == NULL; i++) {
				struct window *w = &windows[i];
				if (x >= w->x && x - w->x < w->width && y >= w->y && y - w->y < w->height)
					top = w;
			}
			uint32_t want = top ? top->color : background;
			uint32_t got = pixel_at(shot, x, y);
			if (top != NULL)
				top->on_top++;
			if (top != NULL && top->outside)
				continue;
			for (int i = 0; i < n; i++)
				if (!windows[i].outside && windows[i].color == got)
					windows[i].shown++;
			if (got == want)
				continue;
			if (wrong++ < MAX_SHOWN) {
				printf("pixel %d,%d is %06x, not %06x (", x, y, got, want);
				if (top != NULL)
					printf("window %ld's)\n", top->id);
				else
					printf("the background)\n");
			}
		}
	}
	int failed = wrong > 0;
	if (wrong > MAX_SHOWN)
		printf("... %ld wrong pixels in all\n", wrong);
	for (int i = 0; i < n; i++) {
		struct window *w = &windows[i];
		if (w->outside)
			continue;
		const char *want = state_of(w);
		bool bad_state = strcmp(w->state, want) != 0, hidden_shows = w->on_top == 0 && w->shown;
		printf("window %ld %d,%d %dx%d %06x: %ld pixels on top, %ld of its colour shown; %s%s%s\n",
		       w->id, w->x, w->y, w->width, w->height, w->color, w->on_top, w->shown,
		       w->state, bad_state ? ", its pixels make it " : "", bad_state ? want : "");
		if (hidden_shows)
			printf("window %ld is covered wholly, yet %ld pixels show its colour\n", w->id,
			       w->shown);
		failed |= bad_state || hidden_shows;
	}
	return failed;
}

/* same: the two shots pixel for pixel; the differing ones counted and their bounds printed. */
static int same(const struct shot *a, const struct shot *b)
{
	if (a->width != b->width || a->height != b->height) {
		printf("the shots differ in size: %dx%d, %dx%d\n", a->width, a->height, b->width,
		       b->height);
		return 1;
	}
	long differ = 0;
	int x1 = a->width, y1 = a->height, x2 = -1, y2 = -1;
	for (int y = 0; y < a->height; y++) {
		for (int x = 0; x < a->width; x++) {
			uint32_t pa = pixel_at(a, x, y), pb = pixel_at(b, x, y);
			if (pa == pb)
				continue;
			if (differ++ < MAX_SHOWN)
				printf("pixel %d,%d is %06x, then %06x\n", x, y, pa, pb);
			x1 = x < x1 ? x : x1, y1 = y < y1 ? y : y1;
			x2 = x > x2 ? x : x2, y2 = y > y2 ? y : y2;
		}
	}
	if (differ > 0)
		printf("%ld pixels differ, within %d,%d %dx%d\n", differ, x1, y1, x2 - x1 + 1,
		       y2 - y1 + 1);
	return differ > 0;
}

int main(int argc, char **argv)
{
	static const char usage[] = "usage: viscomp-pixels check SHOT.ppm RRGGBB < WINDOWS\n"
				    "       viscomp-pixels same A.ppm B.ppm\n";
	struct shot a = { 0 }, b = { 0 };
	int rc = 2;
	if (argc == 4 && strcmp(argv[1], "check") == 0) {
		char *end;
		unsigned long background = strtoul(argv[3], &end, 16);
		if (*argv[3] == '\0' || *end != '\0' || background > 0xffffff)
			fputs(usage, stderr);
		else if (shot_read(&a, argv[2]) == 0)
			rc = check(&a, (uint32_t)background);
	} else if (argc == 4 && strcmp(argv[1], "same") == 0) {
		if (shot_read(&a, argv[2]) == 0 && shot_read(&b, argv[3]) == 0)
			rc = same(&a, &b);
	} else {
		fputs(usage, stderr);
	}
	free(a.rgb);
	free(b.rgb);
	return rc;
}
