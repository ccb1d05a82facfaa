/* visctl's subcommands: each takes its own argv (argv[0] is the subcommand's name). */
#ifndef VISCTL_H
#define VISCTL_H

#include <stdbool.h>
#include <stddef.h>

#include "live.h"
#include "scene.h"

/* Exit statuses shared by every subcommand. */
#define VISCTL_EXIT_OK 0
#define VISCTL_EXIT_FAILURE 1 /* a runtime error: out of memory, a write error, the daemon said no */
#define VISCTL_EXIT_USAGE 2   /* bad usage or bad input */

/* A subcommand: offline ones have run, live ones (talking to visd) have live. */
struct visctl_command {
	const char *name;
	int (*run)(int argc, char **argv);
	live_fn live;
	const char *usage; /* the arguments, after "visctl NAME " */
	const char *help;  /* what it does and prints, for --help; NULL: the usage line alone */
};

/* The subcommand called name, or NULL. */
const struct visctl_command *visctl_command_find(const char *name);

/* Reads a whole file (or stdin for "-") into a new buffer. Returns 0, or -1 with errno set. */
int visctl_read_all(const char *path, char **data, size_t *len);

/* `visctl compute`: reads a scene and prints every window's visibility state. */
int cmd_compute(int argc, char **argv);

/* `visctl gen`: writes a generated scene to stdout. */
int cmd_gen(int argc, char **argv);

/* `visctl bench`: times the engines on generated scenes. */
int cmd_bench(int argc, char **argv);

/* `visctl plot-service` (cmd-plot-service.c): the service benchmark's latency plot. */
int cmd_plot_service(int argc, char **argv);

/* The live subcommands (cmd-live.c): one request each, then a round trip. */
int cmd_create(struct live *l, int argc, char **argv);
int cmd_destroy(struct live *l, int argc, char **argv);
int cmd_map(struct live *l, int argc, char **argv);
int cmd_unmap(struct live *l, int argc, char **argv);
int cmd_move(struct live *l, int argc, char **argv);
int cmd_resize(struct live *l, int argc, char **argv);
int cmd_raise(struct live *l, int argc, char **argv);
int cmd_lower(struct live *l, int argc, char **argv);
int cmd_border(struct live *l, int argc, char **argv);
int cmd_look(struct live *l, int argc, char **argv);
int cmd_shape(struct live *l, int argc, char **argv);
int cmd_opaque(struct live *l, int argc, char **argv);
int cmd_stack(struct live *l, int argc, char **argv);
int cmd_sync(struct live *l, int argc, char **argv);
int cmd_states(struct live *l, int argc, char **argv);
int cmd_tree(struct live *l, int argc, char **argv);
int cmd_region(struct live *l, int argc, char **argv);
int cmd_repaint(struct live *l, int argc, char **argv);
int cmd_lookup(struct live *l, int argc, char **argv);

/* `visctl load` (cmd-load.c): a scene file created as windows in one batch. */
int cmd_load(struct live *l, int argc, char **argv);

/* `visctl snapshot` (cmd-snapshot.c): draws the daemon's windows into an SVG file. */
int cmd_snapshot(struct live *l, int argc, char **argv);

/* What cmd_load_batch() heard: windows[i] (room for the scene's n) is the ID of the scene's i-th
 * window; failed says that a create failed, failed_at which one and error why. Start zeroed. */
struct load {
	uint32_t *windows;
	size_t created;
	bool failed;
	size_t failed_at;
	struct vis_error error;
};

/* Creates the scene's windows with flags (enum vis_create_flags) in one batch and waits for their
 * IDs. 0, or -1 when a create or the connection failed. */
int cmd_load_batch(struct vis_client *c, const struct vis_scene *scene, uint32_t flags,
		   struct load *ld);

/* `visctl stress` (cmd-stress.c): changes a desktop under load, measures, checks. */
int cmd_stress(struct live *l, int argc, char **argv);

/* `visctl watch` (cmd-watch.c): prints notices as they come. */
int cmd_watch(struct live *l, int argc, char **argv);

/* `visctl script` (cmd-script.c): runs live commands from a file on one connection. */
int cmd_script(struct live *l, int argc, char **argv);

#endif
