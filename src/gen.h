/* Scene generators: deterministic for a seed, used by `visctl gen`, the tests and the benchmark. */
#ifndef VIS_GEN_H
#define VIS_GEN_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

#define VIS_GEN_SCREEN_W 3840
#define VIS_GEN_SCREEN_H 2160

/*
 * Scene kinds:
 *   random   desktop-like windows on the screen, some partly or fully off-screen
 *   uniform  random rectangles with coordinates up to 10^6, no screen unless one is given
 *   grid     the paper's Figure 1: n/2 thin horizontal bars above n/2 thin vertical bars
 *   cascade  windows cascading down and right, each offset from the one below
 *   tiles    a tiled desktop with overlapping popups on top
 *   nested   many small windows under a few large ones
 *   shaped   random's windows, two in five with rounded corners, one in five L-shaped, three in
 *            ten with a border of 1–3 pixels (look.h)
 *   translucent  random's windows, a third with client-side shadows (a translucent margin of
 *            8–40 pixels around an opaque inside), one in twenty wholly translucent
 */
enum vis_gen_kind {
	VIS_GEN_RANDOM,
	VIS_GEN_UNIFORM,
	VIS_GEN_GRID,
	VIS_GEN_CASCADE,
	VIS_GEN_TILES,
	VIS_GEN_NESTED,
	VIS_GEN_SHAPED,
	VIS_GEN_TRANSLUCENT,
};

#define VIS_GEN_KIND_COUNT 8

/* The kind's name. O(1). */
const char *vis_gen_kind_name(enum vis_gen_kind kind);

/* Looks a kind up by name; returns 0, or -1 when unknown. O(1). */
int vis_gen_kind_from_name(const char *name, enum vis_gen_kind *kind);

/*
 * Fills an initialized, empty scene with n windows of the kind, IDs 1…n bottom-to-top.
 * screen_w and screen_h (0 for the default 3840×2160) size the screen. Returns 0, or -1 (ENOMEM,
 * or EINVAL for a size out of range). O(n).
 */
int vis_gen(struct vis_scene *scene, enum vis_gen_kind kind, size_t n, uint64_t seed,
	    int32_t screen_w, int32_t screen_h);

#endif
