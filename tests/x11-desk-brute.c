/*
 * The brute force: X's tree read under a server grab (geometry, borders, map states, classes,
 * stacking, bounding shapes, depths, _NET_WM_WINDOW_OPACITY and _NET_WM_OPAQUE_REGION) becomes a
 * vis_wtree, whose states oracle.c paints pixel by pixel. Where a compositing manager runs
 * (--compositor), the translucency rule of visd-x11(1) decides what hides what: a top-level that
 * is 32-bit or below 100% opacity hides, in its whole subtree, only each window's opaque region
 * (nothing without one); every other window hides its pixels, as X paints. The same tree is also
 * computed by visd's engine, so that a difference says whether the bridge or the engine erred.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <xcb/shape.h>

#include "oracle.h"
#include "x11-desk.h"

#define OPAQUE_100 0xffffffffu

/* What a read of one window brings. */
struct cookies {
	xcb_get_window_attributes_cookie_t attrs;
	xcb_get_geometry_cookie_t geom;
	xcb_shape_query_extents_cookie_t extents;
	xcb_shape_get_rectangles_cookie_t shape;
	xcb_get_property_cookie_t opacity, region;
	xcb_query_tree_cookie_t tree;
};

/* Rectangles of a CARDINAL[4n] property (x, y signed), or NULL with *n 0 (*has: it is set). */
static struct vis_rect *region_of(xcb_get_property_reply_t *p, uint32_t *n, bool *has)
{
	*n = 0;
	*has = p != NULL && p->type == XCB_ATOM_CARDINAL && p->format == 32;
	if (!*has)
		return NULL;
	uint32_t count = (uint32_t)xcb_get_property_value_length(p) / 16;
	const uint32_t *v = xcb_get_property_value(p);
	struct vis_rect *r = count ? malloc(count * sizeof *r) : NULL;
	if (r == NULL)
		return NULL;
	for (uint32_t i = 0; i < count; i++)
		r[i] = (struct vis_rect){ (int32_t)v[4 * i], (int32_t)v[4 * i + 1],
					  (int32_t)v[4 * i + 2], (int32_t)v[4 * i + 3] };
	*n = count;
	return r;
}

/*
 * Reads xid's children (bottom to top) into the tree under parent; translucent when parent's
 * top-level hides only opaque regions (NULL parent: the root's children, which decide it).
 */
static void read_children(struct desk *d, struct vis_wtree *tree, struct vis_window *parent,
			  xcb_window_t xid, int translucent)
{
	xcb_query_tree_reply_t *t = xcb_query_tree_reply(d->c, xcb_query_tree(d->c, xid), NULL);
	if (t == NULL)
		return;
	int n = xcb_query_tree_children_length(t);
	xcb_window_t *kids = xcb_query_tree_children(t);
	struct cookies *c = calloc((size_t)(n ? n : 1), sizeof *c);
	if (c == NULL)
		desk_die(d, 1, "out of memory");
	for (int i = 0; i < n; i++) {
		c[i].attrs = xcb_get_window_attributes(d->c, kids[i]);
		c[i].geom = xcb_get_geometry(d->c, kids[i]);
		if (d->shape) {
			c[i].extents = xcb_shape_query_extents(d->c, kids[i]);
			c[i].shape = xcb_shape_get_rectangles(d->c, kids[i], XCB_SHAPE_SK_BOUNDING);
		}
		c[i].opacity = xcb_get_property(d->c, 0, kids[i], d->atom_opacity,
						XCB_ATOM_CARDINAL, 0, 1);
		c[i].region = xcb_get_property(d->c, 0, kids[i], d->atom_opaque_region,
					       XCB_ATOM_CARDINAL, 0, 4096);
	}
	for (int i = 0; i < n; i++) {
		xcb_get_window_attributes_reply_t *a =
			xcb_get_window_attributes_reply(d->c, c[i].attrs, NULL);
		xcb_get_geometry_reply_t *g = xcb_get_geometry_reply(d->c, c[i].geom, NULL);
		xcb_shape_query_extents_reply_t *e =
			d->shape ? xcb_shape_query_extents_reply(d->c, c[i].extents, NULL) : NULL;
		xcb_shape_get_rectangles_reply_t *s =
			d->shape ? xcb_shape_get_rectangles_reply(d->c, c[i].shape, NULL) : NULL;
		xcb_get_property_reply_t *op = xcb_get_property_reply(d->c, c[i].opacity, NULL);
		xcb_get_property_reply_t *rg = xcb_get_property_reply(d->c, c[i].region, NULL);
		struct vis_window *w = NULL;
		int kid_translucent = translucent;
		if (a != NULL && g != NULL) {
			w = vis_wtree_create(tree, parent, g->x, g->y, g->width ? g->width : 1,
					     g->height ? g->height : 1, 0);
			if (w == NULL)
				desk_die(d, 1, "out of memory");
			w->mapped = a->map_state != XCB_MAP_STATE_UNMAPPED;
			w->data = (void *)(uintptr_t)kids[i]; /* its XID */
			bool io = a->_class == XCB_WINDOW_CLASS_INPUT_OUTPUT;
			if (parent == &tree->root) {
				uint32_t opacity = OPAQUE_100;
				if (op != NULL && op->type == XCB_ATOM_CARDINAL && op->format == 32 &&
				    xcb_get_property_value_length(op) >= 4)
					memcpy(&opacity, xcb_get_property_value(op), 4);
				kid_translucent = d->compositor &&
						  ((io && g->depth == 32) || opacity != OPAQUE_100);
			}
			if (!io) {
				vis_wtree_set_input_only(w);
			} else {
				vis_wtree_set_border(w, g->border_width);
				/* Only when QueryExtents says so: GetRectangles of an unshaped
				 * window gives its border box one border too narrow (X.Org's
				 * ProcShapeGetRectangles adds the border once, not twice). */
				if (e != NULL && e->bounding_shaped && s != NULL) {
					uint32_t k = (uint32_t)xcb_shape_get_rectangles_rectangles_length(s);
					xcb_rectangle_t *xr = xcb_shape_get_rectangles_rectangles(s);
					struct vis_rect *r = k ? malloc(k * sizeof *r) : NULL;
					if (k && r == NULL)
						desk_die(d, 1, "out of memory");
					for (uint32_t j = 0; j < k; j++)
						r[j] = (struct vis_rect){ xr[j].x, xr[j].y, xr[j].width,
									  xr[j].height };
					vis_wtree_set_shape(w, true, r, k);
					free(r);
				}
				if (kid_translucent) {
					uint32_t k;
					bool has;
					struct vis_rect *r = region_of(rg, &k, &has);
					vis_wtree_set_opaque(w, k ? VIS_OPAQUE_RECTS : VIS_OPAQUE_NONE, r,
							     k);
					free(r);
				}
			}
		}
		free(a);
		free(g);
		free(e);
		free(s);
		free(op);
		free(rg);
		/* Nothing under an unmapped window is viewable: its subtree changes no state. */
		if (w != NULL && w->mapped)
			read_children(d, tree, w, kids[i], kid_translucent);
	}
	free(c);
	free(t);
}

/* The brute force's order: by XID, as the command's lines. */
static int by_xid(const void *a, const void *b)
{
	const struct brute *p = a, *q = b;
	return (p->xid > q->xid) - (p->xid < q->xid);
}

struct brute *brute_states(struct desk *d, size_t *n)
{
	struct vis_wtree tree;
	vis_wtree_init(&tree, d->screen->width_in_pixels, d->screen->height_in_pixels);
	xcb_grab_server(d->c);
	read_children(d, &tree, &tree.root, d->root, 0);
	xcb_ungrab_server(d->c);
	xcb_flush(d->c);
	desk_check_connection(d);
	uint8_t *painted = malloc(tree.count ? tree.count : 1);
	struct brute *out = malloc((tree.count ? tree.count : 1) * sizeof *out);
	if (painted == NULL || out == NULL || oracle_paint(&tree, painted) < 0 ||
	    vis_wtree_compute(&tree) < 0)
		desk_die(d, 1, "out of memory");
	size_t k = 0, i = 0;
	for (struct vis_window *w = tree.root.bottom; w; w = vis_wtree_next(w), i++)
		if (painted[i] != VIS_WTREE_STATE_NONE)
			out[k++] = (struct brute){ (xcb_window_t)(uintptr_t)w->data, painted[i], w->state };
	if (k > 1)
		qsort(out, k, sizeof *out, by_xid);
	free(painted);
	vis_wtree_finish(&tree);
	*n = k;
	return out;
}

const struct brute *brute_find(const struct brute *b, size_t n, xcb_window_t xid)
{
	struct brute key = { .xid = xid };
	return bsearch(&key, b, n, sizeof *b, by_xid);
}
