/*
 * What viscomp measures of itself, for `viscompctl stats` (the benchmarks read it): the time of
 * libvis's work in each output frame, and how long after a move, raise or lower a surface it
 * covered or uncovered had its frame callbacks withheld or answered.
 *
 * Each series keeps its last STATS_SAMPLES samples in a ring (the figures are of those) and
 * counts every sample it was ever given. A latency is timed from the moment the control command
 * arrived (stats.change_ns, taken once by the next model update that sees the surface's
 * visibility flip) to the first output frame after it in which the surface had a frame callback
 * pending and, covered, was not sent it (withheld) or, uncovered, was. Changes made otherwise
 * (a client's commit, the pointer) are not timed. Each latency is also counted in output frames:
 * the frames handled (stats.frames) from the command's arrival to that frame, that frame
 * included: 1 when it was the first frame after the command. Frames of every output count, so
 * with several outputs the count is the sum of theirs.
 */
#ifndef VISCOMP_STATS_H
#define VISCOMP_STATS_H

#include <stdint.h>

struct control_reply;

#define STATS_SAMPLES 4096

struct stats_series {
	uint64_t ns[STATS_SAMPLES]; /* ns[k % STATS_SAMPLES]: the k-th sample, in nanoseconds */
	uint32_t frames[STATS_SAMPLES]; /* and in output frames (latencies only; else 0) */
	uint64_t count; /* samples ever added */
};

struct stats {
	/* Per output frame: vis_tree_update() and the vis_tree_repaint() calls of its damage. */
	struct stats_series frame;
	struct stats_series cover, uncover; /* from the change to the first callback withheld / sent */
	uint64_t change_ns; /* when the last move, raise or lower arrived; 0 once attributed */
	uint64_t frames; /* output frames handled so far, every output's (output.c) */
	uint64_t change_frames; /* frames when the last move, raise or lower arrived */
};

/* CLOCK_MONOTONIC in nanoseconds. */
uint64_t stats_now_ns(void);

/* Adds a sample. O(1). */
void stats_add(struct stats_series *series, uint64_t ns);

/* Adds a latency: ns, and the output frames it took (1: the first frame after the change). O(1). */
void stats_add_latency(struct stats_series *series, uint64_t ns, uint32_t frames);

/* A move, raise or lower arrived at ns: its visibility flips are timed from it. O(1). */
void stats_mark_change(struct stats *stats, uint64_t ns);

/* Forgets every sample (a latency being timed goes on). O(1). */
void stats_reset(struct stats *stats);

/*
 * Writes one line a series, "NAME count=N median_us=M p99_us=P max_us=X", N every sample ever
 * added, the others of the last STATS_SAMPLES (0 when none); the latencies' lines (cover,
 * uncover) end with " max_frames=F", the most output frames of those samples.
 * O(STATS_SAMPLES log STATS_SAMPLES).
 */
void stats_report(const struct stats *stats, struct control_reply *reply);

#endif
