/*
 * Waits that follow progress instead of guessing the machine's speed. A wait names the processes
 * doing the work it waits for (a daemon, a bridge, an X server); it goes on while they use CPU
 * time, and stops when one of them is gone, when they have used less than PROGRESS_MIN_CPU_MS of
 * it in PROGRESS_STALL_MS (the work has stopped: a hang or a deadlock; an idle X server still
 * wakes up now and then), or after PROGRESS_CEILING_MS in all (a livelock). A
 * slow but working run, a sanitizer build on a loaded machine, passes; a dead or hung one still
 * fails within the stall interval. tests/progress.sh is the same for the shell suites.
 *
 * CPU time is read from /proc (every thread's, in nanoseconds where the kernel has schedstat:
 * client/visctl/proc-cpu.c): where /proc cannot tell, a wait falls back to the stall interval
 * as a plain timeout.
 */
#ifndef VIS_TESTS_PROGRESS_H
#define VIS_TESTS_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

/* Less than PROGRESS_MIN_CPU_MS of CPU time used by the processes in PROGRESS_STALL_MS: the work
 * has stopped. */
#define PROGRESS_STALL_MS 60000
#define PROGRESS_MIN_CPU_MS 100
/* One wait in all, however busy they are (a livelock): 30 minutes, past what a loaded 2-core
 * machine takes under ASan for the longest (visd taking test-x11-faults' 20,000 windows: 150 s
 * of CPU time, at a fifth of a core). A suite whose meson timeout is shorter ends there first. */
#define PROGRESS_CEILING_MS 1800000
#define PROGRESS_MAX_PIDS 8

/* One wait under way. */
struct progress {
	pid_t pid[PROGRESS_MAX_PIDS];
	size_t n;
	double cpu_ms;	    /* the CPU time they had used when it last moved on */
	double start_ms;    /* when the wait began */
	double moved_ms;    /* when their CPU time last grew by PROGRESS_MIN_CPU_MS (or began) */
	char why[160];	    /* why the wait stopped */
};

/* Begins a wait on the processes (at most PROGRESS_MAX_PIDS; 0 entries are left out). */
void progress_begin(struct progress *p, const pid_t *pids, size_t n);
/*
 * Whether the wait must stop: false while the processes make progress; true when one is gone
 * (dead or a zombie), they made no progress for PROGRESS_STALL_MS, or the ceiling is passed,
 * with p->why saying which. Cheap: call it between short polls.
 */
bool progress_stopped(struct progress *p);
/* Whether a process is there and not a zombie. */
bool progress_alive(pid_t pid);
/*
 * The CPU time the processes have used, in milliseconds, every thread's: fine enough (schedstat's
 * nanoseconds) to tell whether they worked over a few milliseconds. Those gone count nothing.
 */
double progress_cpu_ms(const pid_t *pids, size_t n);
/* Milliseconds on the monotonic clock. */
double progress_clock_ms(void);
/* The process at the other end of a local socket (an X server's, visd's), or 0 when unknown. */
pid_t progress_peer_pid(int fd);

#endif
