/* The input every engine reads: a z-ordered stack of rectangles and an optional screen. */
#ifndef VIS_STACK_H
#define VIS_STACK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rect.h"

/*
 * Visibility states, numbered as X11's VisibilityNotify states.
 * unobscured: every pixel of the whole, unclipped window is visible (a window partly off-screen
 * never is); fully-obscured: no pixel is visible (a window entirely off-screen always is);
 * partially-obscured: otherwise.
 */
enum vis_state {
	VIS_UNOBSCURED = 0,
	VIS_PARTIALLY_OBSCURED = 1,
	VIS_FULLY_OBSCURED = 2,
	VIS_NO_STATE = 3, /* an input-only window: it has no pixels to see */
};

struct vis_look;

/*
 * A stack of n windows, rects[0] at the bottom, rects[n - 1] on top. With has_screen, only
 * pixels inside the screen [0, screen_w) × [0, screen_h) can be visible; without, nothing clips.
 * see_through, unless NULL, marks the rectangles that hide nothing (see_through[i] != 0): their
 * own states are asked as any other's, but windows below them show through. A translucent
 * window's pixels are such rectangles (look.h); NULL means every rectangle is opaque.
 * looks, unless NULL, gives each window a border, a shape, an opaque region or no pixels at all
 * (look.h): vis_compute() cuts such windows into rectangles for the engines, which themselves take
 * only stacks without looks.
 */
struct vis_stack {
	const struct vis_rect *rects;
	size_t n;
	bool has_screen;
	int32_t screen_w, screen_h; /* ≥ 1 when has_screen */
	const uint8_t *see_through;
	const struct vis_look *looks;
};

/* Whether rectangle i hides what lies below it. O(1). */
static inline bool vis_stack_opaque(const struct vis_stack *stack, size_t i)
{
	return stack->see_through == NULL || !stack->see_through[i];
}

/* The state's name: "unobscured", "partially-obscured" or "fully-obscured". O(1). */
const char *vis_state_name(enum vis_state state);

/* The box a window's visible pixels must lie in: its own, clipped to the screen. O(1). */
struct vis_box vis_stack_clip(const struct vis_stack *stack, size_t i);

/* Whether window i lies wholly on the screen (always true without a screen). O(1). */
bool vis_stack_on_screen(const struct vis_stack *stack, size_t i);

#endif
