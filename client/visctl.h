/* visctl's subcommands: each takes its own argv (argv[0] is the subcommand's name). */
#ifndef VISCTL_H
#define VISCTL_H

/* Exit statuses shared by every subcommand. */
#define VISCTL_EXIT_OK 0
#define VISCTL_EXIT_FAILURE 1 /* a runtime error: out of memory, a write error, … */
#define VISCTL_EXIT_USAGE 2   /* bad usage or bad input */

/* `visctl compute`: reads a scene and prints every window's visibility state. */
int cmd_compute(int argc, char **argv);

/* `visctl gen`: writes a generated scene to stdout. */
int cmd_gen(int argc, char **argv);

/* `visctl bench`: times the engines on generated scenes. */
int cmd_bench(int argc, char **argv);

#endif
