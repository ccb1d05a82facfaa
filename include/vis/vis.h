/*
 * libvis: visd's visibility core as a library, for a compositor (or anyone) to embed.
 *
 * A tree (struct vis_tree) is a screen and the windows on it, with X's model: windows in a tree,
 * stacked among their siblings from bottom to top and clipped by their ancestors' insides; each
 * with a border, a bounding shape, an opaque region, or no pixels at all (input-only). The
 * library answers what the daemon answers its clients: each window's visibility state (enum
 * vis_visibility, X's VisibilityNotify rule), its visible region, what became newly visible
 * since the last recompute, and what to draw for a damaged area of the screen.
 *
 * Threads, I/O, memory: none, none, and no global state. A tree and its windows belong to one
 * thread at a time; different trees are independent. The library never prints, exits or aborts.
 * It keeps nothing of the caller's arguments after a call returns (rectangles are copied); the
 * arrays it returns are its own, valid until the call the function names.
 *
 * Errors: a function returning int returns 0 (or a count) on success and -1 with errno on
 * failure, one returning a pointer NULL with errno; a failed call changes nothing. errno is
 * EINVAL for a bad argument (NULL where a handle is wanted, a window of another tree, a size or
 * mode out of range, a loop in the tree), EOVERFLOW for a window or a rectangle whose pixels
 * would pass the 32-bit plane (a border box's side past INT32_MAX), E2BIG for more rectangles
 * than VIS_LOOK_MAX_RECTS, EEXIST for an external ID another window carries, EAGAIN for a query
 * that needs vis_tree_update() first, ENOMEM when memory runs out. The checks are the daemon's,
 * the same a client's requests pass (visd-protocol(7)).
 *
 * Coordinates, one convention (the protocol's since protocol 4): a window's place (x, y) is its
 * border box's top-left corner relative to its parent's inside's corner (the screen's corner for
 * top-level windows); its size (width × height) is its inside, which its border of border pixels
 * surrounds. Everything about one window's pixels (shape, opaque region, visible region,
 * exposures, the parts of a repaint) is in window coordinates: relative to the window's inside's
 * top-left corner, so that its border lies at negative coordinates and past width, height.
 * Damage is in screen coordinates. Every rectangle covers x ≤ px < x + width, y ≤ py < y + height.
 *
 * Changes accumulate: vis_tree_update() recomputes once for all the changes made since the last
 * one, at a cost that follows the changes rather than the tree, and lists what they did. Queries
 * answer for the last update: a window's state, its visible region and the repaint set of a
 * damaged box.
 *
 * Two ways keep the states, chosen by the tree's size. Up to 1,024 windows (and until it passes
 * 2,048), each window keeps a tally of its own pixels it sees: a change walks the windows over the
 * box it alters, from the top down, before and after itself, taking off and adding back what each
 * sees there, so that each change costs W, its walks over the windows whose clips meet what is
 * left of that box (a plain top-level window moved or resized walks down to itself once, and
 * below itself over the strips it left and took only), and an update only gives the windows
 * those walks met their states. The walk after the last change also lists the repaint set of its
 * box, which answers vis_tree_repaint() for any damage inside it until the next change: most
 * frames' damage. Past that size, changes only record where the tree changed (W is nothing), and
 * vis_tree_update() runs visd's live engine.
 */
#ifndef VIS_VIS_H
#define VIS_VIS_H

#include <stddef.h>
#include <stdint.h>

#include "vis/common.h"   /* VIS_EXPORT, struct vis_rect32 */
#include "vis/protocol.h" /* the model's numbers: enum vis_visibility, vis_opaque_mode, ... */

#ifdef __cplusplus
extern "C" {
#endif

/* A screen and its windows. */
struct vis_tree;

/* A window of a tree; valid from vis_win_create() until it or an ancestor is destroyed. */
struct vis_win;

/* vis_win_create()'s flags. */
enum vis_win_flags {
	/* No pixels and no state (border 0, no look): a window that only takes input, as X's
	 * InputOnly windows; it hides nothing. */
	VIS_WIN_INPUT_ONLY = 1u << 0,
};

/*
 * Creates an empty tree over a screen of width × height pixels (each 1 … INT32_MAX). NULL with
 * EINVAL or ENOMEM. O(1).
 */
VIS_EXPORT struct vis_tree *vis_tree_create(int32_t width, int32_t height);

/* Destroys a tree and every window in it (their user pointers are the caller's). NULL: no-op.
 * O(n). */
VIS_EXPORT void vis_tree_destroy(struct vis_tree *tree);

/* The screen's size, into *width and *height. 0, or -1 with EINVAL. O(1). */
VIS_EXPORT int vis_tree_screen(const struct vis_tree *tree, int32_t *width, int32_t *height);

/*
 * Creates an unmapped window on top of parent's children (parent NULL: a top-level window), its
 * border box's corner at x, y in the parent's coordinates, its inside width × height (1 …
 * INT32_MAX), its border border (≥ 0, the border box's sides at most INT32_MAX; 0 for an
 * input-only one), flags from enum vis_win_flags. NULL with EINVAL (parent of another tree,
 * sizes, flags), EOVERFLOW (the border box, or the 2^32 − 1 windows a tree can ever create), or
 * ENOMEM. O(1).
 */
VIS_EXPORT struct vis_win *vis_win_create(struct vis_tree *tree, struct vis_win *parent, int32_t x,
					  int32_t y, int32_t width, int32_t height, int32_t border,
					  uint32_t flags);

/* Destroys a window and its descendants (their user pointers are the caller's); what they
 * covered shows at the next update. NULL: no-op. O(size of the subtree) + W. */
VIS_EXPORT void vis_win_destroy(struct vis_win *win);

/* Maps or unmaps a window: it can be seen while it and all its ancestors are mapped (viewable).
 * 0, or -1 with EINVAL. O(size of the subtree) + W. */
VIS_EXPORT int vis_win_map(struct vis_win *win);
VIS_EXPORT int vis_win_unmap(struct vis_win *win);

/*
 * Places a window at x, y (its parent's coordinates) with the inside width × height and the
 * border border, checked as by vis_win_create(); a window with a shape or opaque rectangles is
 * cut into pieces again for a new size (EOVERFLOW when they would leave the 32-bit plane). A new
 * size or border forgets what the window showed: its whole visible region counts as newly
 * exposed at the next update (X's ForgetGravity). 0, or -1 with EINVAL, EOVERFLOW or ENOMEM.
 * O(1), or O(k log k) for a look of k rectangles cut again; + O(size of the subtree) + W.
 */
VIS_EXPORT int vis_win_configure(struct vis_win *win, int32_t x, int32_t y, int32_t width,
				 int32_t height, int32_t border);

/* vis_win_configure() keeping the size and border. 0, or -1 with EINVAL. As it costs. */
VIS_EXPORT int vis_win_move(struct vis_win *win, int32_t x, int32_t y);

/* Puts a window on top of (raise) or below (lower) all its siblings. 0, or -1 with EINVAL.
 * O(1) + W. */
VIS_EXPORT int vis_win_raise(struct vis_win *win);
VIS_EXPORT int vis_win_lower(struct vis_win *win);

/*
 * Puts a window just above (above ≠ 0) or just below sibling, another child of its parent.
 * 0, or -1 with EINVAL. O(1) + W.
 */
VIS_EXPORT int vis_win_restack(struct vis_win *win, struct vis_win *sibling, int above);

/*
 * Moves a window and its subtree under parent (NULL: the screen) at x, y, on top of its new
 * siblings; parent must not be the window or one of its descendants. 0, or -1 with EINVAL.
 * O(size of the subtree) + W.
 */
VIS_EXPORT int vis_win_reparent(struct vis_win *win, struct vis_win *parent, int32_t x, int32_t y);

/*
 * Sets a window's bounding shape: with shaped ≠ 0, its pixels become the union of rects[0 … n)
 * clipped to its border box (window coordinates, each width, height 1 … INT32_MAX, overlaps
 * allowed; n = 0: no pixels); with shaped 0 (n must be 0), its whole border box again. As in X,
 * a shape also clips the window's descendants. 0, or -1 with EINVAL (an input-only window,
 * rects NULL with n > 0, a size out of range), E2BIG (n > VIS_LOOK_MAX_RECTS), EOVERFLOW or
 * ENOMEM. O(k log k) for the look's k rectangles, + W.
 */
VIS_EXPORT int vis_win_set_shape(struct vis_win *win, int shaped, const struct vis_rect32 *rects,
				 uint32_t n);

/*
 * Sets which of a window's pixels hide what lies below (enum vis_opaque_mode): all (the
 * default), none (a translucent window), or with VIS_OPAQUE_MODE_RECTS those in rects[0 … n)
 * (window coordinates; n must be 0 for the other modes). Errors and cost as vis_win_set_shape().
 */
VIS_EXPORT int vis_win_set_opaque(struct vis_win *win, uint32_t mode, const struct vis_rect32 *rects,
				  uint32_t n);

/* The caller's pointer kept with a window (NULL at first), handed back with its changes and
 * repaints. set: 0, or -1 with EINVAL; get: NULL for a NULL window. O(1). */
VIS_EXPORT int vis_win_set_data(struct vis_win *win, void *data);
VIS_EXPORT void *vis_win_get_data(const struct vis_win *win);

/*
 * Tags a window with what it mirrors, for the life of the window: a namespace (enum
 * vis_external_namespace or another, not 0) and a tag unique in it (an XID, …). 0, or -1 with
 * EINVAL (namespace 0, or the window has a tag already), EEXIST (another window has the pair),
 * ENOMEM. Expected O(1).
 */
VIS_EXPORT int vis_win_set_external(struct vis_win *win, uint32_t ext_namespace, uint64_t external);

/* The window tagged (ext_namespace, external), or NULL (always for namespace 0). Expected O(1). */
VIS_EXPORT struct vis_win *vis_tree_find_external(const struct vis_tree *tree,
						  uint32_t ext_namespace, uint64_t external);

/*
 * Starts (on ≠ 0) or stops tracking a window's exposures: while on, each vis_tree_update() lists
 * the window with the part of its visible region that it did not show before (X's Expose, for a
 * compositor: what to draw of it that was not on the screen). Tracking starts from what the window
 * showed at the last update when the tree has not changed since; else (or for a window created
 * since) from nothing, so that all it shows after the next update is newly exposed. Should memory
 * run out while an update computes an exposure, the window starts from nothing again. 0, or -1
 * with EINVAL or ENOMEM. O(n + r log r) when a baseline is taken, as vis_win_visible_region().
 */
VIS_EXPORT int vis_win_track_exposure(struct vis_win *win, int on);

/*
 * What a recompute did to one window: its state before and after (enum vis_visibility;
 * VIS_VISIBILITY_NONE when not viewable, or input-only), equal when it is listed only for an
 * exposure; and, for a window whose exposures are tracked, the pixels newly visible (window
 * coordinates, y-x banded: sorted by y, then x, in bands; none when n_exposed is 0).
 */
struct vis_change {
	struct vis_win *win;
	void *data; /* the window's user pointer */
	uint32_t state, previous;
	uint32_t n_exposed;
	const struct vis_rect32 *exposed;
};

/*
 * Recomputes every window's state after the changes made since the last update, and lists the
 * windows whose state changed or that have newly exposed pixels (tracked ones): in *changes[0 …
 * *n), those no longer viewable first, then the others bottom to top (stacking order). The array
 * and the rectangles it points to are the tree's, valid until the next vis_tree_update() or
 * vis_tree_destroy(), and reused from one update to the next (no allocation per change once they
 * have grown); an entry's window must not be used once destroyed. With no change since the last
 * update, *n is 0 and nothing is recomputed. 0, or -1 with EINVAL or ENOMEM (the states stay as
 * they were, the changes pending: the next update tries again). Cost, with tallies (up to 1,024
 * windows, see above): O(k log k) for the k windows the changes' walks met, and O(n) more after
 * a change of the stacking order or of what is viewable, to number the windows again. Past
 * that, the live recompute, whose cost follows the windows the changes can affect, not the tree,
 * while no viewable window lies inside a shaped window; else a recompute limited to the damage,
 * O(n log n) at worst for n windows (pieces, for windows with looks). Plus, for each tracked
 * window the change may have touched, its visible region (vis_win_visible_region()'s cost and
 * scratch memory, which the list itself does not need).
 */
VIS_EXPORT int vis_tree_update(struct vis_tree *tree, const struct vis_change **changes, size_t *n);

/*
 * A window's state at the last update (enum vis_visibility): unobscured when every pixel of its
 * own is visible, fully obscured when none is, else partially obscured; VIS_VISIBILITY_NONE when
 * it is not viewable or input-only (and for a window created since). Pixels of its own hide
 * nothing of it, its descendants' included; the screen's and its ancestors' edges clip it.
 * Returns it, or -1 with EINVAL. O(1).
 */
VIS_EXPORT int vis_win_state(const struct vis_win *win);

/*
 * A window's visible region at the last update: its pixels, inside its ancestors and the screen,
 * that no opaque pixel of a later window in stacking order covers (its descendants' included,
 * as X's clip list; translucent windows above leave it visible). In *rects[0 … *n), window
 * coordinates, y-x banded; the tree's array, valid until the next query or change of the tree.
 * 0, or -1 with EINVAL, EAGAIN (changes since the last update) or ENOMEM.
 * O(n + r log r) for r pieces of the windows that overlap it.
 */
VIS_EXPORT int vis_win_visible_region(struct vis_win *win, const struct vis_rect32 **rects,
				      size_t *n);

/*
 * One window of a repaint set: the part of it to draw (window coordinates, y-x banded), and
 * where its inside's corner lies on the screen (x, y), to place its rectangles there.
 */
struct vis_repaint {
	struct vis_win *win;
	void *data; /* the window's user pointer */
	int64_t x, y;
	uint32_t n_rects;
	const struct vis_rect32 *rects;
};

/*
 * The repaint set of a damaged box of the screen (screen coordinates, width and height 1 …
 * INT32_MAX), what a render pass walks: the windows with visible pixels in it, bottom to top,
 * each with its visible region's part inside it. Drawn in order, each window covers the damage
 * exactly as the screen shows it: every pixel of it is drawn by the window that shows it on top
 * (opaque there) and by the translucent ones above it, and by no other. In *out[0 … *n): the
 * tree's array, valid until the next query or change of the tree. 0, or -1 with EINVAL, EAGAIN
 * (changes since the last update) or ENOMEM. Cost: inside the box of the last change of a tree
 * with tallies, O(r) for the r rectangles listed for that box; else the region method inside the
 * damage, from the top down, over the windows that meet it until opaque ones have covered it
 * (O(k · r) for k windows visited and r rectangles of what is left; in a tree past tallies, the
 * live engine's grid finds them once 64 top-level windows have left the damage uncovered).
 */
VIS_EXPORT int vis_tree_repaint(struct vis_tree *tree, const struct vis_rect32 *damage,
				const struct vis_repaint **out, size_t *n);

#ifdef __cplusplus
}
#endif

#endif
