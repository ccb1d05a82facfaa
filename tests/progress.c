/* Waits that follow the CPU time of the processes doing the work (progress.h). */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "progress.h"

double progress_clock_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

long long progress_cpu_ticks(pid_t pid)
{
	char path[64], line[1024];
	snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
	FILE *f = fopen(path, "r");
	if (!f)
		return -1;
	size_t n = fread(line, 1, sizeof line - 1, f);
	fclose(f);
	line[n] = '\0';
	/* The name, in parentheses, may hold anything: the fields start after its last ')'. */
	const char *p = strrchr(line, ')');
	char state;
	unsigned long long utime, stime;
	if (!p || sscanf(p + 1, " %c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &state,
			 &utime, &stime) != 3 || state == 'Z' || state == 'X')
		return -1;
	return (long long)(utime + stime);
}

/* The ticks all of them have used, or -1 (naming the one gone in p->why). */
static long long sum_ticks(struct progress *p)
{
	long long sum = 0;
	for (size_t i = 0; i < p->n; i++) {
		long long t = progress_cpu_ticks(p->pid[i]);
		if (t < 0) {
			snprintf(p->why, sizeof p->why, "process %d is gone", (int)p->pid[i]);
			return -1;
		}
		sum += t;
	}
	return sum;
}

void progress_begin(struct progress *p, const pid_t *pids, size_t n)
{
	memset(p, 0, sizeof *p);
	for (size_t i = 0; i < n && p->n < PROGRESS_MAX_PIDS; i++)
		if (pids[i] > 0)
			p->pid[p->n++] = pids[i];
	p->start_ms = p->moved_ms = progress_clock_ms();
	p->cpu = sum_ticks(p);
}

bool progress_stopped(struct progress *p)
{
	double now = progress_clock_ms();
	long long cpu = sum_ticks(p);
	if (cpu < 0)
		return true;
	if (cpu != p->cpu) {
		p->cpu = cpu;
		p->moved_ms = now;
	}
	if (now - p->moved_ms >= PROGRESS_STALL_MS) {
		snprintf(p->why, sizeof p->why, "no progress for %d s (no CPU time used)",
			 PROGRESS_STALL_MS / 1000);
		return true;
	}
	if (now - p->start_ms >= PROGRESS_CEILING_MS) {
		snprintf(p->why, sizeof p->why, "still working after %d s",
			 PROGRESS_CEILING_MS / 1000);
		return true;
	}
	return false;
}
