/* Where and when a measurement was made, for the tables and plots of visctl and bench-wtree. */
#ifndef VISCTL_MACHINE_H
#define VISCTL_MACHINE_H

/* The CPU model, the CPUs online and the local date and time ("unknown …" where unreadable). */
struct machine {
	long ncpu;
	char cpu[128];
	char date[64];
};

/* Fills m from /proc/cpuinfo, sysconf and the clock; never fails. */
void machine_describe(struct machine *m);

#endif
