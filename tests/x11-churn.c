/*
 * x11-churn: a hostile X client for visd-x11's fault tests. It builds a desktop of override-
 * redirect windows (children, borders, InputOnly ones, bounding shapes), then changes it as fast
 * as X takes requests, without ever waiting: windows destroyed right after they are created,
 * reparented, restacked, resized, shaped, mapped and unmapped, so that the bridge's queries of a
 * window keep racing its destruction. With --hold it then keeps its windows until a signal kills
 * it (its windows go with its connection).
 *
 * With --moves M, SIGUSR1 makes it move and raise M of its top-level windows one at a time, each
 * to anywhere on the screen, after the server answered the previous one, a millisecond apart
 * (tools/x11-bench.sh measures the bridge with it); with --drag, each move is a drag instead: by
 * up to 64 pixels each way, without a raise, as a user drags a window.
 *
 * Usage: x11-churn [--display D] [--windows N] [--rounds R] [--seed S] [--hold] [--moves M]
 *                  [--drag]
 */
#include <getopt.h>
#include <signal.h>
#include <stdbool.h>
#include <time.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <xcb/shape.h>
#include <xcb/xcb.h>

#include "rng.h"

struct churn {
	xcb_connection_t *c;
	xcb_screen_t *s;
	struct vis_rng rng;
	xcb_window_t *w; /* live windows; w[i]'s parent is the root or an earlier window */
	size_t n, cap;
};

static uint32_t below(struct churn *k, uint64_t n)
{
	return n ? (uint32_t)vis_rng_below(&k->rng, n) : 0;
}

/* Creates a window under parent (the root, or a live window), mapped most of the time. */
static xcb_window_t make(struct churn *k, xcb_window_t parent)
{
	xcb_window_t id = xcb_generate_id(k->c);
	bool input_only = below(k, 10) == 0;
	uint32_t values[] = { k->s->white_pixel, 1 };
	uint16_t width = (uint16_t)(1 + below(k, 300)), height = (uint16_t)(1 + below(k, 200));
	int16_t x = (int16_t)((int)below(k, k->s->width_in_pixels + 100) - 50);
	int16_t y = (int16_t)((int)below(k, k->s->height_in_pixels + 100) - 50);
	xcb_create_window(k->c, input_only ? 0 : XCB_COPY_FROM_PARENT, id, parent, x, y, width,
			  height, input_only ? 0 : (uint16_t)below(k, 4),
			  input_only ? XCB_WINDOW_CLASS_INPUT_ONLY : XCB_WINDOW_CLASS_INPUT_OUTPUT,
			  XCB_COPY_FROM_PARENT,
			  input_only ? XCB_CW_OVERRIDE_REDIRECT
				     : XCB_CW_BACK_PIXEL | XCB_CW_OVERRIDE_REDIRECT,
			  input_only ? values + 1 : values);
	if (!input_only && below(k, 5) == 0) {
		xcb_rectangle_t r[2] = { { 0, 0, (uint16_t)(width / 2 + 1), height },
					 { (int16_t)(width / 2), (int16_t)(height / 2),
					   (uint16_t)(width / 2 + 1), (uint16_t)(height / 2 + 1) } };
		xcb_shape_rectangles(k->c, XCB_SHAPE_SO_SET, XCB_SHAPE_SK_BOUNDING,
				     XCB_CLIP_ORDERING_UNSORTED, id, 0, 0, 2, r);
	}
	if (below(k, 4) != 0)
		xcb_map_window(k->c, id);
	if (k->n == k->cap) {
		k->cap = k->cap ? 2 * k->cap : 256;
		k->w = realloc(k->w, k->cap * sizeof(*k->w));
		if (!k->w) {
			fprintf(stderr, "x11-churn: out of memory\n");
			exit(1);
		}
	}
	k->w[k->n++] = id;
	return id;
}

/* A parent for a new window: the root most of the time, else a live window. */
static xcb_window_t some_parent(struct churn *k)
{
	return k->n && below(k, 3) == 0 ? k->w[below(k, (uint32_t)k->n)] : k->s->root;
}

/* One change of a random kind, never waiting for X. */
static void change(struct churn *k)
{
	if (!k->n) {
		make(k, k->s->root);
		return;
	}
	size_t i = below(k, (uint32_t)k->n);
	xcb_window_t w = k->w[i];
	switch (below(k, 9)) {
	case 0: /* created and destroyed at once: the bridge's read of it fails */
		xcb_destroy_window(k->c, make(k, some_parent(k)));
		k->n--;
		break;
	case 1: /* destroyed with its subtree; the subtree's IDs stay in the list, harmlessly */
		xcb_destroy_window(k->c, w);
		k->w[i] = k->w[--k->n];
		break;
	case 2:
		make(k, some_parent(k));
		break;
	case 3: {
		/* X refuses a reparent into the window's own subtree: a harmless error. */
		xcb_window_t p = some_parent(k);
		if (p != w)
			xcb_reparent_window(k->c, w, p, (int16_t)below(k, 400), (int16_t)below(k, 300));
		break;
	}
	case 4: {
		uint32_t v[] = { below(k, 600), below(k, 400), 1 + below(k, 300), 1 + below(k, 200) };
		xcb_configure_window(k->c, w,
				     XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y |
					     XCB_CONFIG_WINDOW_WIDTH | XCB_CONFIG_WINDOW_HEIGHT,
				     v);
		break;
	}
	case 5: {
		uint32_t mode = below(k, 2) ? XCB_STACK_MODE_ABOVE : XCB_STACK_MODE_BELOW;
		xcb_configure_window(k->c, w, XCB_CONFIG_WINDOW_STACK_MODE, &mode);
		break;
	}
	case 6:
		xcb_unmap_window(k->c, w);
		break;
	case 7:
		xcb_map_window(k->c, w);
		break;
	default:
		xcb_circulate_window(k->c, below(k, 2), some_parent(k));
		break;
	}
}

static volatile sig_atomic_t moves_asked;

static void on_usr1(int sig)
{
	(void)sig;
	moves_asked = 1;
}

/* Moves and raises m top-level windows (drag: drags them), one at a time, a millisecond apart. */
static void move_some(struct churn *k, unsigned long m, bool drag)
{
	size_t tops = 0;
	for (unsigned long i = 0; i < m; i++) {
		/* Its own top-level windows: those of the list whose parent is the root. */
		xcb_window_t w = 0;
		for (int tries = 0; tries < 100 && !w; tries++) {
			xcb_window_t c = k->w[below(k, (uint32_t)k->n)];
			xcb_query_tree_reply_t *q =
				xcb_query_tree_reply(k->c, xcb_query_tree(k->c, c), NULL);
			if (q && q->parent == k->s->root)
				w = c;
			free(q);
		}
		if (!w)
			break;
		uint32_t v[] = { below(k, k->s->width_in_pixels), below(k, k->s->height_in_pixels),
				 XCB_STACK_MODE_ABOVE };
		uint16_t mask = XCB_CONFIG_WINDOW_X | XCB_CONFIG_WINDOW_Y;
		if (drag) {
			xcb_get_geometry_reply_t *g =
				xcb_get_geometry_reply(k->c, xcb_get_geometry(k->c, w), NULL);
			if (!g)
				continue; /* an X error: no move */
			v[0] = (uint32_t)(int32_t)(g->x + (int)below(k, 129) - 64);
			v[1] = (uint32_t)(int32_t)(g->y + (int)below(k, 129) - 64);
			free(g);
		} else {
			mask |= XCB_CONFIG_WINDOW_STACK_MODE;
		}
		xcb_configure_window(k->c, w, mask, v);
		free(xcb_get_input_focus_reply(k->c, xcb_get_input_focus(k->c), NULL));
		nanosleep(&(struct timespec){ 0, 1000000 }, NULL);
		tops++;
	}
	printf("x11-churn: %zu moves done\n", tops);
	fflush(stdout);
}

int main(int argc, char **argv)
{
	static const struct option longs[] = {
		{ "display", required_argument, NULL, 'd' }, { "windows", required_argument, NULL, 'n' },
		{ "rounds", required_argument, NULL, 'r' },  { "seed", required_argument, NULL, 's' },
		{ "hold", no_argument, NULL, 'h' },          { "moves", required_argument, NULL, 'm' },
		{ "drag", no_argument, NULL, 'g' },          { NULL, 0, NULL, 0 },
	};
	const char *display = NULL;
	unsigned long windows = 100, rounds = 1000, seed = 1, moves = 0;
	bool hold = false, drag = false;
	int opt;
	while ((opt = getopt_long(argc, argv, "", longs, NULL)) != -1) {
		switch (opt) {
		case 'd': display = optarg; break;
		case 'n': windows = strtoul(optarg, NULL, 10); break;
		case 'r': rounds = strtoul(optarg, NULL, 10); break;
		case 's': seed = strtoul(optarg, NULL, 10); break;
		case 'h': hold = true; break;
		case 'm': moves = strtoul(optarg, NULL, 10); break;
		case 'g': drag = true; break;
		default:
			fprintf(stderr, "usage: x11-churn [--display D] [--windows N] [--rounds R] "
					"[--seed S] [--hold] [--moves M] [--drag]\n");
			return 2;
		}
	}
	struct sigaction sa = { .sa_handler = on_usr1 };
	sigaction(SIGUSR1, &sa, NULL);
	struct churn k = { 0 };
	k.c = xcb_connect(display, NULL);
	if (xcb_connection_has_error(k.c)) {
		fprintf(stderr, "x11-churn: cannot connect to the X display\n");
		return 1;
	}
	k.s = xcb_setup_roots_iterator(xcb_get_setup(k.c)).data;
	k.rng.state = seed;
	for (unsigned long i = 0; i < windows; i++)
		make(&k, some_parent(&k));
	for (unsigned long i = 0; i < rounds; i++)
		change(&k);
	/* Every request processed (errors are expected: windows destroyed meanwhile). */
	xcb_generic_event_t *ev;
	free(xcb_get_input_focus_reply(k.c, xcb_get_input_focus(k.c), NULL));
	while ((ev = xcb_poll_for_event(k.c)))
		free(ev);
	int rc = xcb_connection_has_error(k.c) ? 1 : 0;
	printf("x11-churn: %zu windows live after %lu changes\n", k.n, rounds);
	fflush(stdout);
	if (hold && rc == 0) {
		for (;;) {
			pause();
			if (moves_asked && moves && k.n) {
				moves_asked = 0;
				move_some(&k, moves, drag);
			}
		}
	}
	xcb_disconnect(k.c);
	free(k.w);
	return rc;
}
