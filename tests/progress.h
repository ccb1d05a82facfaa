/*
 * Waits that follow progress instead of guessing the machine's speed. A wait names the processes
 * doing the work it waits for (a daemon, a bridge, an X server); it goes on while they use CPU
 * time, and stops when one of them is gone, when none has used any for PROGRESS_STALL_MS (the
 * work has stopped: a hang or a deadlock), or after PROGRESS_CEILING_MS in all (a livelock). A
 * slow but working run, a sanitizer build on a loaded machine, passes; a dead or hung one still
 * fails within the stall interval. tests/progress.sh is the same for the shell suites.
 *
 * CPU time is read from /proc/PID/stat (utime + stime, in clock ticks): where /proc cannot tell,
 * a wait falls back to the stall interval as a plain timeout.
 */
#ifndef VIS_TESTS_PROGRESS_H
#define VIS_TESTS_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

/* No CPU time used by any of the processes for this long: the work has stopped. */
#define PROGRESS_STALL_MS 60000
/* One wait in all, however busy they are: below meson's timeouts times the sanitizer multiplier. */
#define PROGRESS_CEILING_MS 600000
#define PROGRESS_MAX_PIDS 4

/* One wait under way. */
struct progress {
	pid_t pid[PROGRESS_MAX_PIDS];
	size_t n;
	long long cpu;	    /* the ticks they had used at the last sample */
	double start_ms;    /* when the wait began */
	double moved_ms;    /* when their CPU time last grew (or the wait began) */
	char why[160];	    /* why the wait stopped */
};

/* Begins a wait on the processes (at most PROGRESS_MAX_PIDS; 0 entries are left out). */
void progress_begin(struct progress *p, const pid_t *pids, size_t n);
/*
 * Whether the wait must stop: false while the processes make progress; true when one is gone
 * (dead or a zombie), none has used CPU time for PROGRESS_STALL_MS, or the ceiling is passed,
 * with p->why saying which. Cheap: call it between short polls.
 */
bool progress_stopped(struct progress *p);
/* The CPU time a process has used, in clock ticks; -1 when it is gone or /proc cannot tell. */
long long progress_cpu_ticks(pid_t pid);
/* Milliseconds on the monotonic clock. */
double progress_clock_ms(void);

#endif
