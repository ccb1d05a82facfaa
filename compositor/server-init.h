/*
 * Setting a server up and down (server.c), apart from server.h so that the modules that only
 * use a server do not see main's options.
 */
#ifndef VISCOMP_SERVER_INIT_H
#define VISCOMP_SERVER_INIT_H

#include <stddef.h>
#include <stdint.h>

struct server;

struct server_head {
	int32_t width, height;
};

struct server_options {
	/* Headless outputs of these sizes; none: the backend wlroots picks. */
	const struct server_head *heads;
	size_t n_heads;
};

/* Creates the display, the backend, the renderer and the globals, and listens for outputs,
 * surfaces and input. Starts nothing. 0, or -1 (logged); server_finish() cleans up either way. */
int server_init(struct server *server, const struct server_options *options);

/* Destroys the clients, the display and what server_init() created. */
void server_finish(struct server *server);

#endif
