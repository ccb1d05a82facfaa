/* The sweeps' preparation: clipped windows, y edges ranked onto elementary intervals, schedules. */
#ifndef VIS_EVENTS_H
#define VIS_EVENTS_H

#include <stddef.h>
#include <stdint.h>

#include "stack.h"

/*
 * The windows a sweep sees: those whose screen-clipped box is non-empty (a zero-area window would
 * otherwise be inserted and deleted at one x and reported). Kept window k (0 ≤ k < n) is stack
 * window idx[k]; idx increases with k, so k orders the kept windows by z.
 * Leaves are the elementary intervals [Y_i, Y_i+1) between distinct y edges; kept window k covers
 * leaves lo[k] … hi[k] − 1 (lo < hi ≤ nleaves).
 * The x edges are kept (x1, x2) for building schedules.
 */
struct vis_events {
	size_t n;
	uint32_t nleaves;
	uint32_t *idx;
	uint32_t *lo, *hi;
	int64_t *x1, *x2;
};

/* An event: kept window k << 1, | 1 for its deletion (right edge), | 0 for its insertion. */
#define VIS_EV_WINDOW(e) ((e) >> 1)
#define VIS_EV_IS_DELETE(e) ((e) & 1u)

/*
 * Prepares the kept windows of the stack. Returns 0, or -1 (ENOMEM; EOVERFLOW past 2^30 windows).
 * O(n) time and space beyond a radix sort of the 2n y edges (O(n) passes of 11 bits each).
 */
int vis_events_init(struct vis_events *ev, const struct vis_stack *stack);

/* Frees the arrays. O(1). */
void vis_events_finish(struct vis_events *ev);

/*
 * Writes the 2n events in sweep order into sched (room for 2n): by x, and at equal x all
 * insertions in decreasing z, then all deletions in increasing z — the only order in which no
 * intermediate state inside one x produces a report (docs/ENGINES.md, "From the paper's
 * rectangles to pixels"). Returns 0, or -1 (ENOMEM).
 * O(n) radix passes over the x edges.
 */
int vis_events_schedule(const struct vis_events *ev, uint32_t *sched);

#endif
