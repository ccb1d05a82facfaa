#ifndef VISCTL_PROC_CPU_H
#define VISCTL_PROC_CPU_H

#include <sys/types.h>

/*
 * A process's CPU time in seconds, every thread's; < 0 when unreadable. From the threads'
 * /proc/PID/task/TID/schedstat, in nanoseconds, when the kernel has it: /proc/PID/stat, the
 * fallback, counts clock ticks (10 ms), too coarse for short runs (a 0.2 s run could read 120%
 * of a core).
 */
double proc_cpu_seconds(pid_t pid);

#endif
