/*
 * viscomp's server: the wlroots objects of one compositor and the lists that tie them together.
 * One server a process; every module gets it through the object it handles.
 *
 * Coordinates: layout coordinates (wlr_output_layout's) everywhere, which are also the libvis
 * tree's screen coordinates (model.h); outputs lie at x, y ≥ 0.
 */
#ifndef VISCOMP_SERVER_H
#define VISCOMP_SERVER_H

#include <stdbool.h>
#include <stdint.h>
#include <wayland-server-core.h>

#include "model.h"
#include "stats.h"

struct control;
struct mirror;

struct server {
	struct wl_display *display;
	struct wl_event_loop *loop;
	struct wlr_backend *backend;
	struct wlr_renderer *renderer;
	struct wlr_allocator *allocator;
	struct wlr_compositor *compositor;
	struct wlr_output_layout *layout;
	struct wlr_xdg_shell *xdg_shell;
	struct wlr_seat *seat;
	struct wlr_cursor *cursor;
	struct wlr_xcursor_manager *cursor_manager;

	struct model model;
	struct stats stats; /* viscompctl stats */
	struct control *control;
	struct mirror *mirror; /* --visd, or NULL */

	struct wl_list outputs;  /* output.link */
	struct wl_list views;    /* view.link, bottom to top */
	struct wl_list keyboards; /* keyboard.link (input.c) */
	struct view *focused;    /* the view with the keyboard focus, or NULL */
	uint32_t next_view_id;   /* the IDs viscompctl names views by: 1, 2, ... never reused */
	int32_t cascade;         /* how many views placed since the cascade last went back */

	/* An interactive move or resize by the pointer (input.c); view NULL when none. */
	struct {
		struct view *view;
		uint32_t edges;  /* 0: a move; else enum wlr_edges of a resize */
		double grab_x, grab_y;
		int32_t x, y, width, height; /* the view's box when the grab began */
	} grab;

	struct wl_listener new_output;
	struct wl_listener new_xdg_surface;
	struct wl_listener new_surface;
	struct wl_listener new_input;
	struct wl_listener cursor_motion;
	struct wl_listener cursor_motion_absolute;
	struct wl_listener cursor_button;
	struct wl_listener cursor_axis;
	struct wl_listener cursor_frame;
	struct wl_listener request_cursor;
	struct wl_listener request_set_selection;
};

/* Milliseconds of CLOCK_MONOTONIC, for the rates viscompctl reports. */
uint64_t server_now_ms(void);

/* Adds the screen box x, y, width × height to every output's damage it meets (layout coordinates). */
void server_damage_box(struct server *server, int32_t x, int32_t y, int32_t width, int32_t height);

/* Damages every output whole: its next frame is drawn from scratch (viscompctl redraw), what
 * the tests compare the frames drawn from damage alone with. */
void server_damage_whole(struct server *server);

/* Asks every output that meets the box for a frame, even with nothing to draw: frame callbacks
 * are answered at output frames (output.c). */
void server_schedule_frames(struct server *server, int32_t x, int32_t y, int32_t width,
			    int32_t height);

/* Sets the libvis tree's outside (what no output shows) from the outputs' boxes. */
void server_outputs_changed(struct server *server);

#endif
