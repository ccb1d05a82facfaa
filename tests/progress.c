/* Waits that follow the CPU time of the processes doing the work (progress.h). */
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>

#include "proc-cpu.h"
#include "progress.h"

double progress_clock_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

bool progress_alive(pid_t pid)
{
	char path[64], line[1024];
	snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
	FILE *f = pid > 0 ? fopen(path, "r") : NULL;
	if (!f)
		return false;
	size_t n = fread(line, 1, sizeof line - 1, f);
	fclose(f);
	line[n] = '\0';
	/* The name, in parentheses, may hold anything: the state follows its last ')'. */
	const char *p = strrchr(line, ')');
	char state;
	return p && sscanf(p + 1, " %c", &state) == 1 && state != 'Z' && state != 'X';
}

double progress_cpu_ms(const pid_t *pids, size_t n)
{
	double sum = 0;
	for (size_t i = 0; i < n; i++) {
		double s = proc_cpu_seconds(pids[i]);
		sum += s > 0 ? s * 1e3 : 0;
	}
	return sum;
}

pid_t progress_peer_pid(int fd)
{
	struct ucred cred;
	socklen_t len = sizeof cred;
	if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) < 0 || len != sizeof cred)
		return 0;
	return cred.pid;
}

void progress_begin(struct progress *p, const pid_t *pids, size_t n)
{
	memset(p, 0, sizeof *p);
	for (size_t i = 0; i < n && p->n < PROGRESS_MAX_PIDS; i++)
		if (pids[i] > 0)
			p->pid[p->n++] = pids[i];
	p->start_ms = p->moved_ms = progress_clock_ms();
	p->cpu_ms = progress_cpu_ms(p->pid, p->n);
}

bool progress_stopped(struct progress *p)
{
	for (size_t i = 0; i < p->n; i++)
		if (!progress_alive(p->pid[i])) {
			snprintf(p->why, sizeof p->why, "process %d is gone", (int)p->pid[i]);
			return true;
		}
	double now = progress_clock_ms(), cpu = progress_cpu_ms(p->pid, p->n);
	if (cpu >= p->cpu_ms + PROGRESS_MIN_CPU_MS) {
		p->cpu_ms = cpu;
		p->moved_ms = now;
	}
	if (now - p->moved_ms >= PROGRESS_STALL_MS) {
		snprintf(p->why, sizeof p->why, "no progress for %d s (under %d ms of CPU time used)",
			 PROGRESS_STALL_MS / 1000, PROGRESS_MIN_CPU_MS);
		return true;
	}
	if (now - p->start_ms >= PROGRESS_CEILING_MS) {
		snprintf(p->why, sizeof p->why, "still working after %d s",
			 PROGRESS_CEILING_MS / 1000);
		return true;
	}
	return false;
}
