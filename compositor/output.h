/*
 * Outputs: each renders its frames from the model's repaint sets over its damage, and answers
 * the frame callbacks of the surfaces it shows a pixel of, and of no others.
 */
#ifndef VISCOMP_OUTPUT_H
#define VISCOMP_OUTPUT_H

#include <stdint.h>
#include <wayland-server-core.h>

struct server;

struct output {
	struct server *server;
	struct wlr_output *wlr_output;
	struct wlr_output_damage *damage;
	struct wl_list link; /* server.outputs */
	uint64_t frames; /* frames rendered and committed */
	struct wl_listener frame;
	struct wl_listener destroy;
};

/* Listens for the backend's outputs: each is enabled in its preferred mode, laid out left to
 * right, and rendered from then on. */
void output_init(struct server *server);

#endif
