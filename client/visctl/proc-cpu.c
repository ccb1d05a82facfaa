/* A process's CPU time, for the benchmarks (visctl stress's visd, xorg-replay's X server). */
#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "proc-cpu.h"

double proc_cpu_seconds(pid_t pid)
{
	char path[64], buf[1024];
	double sum = 0;
	bool any = false;
	snprintf(path, sizeof(path), "/proc/%d/task", (int)pid);
	DIR *d = pid > 0 ? opendir(path) : NULL;
	for (struct dirent *e; d && (e = readdir(d));) {
		unsigned long long ns;
		if (e->d_name[0] == '.')
			continue;
		snprintf(buf, sizeof(buf), "/proc/%d/task/%.16s/schedstat", (int)pid, e->d_name);
		FILE *f = fopen(buf, "r");
		if (f && fscanf(f, "%llu", &ns) == 1) {
			sum += (double)ns / 1e9;
			any = true;
		}
		if (f)
			fclose(f);
	}
	if (d)
		closedir(d);
	if (any)
		return sum;
	snprintf(path, sizeof(path), "/proc/%d/stat", (int)pid);
	FILE *f = pid > 0 ? fopen(path, "r") : NULL;
	if (!f)
		return -1;
	size_t n = fread(buf, 1, sizeof(buf) - 1, f);
	fclose(f);
	buf[n] = '\0';
	const char *p = strrchr(buf, ')');
	unsigned long long user, sys;
	if (!p || sscanf(p + 1, " %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &user,
			 &sys) != 2)
		return -1;
	return (double)(user + sys) / (double)sysconf(_SC_CLK_TCK);
}
