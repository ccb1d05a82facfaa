/*
 * Asks a real X server for the states of a scene: creates every window of the scene (bottom to
 * top, so each new one is stacked on top) as an unmanaged child of the root, maps them all, and
 * prints the last VisibilityNotify state each received, as `visctl compute` prints states. The
 * scene's screen must be the X screen's size; X limits coordinates to int16 and sizes to uint16.
 * Usage: xorg-states SCENE (with DISPLAY set).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <xcb/xcb.h>

#include "scene.h"

/* Reads a whole file into a NUL-terminated buffer. */
static char *slurp(const char *path, size_t *len)
{
	FILE *f = fopen(path, "rb");
	if (!f)
		return NULL;
	size_t cap = 1 << 16, n = 0;
	char *buf = malloc(cap);
	size_t got;
	while (buf && (got = fread(buf + n, 1, cap - n, f)) > 0) {
		n += got;
		if (n == cap) {
			char *nb = realloc(buf, cap *= 2);
			if (!nb) {
				free(buf);
				buf = NULL;
			}
			buf = nb;
		}
	}
	fclose(f);
	*len = n;
	return buf;
}

static int by_id(const void *a, const void *b, void *ids)
{
	uint32_t x = ((const uint32_t *)ids)[*(const size_t *)a];
	uint32_t y = ((const uint32_t *)ids)[*(const size_t *)b];
	return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: xorg-states SCENE\n");
		return 2;
	}
	size_t len;
	char *text = slurp(argv[1], &len);
	struct vis_scene scene;
	struct vis_scene_error err;
	vis_scene_init(&scene);
	if (!text || vis_scene_parse(&scene, text, len, &err) < 0) {
		fprintf(stderr, "xorg-states: %s: cannot read or parse\n", argv[1]);
		return 2;
	}
	xcb_connection_t *c = xcb_connect(NULL, NULL);
	if (xcb_connection_has_error(c)) {
		fprintf(stderr, "xorg-states: cannot connect to the X server\n");
		return 1;
	}
	xcb_screen_t *screen = xcb_setup_roots_iterator(xcb_get_setup(c)).data;
	if (!scene.has_screen || scene.screen_w != screen->width_in_pixels ||
	    scene.screen_h != screen->height_in_pixels) {
		fprintf(stderr, "xorg-states: the scene's screen must be %ux%u\n",
			screen->width_in_pixels, screen->height_in_pixels);
		return 2;
	}
	xcb_window_t *wid = calloc(scene.n + 1, sizeof(*wid));
	int *state = malloc((scene.n + 1) * sizeof(*state));
	for (size_t i = 0; i < scene.n; i++) {
		struct vis_rect r = scene.rects[i];
		if (r.x < INT16_MIN || r.x > INT16_MAX || r.y < INT16_MIN || r.y > INT16_MAX ||
		    r.w > UINT16_MAX || r.h > UINT16_MAX) {
			fprintf(stderr, "xorg-states: window %u does not fit X's coordinates\n",
				scene.ids[i]);
			return 2;
		}
		uint32_t values[] = { 1, XCB_EVENT_MASK_VISIBILITY_CHANGE };
		wid[i] = xcb_generate_id(c);
		state[i] = -1;
		xcb_create_window(c, XCB_COPY_FROM_PARENT, wid[i], screen->root, (int16_t)r.x,
				  (int16_t)r.y, (uint16_t)r.w, (uint16_t)r.h, 0,
				  XCB_WINDOW_CLASS_INPUT_OUTPUT, XCB_COPY_FROM_PARENT,
				  XCB_CW_OVERRIDE_REDIRECT | XCB_CW_EVENT_MASK, values);
	}
	for (size_t i = 0; i < scene.n; i++)
		xcb_map_window(c, wid[i]);
	free(xcb_get_input_focus_reply(c, xcb_get_input_focus(c), NULL)); /* a round trip */
	xcb_generic_event_t *ev;
	while ((ev = xcb_poll_for_event(c))) {
		if ((ev->response_type & 0x7f) == XCB_VISIBILITY_NOTIFY) {
			xcb_visibility_notify_event_t *v = (void *)ev;
			for (size_t i = 0; i < scene.n; i++)
				if (wid[i] == v->window)
					state[i] = v->state;
		}
		free(ev);
	}
	size_t *order = malloc((scene.n + 1) * sizeof(*order));
	for (size_t i = 0; i < scene.n; i++)
		order[i] = i;
	qsort_r(order, scene.n, sizeof(*order), by_id, scene.ids);
	static const char *const names[] = { "unobscured", "partially-obscured", "fully-obscured" };
	for (size_t j = 0; j < scene.n; j++) {
		size_t i = order[j];
		printf("%u %s\n", scene.ids[i], state[i] >= 0 && state[i] <= 2 ? names[state[i]] : "none");
	}
	for (size_t i = 0; i < scene.n; i++)
		xcb_destroy_window(c, wid[i]);
	xcb_flush(c);
	xcb_disconnect(c);
	return 0;
}
