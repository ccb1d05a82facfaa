/* The visibility engines and the entry point that picks one. */
#ifndef VIS_ENGINE_H
#define VIS_ENGINE_H

#include <stdint.h>

#include "stack.h"

enum vis_engine {
	VIS_ENGINE_AUTO,     /* region method until it is forecast to cost more than the sweep */
	VIS_ENGINE_GMV,      /* section 6 sweep: offline top-of-heap lists */
	VIS_ENGINE_GMV_HEAP, /* sections 4–5 sweep: per-node max-heaps */
	VIS_ENGINE_REGION,   /* top-down pixman region subtraction, as X.Org does */
	VIS_ENGINE_BRUTE,    /* coordinate compression and painting: obviously correct, slow */
};

#define VIS_ENGINE_COUNT 5

/* The engine's name as visctl spells it ("auto", "gmv", "gmv-heap", "region", "brute"). O(1). */
const char *vis_engine_name(enum vis_engine engine);

/* Looks an engine up by name; returns 0, or -1 when the name is unknown. O(1). */
int vis_engine_from_name(const char *name, enum vis_engine *engine);

/*
 * Computes the state of every window of the stack: states[i] is that of stack->rects[i]
 * (VIS_NO_STATE for an input-only window). Windows with a look (stack->looks) are cut into their
 * opaque and see-through pieces (look.h), which the engine classifies; the engine functions below
 * take stacks without looks. Returns 0, or -1 with errno set (ENOMEM; EOVERFLOW for a stack larger
 * than the engine can index; EINVAL for a look vis_look_check() refuses). Time and space are those
 * of the engine chosen over N = the pieces (one per plain window); see each engine's function.
 */
int vis_compute(enum vis_engine engine, const struct vis_stack *stack, uint8_t *states);

/*
 * O(n log² n) time, O(n log n) space: the sweep with per-node heaps; the three states cost
 * O(n log n) more inside it. See-through rectangles are asked of the same sweep, in per-node
 * heaps of their own: O(n log² n) still.
 */
int vis_gmv_heap_compute(const struct vis_stack *stack, uint8_t *states);

/*
 * O(n log n · α(n)) time, O(n log n) space: the sweep reading offline top lists; the three states
 * cost O(n log n) more inside it. A stack with see-through rectangles costs O(n log² n): they are
 * asked of the same sweep through per-node heaps of their own (sweep-impl.h, "Queries").
 */
int vis_gmv_compute(const struct vis_stack *stack, uint8_t *states);

/*
 * Region subtraction with pixman: O(n · r) time and O(r) space, where r is the size of the union of
 * the windows above; r reaches Θ(n²) on the grid scene, and 1 once the union covers the screen.
 */
int vis_region_compute(const struct vis_stack *stack, uint8_t *states);

/*
 * The region method that gives up once its work passes budget: returns 1 then, with states partly
 * written; otherwise as above. Work, a measure of its time: per window, 1 + log2 of the union's
 * boxes for the containment test, plus the union's boxes when the window is added to it.
 */
int vis_region_compute_within(const struct vis_stack *stack, uint8_t *states, uint64_t budget);

/*
 * A hand-over is early while the region method's work is at most 1/VIS_RIVAL_EARLY of the
 * rival's: little is thrown away then, so region.c acts on a lone forecast, and auto.c measures
 * the sweep for it only where a sample fits.
 */
#define VIS_RIVAL_EARLY 4

/*
 * What the region method is weighed against: the other method's cost in units of region work,
 * or a first estimate that sharpen(), when not NULL, replaces, given the work done so far. It is
 * called at the first checkpoint where the work done or a forecast passes floor units and at
 * every checkpoint after, with handing false, and before any hand-over with handing true, the
 * hand-over being decided again on what it returns (auto measures the sweep there); it sets
 * *measured when what it returns is a measurement (region.c's rule then changes, hand_over()).
 */
struct vis_rival {
	uint64_t units, floor;
	uint64_t (*sharpen)(const struct vis_stack *stack, const void *data, uint64_t work,
			    bool handing, bool *measured);
	const void *data;
};

/*
 * The region method that gives up once its remaining work, forecast from the work it has done
 * (region.c says how), is predicted to exceed the rival's units: returns 1 then, with states
 * partly written; otherwise as vis_region_compute(). O(log n) forecasts of O(r) each.
 */
int vis_region_compute_against(const struct vis_stack *stack, uint8_t *states,
			       const struct vis_rival *rival);

/* Painting on the compressed grid: O(n³) time, O(n²) space. For tests only. */
int vis_brute_compute(const struct vis_stack *stack, uint8_t *states);

/*
 * The region method until its time reaches the gmv-heap sweep's, or half of it with the rest of
 * its work forecast to cost more, or early on a forecast; the sweep after that (auto.c). The
 * sweep's time is measured on samples of the stack once a hand-over is near. Within about 3 times
 * the faster engine's time where the sweep is measured; O(n log² n) time in the worst case.
 */
int vis_auto_compute(const struct vis_stack *stack, uint8_t *states);

/*
 * vis_auto_compute() with a sweep step priced at units_per_step units of region work instead of
 * the measured price: the tests force an early hand-over with a low one (0 or 1) and none with
 * UINT64_MAX.
 */
int vis_auto_compute_priced(const struct vis_stack *stack, uint8_t *states, uint64_t units_per_step);

#endif
