/*
 * X's window model beyond an opaque rectangle: a border, a bounding shape, an opaque region and
 * input-only windows. The engines know only rectangles, opaque or see-through (stack.h); this
 * module cuts windows with a look into such pieces, and joins the pieces' states back into the
 * windows' states, so that every engine takes the model from one place.
 */
#ifndef VIS_LOOK_H
#define VIS_LOOK_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "stack.h"

/* Which of its pixels hide what lies below a window; the numbers are the protocol's modes. */
enum vis_opaque {
	VIS_OPAQUE_ALL = 0,   /* every pixel of its shape (the default) */
	VIS_OPAQUE_NONE = 1,  /* none: the window is translucent */
	VIS_OPAQUE_RECTS = 2, /* the pixels of its shape inside opaque_rects */
};

/*
 * A window's look. The window's rectangle (x, y, w, h) is X's geometry: x, y is the border box's
 * top-left corner, w × h the inside, and the border box is the inside grown by border on every
 * side: (x, y, w + 2·border, h + 2·border). Its pixels are the union of the shape's rectangles
 * clipped to the border box (the whole border box when not shaped; none when shaped with no
 * rectangles). Shape and opaque rectangles are in window coordinates: relative to the inside's
 * top-left corner (x + border, y + border), as X's SHAPE extension has them, so a shape reaches
 * into the border with negative coordinates. Rectangles may overlap; their union counts.
 * An input-only window has no pixels, hides nothing and has no state (border 0, no shape, as X
 * requires of InputOnly windows). The zero look is a plain opaque window.
 */
struct vis_look {
	int32_t border; /* 0 ≤ border, and w + 2·border, h + 2·border ≤ INT32_MAX */
	bool input_only;
	bool shaped;
	uint8_t opaque; /* enum vis_opaque */
	uint32_t n_shape, n_opaque;
	struct vis_rect *shape;        /* n_shape rectangles, each w, h ≥ 1; its owner's */
	struct vis_rect *opaque_rects; /* n_opaque rectangles, with VIS_OPAQUE_RECTS; its owner's */
};

/* Whether a look is the zero one: a plain opaque rectangle. O(1). */
bool vis_look_plain(const struct vis_look *look);

/* Whether pieces may start inside the border box: a shape or opaque rectangles. O(1). */
bool vis_look_cuts_inside(const struct vis_look *look);

/*
 * Whether the window rect with this look can be cut into pieces: its border box's sides fit in
 * 31 bits, and, when pieces start inside it (a shape or opaque rectangles), its border box ends
 * within the 32-bit plane (x + w + 2·border ≤ 2^31, and so for y), where pieces can start.
 * Returns NULL, or the reason it cannot.
 */
const char *vis_look_check(struct vis_rect rect, const struct vis_look *look);

/*
 * The translucent flag's rule: whether a window with this look, inside width × height, has a
 * pixel that hides nothing, one of its pixels (its shape clipped to its border box) outside its
 * opaque region. Never for mode all, an input-only window or one without pixels. 1 translucent,
 * 0 not, or -1 with ENOMEM or EOVERFLOW. O(1) without a shape or opaque rectangles, else
 * O(k log k + b) for the look's k rectangles and its b pieces (a window keeps its pieces:
 * vis_wtree_translucent() costs O(1) when they are kept).
 */
int vis_look_translucent(const struct vis_look *look, int32_t width, int32_t height);

/*
 * The pieces of a stack of windows with looks: disjoint rectangles per window, bottom to top,
 * each opaque or see-through, as the engines take them (pieces.stack).
 */
struct vis_pieces {
	struct vis_stack stack; /* rects, n, see_through and the windows' screen */
	struct vis_rect *rects;
	uint8_t *see_through;
	uint32_t *window; /* by piece: the window it belongs to */
	size_t cap;
};

/*
 * Cuts the windows of a stack with looks (windows->looks, which may be NULL: every window plain)
 * into pieces, initializing pieces. Returns 0, or -1 with errno ENOMEM, EOVERFLOW (more than
 * 2^32 − 1 windows or pieces) or EINVAL (a look vis_look_check() refuses).
 * O(n + Σ k log k + b) for k rectangles of a window's shape and opaque region and b pieces out.
 */
int vis_pieces_init(struct vis_pieces *pieces, const struct vis_stack *windows);

/*
 * Appends the pieces of one window, numbered window, with the look (NULL: plain) and the absolute
 * border box abs, clipped to clip: its opaque pieces, then its see-through ones, disjoint. The
 * caller sets pieces->stack.rects and see_through to the arrays before use (they move as they
 * grow). Returns 1 when the clip cut away some of the window's pixels (it can then never be
 * unobscured), 0 when it did not, or -1 with errno ENOMEM or EOVERFLOW (a piece not inside the
 * 32-bit plane). O(k log k + b) for the look's k rectangles and the b pieces out.
 */
int vis_pieces_add(struct vis_pieces *pieces, const struct vis_look *look, struct vis_box abs,
		   struct vis_box clip, uint32_t window);

/*
 * As vis_pieces_add(), the pixels further restricted to the union of within[0 … n_within)
 * (absolute boxes; NULL: no restriction), as a shaped ancestor clips its descendants in X: the
 * window counts as cut when the restriction takes pixels away too. O(k log k + w + b) for the
 * look's k rectangles, the w boxes of within and the b pieces out.
 */
int vis_pieces_add_within(struct vis_pieces *pieces, const struct vis_look *look,
			  struct vis_box abs, struct vis_box clip, const struct vis_box *within,
			  size_t n_within, uint32_t window);

/*
 * A look's pieces cut once, for a border box of one size and relative to its corner: what a window
 * keeps across recomputes, so that placing it again costs its pieces' count, not their cutting.
 * rects[0 … n_opaque) are opaque, rects[n_opaque … n) see-through, all disjoint, their union the
 * window's pixels; each of the two runs is y-x banded as pixman's regions are (sorted by top, then
 * left; the rectangles of a band share their top and bottom, and bands do not overlap), so that
 * those meeting a box are found by a binary search. Valid for a window whose border and inside
 * are border and width × height; the zero cut (width 0) is valid for none.
 */
struct vis_look_cut {
	int32_t border, width, height;
	uint32_t n, n_opaque;
	struct vis_rect *rects;
};

/*
 * Cuts a look (not input-only) for an inside of width × height into cut, replacing what it held.
 * Returns 0, or -1 with errno ENOMEM, or EOVERFLOW when a side of the border box passes INT32_MAX
 * (cut is then left zero). O(k log k + b) for the look's k rectangles and its b pieces.
 */
int vis_look_cut_fill(struct vis_look_cut *cut, const struct vis_look *look, int32_t width,
		      int32_t height);

/* Whether a valid cut has a see-through piece: the look's translucent flag at its size. O(1). */
static inline bool vis_look_cut_translucent(const struct vis_look_cut *cut)
{
	return cut->n > cut->n_opaque;
}

/* Frees a cut's array and leaves it zero. O(1). */
void vis_look_cut_finish(struct vis_look_cut *cut);

/*
 * As vis_pieces_add(), from a valid cut instead of a look: its pieces placed with the border box
 * at abs, each clipped to clip. Returns 1 when the clip cut away some pixel, 0 when it did not, or
 * -1 with errno ENOMEM or EOVERFLOW. O(b) for the cut's b pieces.
 */
int vis_pieces_add_cut(struct vis_pieces *pieces, const struct vis_look_cut *cut,
		       struct vis_box abs, struct vis_box clip, uint32_t window);

/* Empties the pieces, keeping their arrays for reuse. O(1). */
void vis_pieces_reset(struct vis_pieces *pieces);

/* Frees the pieces. O(1). */
void vis_pieces_finish(struct vis_pieces *pieces);

/*
 * Joins the pieces' states into the windows' states: unobscured when every piece of the window
 * is, fully obscured when every piece is (a window with no pixels is), else partially obscured;
 * VIS_NO_STATE for input-only windows. O(n + pieces).
 */
void vis_pieces_join(const struct vis_pieces *pieces, const struct vis_stack *windows,
		     const uint8_t *piece_states, uint8_t *states);

#endif
