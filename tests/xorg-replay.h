/*
 * xorg-replay: a `visctl stress --record` script replayed on an X server, measured as visctl
 * stress measures visd, and X's states checked against the record's final states (xorg-replay.c
 * says how). Shared by the script reader (xorg-replay-script.c), the X side (xorg-replay-x.c) and
 * the options and report (xorg-replay.c).
 */
#ifndef VIS_TESTS_XORG_REPLAY_H
#define VIS_TESTS_XORG_REPLAY_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/types.h>

#include "histogram.h"
#include "rect.h"

/* The operations a record may hold that X can replay one request each (no batches or looks). */
enum replay_kind {
	REPLAY_MOVE,
	REPLAY_RESIZE,
	REPLAY_RAISE,
	REPLAY_LOWER,
	REPLAY_RESTACK,
	REPLAY_MAP,
	REPLAY_UNMAP,
};
#define REPLAY_KINDS 7

/* The kind's name, as the record spells it ("stack" for a restack). */
const char *replay_kind_name(enum replay_kind kind);

/* One operation on the window in slot (creation order, from 0: the record's @slot+1). */
struct replay_op {
	enum replay_kind kind;
	bool above;        /* restack: above the sibling (else below it) */
	uint32_t slot, sibling;
	int32_t a, b;      /* move: x, y; resize: width, height */
};

/*
 * A record, read and checked. Invariants: every window and every place and size it takes fits
 * X's 16 bits (edges within -32768..32767, sizes 1..65535); slots and siblings are < n; want[k]
 * is the final state of window k (enum vis_visibility), VIS_VISIBILITY_NONE exactly for the
 * windows the operations leave unmapped.
 */
struct replay_script {
	int32_t screen_w, screen_h;
	uint32_t n;
	struct vis_rect *rects; /* the windows as created, bottom to top */
	struct replay_op *ops;
	size_t n_ops;
	uint8_t *want;
	uint32_t *order;        /* the stacking order the operations leave, bottom to top */
	struct vis_rect *end;   /* each window's rectangle as the operations leave it */
	uint64_t seed;
};

/*
 * Reads the record at path (a `visctl stress --record` file of the kinds above). 0; 1 when the
 * file cannot be read; 2 when it is not such a record or does not fit X, after saying why on
 * stderr as PATH:LINE: reason. The caller frees with replay_script_finish().
 */
int replay_script_read(const char *path, struct replay_script *s);
void replay_script_finish(struct replay_script *s);

/* What one replay measured, as visctl stress measures a run. */
struct replay_result {
	uint64_t ops, notices, ops_without_notices; /* notices: the operations' VisibilityNotify */
	uint64_t kind_ops[REPLAY_KINDS];
	struct histogram latency, kind_latency[REPLAY_KINDS]; /* large: allocate the result */
	double seconds;           /* from the first operation's start to the last confirmation */
	double server_cpu;        /* seconds; < 0: unknown */
	double setup_seconds;     /* creating the windows, subscribing, mapping */
	uint64_t mismatches;
};

struct replay_options {
	const char *display; /* NULL: $DISPLAY */
	uint32_t clients;    /* subscribers */
	pid_t pid;           /* the X server's, for its CPU time; 0: not measured */
	bool progress;       /* a line a second on stderr */
};

/*
 * Replays the script on the X server: makes the desktop, connects the subscribers, runs the
 * operations one at a time measuring each, then checks every subscriber's last state of every
 * viewable window, and X's stacking order, against the script. 0 when it ran (r->mismatches says
 * whether the check passed), or -1 after saying why on stderr (no X server, an X error, the
 * server gone, a stall).
 */
int replay_x_run(const struct replay_options *o, const struct replay_script *s,
		 struct replay_result *r);

#endif
