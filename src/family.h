/*
 * A family of scenes with continuous parameters, drawn at random: the scenes an engine choice is
 * judged on, which nobody tuned it for (`visctl bench --family`). Deterministic for a seed.
 */
#ifndef VIS_FAMILY_H
#define VIS_FAMILY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "rng.h"
#include "scene.h"

/* The most centres a clustered member has. */
#define VIS_FAMILY_CLUSTERS_MAX 12

/* Where windows go. */
enum vis_family_place {
	VIS_FAMILY_SCATTER, /* anywhere in the area */
	VIS_FAMILY_CLUSTER, /* around a few centres */
	VIS_FAMILY_CASCADE, /* each a step from the one below, wrapping at the area's edge */
	VIS_FAMILY_LATTICE, /* on a lattice of the median size: abutting, stacked where they repeat */
};

/*
 * One member: n windows in an area of w × h (the screen when screen, else the extent the windows
 * are placed in, nothing clipping them). Window sides are log-normal, the width's median size·w
 * and the height's size·h/aspect... (see vis_family_gen()), with sigma spread; a share thin of
 * the windows are bars 1-4 pixels thin, across or down (the paper's grid when it is large); a
 * share out lies partly outside the area. With snap > 1, corners and sides are multiples of snap:
 * shared edges and identical rectangles.
 */
struct vis_family {
	size_t n;
	bool screen;
	int32_t w, h;
	double size, spread, aspect, thin, out;
	enum vis_family_place place;
	uint32_t clusters;    /* cluster: how many centres */
	double cluster_sigma; /* cluster: their spread, a share of the area's side */
	int32_t step_x, step_y; /* cascade */
	int32_t snap;
};

/* Draws a member's parameters, n log-uniform in [min_n, max_n] (min_n ≥ 1). */
void vis_family_draw(struct vis_rng *rng, size_t min_n, size_t max_n, struct vis_family *f);

/* Fills an initialized, empty scene with the member's windows, from seed. 0, or -1 (ENOMEM). */
int vis_family_gen(struct vis_scene *scene, const struct vis_family *f, uint64_t seed);

/* The parameters as one line of text (as many bytes as snprintf would write). */
int vis_family_describe(const struct vis_family *f, char *buf, size_t len);

#endif
