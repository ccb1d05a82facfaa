/*
 * The desktop x11-desk drives: top-levels of its own under the window manager (subwindows with
 * borders, bounding shapes, an InputOnly child now and then, one 32-bit ARGB top-level where the
 * screen has such a visual), two override-redirect windows, and real clients (xlogo, xeyes,
 * xterm) started as processes and killed at the end. Every window of its own is created with
 * the recorder's events selected, so none of them is ever late (x11-desk-record.c).
 */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>
#include <xcb/shape.h>

#include "x11-desk.h"
#include "xorg-shape.h"

/* WM_NORMAL_HINTS flags (ICCCM 4.1.2.3). */
#define US_POSITION 1u
#define US_SIZE 2u

/* Creates a window of ours with the recorder's events selected; the caller maps it. */
static xcb_window_t create(struct desk *d, xcb_window_t parent, int32_t x, int32_t y, uint32_t w,
			   uint32_t h, uint32_t border, bool input_only, bool override, bool argb)
{
	xcb_window_t xid = xcb_generate_id(d->c);
	uint32_t mask = 0, values[6], n = 0;
	uint8_t depth = XCB_COPY_FROM_PARENT;
	xcb_visualid_t visual = XCB_COPY_FROM_PARENT;
	if (input_only) {
		mask = XCB_CW_OVERRIDE_REDIRECT | XCB_CW_EVENT_MASK;
		values[n++] = override;
		values[n++] = record_mask(true);
	} else {
		/* Another depth than the parent's needs its own border pixel and colormap. */
		uint32_t pixel = (uint32_t)vis_rng_next(&d->rng) & 0xffffff;
		mask = XCB_CW_BACK_PIXEL | XCB_CW_BORDER_PIXEL | XCB_CW_OVERRIDE_REDIRECT |
		       XCB_CW_EVENT_MASK;
		values[n++] = argb ? 0x80000000u | pixel : pixel;
		values[n++] = argb ? 0xff000000u : d->screen->black_pixel;
		values[n++] = override;
		values[n++] = record_mask(false);
		if (argb) {
			mask |= XCB_CW_COLORMAP;
			values[n++] = d->argb_colormap;
			depth = 32;
			visual = d->argb_visual;
		}
	}
	xcb_create_window(d->c, depth, xid, parent, (int16_t)x, (int16_t)y, (uint16_t)w, (uint16_t)h,
			  (uint16_t)border,
			  input_only ? XCB_WINDOW_CLASS_INPUT_ONLY : XCB_WINDOW_CLASS_INPUT_OUTPUT,
			  visual, mask, values);
	record_own(d, xid, input_only);
	return xid;
}

/* Gives xid a random bounding shape (or none, a third of the time). */
static void maybe_shape(struct desk *d, xcb_window_t xid, uint32_t w, uint32_t h, uint32_t border)
{
	if (!d->shape || vis_rng_below(&d->rng, 3) != 0)
		return;
	xcb_rectangle_t r[2];
	bool past;
	uint32_t n = xorg_random_shape(&d->rng, w, h, border, r, &past);
	xcb_shape_rectangles(d->c, XCB_SHAPE_SO_SET, XCB_SHAPE_SK_BOUNDING, XCB_CLIP_ORDERING_UNSORTED,
			     xid, 0, 0, n, r);
}

/* One to three children of parent (w×h), some with a child of their own; all mapped. */
static int add_kids(struct desk *d, xcb_window_t parent, uint32_t w, uint32_t h, int depth,
		    xcb_window_t *kids, int room)
{
	int n = 0, want = 1 + (int)vis_rng_below(&d->rng, 3);
	for (int i = 0; i < want && n < room; i++) {
		uint32_t kw = 1 + (uint32_t)vis_rng_below(&d->rng, w * 2 / 3 + 1);
		uint32_t kh = 1 + (uint32_t)vis_rng_below(&d->rng, h * 2 / 3 + 1);
		int32_t kx = (int32_t)vis_rng_range(&d->rng, -4, (int64_t)w - 2);
		int32_t ky = (int32_t)vis_rng_range(&d->rng, -4, (int64_t)h - 2);
		bool input_only = vis_rng_below(&d->rng, 8) == 0;
		uint32_t border = input_only ? 0 : (uint32_t)vis_rng_below(&d->rng, 4);
		xcb_window_t k = create(d, parent, kx, ky, kw, kh, border, input_only, false, false);
		if (!input_only)
			maybe_shape(d, k, kw, kh, border);
		if (!input_only && depth < 2 && vis_rng_below(&d->rng, 3) == 0) {
			xcb_window_t grand;
			add_kids(d, k, kw, kh, depth + 1, &grand, 1);
		}
		xcb_map_window(d->c, k);
		kids[n++] = k;
	}
	return n;
}

/* A title and position and size hints the WM honours (USPosition, USSize). */
static void set_hints(struct desk *d, xcb_window_t xid, int32_t x, int32_t y, uint32_t w, uint32_t h)
{
	char name[32];
	int len = snprintf(name, sizeof name, "x11-desk 0x%x", xid);
	xcb_change_property(d->c, XCB_PROP_MODE_REPLACE, xid, XCB_ATOM_WM_NAME, XCB_ATOM_STRING, 8,
			    (uint32_t)len, name);
	uint32_t hints[18] = { US_POSITION | US_SIZE, (uint32_t)x, (uint32_t)y, w, h };
	xcb_change_property(d->c, XCB_PROP_MODE_REPLACE, xid, XCB_ATOM_WM_NORMAL_HINTS,
			    XCB_ATOM_WM_SIZE_HINTS, 32, 18, hints);
}

int build_top(struct desk *d)
{
	if (d->n_tops == DESK_MAX_TOPS)
		return -1;
	struct top *t = &d->tops[d->n_tops];
	int32_t W = d->screen->width_in_pixels, H = d->screen->height_in_pixels;
	memset(t, 0, sizeof *t);
	t->ours = true;
	t->w = 40 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)W / 2);
	t->h = 30 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)H / 2);
	t->x = (int32_t)vis_rng_range(&d->rng, -20, W - (int32_t)t->w / 2);
	t->y = (int32_t)vis_rng_range(&d->rng, 0, H - (int32_t)t->h / 2);
	bool argb = d->argb_visual != 0 && d->argb_top == 0;
	t->xid = create(d, d->root, t->x, t->y, t->w, t->h, 0, false, false, argb);
	if (argb)
		d->argb_top = t->xid;
	set_hints(d, t->xid, t->x, t->y, t->w, t->h);
	maybe_shape(d, t->xid, t->w, t->h, 0);
	t->n_kids = add_kids(d, t->xid, t->w, t->h, 0, t->kids, 4);
	xcb_map_window(d->c, t->xid);
	t->state = TOP_NORMAL;
	return d->n_tops++;
}

/* Whether name is an executable on PATH. */
static bool on_path(const char *name)
{
	const char *path = getenv("PATH");
	if (path == NULL)
		return false;
	char buf[4096];
	for (const char *p = path; *p;) {
		size_t len = strcspn(p, ":");
		if (snprintf(buf, sizeof buf, "%.*s/%s", (int)len, p, name) < (int)sizeof buf &&
		    access(buf, X_OK) == 0)
			return true;
		p += len;
		if (*p == ':')
			p++;
	}
	return false;
}

/* Starts a client; it dies with us should we die without killing it. */
static void spawn(struct desk *d, const char *name, char *const argv[])
{
	if (!on_path(name)) {
		fprintf(stderr, "x11-desk: %s not found on PATH: skipped\n", name);
		return;
	}
	fflush(NULL);
	pid_t pid = fork();
	if (pid < 0)
		desk_die(d, 1, "cannot fork for %s", name);
	if (pid == 0) {
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		int null = open("/dev/null", O_WRONLY);
		if (!d->verbose && null >= 0) {
			dup2(null, 1);
			dup2(null, 2);
		}
		execvp(name, argv);
		_exit(127);
	}
	d->clients[d->n_clients++] = (struct client){ .argv0 = name, .pid = pid };
}

/* Whether xid's WM_CLASS instance is name. */
static bool has_class(struct desk *d, xcb_window_t xid, const char *name)
{
	xcb_get_property_reply_t *p = xcb_get_property_reply(
		d->c, xcb_get_property(d->c, 0, xid, XCB_ATOM_WM_CLASS, XCB_ATOM_STRING, 0, 64), NULL);
	bool yes = p != NULL && xcb_get_property_value_length(p) > (int)strlen(name) &&
		   strcmp(xcb_get_property_value(p), name) == 0;
	free(p);
	return yes;
}

/* Whether xid is managed in NormalState (the WM set WM_STATE) and viewable. */
static bool managed(struct desk *d, xcb_window_t xid)
{
	xcb_atom_t wm_state = d->atoms[ATOM_WM_STATE];
	xcb_get_property_reply_t *p = xcb_get_property_reply(
		d->c, xcb_get_property(d->c, 0, xid, wm_state, wm_state, 0, 2), NULL);
	bool normal = p != NULL && p->format == 32 && xcb_get_property_value_length(p) >= 4 &&
		      *(uint32_t *)xcb_get_property_value(p) == 1;
	free(p);
	if (!normal)
		return false;
	xcb_get_window_attributes_reply_t *a =
		xcb_get_window_attributes_reply(d->c, xcb_get_window_attributes(d->c, xid), NULL);
	bool viewable = a != NULL && a->map_state == XCB_MAP_STATE_VIEWABLE;
	free(a);
	return viewable;
}

/* Finds each started client's managed top-level; true when all are there. */
static bool clients_mapped(struct desk *d, void *arg)
{
	(void)arg;
	bool all = true;
	for (int i = 0; i < d->n_clients; i++) {
		struct client *cl = &d->clients[i];
		for (size_t k = 0; k < d->rec.n && cl->xid == 0; k++) {
			struct rec_window *w = &d->rec.w[k];
			if (!w->input_only && has_class(d, w->xid, cl->argv0) && managed(d, w->xid))
				cl->xid = w->xid;
		}
		all = all && cl->xid != 0;
	}
	return all;
}

/* The managed windows of the clients join the tops the operations drive. */
static void wait_clients(struct desk *d)
{
	pid_t pids[DESK_MAX_CLIENTS];
	for (int i = 0; i < d->n_clients; i++)
		pids[i] = d->clients[i].pid;
	record_until(d, pids, (size_t)d->n_clients, clients_mapped, NULL,
		     "the clients did not map their windows");
	for (int i = 0; i < d->n_clients; i++) {
		struct client *cl = &d->clients[i];
		xcb_get_geometry_reply_t *g =
			xcb_get_geometry_reply(d->c, xcb_get_geometry(d->c, cl->xid), NULL);
		struct top *t = &d->tops[d->n_tops++];
		memset(t, 0, sizeof *t);
		*t = (struct top){ .xid = cl->xid, .state = TOP_NORMAL, .w = g ? g->width : 100,
				   .h = g ? g->height : 100 };
		free(g);
	}
}

/* The screen's 32-bit TrueColor visual, and a colormap for it; none where there is none. */
static void find_argb(struct desk *d)
{
	xcb_depth_iterator_t di = xcb_screen_allowed_depths_iterator(d->screen);
	for (; di.rem && d->argb_visual == 0; xcb_depth_next(&di)) {
		if (di.data->depth != 32)
			continue;
		xcb_visualtype_iterator_t vi = xcb_depth_visuals_iterator(di.data);
		for (; vi.rem; xcb_visualtype_next(&vi))
			if (vi.data->_class == XCB_VISUAL_CLASS_TRUE_COLOR) {
				d->argb_visual = vi.data->visual_id;
				break;
			}
	}
	if (d->argb_visual == 0)
		return;
	d->argb_colormap = xcb_generate_id(d->c);
	xcb_create_colormap(d->c, XCB_COLORMAP_ALLOC_NONE, d->argb_colormap, d->root, d->argb_visual);
}

void build_desktop(struct desk *d, int n_tops)
{
	find_argb(d);
	if (d->argb_visual == 0)
		fprintf(stderr, "x11-desk: the screen has no 32-bit visual: no ARGB window\n");
	static char *xlogo[] = { "xlogo", "-geometry", "120x120+40+60", NULL };
	static char *xeyes[] = { "xeyes", "-shape", "-geometry", "150x100+220+40", NULL };
	static char *xterm[] = { "xterm", "-geometry", "40x10+120+200", NULL };
	spawn(d, "xlogo", xlogo);
	spawn(d, "xeyes", xeyes);
	spawn(d, "xterm", xterm);
	for (int i = 0; i < n_tops; i++)
		build_top(d);
	int32_t W = d->screen->width_in_pixels, H = d->screen->height_in_pixels;
	for (int i = 0; i < DESK_N_OVERRIDE; i++) {
		uint32_t w = 20 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)W / 3);
		uint32_t h = 10 + (uint32_t)vis_rng_below(&d->rng, (uint64_t)H / 4);
		int32_t x = (int32_t)vis_rng_range(&d->rng, 0, W - 20);
		int32_t y = (int32_t)vis_rng_range(&d->rng, 0, H - 10);
		uint32_t border = (uint32_t)vis_rng_below(&d->rng, 3);
		d->override[i] = create(d, d->root, x, y, w, h, border, false, true, false);
		xcb_window_t kid;
		add_kids(d, d->override[i], w, h, 1, &kid, 1);
		xcb_map_window(d->c, d->override[i]);
		d->override_mapped[i] = true;
	}
	xcb_flush(d->c);
	wait_clients(d);
}

void build_kill_clients(struct desk *d)
{
	for (int i = 0; i < d->n_clients; i++)
		if (d->clients[i].pid > 0)
			kill(d->clients[i].pid, SIGTERM);
	for (int i = 0; i < d->n_clients; i++)
		if (d->clients[i].pid > 0)
			waitpid(d->clients[i].pid, NULL, 0);
	d->n_clients = 0;
}
