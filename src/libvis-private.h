/*
 * libvis's handles over the core (wtree.h), private to src/libvis*.c: the public tree and window
 * wrap the core's, and keep what a compositor needs beyond the states (wtree.h's recomputes give
 * those): where the tree changed since the last update, which windows' exposures are tracked and
 * what they showed, and the arrays the calls return, reused from call to call.
 */
#ifndef VIS_LIBVIS_PRIVATE_H
#define VIS_LIBVIS_PRIVATE_H

#include <pixman.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bands.h"
#include "look.h"
#include "vis/vis.h"
#include "wtree.h"

/* Damage boxes kept per update; past that many changes, the damage is everywhere. */
#define LIBVIS_DAMAGE_BOXES 1024

/*
 * A window: the core's (whose data points back here) and the caller's pointer. While tracked,
 * it is in its tree's tracked list at tracked_slot − 1, and region holds what it showed at the
 * last update when known (else it showed nothing as far as exposures go).
 */
struct vis_win {
	struct vis_window *core;
	struct vis_tree *tree;
	void *data;
	bool tracked, known;
	uint32_t tracked_slot;
	uint64_t listed; /* the update (tree->serial) whose changes listed it last */
	pixman_region32_t region;
	/* While the tree keeps tallies (libvis-tally.c): its own pixels, and those of them seen
	 * (counted modulo 2^64 as walks take them off and put them back). */
	uint64_t total, seen;
	uint32_t touched_slot; /* 1 + its index in tree->touched, or 0 */
};

/* Windows up to which a tree keeps tallies, by default (libvis-tally.c). */
#define LIBVIS_TALLY_WINDOWS 1024

/*
 * A repaint set as a walk lists it, top window first: wins[0 … n), each with the next n_rects of
 * rects[0 … n_rects) (their rects pointers are set when handed out, and data: the window's
 * user pointer may change while a set is kept).
 */
struct libvis_set {
	struct vis_repaint *wins;
	size_t n, cap;
	struct vis_rect32 *rects;
	size_t n_rects, cap_rects;
};

/*
 * A walk over a damaged area, from the top window down (libvis-tally.c): left is what is left
 * of the area, scratch its double; saves[d] what was left where a window at nesting d began
 * (its descendants hide nothing of it); entered the windows whose children the walk is in, from
 * the outermost. sign: the tallies' walk (−1 before a change, +1 after),
 * or 0; out: the repaint set it lists, or NULL.
 */
struct libvis_entered {
	const struct vis_window *w;
	bool saved; /* what was left where it began is in saves, for its tally */
};

struct libvis_walk {
	struct vis_bands left, scratch;
	struct vis_bands *saves;
	size_t cap_saves;
	struct libvis_entered *entered; /* the windows whose children a walk is in */
	size_t cap_entered;
	int sign;
	struct libvis_set *out;
	const struct vis_window *stop; /* a top-level window the walk stops at, or NULL */
	/* With within, tallies count only inside in[0 … n_in), less what is inside less[0 …
	 * n_less), which the set does not list (a moved window's pixels before and after). */
	bool within;
	const pixman_box32_t *in, *less;
	size_t n_in, n_less;
	struct vis_bands listed; /* a part less those boxes */
	/* Top-level windows a repaint walk passes one by one before it asks the live engine's
	 * grid, when there is one (LIBVIS_GRID_AFTER; the tests take it lower). */
	size_t grid_after;
};

#define LIBVIS_GRID_AFTER 64

/*
 * A tree. dirty: changed since the last update; damage[0 … n_damage) holds the border boxes of
 * the changes' windows before and after each change (damage_all: too many to keep), for the
 * exposures' test of which tracked windows may have changed (maybe_exposed in libvis-update.c).
 */
struct vis_tree {
	struct vis_wtree core;
	bool dirty, damage_all;
	size_t n_damage;
	pixman_box32_t *damage; /* LIBVIS_DAMAGE_BOXES */
	uint64_t serial;        /* updates done */
	struct vis_win **tracked;
	size_t n_tracked, cap_tracked;
	/* The update's arrays: the windows to look at, the changes and their exposures. */
	struct vis_win **list;
	size_t cap_list;
	struct vis_change *changes;
	size_t n_changes, cap_changes;
	struct vis_rect32 *rects;
	size_t n_rects, cap_rects;
	/* The queries' arrays and scratch. */
	struct vis_rect32 *qrects;
	size_t n_qrects, cap_qrects;
	struct libvis_set shown; /* the last repaint query's */
	struct vis_pieces pieces;
	pixman_box32_t *boxes; /* a window's pieces as pixman's boxes */
	size_t cap_boxes;
	pixman_box32_t *parts; /* what of them a walk finds left */
	size_t cap_parts;
	pixman_region32_t now, exposed, part;
	struct libvis_walk walk;
	/*
	 * Tallies (libvis-tally.c): while tally is on, each window's seen pixels are kept by walks
	 * over what each change may alter, and an update takes the states from them. tally_max:
	 * the windows up to which they are taken up (0: never); broken: a walk failed (no memory),
	 * the next update goes through the core; changed: the box a change walks, before and after.
	 */
	bool tally, tally_broken;
	size_t tally_max;
	struct vis_box tally_box;
	/* The repaint set of kept_box, listed by the walk after the last change (kept_ok). */
	struct libvis_set kept;
	struct vis_box kept_box;
	bool kept_ok;
	/* A window moving alone (libvis_tally_begin_move()): it and the pixels it saw before, and
	 * what the windows above it leave of the change's box. */
	struct vis_window *moved;
	uint64_t moved_seen;
	struct vis_bands above;
	pixman_box32_t *opaque_was, *opaque_is; /* its opaque pixels before and after */
	size_t n_opaque_was, cap_opaque_was, n_opaque_is, cap_opaque_is;
	/* The windows whose states may have changed since the last update (their tallies met by
	 * walks, or their subtree's viewability changed); restacked: some change moved windows in
	 * the order or in and out of it (restacks: the change under way), so that the update
	 * numbers them again. */
	struct vis_window **touched;
	size_t n_touched, cap_touched;
	bool tally_restacked, tally_restacks;
};

/* Records that win is about to change or has changed (libvis-update.c): the tree is dirty, the
 * live recompute notes it, and its border box joins the damage. */
void libvis_damage(struct vis_tree *tree, struct vis_win *win);

/*
 * The walks (libvis-walk.c). libvis_walk() walks the box d of the screen (inside it), top window
 * down to the top-level window stop (not walked; NULL: all): sign ±1 adds each window's seen
 * pixels there to its tally, or takes them off; out, if not NULL, gets the repaint set of d.
 * libvis_walk_left() walks what tree->walk.left holds from the top-level window start down
 * (out is not emptied first; with tree->walk.in set, the tallies count only inside its
 * disjoint boxes, for this walk). 0, or -1 with ENOMEM. O(windows whose clips meet what is left,
 * times its boxes).
 */
int libvis_walk(struct vis_tree *tree, struct vis_box d, int sign, struct libvis_set *out,
		const struct vis_window *stop);
int libvis_walk_left(struct vis_tree *tree, const struct vis_window *start,
		     const struct vis_window *stop, int sign, struct libvis_set *out);

/* Lists w in the walk's set (tree->walk.out) with what is left of the screen box b, and sets
 * *pixels to that part's. 0, or -1. */
int libvis_draw_box(struct vis_tree *tree, const struct vis_window *w, struct vis_box b,
		    uint64_t *pixels);

/*
 * The opaque pixels of a viewable window whose pixels are its clip (not LIBVIS_PIECES): its clip,
 * or its cut's opaque pieces in it, as disjoint boxes in *out[0 … n) (the tree's scratch, until
 * the next walk). n, or -1 with ENOMEM.
 */
long libvis_opaque_boxes(struct vis_tree *tree, const struct vis_window *w,
			 const pixman_box32_t **out);

/* Lists w among the windows whose states the next update looks at, once. 0, or -1 (ENOMEM). */
int libvis_touch(struct vis_tree *tree, struct vis_window *w);

/* What a window's pixels are, for a walk: its clip, all opaque (a plain window, or one with a
 * border alone); its clip, opaque where its cut's opaque pieces are (a see-through look without a
 * shape); or its pieces (a shape of its own or of an ancestor, which clips it). O(depth). */
enum libvis_pixels { LIBVIS_CLIP, LIBVIS_CLIP_SEE_THROUGH, LIBVIS_PIECES };
enum libvis_pixels libvis_pixels_of(const struct vis_window *w);

/*
 * The tallies (libvis-tally.c). Around every change, libvis_tally_begin() before it (win: the
 * window changed; after: the screen box its subtree takes after the change, if shows_after;
 * restacks: the change moves windows in the order of the viewable ones, or in or out of it; or
 * libvis_tally_begin_move() for a change of place or size alone, after: its new box),
 * libvis_tally_end() after it (win NULL once destroyed). libvis_tally_start() takes them up after
 * an update through the core. libvis_tally_update() is an update from them: 0 with the windows
 * whose states it changed among *changed[0 … *n) (their old states in old_state), or -1 with
 * ENOMEM (nothing changed then). libvis_tally_forget() drops a window destroyed from their
 * lists. libvis_tally_stop() leaves them to the core.
 */
void libvis_tally_begin(struct vis_tree *tree, struct vis_win *win, struct vis_box after,
			bool shows_after, bool restacks);
void libvis_tally_begin_move(struct vis_tree *tree, struct vis_win *win, struct vis_box after);
void libvis_tally_end(struct vis_tree *tree, struct vis_win *win);
int libvis_tally_start(struct vis_tree *tree);
int libvis_tally_update(struct vis_tree *tree, struct vis_window *const **changed, size_t *n);
void libvis_tally_forget(struct vis_tree *tree, struct vis_win *win);
void libvis_tally_stop(struct vis_tree *tree);

/* Sets the windows up to which a tree keeps tallies (0: never, as visd, which changes the core
 * itself). O(1). */
void libvis_tally_below(struct vis_tree *tree, size_t windows);

/* Stops tracking win's exposures, forgetting what it showed. O(1). */
void libvis_untrack(struct vis_win *win);

/*
 * For in-tree code that changes the core itself (visd, whose requests reach fields vis.h does not
 * offer: protocol IDs, owners, retained flags) and tells libvis through libvis_damage():
 *
 * libvis_wrap() gives w, a window just created in tree->core, its handle (w->data points to it
 * from then on): NULL with ENOMEM, w untouched then. O(1).
 * libvis_forget() frees the handle of w as the core destroys it: call it from
 * vis_wtree_destroy()'s callback, for each window destroyed. O(1).
 * libvis_forget_shown() forgets what win showed, as a new size or border does (X's
 * ForgetGravity): if tracked, all it shows at the next update is newly exposed. O(1).
 */
struct vis_win *libvis_wrap(struct vis_tree *tree, struct vis_window *w);
void libvis_forget(struct vis_window *w);
void libvis_forget_shown(struct vis_win *win);

/*
 * Appends region's rectangles, moved by -dx, -dy, to *arr (*n used of *cap), growing it.
 * 0, or -1 with ENOMEM (nothing appended then).
 */
int libvis_append_rects(pixman_region32_t *region, int64_t dx, int64_t dy,
			struct vis_rect32 **arr, size_t *n, size_t *cap);

/*
 * Makes room for count elements of size size in the array whose pointer is at arr (a T **, any
 * T), *cap of them now, doubling it at least. 0, or -1 with ENOMEM or EOVERFLOW (it stays then).
 * Inline for the walks, which ask at every window; libvis_grow() grows.
 */
int libvis_grow(void *arr, size_t *cap, size_t count, size_t size);

static inline int libvis_reserve(void *arr, size_t *cap, size_t count, size_t size)
{
	return count <= *cap ? 0 : libvis_grow(arr, cap, count, size);
}

#endif
