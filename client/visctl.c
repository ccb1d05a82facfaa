/* visctl: the command-line tool; this file only finds the subcommand and hands over argv. */
#include <stdio.h>
#include <string.h>

#include "visctl.h"

struct command {
	const char *name;
	int (*run)(int argc, char **argv);
	const char *usage;
};

static const struct command commands[] = {
	{ "compute", cmd_compute,
	  "compute [--engine=auto|gmv|gmv-heap|region|brute] [--visible] [--time] SCENE" },
	{ "gen", cmd_gen, "gen KIND N SEED [W H]" },
	{ "bench", cmd_bench, "bench [OPTIONS]  (see `visctl bench --help`)" },
};

/* Prints the list of subcommands, to stdout when asked for and to stderr after a mistake. */
static void usage(FILE *f)
{
	fprintf(f, "usage: visctl COMMAND [ARGS]\n"
		   "       visctl help\n"
		   "commands:\n");
	for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		fprintf(f, "  visctl %s\n", commands[i].usage);
	fprintf(f, "SCENE is a path or '-' for stdin; `visctl COMMAND --help` says more.\n"
		   "exit status: 0 ok, 1 runtime error, 2 usage or bad input\n");
}

/* Dispatches to the subcommand named by argv[1]; each subcommand parses its own options. */
int main(int argc, char **argv)
{
	if (argc < 2) {
		usage(stderr);
		return VISCTL_EXIT_USAGE;
	}
	const char *name = argv[1];
	if (strcmp(name, "help") == 0 || strcmp(name, "--help") == 0 || strcmp(name, "-h") == 0) {
		usage(stdout);
		return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
	}
	for (size_t i = 0; i < sizeof(commands) / sizeof(commands[0]); i++)
		if (strcmp(name, commands[i].name) == 0)
			return commands[i].run(argc - 1, argv + 1);

	if (name[0] == '-')
		fprintf(stderr, "visctl: unknown option '%s'\n", name);
	else
		fprintf(stderr, "visctl: unknown command '%s'\n", name);
	usage(stderr);
	return VISCTL_EXIT_USAGE;
}
