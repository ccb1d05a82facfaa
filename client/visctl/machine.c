/* The machine and the date a benchmark names, read once for its table or plot. */
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "machine.h"

void machine_describe(struct machine *m)
{
	FILE *f = fopen("/proc/cpuinfo", "r");
	char line[512];
	time_t t = time(NULL);
	struct tm tm;

	snprintf(m->cpu, sizeof(m->cpu), "unknown CPU");
	while (f != NULL && fgets(line, sizeof(line), f) != NULL) {
		char *colon = strchr(line, ':');

		/* x86 says "model name", some ARM kernels only "Hardware" or "Processor". */
		if (colon == NULL || (strncmp(line, "model name", 10) != 0 &&
				      strncmp(line, "Processor", 9) != 0))
			continue;
		colon += strspn(colon + 1, " \t") + 1;
		colon[strcspn(colon, "\n")] = '\0';
		snprintf(m->cpu, sizeof(m->cpu), "%s", colon);
		break;
	}
	if (f != NULL)
		fclose(f);
	m->ncpu = sysconf(_SC_NPROCESSORS_ONLN);
	if (localtime_r(&t, &tm) == NULL ||
	    strftime(m->date, sizeof(m->date), "%Y-%m-%d %H:%M %Z", &tm) == 0)
		snprintf(m->date, sizeof(m->date), "unknown date");
}
