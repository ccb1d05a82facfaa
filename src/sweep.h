/* The Grove–Murali–Vitter sweep: which windows have a visible pixel. */
#ifndef VIS_SWEEP_H
#define VIS_SWEEP_H

#include <stdint.h>

#include "events.h"

/*
 * Where the sweep reads top(H_v), the highest window stored at node v, from: per-node heaps
 * (sections 4–5) or offline lists of tops (section 6). Windows are named by z = k + 1 for kept
 * window k, 0 standing for "none" (the paper's −∞). The sweep calls insert and remove once per
 * canonical node of each event, in schedule order; each returns the node's new top.
 * deleted is called once before a window's removals begin.
 */
struct vis_top_source {
	uint32_t (*insert)(void *ctx, uint32_t v, uint32_t z);
	uint32_t (*remove)(void *ctx, uint32_t v, uint32_t z);
	void (*deleted)(void *ctx, uint32_t z);
	void *ctx;
};

/*
 * Runs the sweep over the events in VIS_ORDER_VISIBILITY order and writes the state of every kept
 * window k into states[ev->idx[k]]; onscreen[k] says whether k lies wholly on the screen.
 * Returns 0, or -1 (ENOMEM). O(n log n) node visits, plus what the top source costs.
 */
int vis_sweep_run(const struct vis_events *ev, const uint32_t *sched,
		  const struct vis_top_source *src, const uint8_t *onscreen, uint8_t *states);

/*
 * The sweep's whole job for one engine: events, schedule, the sweep with the given source, and
 * the three-state classification. make_source builds the source for the events and schedule;
 * free_source releases it. Returns 0, or -1 with errno.
 */
struct vis_top_source_ops {
	int (*make)(struct vis_top_source *src, const struct vis_events *ev, const uint32_t *sched);
	void (*free)(struct vis_top_source *src);
};
int vis_sweep_compute(const struct vis_stack *stack, const struct vis_top_source_ops *ops,
		      uint8_t *states);

#endif
