#include <stdlib.h>

#include <linux/input-event-codes.h>
#include <wlr/backend.h>
#include <wlr/types/wlr_cursor.h>
#include <wlr/types/wlr_data_device.h>
#include <wlr/types/wlr_input_device.h>
#include <wlr/types/wlr_keyboard.h>
#include <wlr/types/wlr_output_layout.h>
#include <wlr/types/wlr_pointer.h>
#include <wlr/types/wlr_seat.h>
#include <wlr/types/wlr_xcursor_manager.h>
#include <wlr/types/wlr_xdg_shell.h>
#include <wlr/util/edges.h>
#include <wlr/util/log.h>
#include <xkbcommon/xkbcommon.h>

#include "input.h"
#include "server.h"
#include "view.h"

struct keyboard {
	struct server *server;
	struct wlr_input_device *device;
	struct wl_list link; /* server.keyboards */
	struct wl_listener modifiers;
	struct wl_listener key;
	struct wl_listener destroy;
};

/* Focuses the bottom view: with focus raising, repeated, it goes through them all. */
static void cycle(struct server *server)
{
	struct view *view;
	wl_list_for_each(view, &server->views, link) {
		if (view->mapped && view != server->focused) {
			view_focus(view);
			return;
		}
	}
}

/* The compositor's own keys (with Alt held); true when the key was one. */
static bool handle_binding(struct server *server, xkb_keysym_t sym, uint32_t modifiers)
{
	if (sym == XKB_KEY_F4 && server->focused != NULL) {
		view_close(server->focused);
	} else if (sym == XKB_KEY_Tab || sym == XKB_KEY_ISO_Left_Tab) {
		cycle(server);
	} else if (sym == XKB_KEY_Escape && (modifiers & WLR_MODIFIER_SHIFT)) {
		wl_display_terminate(server->display);
	} else {
		return false;
	}
	return true;
}

/* Tells the focused client of a keyboard's modifiers. */
static void keyboard_modifiers(struct wl_listener *listener, void *data)
{
	(void)data;
	struct keyboard *keyboard = wl_container_of(listener, keyboard, modifiers);
	struct wlr_seat *seat = keyboard->server->seat;
	wlr_seat_set_keyboard(seat, keyboard->device);
	wlr_seat_keyboard_notify_modifiers(seat, &keyboard->device->keyboard->modifiers);
}

/* A key: the compositor's own bindings first, the focused client the rest. */
static void keyboard_key(struct wl_listener *listener, void *data)
{
	struct keyboard *keyboard = wl_container_of(listener, keyboard, key);
	struct server *server = keyboard->server;
	struct wlr_event_keyboard_key *event = data;
	struct wlr_keyboard *kb = keyboard->device->keyboard;
	const xkb_keysym_t *syms;
	int n = xkb_state_key_get_syms(kb->xkb_state, event->keycode + 8, &syms);
	uint32_t modifiers = wlr_keyboard_get_modifiers(kb);
	bool handled = false;
	if ((modifiers & WLR_MODIFIER_ALT) && event->state == WL_KEYBOARD_KEY_STATE_PRESSED)
		for (int i = 0; i < n && !handled; i++)
			handled = handle_binding(server, syms[i], modifiers);
	if (!handled) {
		wlr_seat_set_keyboard(server->seat, keyboard->device);
		wlr_seat_keyboard_notify_key(server->seat, event->time_msec, event->keycode,
					     event->state);
	}
}

/* Forgets a keyboard that went away. */
static void keyboard_destroy(struct wl_listener *listener, void *data)
{
	(void)data;
	struct keyboard *keyboard = wl_container_of(listener, keyboard, destroy);
	wl_list_remove(&keyboard->modifiers.link);
	wl_list_remove(&keyboard->key.link);
	wl_list_remove(&keyboard->destroy.link);
	wl_list_remove(&keyboard->link);
	free(keyboard);
}

/* Sets a new keyboard up: its keymap, its repeat rate, its keys for the seat. */
static void new_keyboard(struct server *server, struct wlr_input_device *device)
{
	struct keyboard *keyboard = calloc(1, sizeof(*keyboard));
	if (keyboard == NULL)
		return;
	keyboard->server = server;
	keyboard->device = device;
	/* The keymap from XKB_DEFAULT_* (xkbcommon reads them), else us. */
	struct xkb_context *context = xkb_context_new(XKB_CONTEXT_NO_FLAGS);
	struct xkb_keymap *keymap =
		context ? xkb_keymap_new_from_names(context, NULL, XKB_KEYMAP_COMPILE_NO_FLAGS) : NULL;
	if (keymap != NULL)
		wlr_keyboard_set_keymap(device->keyboard, keymap);
	xkb_keymap_unref(keymap);
	xkb_context_unref(context);
	wlr_keyboard_set_repeat_info(device->keyboard, 25, 600);
	keyboard->modifiers.notify = keyboard_modifiers;
	wl_signal_add(&device->keyboard->events.modifiers, &keyboard->modifiers);
	keyboard->key.notify = keyboard_key;
	wl_signal_add(&device->keyboard->events.key, &keyboard->key);
	keyboard->destroy.notify = keyboard_destroy;
	wl_signal_add(&device->events.destroy, &keyboard->destroy);
	wlr_seat_set_keyboard(server->seat, device);
	wl_list_insert(&server->keyboards, &keyboard->link);
}

/* A new input device: keyboards get a keymap, pointers move the cursor. */
static void handle_new_input(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, new_input);
	struct wlr_input_device *device = data;
	if (device->type == WLR_INPUT_DEVICE_KEYBOARD)
		new_keyboard(server, device);
	else if (device->type == WLR_INPUT_DEVICE_POINTER)
		wlr_cursor_attach_input_device(server->cursor, device);
	uint32_t caps = WL_SEAT_CAPABILITY_POINTER;
	if (!wl_list_empty(&server->keyboards))
		caps |= WL_SEAT_CAPABILITY_KEYBOARD;
	wlr_seat_set_capabilities(server->seat, caps);
}

/* Follows a grab: the view moves with the pointer, or its grabbed edges do. */
static void follow_grab(struct server *server)
{
	struct view *view = server->grab.view;
	int32_t dx = (int32_t)(server->cursor->x - server->grab.grab_x);
	int32_t dy = (int32_t)(server->cursor->y - server->grab.grab_y);
	if (server->grab.edges == 0) {
		view_move(view, server->grab.x + dx, server->grab.y + dy);
		return;
	}
	int32_t x = server->grab.x, y = server->grab.y;
	int32_t width = server->grab.width, height = server->grab.height;
	if (server->grab.edges & WLR_EDGE_LEFT)
		x += dx, width -= dx;
	else if (server->grab.edges & WLR_EDGE_RIGHT)
		width += dx;
	if (server->grab.edges & WLR_EDGE_TOP)
		y += dy, height -= dy;
	else if (server->grab.edges & WLR_EDGE_BOTTOM)
		height += dy;
	if (width < 1 || height < 1)
		return;
	view_move(view, x, y);
	view_resize(view, width, height);
}

/* Gives a pointer motion to a grab, or to the surface under the pointer. */
static void pointer_moved(struct server *server, uint32_t time)
{
	if (server->grab.view != NULL) {
		follow_grab(server);
		return;
	}
	struct wlr_surface *surface = NULL;
	double sx, sy;
	struct view *view = view_at(server, server->cursor->x, server->cursor->y, &surface, &sx, &sy);
	if (view == NULL) {
		wlr_xcursor_manager_set_cursor_image(server->cursor_manager, "left_ptr", server->cursor);
		wlr_seat_pointer_clear_focus(server->seat);
		return;
	}
	wlr_seat_pointer_notify_enter(server->seat, surface, sx, sy);
	wlr_seat_pointer_notify_motion(server->seat, time, sx, sy);
}

/* Relative pointer motion. */
static void cursor_motion(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, cursor_motion);
	struct wlr_event_pointer_motion *event = data;
	wlr_cursor_move(server->cursor, event->device, event->delta_x, event->delta_y);
	pointer_moved(server, event->time_msec);
}

/* Absolute pointer motion (a nested window's pointer, a tablet). */
static void cursor_motion_absolute(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, cursor_motion_absolute);
	struct wlr_event_pointer_motion_absolute *event = data;
	wlr_cursor_warp_absolute(server->cursor, event->device, event->x, event->y);
	pointer_moved(server, event->time_msec);
}

/* A button: focus and raise on press, Alt-drag grabs; the release ends a grab. */
static void cursor_button(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, cursor_button);
	struct wlr_event_pointer_button *event = data;
	if (event->state == WLR_BUTTON_RELEASED) {
		if (server->grab.view != NULL) {
			server->grab.view = NULL;
			return;
		}
		wlr_seat_pointer_notify_button(server->seat, event->time_msec, event->button,
					       event->state);
		return;
	}
	struct wlr_surface *surface = NULL;
	double sx, sy;
	struct view *view = view_at(server, server->cursor->x, server->cursor->y, &surface, &sx, &sy);
	if (view == NULL)
		return;
	view_focus(view);
	struct wlr_keyboard *keyboard = wlr_seat_get_keyboard(server->seat);
	if (keyboard != NULL && (wlr_keyboard_get_modifiers(keyboard) & WLR_MODIFIER_ALT) &&
	    (event->button == BTN_LEFT || event->button == BTN_RIGHT)) {
		server->grab.view = view;
		server->grab.edges = event->button == BTN_LEFT ? 0 : WLR_EDGE_BOTTOM | WLR_EDGE_RIGHT;
		server->grab.grab_x = server->cursor->x;
		server->grab.grab_y = server->cursor->y;
		view_box(view, &server->grab.x, &server->grab.y, &server->grab.width,
			 &server->grab.height);
		return;
	}
	wlr_seat_pointer_notify_button(server->seat, event->time_msec, event->button, event->state);
}

/* Scrolling, for the surface under the pointer. */
static void cursor_axis(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, cursor_axis);
	struct wlr_event_pointer_axis *event = data;
	wlr_seat_pointer_notify_axis(server->seat, event->time_msec, event->orientation,
				     event->delta, event->delta_discrete, event->source);
}

/* The end of a group of pointer events. */
static void cursor_frame(struct wl_listener *listener, void *data)
{
	(void)data;
	struct server *server = wl_container_of(listener, server, cursor_frame);
	wlr_seat_pointer_notify_frame(server->seat);
}

/* A client sets the pointer's image. */
static void request_cursor(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, request_cursor);
	struct wlr_seat_pointer_request_set_cursor_event *event = data;
	/* Only the client under the pointer may set its image. */
	if (server->seat->pointer_state.focused_client == event->seat_client)
		wlr_cursor_set_surface(server->cursor, event->surface, event->hotspot_x,
				       event->hotspot_y);
}

/* A client sets the clipboard. */
static void request_set_selection(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, request_set_selection);
	struct wlr_seat_request_set_selection_event *event = data;
	wlr_seat_set_selection(server->seat, event->source, event->serial);
}

int input_init(struct server *server)
{
	server->seat = wlr_seat_create(server->display, "seat0");
	server->cursor = wlr_cursor_create();
	server->cursor_manager = wlr_xcursor_manager_create(NULL, 24);
	if (server->seat == NULL || server->cursor == NULL || server->cursor_manager == NULL) {
		wlr_log(WLR_ERROR, "cannot create the seat");
		return -1;
	}
	wlr_cursor_attach_output_layout(server->cursor, server->layout);
	wlr_xcursor_manager_load(server->cursor_manager, 1);
	server->new_input.notify = handle_new_input;
	wl_signal_add(&server->backend->events.new_input, &server->new_input);
	server->cursor_motion.notify = cursor_motion;
	wl_signal_add(&server->cursor->events.motion, &server->cursor_motion);
	server->cursor_motion_absolute.notify = cursor_motion_absolute;
	wl_signal_add(&server->cursor->events.motion_absolute, &server->cursor_motion_absolute);
	server->cursor_button.notify = cursor_button;
	wl_signal_add(&server->cursor->events.button, &server->cursor_button);
	server->cursor_axis.notify = cursor_axis;
	wl_signal_add(&server->cursor->events.axis, &server->cursor_axis);
	server->cursor_frame.notify = cursor_frame;
	wl_signal_add(&server->cursor->events.frame, &server->cursor_frame);
	server->request_cursor.notify = request_cursor;
	wl_signal_add(&server->seat->events.request_set_cursor, &server->request_cursor);
	server->request_set_selection.notify = request_set_selection;
	wl_signal_add(&server->seat->events.request_set_selection, &server->request_set_selection);
	return 0;
}

void input_finish(struct server *server)
{
	wlr_xcursor_manager_destroy(server->cursor_manager);
	wlr_cursor_destroy(server->cursor);
}
