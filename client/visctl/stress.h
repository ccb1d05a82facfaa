/*
 * `visctl stress`: a manager changes a desktop of generated windows while subscribers count the
 * notices, the time from each operation to the last notice it causes is measured, and at the end
 * the daemon's states must equal those of a model of the stack. Shared by the options and the
 * report (cmd-stress.c), the run (stress-run.c) and the model (stress-model.c).
 */
#ifndef VISCTL_STRESS_H
#define VISCTL_STRESS_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "gen.h"
#include "histogram.h"
#include "idmap.h"
#include "look.h"
#include "rect.h"
#include "rng.h"
#include "vis/visclient.h"

/* The operations, as --mix names them. A batch holds several changes of the other kinds. */
enum stress_kind {
	STRESS_MOVE,
	STRESS_RESIZE,
	STRESS_RAISE,
	STRESS_LOWER,
	STRESS_RESTACK,
	STRESS_MAP, /* maps an unmapped window or unmaps a mapped one */
	STRESS_BATCH,
	STRESS_BORDER, /* a new border width (configure, keeping the place and inside) */
	STRESS_SHAPE,  /* a shape: rounded corners, an L, the border box again, or none */
	STRESS_OPAQUE, /* an opaque region: all, none, or the inside of a shadow margin */
};
#define STRESS_KINDS 10
/* The most rectangles a change's shape or opaque region has. */
#define STRESS_LOOK_RECTS 5

/* The kind's name in --mix and in the reports. */
const char *stress_kind_name(enum stress_kind kind);

struct stress_options {
	const char *socket; /* NULL: the default socket */
	uint32_t clients;   /* subscribers */
	uint32_t windows;
	enum vis_gen_kind scene; /* the desktop: a kind of visctl gen without looks */
	uint64_t count;     /* operations; 0: until the duration is over */
	double duration;    /* seconds; 0: until count operations are done */
	double rate;        /* intended operations a second; 0: as fast as the pipeline allows */
	uint32_t pipeline;  /* operations sent and not yet confirmed, at most */
	uint32_t mix[STRESS_KINDS]; /* weights */
	uint32_t batch_size;        /* changes a batch */
	bool exposure;      /* subscribers also ask for exposure notices */
	uint64_t seed;
	FILE *record;       /* the operations as a visctl script, or NULL */
	pid_t pid;          /* visd's pid for CPU and memory; 0: the socket's peer */
	bool progress;      /* a progress line on stderr */
	bool progress_tty;  /* stderr is a terminal: overwrite the line in place */
	bool corrupt_model; /* for the tests: the model drifts from the daemon, which must be seen */
};

/* One request that changes the stack, on windows named by slot (creation order, from 0). */
struct stress_change {
	enum stress_kind kind; /* not STRESS_BATCH */
	bool flag;             /* map: true maps, false unmaps; restack: true above, false below */
	uint32_t slot, sibling;
	int32_t a, b; /* move: x, y; resize: width, height; border: the width */
	uint32_t mode; /* shape: 1 shaped, 0 the border box; opaque: enum vis_opaque_mode */
	uint32_t n_rects;
	struct vis_rect rects[STRESS_LOOK_RECTS]; /* shape or opaque: window coordinates */
};

/*
 * A top-level window of the model. Invariant: the windows form one doubly linked list in stacking
 * order, bottom to top, through below and above (slots; STRESS_NONE at the ends); unmapped_at
 * is the window's index in the model's unmapped array, or STRESS_NONE when it is mapped.
 */
struct stress_window {
	uint32_t id; /* the daemon's */
	struct vis_rect r;
	uint32_t below, above, unmapped_at;
	struct vis_look look; /* its arrays point into shape and opaque */
	struct vis_rect shape[STRESS_LOOK_RECTS], opaque[STRESS_LOOK_RECTS];
};
#define STRESS_NONE UINT32_MAX

/* The model of the daemon's stack, which is all the stress run's windows and nothing else. */
struct stress_model {
	struct stress_window *w;
	uint32_t n, bottom, top;
	uint32_t *unmapped, n_unmapped;
	int32_t screen_w, screen_h;
	struct vis_idmap by_id; /* daemon ID → struct stress_window */
	struct vis_rng rng;
};

/* Makes the model of n mapped windows with the rectangles given, bottom to top, on the screen; the
 * daemon's IDs come later (stress_model_set_id). 0, or -1 (ENOMEM). */
int stress_model_init(struct stress_model *m, const struct vis_rect *rects, uint32_t n,
		      int32_t screen_w, int32_t screen_h, uint64_t seed);
void stress_model_finish(struct stress_model *m);

/* Records the daemon's ID of the window in slot. 0, or -1 (ENOMEM). */
int stress_model_set_id(struct stress_model *m, uint32_t slot, uint32_t id);

/* The slot of the window the daemon calls id, or STRESS_NONE. */
uint32_t stress_model_slot(const struct stress_model *m, uint32_t id);

/* Draws a change of the kind (not a batch) on a random window and applies it to the model. */
void stress_model_change(struct stress_model *m, enum stress_kind kind, struct stress_change *c);

/* Draws a kind by the weights of the mix (weights of excluded kinds count as 0). */
enum stress_kind stress_model_kind(struct stress_model *m, const uint32_t *mix, bool no_batch);

/*
 * The state of every window, by slot, computed from the model by the engines visctl compute uses
 * (enum vis_visibility; VIS_VISIBILITY_NONE for unmapped windows). 0, or -1 (ENOMEM).
 */
int stress_model_states(const struct stress_model *m, uint8_t *states);

/*
 * Compares the daemon's tree (as get-tree gives it) with the model: order, geometry, mapped.
 * Says what differs on stderr (up to limit lines) and returns the number of differences.
 */
uint64_t stress_model_compare_tree(const struct stress_model *m,
				   const struct vis_window_info *tree, size_t n, uint64_t limit);

/* Moves the top window of the model off the screen without telling the daemon: the tests' way to
 * make the model differ. */
void stress_model_corrupt(struct stress_model *m);

/* Writes a change as a visctl script line, naming the window in slot k as @(k + 1). */
void stress_model_record(FILE *f, const struct stress_change *c);

/* What a run measured. The histograms are large: allocate the result. */
struct stress_result {
	uint64_t ops, changes, notices, ops_with_notices;
	uint64_t kind_ops[STRESS_KINDS];
	struct histogram latency, kind_latency[STRESS_KINDS];
	double seconds;    /* from the first operation to the last confirmation */
	int32_t screen_w, screen_h;
	pid_t daemon_pid;  /* 0: unknown */
	double daemon_cpu; /* seconds; < 0: unknown */
	long daemon_rss_kb, daemon_hwm_kb; /* < 0: unknown */
	double self_cpu;   /* visctl's own CPU seconds during the run */
	uint64_t mismatches;
};

/* A subscriber: its connection and what it learned from its notices. */
struct stress_sub {
	struct stress *s;
	struct vis_client *c;
	uint8_t *view; /* by slot: the last state heard of (initial states, then notices) */
	uint64_t serial, notices;
	uint64_t gap_after; /* the serial a gap followed, or 0 */
	bool gap;
	bool unread; /* its first get-states failed */
};

/* An operation sent and not yet confirmed. */
struct stress_op {
	uint64_t start, applied; /* ns */
	enum stress_kind kind;
};

/* A run in progress (stress-run.c sets it up, stress-loop.c runs the operations). */
struct stress {
	const struct stress_options *o;
	struct stress_result *r;
	struct stress_model m;
	struct vis_client *mgr;
	struct stress_sub *subs;
	/* Operations are numbered from 0 in the order sent: [confirmed, applied) have the manager's
	 * reply, [applied, sent) not yet; ring[i % pipeline] holds operation i. upto[j % pipeline]
	 * is the number of operations sent before the j-th burst's sync. */
	struct stress_op *ring;
	uint64_t *upto;
	uint64_t sent, applied, confirmed, syncs_sent, syncs_done;
	bool stopping, round;
	uint64_t round_covers; /* operations the round in flight confirms */
	uint32_t round_pending;
	uint64_t t0, now, last_notice, last_heard, last_progress;
	uint64_t room_at; /* when the pipeline last stopped being full */
	uint64_t mgr_errors;
	struct vis_error first_error;
};

/* The monotonic clock in nanoseconds. */
uint64_t stress_loop_now(void);

/* The subscribers' notice handler (data: the struct stress_sub). */
void stress_loop_notice(void *data, const struct vis_notice *n);

/* The manager's error handler (data: the struct stress): every change must succeed. */
void stress_loop_error(void *data, const struct vis_error *e);

/* Sends and receives until every operation is sent and confirmed. 0, or -1 after saying why. */
int stress_loop_run(struct stress *s);

/* Says on stderr that a connection failed (who: which one); returns -1. */
int stress_run_lost(struct vis_client *c, const char *who);

/*
 * Runs the stress test: sets up the windows and subscribers, runs the operations, checks the
 * daemon against the model. Returns 0 when it ran (mismatches say whether the check passed), or
 * -1 after saying why on stderr (the daemon unreachable, the manager role refused, a connection
 * lost).
 */
int stress_run(const struct stress_options *o, struct stress_result *r);

#endif
