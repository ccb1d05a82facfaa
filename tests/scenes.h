/* Scenes for the tests: the standard generators plus nasty ones aimed at the semantics' edges. */
#ifndef VIS_TEST_SCENES_H
#define VIS_TEST_SCENES_H

#include <stddef.h>
#include <stdint.h>

#include "scene.h"

/*
 * Kinds 0 … VIS_GEN_KIND_COUNT - 1 are vis_gen()'s (random, uniform, grid, cascade, tiles,
 * nested, shaped, translucent); the rest are nasty:
 *   dup         identical rectangles
 *   abut        windows on a coarse lattice: shared edges, abutting windows
 *   cover       windows covered exactly by abutting windows above (split in x, in y, 2×2,
 *               L-shaped), sometimes with one pixel left free
 *   tiny        1×1 windows around the edges of others
 *   edge        off-screen windows, windows touching the screen from outside, ending exactly
 *               at W or H, exactly the screen's size
 *   limits      coordinates near the int32 limits (x = INT32_MIN, x + w above INT32_MAX,
 *               w = INT32_MAX), mostly without a screen
 *   tinyscreen  a screen of 3×2 … 8×8 with small windows around it, so many edges coincide
 *   mix         all of the above in one stack
 *   looks       mix's windows with looks: borders, shapes and opaque regions cutting the border
 *               box into abutting pieces (or all but a pixel of it), empty shapes, translucent
 *               and input-only windows
 */
#define SCENES_KIND_COUNT 17

/* The kind's name. */
const char *scenes_kind_name(unsigned kind);

/* Looks a kind up by name; returns 0, or -1 when unknown. */
int scenes_kind_from_name(const char *name, unsigned *kind);

/*
 * Fills an initialized, empty scene with n windows of the kind (IDs 1…n bottom-to-top),
 * the same for the same seed on every machine. Returns 0, or -1 with errno set.
 */
int scenes_make(struct vis_scene *scene, unsigned kind, size_t n, uint64_t seed);

#endif
