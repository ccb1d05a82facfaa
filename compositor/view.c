#include <stdlib.h>

#include <vis/vis.h>
#include <wlr/types/wlr_cursor.h>
#include <wlr/types/wlr_output_layout.h>
#include <wlr/types/wlr_seat.h>
#include <wlr/types/wlr_xdg_shell.h>
#include <wlr/util/edges.h>
#include <wlr/util/log.h>

#include "model.h"
#include "server.h"
#include "view.h"

/* The cascade: each new view 32 pixels right and down of the last, from 32, 32 of the first
 * output, back to the corner when the next would not fit. */
#define CASCADE_STEP 32

struct view *view_from_id(struct server *server, uint32_t id)
{
	struct view *view;
	wl_list_for_each(view, &server->views, link)
		if (view->id == id)
			return view;
	return NULL;
}

struct view *view_from_surface(struct wlr_surface *surface)
{
	/* Up through subsurfaces to a role surface, then up through popups to the toplevel. */
	for (int depth = 0; surface != NULL && depth < 64; depth++) {
		surface = wlr_surface_get_root_surface(surface);
		if (!wlr_surface_is_xdg_surface(surface))
			return NULL;
		struct wlr_xdg_surface *xdg = wlr_xdg_surface_from_wlr_surface(surface);
		if (xdg == NULL)
			return NULL;
		if (xdg->role == WLR_XDG_SURFACE_ROLE_TOPLEVEL)
			return xdg->data;
		if (xdg->role != WLR_XDG_SURFACE_ROLE_POPUP || xdg->popup == NULL)
			return NULL;
		surface = xdg->popup->parent;
	}
	return NULL;
}

void view_box(const struct view *view, int32_t *x, int32_t *y, int32_t *width, int32_t *height)
{
	struct wlr_box geo;
	wlr_xdg_surface_get_geometry(view->xdg, &geo);
	*x = view->x, *y = view->y, *width = geo.width, *height = geo.height;
}

int view_state(const struct view *view)
{
	struct model_surface *ms = model_surface_from_wlr(view->xdg->surface);
	return ms ? model_surface_state(ms) : VIS_VISIBILITY_NONE;
}

/* Puts a window where view_sync() wants it, unless it is there already: a restack damages the
 * window in libvis (a recompute and a repaint), and views restack on every commit. */
static void restack(struct model_surface *ms, struct model_surface *ref, bool above)
{
	if (ms->stack_ref == ref && ms->stack_above == above)
		return;
	if (vis_win_restack(ms->win, ref->win, above) < 0) {
		wlr_log_errno(WLR_ERROR, "vis_win_restack");
		return;
	}
	ms->stack_ref = ref, ms->stack_above = above;
	/* What shows there may have changed: a subsurface put above a sibling that hid it. */
	if (ms->mapped)
		server_damage_box(ms->model->server, ms->x, ms->y, ms->width, ms->height);
}

struct sync {
	struct view *view;
	int32_t ox, oy; /* the toplevel surface's origin on the screen */
};

/* Places one surface of a view's (wlroots' iteration: bottom to top, origin-relative). */
static void sync_surface(struct wlr_surface *surface, int sx, int sy, void *data)
{
	struct sync *sync = data;
	struct view *view = sync->view;
	struct model_surface *ms = model_surface_from_wlr(surface);
	if (ms == NULL)
		return;
	ms->view = view;
	/* Visited ones move to the end in drawing order; unvisited ones are left at the front. */
	wl_list_remove(&ms->view_link);
	wl_list_insert(view->surfaces.prev, &ms->view_link);
	ms->stamp = view->sync_stamp;
	model_surface_place(ms, sync->ox + sx, sync->oy + sy, true);
}

/* Forgets a surface that left its view (an unmapped popup or subsurface, a dead toplevel). */
static void drop_surface(struct model_surface *ms)
{
	if (ms->win != NULL)
		model_surface_place(ms, ms->x, ms->y, false);
	wl_list_remove(&ms->view_link);
	wl_list_init(&ms->view_link);
	ms->view = NULL;
	ms->stack_ref = NULL;
}

void view_sync(struct view *view)
{
	struct model_surface *ms, *tmp;
	if (!view->mapped) {
		wl_list_for_each_safe(ms, tmp, &view->surfaces, view_link)
			drop_surface(ms);
		return;
	}
	struct wlr_box geo;
	wlr_xdg_surface_get_geometry(view->xdg, &geo);
	struct sync sync = { view, view->x - geo.x, view->y - geo.y };
	view->sync_stamp++;
	wlr_xdg_surface_for_each_surface(view->xdg, sync_surface, &sync);
	wl_list_for_each_safe(ms, tmp, &view->surfaces, view_link)
		if (ms->stamp != view->sync_stamp)
			drop_surface(ms);

	/* Each window right above the one before it, around the toplevel's, which stays put. */
	struct model_surface *anchor = model_surface_from_wlr(view->xdg->surface);
	if (anchor == NULL || anchor->win == NULL || anchor->view != view)
		return;
	for (ms = anchor; ms->view_link.prev != &view->surfaces;) {
		struct model_surface *below = wl_container_of(ms->view_link.prev, below, view_link);
		if (below->win != NULL)
			restack(below, ms, false);
		ms = below;
	}
	for (ms = anchor; ms->view_link.next != &view->surfaces;) {
		struct model_surface *above = wl_container_of(ms->view_link.next, above, view_link);
		if (above->win != NULL)
			restack(above, ms, true);
		ms = above;
	}
}

void view_surface_committed(struct server *server, struct model_surface *ms)
{
	struct view *view = view_from_surface(ms->surface);
	if (view == NULL || !view->mapped)
		return;
	uint64_t now = server_now_ms();
	rate_add(&view->commits, now);
	view->commits_total++;
	view_sync(view);
	/* What the client drew, where it shows. Not at all where no pixel of it could be seen at
	 * the last update: a covered client drawing at its own rate would have the screen redraw
	 * its cover at that rate, for nothing. Whatever uncovers it since damages what it
	 * uncovers (a move, a resize, an unmap, a restack, an opaque region's change: model.c and
	 * here), and that repaint draws its buffer as it is then. */
	if (model_surface_state(ms) == VIS_VISIBILITY_FULLY_OBSCURED)
		return;
	pixman_region32_t damage;
	pixman_region32_init(&damage);
	wlr_surface_get_effective_damage(ms->surface, &damage);
	int n = 0;
	const pixman_box32_t *boxes = pixman_region32_rectangles(&damage, &n);
	for (int i = 0; i < n && ms->mapped; i++)
		server_damage_box(server, ms->x + boxes[i].x1, ms->y + boxes[i].y1,
				  boxes[i].x2 - boxes[i].x1, boxes[i].y2 - boxes[i].y1);
	pixman_region32_fini(&damage);
	/* Its frame callbacks are answered at the next frame of an output that shows it; none
	 * while it cannot be seen (model_update() asks a frame the moment it can again). */
	if (ms->mapped && model_surface_visible(ms) &&
	    !wl_list_empty(&ms->surface->current.frame_callback_list))
		server_schedule_frames(server, ms->x, ms->y, ms->width, ms->height);
}

void view_surface_destroyed(struct server *server, struct model_surface *ms)
{
	(void)server;
	if (ms->view == NULL)
		return;
	struct model_surface *other;
	wl_list_for_each(other, &ms->view->surfaces, view_link)
		if (other->stack_ref == ms)
			other->stack_ref = NULL;
}

/* Places a new view: the next step of the cascade on the first output. */
static void place(struct view *view)
{
	struct server *server = view->server;
	struct wlr_box geo;
	wlr_xdg_surface_get_geometry(view->xdg, &geo);
	struct wlr_box area = { 0, 0, 1280, 720 };
	struct wlr_box *first = wlr_output_layout_get_box(server->layout, NULL);
	if (first != NULL && first->width > 0)
		area = *first;
	int32_t step = CASCADE_STEP * (server->cascade + 1);
	if (step + geo.width > area.width || step + geo.height > area.height) {
		server->cascade = 0;
		step = CASCADE_STEP;
	}
	server->cascade++;
	view->x = area.x + step;
	view->y = area.y + step;
	view->placed = true;
}

void view_move(struct view *view, int32_t x, int32_t y)
{
	view->x = x, view->y = y;
	view_sync(view);
}

void view_resize(struct view *view, int32_t width, int32_t height)
{
	wlr_xdg_toplevel_set_size(view->xdg, (uint32_t)width, (uint32_t)height);
}

/* Damages all the view's surfaces show: a restack changes what shows there. */
static void damage_view(struct view *view)
{
	struct model_surface *ms;
	wl_list_for_each(ms, &view->surfaces, view_link)
		if (ms->mapped)
			server_damage_box(view->server, ms->x, ms->y, ms->width, ms->height);
}

void view_raise(struct view *view)
{
	struct model *model = &view->server->model;
	wl_list_remove(&view->link);
	wl_list_insert(view->server->views.prev, &view->link);
	/* Each right below the outside in drawing order: on top of all, their own order kept. */
	struct model_surface *ms;
	wl_list_for_each(ms, &view->surfaces, view_link)
		if (ms->win != NULL)
			vis_win_restack(ms->win, model->outside, 0);
	view_sync(view);
	damage_view(view);
}

void view_lower(struct view *view)
{
	wl_list_remove(&view->link);
	wl_list_insert(&view->server->views, &view->link);
	struct model_surface *ms;
	wl_list_for_each_reverse(ms, &view->surfaces, view_link)
		if (ms->win != NULL)
			vis_win_lower(ms->win);
	view_sync(view);
	damage_view(view);
}

void view_close(struct view *view)
{
	wlr_xdg_toplevel_send_close(view->xdg);
}

void view_focus(struct view *view)
{
	struct server *server = view ? view->server : NULL;
	if (view == NULL)
		return;
	struct wlr_seat *seat = server->seat;
	struct view *old = server->focused;
	if (old != NULL && old != view)
		wlr_xdg_toplevel_set_activated(old->xdg, false);
	server->focused = view;
	view_raise(view);
	wlr_xdg_toplevel_set_activated(view->xdg, true);
	struct wlr_keyboard *keyboard = wlr_seat_get_keyboard(seat);
	if (keyboard != NULL)
		wlr_seat_keyboard_notify_enter(seat, view->xdg->surface, keyboard->keycodes,
					       keyboard->num_keycodes, &keyboard->modifiers);
}

struct view *view_at(struct server *server, double lx, double ly, struct wlr_surface **surface,
		     double *sx, double *sy)
{
	struct view *view;
	wl_list_for_each_reverse(view, &server->views, link) {
		if (!view->mapped)
			continue;
		struct wlr_box geo;
		wlr_xdg_surface_get_geometry(view->xdg, &geo);
		double vx = lx - (view->x - geo.x), vy = ly - (view->y - geo.y);
		struct wlr_surface *s = wlr_xdg_surface_surface_at(view->xdg, vx, vy, sx, sy);
		if (s != NULL) {
			*surface = s;
			return view;
		}
	}
	return NULL;
}

/* A toplevel is mapped: placed once, on top, focused. */
static void handle_map(struct wl_listener *listener, void *data)
{
	(void)data;
	struct view *view = wl_container_of(listener, view, map);
	if (!view->placed)
		place(view);
	view->mapped = true;
	wl_list_remove(&view->link);
	wl_list_insert(view->server->views.prev, &view->link);
	view_sync(view);
	view_focus(view);
}

/* A toplevel is unmapped: its surfaces leave the model's screen; the focus moves on. */
static void handle_unmap(struct wl_listener *listener, void *data)
{
	(void)data;
	struct view *view = wl_container_of(listener, view, unmap);
	view->mapped = false;
	view_sync(view);
	struct server *server = view->server;
	if (server->grab.view == view)
		server->grab.view = NULL;
	if (server->focused == view) {
		server->focused = NULL;
		/* The focus goes to the topmost view left. */
		struct view *next;
		wl_list_for_each_reverse(next, &server->views, link) {
			if (next != view && next->mapped) {
				view_focus(next);
				break;
			}
		}
	}
}

/* A toplevel is destroyed. */
static void handle_destroy(struct wl_listener *listener, void *data)
{
	(void)data;
	struct view *view = wl_container_of(listener, view, destroy);
	view->mapped = false;
	view_sync(view);
	if (view->server->focused == view)
		view->server->focused = NULL;
	if (view->server->grab.view == view)
		view->server->grab.view = NULL;
	wl_list_remove(&view->link);
	wl_list_remove(&view->map.link);
	wl_list_remove(&view->unmap.link);
	wl_list_remove(&view->destroy.link);
	wl_list_remove(&view->request_move.link);
	wl_list_remove(&view->request_resize.link);
	free(view);
}

/* Starts a pointer grab (input.c follows it) when the client asks with a button press. */
static void begin_grab(struct view *view, uint32_t edges)
{
	struct server *server = view->server;
	if (server->focused != view || server->cursor == NULL)
		return;
	server->grab.view = view;
	server->grab.edges = edges;
	server->grab.grab_x = server->cursor->x;
	server->grab.grab_y = server->cursor->y;
	view_box(view, &server->grab.x, &server->grab.y, &server->grab.width,
		 &server->grab.height);
}

/* The client asks for an interactive move (its title bar was dragged). */
static void handle_request_move(struct wl_listener *listener, void *data)
{
	(void)data;
	struct view *view = wl_container_of(listener, view, request_move);
	begin_grab(view, 0);
}

/* The client asks for an interactive resize (its border was dragged). */
static void handle_request_resize(struct wl_listener *listener, void *data)
{
	struct wlr_xdg_toplevel_resize_event *event = data;
	struct view *view = wl_container_of(listener, view, request_resize);
	begin_grab(view, event->edges ? event->edges : WLR_EDGE_BOTTOM | WLR_EDGE_RIGHT);
}

/* A popup or a subsurface went away without a commit of its view: the views sync at idle. */
static void sync_all(void *data)
{
	struct server *server = data;
	struct view *view;
	wl_list_for_each(view, &server->views, link)
		view_sync(view);
}

struct popup {
	struct server *server;
	struct wl_listener unmap;
	struct wl_listener destroy;
};

/* A popup is unmapped. */
static void popup_unmap(struct wl_listener *listener, void *data)
{
	(void)data;
	struct popup *popup = wl_container_of(listener, popup, unmap);
	wl_event_loop_add_idle(popup->server->loop, sync_all, popup->server);
}

/* A popup is destroyed. */
static void popup_destroy(struct wl_listener *listener, void *data)
{
	(void)data;
	struct popup *popup = wl_container_of(listener, popup, destroy);
	wl_event_loop_add_idle(popup->server->loop, sync_all, popup->server);
	wl_list_remove(&popup->unmap.link);
	wl_list_remove(&popup->destroy.link);
	free(popup);
}

/* Keeps a new popup on the output its toplevel's corner is on (as the client's positioner
 * allows): a menu cut by the screen's edge helps no one. */
static void unconstrain(struct wlr_xdg_surface *xdg)
{
	struct view *view = view_from_surface(xdg->popup->parent);
	if (view == NULL)
		return;
	struct server *server = view->server;
	struct wlr_output *output = wlr_output_layout_output_at(server->layout, view->x, view->y);
	struct wlr_box *box = output ? wlr_output_layout_get_box(server->layout, output) : NULL;
	if (box == NULL)
		return;
	/* In the toplevel surface's coordinates, which wlroots wants. */
	struct wlr_box geo;
	wlr_xdg_surface_get_geometry(view->xdg, &geo);
	struct wlr_box area = { box->x - view->x + geo.x, box->y - view->y + geo.y, box->width,
				box->height };
	wlr_xdg_popup_unconstrain_from_box(xdg->popup, &area);
}

/* A new xdg surface: a toplevel becomes a view; a popup is kept on screen and followed. */
static void handle_new_xdg_surface(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, new_xdg_surface);
	struct wlr_xdg_surface *xdg = data;
	if (xdg->role == WLR_XDG_SURFACE_ROLE_POPUP) {
		unconstrain(xdg);
		struct popup *popup = calloc(1, sizeof(*popup));
		if (popup == NULL)
			return;
		popup->server = server;
		popup->unmap.notify = popup_unmap;
		wl_signal_add(&xdg->events.unmap, &popup->unmap);
		popup->destroy.notify = popup_destroy;
		wl_signal_add(&xdg->events.destroy, &popup->destroy);
		return;
	}
	if (xdg->role != WLR_XDG_SURFACE_ROLE_TOPLEVEL)
		return;
	struct view *view = calloc(1, sizeof(*view));
	if (view == NULL) {
		wlr_log(WLR_ERROR, "out of memory for a view");
		return;
	}
	view->server = server;
	view->xdg = xdg;
	view->id = ++server->next_view_id;
	xdg->data = view;
	wl_list_init(&view->surfaces);
	wl_list_insert(server->views.prev, &view->link);
	view->map.notify = handle_map;
	wl_signal_add(&xdg->events.map, &view->map);
	view->unmap.notify = handle_unmap;
	wl_signal_add(&xdg->events.unmap, &view->unmap);
	view->destroy.notify = handle_destroy;
	wl_signal_add(&xdg->events.destroy, &view->destroy);
	view->request_move.notify = handle_request_move;
	wl_signal_add(&xdg->toplevel->events.request_move, &view->request_move);
	view->request_resize.notify = handle_request_resize;
	wl_signal_add(&xdg->toplevel->events.request_resize, &view->request_resize);
}

void view_init(struct server *server)
{
	server->new_xdg_surface.notify = handle_new_xdg_surface;
	wl_signal_add(&server->xdg_shell->events.new_surface, &server->new_xdg_surface);
}
