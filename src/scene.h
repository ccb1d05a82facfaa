/* Scenes: a stack of windows with IDs, read from and written to the text scene format. */
#ifndef VIS_SCENE_H
#define VIS_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "look.h"
#include "stack.h"

/*
 * A scene: n windows bottom-to-top, ids[i] naming rects[i]; IDs are unique.
 * Text format, one record a line ('#' starts a comment, blank lines ignored, CRLF accepted):
 *   screen W H            optional, at most once, before any window; 1 ≤ W, H ≤ INT32_MAX
 *   window ID X Y W H     ID 0…UINT32_MAX, X and Y signed 32-bit, 1 ≤ W, H ≤ INT32_MAX;
 *                         X Y the border box's corner, W H the inside, as X has them
 * Later windows are higher in the stack. Optional records after a window's line give it a look
 * (look.h), each at most once:
 *   border B              0 ≤ B, the border box's sides within INT32_MAX
 *   shape X,Y,W,H …       its bounding shape, in window coordinates; none: an empty shape
 *   opaque none|all       which of its pixels hide what lies below (default all)
 *   opaque X,Y,W,H …      those inside these rectangles
 *   input-only            no pixels, no state (no border, shape or opaque record)
 */
struct vis_scene {
	bool has_screen;
	int32_t screen_w, screen_h;
	size_t n, cap;
	uint32_t *ids;
	struct vis_rect *rects;
	struct vis_look *looks; /* NULL while every window is plain; else one a window */
};

/* Where and why parsing failed: line is 1-based (0 when no line is to blame). */
struct vis_scene_error {
	size_t line;
	char reason[160];
};

/* Makes an empty scene without a screen. O(1). */
void vis_scene_init(struct vis_scene *scene);

/* Frees the scene's arrays and leaves it empty. O(1). */
void vis_scene_finish(struct vis_scene *scene);

/* Appends a window on top; the caller keeps IDs unique. Returns 0, or -1 (ENOMEM). Amortized O(1). */
int vis_scene_push(struct vis_scene *scene, uint32_t id, struct vis_rect rect);

/*
 * Window i's look, for changing it: the scene makes room for looks on first use, so this may fail
 * (NULL, ENOMEM). Rectangle arrays set in it belong to the scene, freed with malloc's free(). O(n)
 * the first time, else O(1).
 */
struct vis_look *vis_scene_look(struct vis_scene *scene, size_t i);

/* The engines' view of the scene (valid while the scene is unchanged). O(1). */
struct vis_stack vis_scene_stack(const struct vis_scene *scene);

/*
 * Parses len bytes of scene text into an initialized, empty scene. Returns 0; or -1 with err
 * saying where and why (the scene is then emptied). O(n log n) (duplicate IDs are found by sorting).
 */
int vis_scene_parse(struct vis_scene *scene, const char *text, size_t len,
		    struct vis_scene_error *err);

/*
 * Writes the scene as text into a newly allocated, NUL-terminated buffer (*out, *len without the
 * NUL). Returns 0, or -1 (ENOMEM). O(n).
 */
int vis_scene_format(const struct vis_scene *scene, char **out, size_t *len);

#endif
