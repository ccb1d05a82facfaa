#include <stdlib.h>

#include <wlr/backend.h>
#include <wlr/backend/headless.h>
#include <wlr/render/allocator.h>
#include <wlr/render/pixman.h>
#include <wlr/render/wlr_renderer.h>
#include <wlr/types/wlr_compositor.h>
#include <wlr/types/wlr_data_device.h>
#include <wlr/types/wlr_output_layout.h>
#include <wlr/types/wlr_screencopy_v1.h>
#include <wlr/types/wlr_xdg_output_v1.h>
#include <wlr/types/wlr_xdg_shell.h>
#include <wlr/util/log.h>

#include "control.h"
#include "input.h"
#include "mirror.h"
#include "output.h"
#include "server.h"
#include "server-init.h"
#include "view.h"

/* Every wl_surface is tracked by the model from its creation. */
static void handle_new_surface(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, new_surface);
	model_surface_create(&server->model, data);
}

/* The backend and renderer: headless outputs of the sizes asked, drawn by pixman (no GPU, the
 * same pixels everywhere); else what wlroots picks for where it runs (X11, Wayland, DRM). */
static int create_backend(struct server *server, const struct server_options *options)
{
	if (options->n_heads > 0) {
		server->backend = wlr_headless_backend_create(server->display);
		if (server->backend == NULL)
			return -1;
		server->renderer = wlr_pixman_renderer_create();
	} else {
		server->backend = wlr_backend_autocreate(server->display);
		if (server->backend == NULL)
			return -1;
		server->renderer = wlr_renderer_autocreate(server->backend);
	}
	if (server->renderer == NULL) {
		wlr_log(WLR_ERROR, "no renderer");
		return -1;
	}
	for (size_t i = 0; i < options->n_heads; i++) {
		if (wlr_headless_add_output(server->backend, (unsigned)options->heads[i].width,
					    (unsigned)options->heads[i].height) == NULL) {
			wlr_log(WLR_ERROR, "cannot add a headless output");
			return -1;
		}
	}
	return 0;
}

int server_init(struct server *server, const struct server_options *options)
{
	wl_list_init(&server->outputs);
	wl_list_init(&server->views);
	wl_list_init(&server->keyboards);
	server->display = wl_display_create();
	if (server->display == NULL)
		return -1;
	server->loop = wl_display_get_event_loop(server->display);
	if (model_init(&server->model, server) < 0) {
		wlr_log_errno(WLR_ERROR, "cannot create the libvis tree");
		return -1;
	}
	if (create_backend(server, options) < 0)
		return -1;
	if (!wlr_renderer_init_wl_display(server->renderer, server->display))
		return -1;
	server->allocator = wlr_allocator_autocreate(server->backend, server->renderer);
	if (server->allocator == NULL) {
		wlr_log(WLR_ERROR, "no allocator");
		return -1;
	}
	server->compositor = wlr_compositor_create(server->display, server->renderer);
	wlr_data_device_manager_create(server->display);
	server->layout = wlr_output_layout_create();
	if (server->compositor == NULL || server->layout == NULL)
		return -1;
	/* What grim needs to take a picture of the screen: the outputs' places (xdg-output) and
	 * their pixels (screencopy). */
	if (wlr_xdg_output_manager_v1_create(server->display, server->layout) == NULL ||
	    wlr_screencopy_manager_v1_create(server->display) == NULL)
		return -1;
	server->new_surface.notify = handle_new_surface;
	wl_signal_add(&server->compositor->events.new_surface, &server->new_surface);
	output_init(server);
	server->xdg_shell = wlr_xdg_shell_create(server->display);
	if (server->xdg_shell == NULL)
		return -1;
	view_init(server);
	if (input_init(server) < 0)
		return -1;
	return 0;
}

void server_finish(struct server *server)
{
	control_destroy(server->control);
	server->control = NULL;
	mirror_destroy(server->mirror);
	server->mirror = NULL;
	if (server->display != NULL) {
		wl_display_destroy_clients(server->display);
		wl_display_destroy(server->display);
	}
	/* The backend went with the display; what it drew with is ours to free. */
	wlr_allocator_destroy(server->allocator);
	wlr_renderer_destroy(server->renderer);
	input_finish(server);
	model_finish(&server->model);
	wlr_output_layout_destroy(server->layout);
}
