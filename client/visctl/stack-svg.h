/*
 * Pictures of a window stack, as SVG: the screen, every window outlined in the colour of its
 * state (fully-obscured ones dashed), its visible parts filled, its ID as a label. `visctl
 * compute --svg` draws a scene, `visctl snapshot --svg` the daemon's tree.
 */
#ifndef VISCTL_STACK_SVG_H
#define VISCTL_STACK_SVG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "rect.h"
#include "stack.h"

/* Past this many windows a picture has no labels or tooltips: they could not be read anyway. */
#define STACK_SVG_MAX_LABELS 5000

/*
 * One window of a picture. box is absolute (screen coordinates; x1, y1 inclusive, x2, y2
 * exclusive). Its visible parts are the picture's parts[first … first + n_parts), absolute too.
 */
struct stack_svg_window {
	uint32_t id;
	uint32_t parent; /* 0: the screen */
	uint8_t state;   /* enum vis_state */
	struct vis_box box;   /* the border box */
	struct vis_box inside; /* the inside: box, less the border */
	size_t first, n_parts;
	/* Its pixels when it has a shape or translucent pixels: pixels[first_px …] (n_px = 0: the
	 * whole box, opaque). */
	size_t first_px, n_px;
	bool translucent; /* some pixels hide nothing, which ones unknown (snapshots): faint fill */
};

/* A piece of a window's pixels, absolute, and whether it hides what lies below it. */
struct stack_svg_pixels {
	struct vis_box box;
	bool see_through;
};

/*
 * A picture: windows bottom to top, each drawn over the ones before it. Without a screen it
 * shows the windows' bounding box. Invariant: the windows' parts are disjoint ranges of parts.
 * has_parts is false when the visible parts are unknown (then only outlines are drawn, and note
 * says why).
 */
struct stack_svg {
	const char *title; /* the caller's; the first line of the picture */
	bool has_screen;
	int64_t screen_w, screen_h;
	struct stack_svg_window *windows;
	size_t n, cap;
	struct vis_box *parts;
	size_t n_parts, cap_parts;
	struct stack_svg_pixels *pixels;
	size_t n_pixels, cap_pixels;
	bool has_parts;
	char note[400]; /* what the picture leaves out, shown under the legend */
};

/* Starts an empty picture without a screen; title must outlive it. */
void stack_svg_init(struct stack_svg *p, const char *title);

/* Frees the picture's arrays. */
void stack_svg_finish(struct stack_svg *p);

/* Appends a window on top, without visible parts yet. Returns 0, or -1 (ENOMEM). */
int stack_svg_add(struct stack_svg *p, uint32_t id, uint32_t parent, struct vis_box box,
		  uint8_t state);

/*
 * Gives the last window added a piece of its pixels (for shaped and translucent windows; pieces
 * disjoint, added in order). Returns 0, or -1 (ENOMEM).
 */
int stack_svg_add_pixels(struct stack_svg *p, struct vis_box box, bool see_through);

/*
 * Makes room for window i's n visible parts (replacing any it had) and returns where the caller
 * writes them, valid until the next call; NULL (ENOMEM, or EOVERFLOW).
 */
struct vis_box *stack_svg_parts(struct stack_svg *p, size_t i, size_t n);

/* Adds a sentence to the note under the legend (printf-style; cut short when full). */
void stack_svg_note(struct stack_svg *p, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/*
 * Finds the visible parts of every window of stack, whose rectangle k belongs to the picture's
 * window window_of[k] (NULL: window k), in the same order: the stack walked top-down, each
 * rectangle's screen-clipped box minus the union of the opaque ones above (pixman regions, on the
 * edges' ranks so that any coordinates fit). The work is capped so that huge or fragmented scenes
 * stay fast: past the cap, has_parts becomes false and the note says so. Returns 0, or -1
 * (ENOMEM, EOVERFLOW).
 */
int stack_svg_find_parts(struct stack_svg *p, const struct vis_stack *stack,
			 const uint32_t *window_of);

/* Writes the picture as a standalone SVG document. Returns 0, or -1 when f has an error. O(n + parts). */
int stack_svg_write(const struct stack_svg *p, FILE *f);

#endif
