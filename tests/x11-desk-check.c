/*
 * The comparison: X's viewable InputOutput windows, read from the server's tree at the quiet
 * point, each with the recorder's last VisibilityNotify state, against the states a command
 * (visctl … states --x11) prints as "0x%x STATE" lines. A difference is printed with the
 * window's path from the root, so that it can be understood without rerunning.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <xcb/shape.h>

#include "x11-desk.h"

#define NO_RECORD (-2) /* a window the recorder does not know: its bug */

static const char *const state_names[] = { "unobscured", "partially-obscured", "fully-obscured" };

const char *check_state_name(int state)
{
	if (state == NO_RECORD)
		return "(unknown to the recorder)";
	if (state < 0 || state > 2)
		return "(no VisibilityNotify)";
	return state_names[state];
}

struct views {
	struct x_view *v;
	size_t n, cap;
};

/* Appends a window to a growing list; dies when memory runs out. */
static void push(struct desk *d, struct views *vs, xcb_window_t xid, int state, int told,
		 bool redirected)
{
	if (vs->n == vs->cap) {
		size_t cap = vs->cap ? vs->cap * 2 : 64;
		struct x_view *v = realloc(vs->v, cap * sizeof *v);
		if (v == NULL) {
			free(vs->v);
			desk_die(d, 1, "out of memory");
		}
		vs->v = v;
		vs->cap = cap;
	}
	vs->v[vs->n++] = (struct x_view){ xid, state, told, redirected };
}

/*
 * Adds the viewable InputOutput windows among xid's subtree (xid itself included); parent_depth
 * is its parent's depth, redirected whether an ancestor is redirected.
 */
static void walk(struct desk *d, struct views *vs, xcb_window_t xid, uint8_t parent_depth,
		 bool redirected)
{
	xcb_get_window_attributes_cookie_t ac = xcb_get_window_attributes(d->c, xid);
	xcb_get_geometry_cookie_t gc = xcb_get_geometry(d->c, xid);
	xcb_get_window_attributes_reply_t *a = xcb_get_window_attributes_reply(d->c, ac, NULL);
	xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(d->c, gc, NULL);
	if (a == NULL || g == NULL) {
		free(a);
		free(g);
		return;
	}
	uint8_t depth = g->depth;
	free(g);
	/* Composite redirects a 32-bit (ARGB) window whose parent has another depth. */
	if (xid != d->root && a->_class == XCB_WINDOW_CLASS_INPUT_OUTPUT && depth == 32 &&
	    parent_depth != 32)
		redirected = true;
	if (a->_class != XCB_WINDOW_CLASS_INPUT_OUTPUT)
		depth = parent_depth; /* an InputOnly window has no depth of its own */
	bool viewable = a->map_state == XCB_MAP_STATE_VIEWABLE;
	if (viewable && xid != d->root && a->_class == XCB_WINDOW_CLASS_INPUT_OUTPUT) {
		struct rec_window *w = record_find(&d->rec, xid);
		push(d, vs, xid, w ? w->state : NO_RECORD, w ? w->told : NO_RECORD, redirected);
	}
	free(a);
	if (!viewable && xid != d->root)
		return; /* nothing below is viewable */
	xcb_query_tree_reply_t *t = xcb_query_tree_reply(d->c, xcb_query_tree(d->c, xid), NULL);
	if (t == NULL)
		return;
	xcb_window_t *kids = xcb_query_tree_children(t);
	for (int i = 0; i < xcb_query_tree_children_length(t); i++)
		walk(d, vs, kids[i], depth, redirected);
	free(t);
}

/* The order of visctl's lines: by XID. */
static int by_xid(const void *a, const void *b)
{
	const struct x_view *p = a, *q = b;
	return (p->xid > q->xid) - (p->xid < q->xid);
}

struct x_view *check_x_views(struct desk *d, size_t *n)
{
	struct views vs = { 0 };
	xcb_grab_server(d->c);
	walk(d, &vs, d->root, d->screen->root_depth, false);
	xcb_ungrab_server(d->c);
	xcb_flush(d->c);
	if (vs.n > 1)
		qsort(vs.v, vs.n, sizeof *vs.v, by_xid);
	*n = vs.n;
	return vs.v;
}

void check_print(struct desk *d, unsigned long step)
{
	size_t n;
	struct x_view *v = check_x_views(d, &n);
	for (size_t i = 0; i < n; i++)
		printf("step %lu: 0x%x %s%s\n", step, v[i].xid, check_state_name(v[i].state),
		       v[i].redirected ? " (redirected by X)" : "");
	fflush(stdout);
	free(v);
}

/* Prints one window of a path: its geometry, border, map state, class, override-redirect, shape. */
static void print_window(FILE *f, struct desk *d, xcb_window_t xid, int depth)
{
	xcb_get_geometry_cookie_t gc = xcb_get_geometry(d->c, xid);
	xcb_get_window_attributes_cookie_t ac = xcb_get_window_attributes(d->c, xid);
	xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(d->c, gc, NULL);
	xcb_get_window_attributes_reply_t *a = xcb_get_window_attributes_reply(d->c, ac, NULL);
	xcb_shape_query_extents_reply_t *s = NULL;
	if (d->shape)
		s = xcb_shape_query_extents_reply(d->c, xcb_shape_query_extents(d->c, xid), NULL);
	static const char *const map_states[] = { "unmapped", "unviewable", "viewable" };
	fprintf(f, "  %*s0x%x", 2 * depth, "", xid);
	if (g != NULL)
		fprintf(f, " %ux%u%+d%+d border %u", g->width, g->height, g->x, g->y, g->border_width);
	if (a != NULL)
		fprintf(f, " %s %s%s", a->map_state <= 2 ? map_states[a->map_state] : "?",
		       a->_class == XCB_WINDOW_CLASS_INPUT_ONLY ? "InputOnly" : "InputOutput",
		       a->override_redirect ? " override-redirect" : "");
	if (s != NULL && s->bounding_shaped) {
		fprintf(f, " shaped");
		xcb_shape_get_rectangles_reply_t *r = xcb_shape_get_rectangles_reply(
			d->c, xcb_shape_get_rectangles(d->c, xid, XCB_SHAPE_SK_BOUNDING), NULL);
		int n = r != NULL ? xcb_shape_get_rectangles_rectangles_length(r) : 0;
		xcb_rectangle_t *rr = r != NULL ? xcb_shape_get_rectangles_rectangles(r) : NULL;
		for (int i = 0; i < n && i < 8; i++)
			fprintf(f, " %ux%u%+d%+d", rr[i].width, rr[i].height, rr[i].x, rr[i].y);
		if (n > 8)
			fprintf(f, " …");
		free(r);
	}
	if (g == NULL || a == NULL)
		fprintf(f, " (gone)");
	fprintf(f, "\n");
	free(g);
	free(a);
	free(s);
}

void check_print_path(FILE *f, struct desk *d, xcb_window_t xid)
{
	xcb_window_t chain[64];
	int n = 0;
	for (xcb_window_t w = xid; w != XCB_NONE && n < 64;) {
		chain[n++] = w;
		if (w == d->root)
			break;
		xcb_query_tree_reply_t *t = xcb_query_tree_reply(d->c, xcb_query_tree(d->c, w), NULL);
		w = t ? t->parent : XCB_NONE;
		free(t);
	}
	for (int i = n - 1; i >= 0; i--)
		print_window(f, d, chain[i], n - 1 - i);
}

/* Parses "0x%x STATE" lines into a sorted array; dies on a line it cannot read. */
static struct x_view *read_cmd(struct desk *d, const char *cmd, size_t *n)
{
	FILE *f = popen(cmd, "r");
	if (f == NULL)
		desk_die(d, 1, "cannot run %s", cmd);
	struct views vs = { 0 };
	char *line = NULL, word[32];
	size_t cap = 0;
	unsigned long lineno = 0;
	unsigned int xid;
	while (getline(&line, &cap, f) > 0) {
		lineno++;
		int end = 0, state = -1;
		if (sscanf(line, "0x%x %31s %n", &xid, word, &end) == 2 && line[end] == '\0')
			for (int s = 0; s < 3; s++)
				if (strcmp(word, state_names[s]) == 0)
					state = s;
		if (state < 0) {
			line[strcspn(line, "\n")] = '\0';
			fprintf(stderr, "x11-desk: %s, line %lu: not \"0x… STATE\": %s\n", cmd, lineno,
				line);
			free(line);
			free(vs.v);
			pclose(f);
			desk_die(d, 1, "cannot read the states of %s", cmd);
		}
		push(d, &vs, xid, state, state, false);
	}
	free(line);
	int status = pclose(f);
	if (status != 0) {
		free(vs.v);
		if (WIFEXITED(status))
			desk_die(d, 1, "%s failed (exit status %d)", cmd, WEXITSTATUS(status));
		desk_die(d, 1, "%s failed (wait status %d)", cmd, status);
	}
	if (vs.n > 1)
		qsort(vs.v, vs.n, sizeof *vs.v, by_xid);
	*n = vs.n;
	return vs.v;
}

/*
 * Whether xid is shaped with a piece reaching past its border box: X then says partially obscured
 * where every pixel is seen (miShapedWindowIn counts a band wholly outside the box as obscured),
 * and visd follows the pixels, as test-xorg.c marks too.
 */
static bool shape_past_box(struct desk *d, xcb_window_t xid)
{
	if (!d->shape)
		return false;
	xcb_shape_query_extents_cookie_t ec = xcb_shape_query_extents(d->c, xid);
	xcb_get_geometry_cookie_t gc = xcb_get_geometry(d->c, xid);
	xcb_shape_get_rectangles_cookie_t rc =
		xcb_shape_get_rectangles(d->c, xid, XCB_SHAPE_SK_BOUNDING);
	xcb_shape_query_extents_reply_t *e = xcb_shape_query_extents_reply(d->c, ec, NULL);
	xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(d->c, gc, NULL);
	xcb_shape_get_rectangles_reply_t *r = xcb_shape_get_rectangles_reply(d->c, rc, NULL);
	bool past = false;
	if (e != NULL && e->bounding_shaped && g != NULL && r != NULL) {
		int b = g->border_width, n = xcb_shape_get_rectangles_rectangles_length(r);
		xcb_rectangle_t *rr = xcb_shape_get_rectangles_rectangles(r);
		for (int i = 0; i < n; i++)
			past = past || rr[i].x < -b || rr[i].y < -b ||
			       rr[i].x + rr[i].width > g->width + b ||
			       rr[i].y + rr[i].height > g->height + b;
	}
	free(e);
	free(g);
	free(r);
	return past;
}

/* Differences of a step shown with their windows' paths; the rest are counted. */
#define SHOWN_DIFFS 6

/* Reports one difference (who says what, and visd); the first of a step names the step. */
static void report(struct desk *d, unsigned long step, const char *what, unsigned long *diffs,
		   xcb_window_t xid, const char *who, const char *x_says, const char *cmd_says)
{
	if (*diffs == 0)
		printf("x11-desk: step %lu (%s):\n", step, what);
	if (++*diffs > SHOWN_DIFFS)
		return; /* counted; the first ones tell the story */
	printf("  0x%x: %s %s, visd %s; its path from the root:\n", xid, who, x_says, cmd_says);
	check_print_path(stdout, d, xid);
}

/*
 * Under a compositor: what a client that selected VisibilityChangeMask was told last (X's word or
 * the bridge's synthetic event) must be visd's state, unless the bridge sends nothing (never);
 * X's own word is only counted when it differs.
 */
static void compare_told(struct desk *d, unsigned long step, const char *what,
			 unsigned long *diffs, const struct x_view *x, const struct x_view *c)
{
	if (x->state >= 0 && x->state != c->state)
		d->x_wrong++;
	if (x->told == NO_RECORD) {
		d->harness_failures++;
		printf("x11-desk: step %lu (%s): harness: 0x%x is viewable, %s\n", step, what,
		       x->xid, check_state_name(x->told));
		return;
	}
	if (x->told < 0) {
		d->untold++;
		return;
	}
	if (d->send_events == SEND_NEVER || x->told == c->state)
		return;
	char says[96];
	snprintf(says, sizeof says, "%s (X's own word: %s)", check_state_name(x->told),
		 check_state_name(x->state));
	report(d, step, what, diffs, x->xid, "its clients were told", says,
	       check_state_name(c->state));
}

/* Every window visd has a state for against the brute force over X's tree. */
static void compare_brute(struct desk *d, unsigned long step, const char *what,
			  unsigned long *diffs, const struct check_read *r)
{
	const struct x_view *c = r->c;
	size_t nc = r->nc, nb = r->nb;
	const struct brute *b = r->b;
	for (size_t k = 0; k < nc; k++) {
		const struct brute *f = brute_find(b, nb, c[k].xid);
		if (f == NULL)
			continue; /* not a viewable InputOutput window: the X views say so */
		d->brute_checked++;
		if (f->state == c[k].state)
			continue;
		char says[96];
		snprintf(says, sizeof says, "%s (visd's engine on X's tree: %s)",
			 check_state_name(f->state), check_state_name(f->engine));
		report(d, step, what, diffs, c[k].xid, "the brute force says", says,
		       check_state_name(c[k].state));
	}
}

/*
 * --send-events always: every window whose visd state changed since the last quiet point must
 * have got a synthetic event since (a change and its undoing between two points go unseen).
 */
static void compare_changes(struct desk *d, unsigned long step, const char *what,
			    unsigned long *diffs, const struct x_view *c, size_t nc)
{
	const struct x_view *p = d->prev_visd;
	for (size_t i = 0, k = 0; i < d->n_prev_visd && k < nc;) {
		if (p[i].xid != c[k].xid) {
			if (p[i].xid < c[k].xid)
				i++;
			else
				k++;
			continue;
		}
		if (p[i].state != c[k].state) {
			d->visd_changes++;
			struct rec_window *w = record_find(&d->rec, c[k].xid);
			if (d->send_events == SEND_ALWAYS &&
			    (w == NULL || w->synthetic == w->synthetic_mark)) {
				d->changes_untold++;
				char says[96];
				snprintf(says, sizeof says, "nothing synthetic after visd's %s",
					 check_state_name(p[i].state));
				report(d, step, what, diffs, c[k].xid, "its clients got", says,
				       check_state_name(c[k].state));
			}
		}
		i++;
		k++;
	}
	for (size_t i = 0; i < d->rec.n; i++)
		d->rec.w[i].synthetic_mark = d->rec.w[i].synthetic;
}

void check_read(struct desk *d, const char *cmd, struct check_read *r)
{
	r->c = read_cmd(d, cmd, &r->nc);
	r->x = check_x_views(d, &r->nx);
	r->b = brute_states(d, &r->nb);
}

void check_read_free(struct check_read *r)
{
	free(r->c);
	free(r->x);
	free(r->b);
	*r = (struct check_read){ 0 };
}

unsigned long check_compare(struct desk *d, struct check_read *r, unsigned long step,
			    const char *what, unsigned long *checked)
{
	size_t nx = r->nx, nc = r->nc;
	const struct x_view *x = r->x, *c = r->c;
	unsigned long diffs = 0;
	size_t i = 0, k = 0;
	while (i < nx || k < nc) {
		bool in_x = i < nx && (k == nc || x[i].xid <= c[k].xid);
		bool in_cmd = k < nc && (i == nx || c[k].xid <= x[i].xid);
		if (in_x && !d->compositor && x[i].redirected) {
			d->redirected++;
		} else if (in_x && !d->compositor && x[i].state < 0) {
			/* The harness's failure, not visd's: X's truth is missing. */
			d->harness_failures++;
			printf("x11-desk: step %lu (%s): harness: 0x%x is viewable, %s\n", step, what,
			       x[i].xid, check_state_name(x[i].state));
			check_print_path(stdout, d, x[i].xid);
		} else if (in_x && in_cmd) {
			++*checked;
			if (d->compositor)
				compare_told(d, step, what, &diffs, &x[i], &c[k]);
			else if (x[i].state == XCB_VISIBILITY_PARTIALLY_OBSCURED &&
				 c[k].state == XCB_VISIBILITY_UNOBSCURED && shape_past_box(d, x[i].xid))
				d->past_box++;
			else if (x[i].state != c[k].state)
				report(d, step, what, &diffs, x[i].xid, "X", check_state_name(x[i].state),
				       check_state_name(c[k].state));
		} else if (in_x) {
			report(d, step, what, &diffs, x[i].xid, "X", check_state_name(x[i].state),
			       "lists nothing");
		} else if (c[k].xid != d->root) {
			report(d, step, what, &diffs, c[k].xid, "X", "has no such viewable InputOutput window",
			       check_state_name(c[k].state));
		}
		i += in_x;
		k += in_cmd;
	}
	compare_brute(d, step, what, &diffs, r);
	compare_changes(d, step, what, &diffs, c, nc);
	if (diffs > SHOWN_DIFFS)
		printf("  … and %lu more differences\n", diffs - SHOWN_DIFFS);
	fflush(stdout);
	free(d->prev_visd);
	d->prev_visd = r->c;
	d->n_prev_visd = nc;
	r->c = NULL;
	check_read_free(r);
	return diffs;
}
