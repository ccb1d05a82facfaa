/*
 * Views: the xdg-shell toplevels, with their subsurfaces and popups. A view owns the placement
 * (cascade), the stacking (server.views, bottom to top) and the focus; it keeps the model's
 * windows of its surfaces in the order wlroots draws them (view_sync()).
 */
#ifndef VISCOMP_VIEW_H
#define VISCOMP_VIEW_H

#include <stdbool.h>
#include <stdint.h>
#include <wayland-server-core.h>

#include "rate.h"

struct server;
struct model_surface;
struct wlr_surface;
struct wlr_xdg_surface;

struct view {
	struct server *server;
	struct wlr_xdg_surface *xdg;
	uint32_t id;
	struct wl_list link; /* server.views, bottom to top */
	struct wl_list surfaces; /* model_surface.view_link, bottom to top, as last synced */
	bool mapped, placed;
	int32_t x, y; /* its window geometry's top-left corner, layout coordinates */
	uint32_t sync_stamp;
	struct rate commits; /* of any of its surfaces */
	struct rate frames; /* frame done events its toplevel surface was sent */
	uint64_t commits_total, frames_total; /* the same since it was created */

	struct wl_listener map;
	struct wl_listener unmap;
	struct wl_listener destroy;
	struct wl_listener request_move;
	struct wl_listener request_resize;
};

/* Listens for new xdg surfaces: toplevels become views. */
void view_init(struct server *server);

/* A surface committed: counts it for its view and places the view's surfaces again. */
void view_surface_committed(struct server *server, struct model_surface *ms);

/* A surface is being destroyed: the views forget it. */
void view_surface_destroyed(struct server *server, struct model_surface *ms);

/* Places the view's surfaces (positions, sizes, opaque regions, mapping, stacking) in the model. */
void view_sync(struct view *view);

/* The view with this ID, or NULL. */
struct view *view_from_id(struct server *server, uint32_t id);

/* The view a wlr_surface belongs to (a toplevel's, its subsurfaces', its popups'), or NULL. */
struct view *view_from_surface(struct wlr_surface *surface);

/* The view's window geometry on the screen. */
void view_box(const struct view *view, int32_t *x, int32_t *y, int32_t *width, int32_t *height);

/* The view's state: its toplevel surface's, as libvis had it at the last update. */
int view_state(const struct view *view);

void view_move(struct view *view, int32_t x, int32_t y);
/* Asks the client for this size (it answers with a commit of its own choosing). */
void view_resize(struct view *view, int32_t width, int32_t height);
void view_raise(struct view *view);
void view_lower(struct view *view);
void view_close(struct view *view);
/* Gives the view the keyboard focus and raises it. NULL: no focus. */
void view_focus(struct view *view);

/* The topmost view with a surface under the layout point lx, ly; the surface and the point in
 * its coordinates into *surface, *sx, *sy. NULL when there is none. */
struct view *view_at(struct server *server, double lx, double ly, struct wlr_surface **surface,
		     double *sx, double *sy);

#endif
