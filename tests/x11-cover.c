/*
 * x11-cover: a cover for test-realapps.sh and tools/realapps-bench.sh, driven line by line from
 * its standard input. Its window is override-redirect, so that no window manager places, raises
 * or decorates it: it lies exactly where it is told, above every window it is raised over (an
 * override-redirect screen locker's too), and hides what lies under it. Each command is answered
 * with one line once the X server has handled it (a round trip), so a script knows the cover is
 * there before it measures anything:
 *
 *   map X Y W H   the cover at X, Y (W x H), raised to the top and mapped   -> ok
 *   raise         raised to the top again                                   -> ok
 *   unmap         unmapped                                                  -> ok
 *   top           the topmost viewable child of the root                    -> 0x… (or 0x0)
 *   cm            the owner of _NET_WM_CM_S0, the compositing manager       -> 0x… (or 0x0)
 *   id            the cover's own window                                    -> 0x…
 *
 * End of input ends it (its window goes with its connection). A bad command is answered "error"
 * with the reason on stderr. Usage: x11-cover [--display D]
 */
#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <xcb/xcb.h>

struct cover {
	xcb_connection_t *c;
	xcb_screen_t *s;
	xcb_window_t w;
};

/* Waits until the server has handled every request sent (a round trip). */
static void sync_server(struct cover *k)
{
	free(xcb_get_input_focus_reply(k->c, xcb_get_input_focus(k->c), NULL));
}

static void raise_top(struct cover *k)
{
	uint32_t above = XCB_STACK_MODE_ABOVE;
	xcb_configure_window(k->c, k->w, XCB_CONFIG_WINDOW_STACK_MODE, &above);
}

/* Places the cover and maps it on top; the window is made on the first call. */
static void map_at(struct cover *k, int x, int y, unsigned w, unsigned h)
{
	uint32_t geometry[] = { (uint32_t)x, (uint32_t)y, w, h };
	if (!k->w) {
		uint32_t values[] = { k->s->black_pixel, 1 };
		k->w = xcb_generate_id(k->c);
		xcb_create_window(k->c, XCB_COPY_FROM_PARENT, k->w, k->s->root, (int16_t)x,
				  (int16_t)y, (uint16_t)w, (uint16_t)h, 0,
				  XCB_WINDOW_CLASS_INPUT_OUTPUT, XCB_COPY_FROM_PARENT,
				  XCB_CW_BACK_PIXEL | XCB_CW_OVERRIDE_REDIRECT, values);
		const char name[] = "x11-cover";
		xcb_change_property(k->c, XCB_PROP_MODE_REPLACE, k->w, XCB_ATOM_WM_NAME,
				    XCB_ATOM_STRING, 8, sizeof(name) - 1, name);
	}
	xcb_configure_window(k->c, k->w,
			     XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y | XCB_CONFIG_WINDOW_WIDTH |
				     XCB_CONFIG_WINDOW_HEIGHT,
			     geometry);
	raise_top(k);
	xcb_map_window(k->c, k->w);
}

/* The topmost viewable child of the root (QueryTree lists them bottom to top), or 0. */
static xcb_window_t top(struct cover *k)
{
	xcb_query_tree_reply_t *t = xcb_query_tree_reply(k->c, xcb_query_tree(k->c, k->s->root),
							 NULL);
	xcb_window_t found = 0;
	if (!t)
		return 0;
	xcb_window_t *kids = xcb_query_tree_children(t);
	for (int i = xcb_query_tree_children_length(t) - 1; i >= 0 && !found; i--) {
		xcb_get_window_attributes_reply_t *a = xcb_get_window_attributes_reply(
			k->c, xcb_get_window_attributes(k->c, kids[i]), NULL);
		if (a && a->map_state == XCB_MAP_STATE_VIEWABLE)
			found = kids[i];
		free(a);
	}
	free(t);
	return found;
}

/* The owner of _NET_WM_CM_S0 (screen 0's compositing manager), or 0. */
static xcb_window_t compositor(struct cover *k)
{
	const char name[] = "_NET_WM_CM_S0";
	xcb_intern_atom_reply_t *a = xcb_intern_atom_reply(
		k->c, xcb_intern_atom(k->c, 0, sizeof(name) - 1, name), NULL);
	if (!a)
		return 0;
	xcb_get_selection_owner_reply_t *o = xcb_get_selection_owner_reply(
		k->c, xcb_get_selection_owner(k->c, a->atom), NULL);
	xcb_window_t owner = o ? o->owner : 0;
	free(o);
	free(a);
	return owner;
}

/* Carries out one command line; 0, or -1 for a bad one. */
static int command(struct cover *k, const char *line)
{
	int x, y;
	unsigned w, h;
	char extra;
	if (sscanf(line, "map %d %d %u %u %c", &x, &y, &w, &h, &extra) == 4) {
		if (w == 0 || h == 0 || w > 32767 || h > 32767 || x < -32768 || x > 32767 ||
		    y < -32768 || y > 32767)
			return -1;
		map_at(k, x, y, w, h);
	} else if (strcmp(line, "raise") == 0 && k->w) {
		raise_top(k);
	} else if (strcmp(line, "unmap") == 0 && k->w) {
		xcb_unmap_window(k->c, k->w);
	} else if (strcmp(line, "top") == 0) {
		printf("0x%x\n", top(k));
		return 0;
	} else if (strcmp(line, "cm") == 0) {
		printf("0x%x\n", compositor(k));
		return 0;
	} else if (strcmp(line, "id") == 0) {
		printf("0x%x\n", k->w);
		return 0;
	} else {
		return -1;
	}
	sync_server(k);
	puts("ok");
	return 0;
}

int main(int argc, char **argv)
{
	static const struct option options[] = { { "display", required_argument, NULL, 'd' },
						  { NULL, 0, NULL, 0 } };
	const char *display = NULL;
	int opt;
	while ((opt = getopt_long(argc, argv, "d:", options, NULL)) != -1) {
		if (opt != 'd') {
			fprintf(stderr, "usage: x11-cover [--display D]\n");
			return 2;
		}
		display = optarg;
	}
	struct cover k = { 0 };
	int screen;
	k.c = xcb_connect(display, &screen);
	if (xcb_connection_has_error(k.c)) {
		fprintf(stderr, "x11-cover: cannot open the display\n");
		return 1;
	}
	xcb_screen_iterator_t it = xcb_setup_roots_iterator(xcb_get_setup(k.c));
	for (; screen > 0 && it.rem; screen--)
		xcb_screen_next(&it);
	k.s = it.data;
	setvbuf(stdout, NULL, _IOLBF, 0);

	char line[256];
	while (fgets(line, sizeof(line), stdin)) {
		line[strcspn(line, "\n")] = '\0';
		if (command(&k, line) < 0) {
			fprintf(stderr, "x11-cover: bad command: %s\n", line);
			puts("error");
		}
		if (xcb_connection_has_error(k.c)) {
			fprintf(stderr, "x11-cover: the connection to X broke\n");
			return 1;
		}
	}
	xcb_disconnect(k.c);
	return 0;
}
