/* The window tree the daemon keeps: X11-style windows, stacked among siblings, clipped by parents. */
#ifndef VIS_WTREE_H
#define VIS_WTREE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "idmap.h"
#include "look.h"
#include "rect.h"

/*
 * A window, in X's geometry: x, y place its border box's corner relative to its parent's origin
 * (the parent's inside's corner; the screen's for top-level windows); width × height is its inside,
 * 1 ≤ width, height; the border box is the inside grown by look.border on every side, its sides
 * at most INT32_MAX. Its pixels are its look's (look.h: border box, shape, opaque region,
 * input-only); its children are positioned relative to its inside and clipped to it (and to its
 * ancestors'). Siblings form a list from bottom to top. Invariants: a window is in its parent's
 * child list and in the ID map exactly while it exists; depth = its parent's depth + 1
 * (top-level windows: 1); look's arrays are the window's own.
 */
struct vis_window {
	/* The live recompute's walks (wtree-live-walk.c) read these of window after window, most of
	 * them once: they come first, to share a cache line. */
	struct vis_window *parent; /* the root for top-level windows */
	/* Grows with pre-order among the viewable windows after any recompute (0 for the others),
	 * so that "is a below b" is a comparison: positions are not kept by vis_wtree_update(). */
	uint64_t key;
	/* vis_wtree_update()'s (wtree-live.c): slots in its lists (1-based, 0: in none), a mark for
	 * the windows it has taken, its slot among the indexed windows (while live_indexed), whether
	 * it indexed the clip and counted the window as having a look, whether it has a look as
	 * indexed (live_look: its pixels hide what lies below only where opaque) and had one when
	 * taken out of the grid last (live_looked), whether the window is
	 * viewable (while it works), and whether it had no viewable descendants at the last
	 * recompute (or may have had: false); the parent it had when first noted since the last
	 * recompute (a reparented window's subtree saw pixels elsewhere). */
	uint32_t live_seen, live_mark, live_cand, live_slot;
	bool live_indexed, live_viewable, live_leaf, live_look, live_looked;
	/* Set by vis_wtree_compute(): enum vis_visibility numbering, 3 (none) when not viewable. */
	uint8_t state, old_state;
	bool mapped, retained;
	uint32_t id;
	uint32_t owner; /* the creating connection's ID; 0 once a retained window's owner is gone */
	uint32_t live_dirty, live_changed;
	struct vis_window *live_parent;
	struct vis_window *below, *above;   /* siblings; NULL at the ends */
	struct vis_window *bottom, *top;    /* children */
	int32_t x, y;
	int32_t width, height;
	struct vis_look look; /* border, shape, opaque region, input-only: see the setters below */
	/* The look's pieces for the window's size (vis_wtree_cut()): there exactly while the look
	 * has a shape or opaque rectangles; its contents kept from one recompute to the next. */
	struct vis_look_cut *cut;
	/* What the window mirrors (an X window of a bridge, …): an opaque tag in a namespace (enum
	 * vis_external_namespace), 0 and 0 for none; set once, by vis_wtree_set_external(). */
	uint32_t ext_namespace;
	uint64_t external;
	struct vis_window *ext_next; /* the next window of its chain in the tree's externals */
	uint32_t depth;
	/* Set by vis_wtree_compute() for viewable windows: the absolute border box; clipped to the
	 * parent's inner box (the screen for top-level windows), the box its pixels can be seen in
	 * (possibly empty); and the box its children are clipped to: its inside, clipped so (its
	 * box, clipped so, for an input-only window, which has no border). As in X, a shaped
	 * window's descendants are also clipped to its bounding shape: the boxes bound that, and the
	 * recomputes cut such windows by the shapes above them (UNDER, wtree-work.h). */
	struct vis_box box, clip, inner;
	size_t pos; /* index in the tree's order, for viewable windows */
	void *data; /* the daemon's */
};

#define VIS_WTREE_STATE_NONE 3

struct vis_wtree_work;
struct vis_wtree_live;

/*
 * The external IDs of a tree's windows are indexed by a hash of (namespace, tag), never 0, in an
 * ID map whose value is the first window of a chain (ext_next) of the windows with that hash. The
 * pairs are unique among the windows that exist (vis_wtree_set_external() refuses a taken one),
 * and a window is in its chain exactly while it exists with a namespace other than 0. Chains stay
 * short for any tags but ones chosen to collide, which only the one who sets them (the daemon's
 * manager) could choose, at the cost of its own requests.
 */
struct vis_wtree {
	struct vis_window root; /* the screen; id 0 */
	struct vis_idmap ids;
	struct vis_idmap externals; /* hash of (namespace, tag) → chain, see above */
	/* IDs handed out so far + 1, the counter IDs are made from (0 once 2^32 − 1 were): a window's
	 * ID is vis_wtree_id_permute(id_key, its number), unique and never reused. */
	uint32_t next_id;
	uint64_t id_key; /* vis_wtree_set_id_key(); 0: IDs are the counter itself */
	size_t count;
	/* Viewable windows in pre-order (bottom to top) after vis_wtree_compute(); windows destroyed
	 * since leave NULL behind. */
	struct vis_window **order;
	size_t n_order, cap_order;
	/* A recompute failed after it had rewritten the boxes: the states no longer go with them,
	 * so the next recompute must be a full one. */
	bool stale;
	struct vis_wtree_work *work; /* the recomputes' scratch (wtree-work.h), or NULL */
	struct vis_wtree_live *live; /* vis_wtree_update()'s structures (wtree-live.c), or NULL */
};

/* Sets up an empty tree over a screen of width × height (≥ 1). O(1). */
void vis_wtree_init(struct vis_wtree *tree, int32_t width, int32_t height);

/* Frees every window (not their data). O(n). */
void vis_wtree_finish(struct vis_wtree *tree);

/* Frees the recomputes' scratch, for vis_wtree_finish(); NULL is a no-op. */
void vis_wtree_work_destroy(struct vis_wtree_work *work);

/*
 * Makes the IDs of the windows created from now on say nothing about the windows others created:
 * the n-th window gets vis_wtree_id_permute(key, n) instead of n. The daemon gives a random key at
 * start-up; key 0 (the default) keeps IDs sequential, for tests. Set it before the first window.
 */
void vis_wtree_set_id_key(struct vis_wtree *tree, uint64_t key);

/*
 * A keyed bijection of 1 … 2^32 − 1 onto itself, n itself for key 0: a 6-round Feistel network
 * over 32 bits, walking its cycle past 0 (the screen's ID, never a window's). So IDs made from a
 * counter stay unique, and none is reused, while consecutive ones are unrelated numbers: a client
 * cannot count the windows created between two of its own. O(1) expected (a walk past 0 takes
 * one more round trip, for one n of 2^32).
 */
uint32_t vis_wtree_id_permute(uint64_t key, uint32_t n);

/* The window with this ID, or NULL (the root is not found: its ID 0 means "the screen"). */
struct vis_window *vis_wtree_find(const struct vis_wtree *tree, uint32_t id);

/*
 * Creates an unmapped window on top of parent's children. Returns it, or NULL with errno ENOMEM,
 * or EOVERFLOW once 2^32 − 1 IDs were handed out (IDs are never reused). O(1).
 */
struct vis_window *vis_wtree_create(struct vis_wtree *tree, struct vis_window *parent,
				    int32_t x, int32_t y, int32_t width, int32_t height,
				    uint32_t owner);

/*
 * Destroys a window and its descendants, calling gone(data, w) for each, children before their
 * parent, while the window is still linked. O(size of the subtree).
 */
void vis_wtree_destroy(struct vis_wtree *tree, struct vis_window *window,
		       void (*gone)(void *data, struct vis_window *w), void *data);

/*
 * Sets a window's inside, width × height (≥ 1), and its border width (≥ 0). Returns 0, or -1
 * with EINVAL when the border box's sides would pass INT32_MAX or an input-only window would
 * get a border (nothing changes then). O(1): a look with a shape or opaque rectangles is cut again
 * for the new size when next asked (vis_wtree_cut()).
 */
int vis_wtree_set_size(struct vis_window *window, int32_t width, int32_t height, int32_t border);

/* vis_wtree_set_size() with the window's inside as it is. */
int vis_wtree_set_border(struct vis_window *window, int32_t border);

/*
 * Sets a window's bounding shape to a copy of rects[0 … n) (window coordinates, each w, h ≥ 1,
 * overlaps allowed; n = 0: no pixels), or with shaped false back to its border box. Returns 0, or
 * -1 with ENOMEM, or EINVAL for an input-only window (nothing changes then). O(n); the look is
 * cut when next asked (vis_wtree_cut()).
 */
int vis_wtree_set_shape(struct vis_window *window, bool shaped, const struct vis_rect *rects,
			uint32_t n);

/*
 * Sets which of a window's pixels hide what lies below: mode VIS_OPAQUE_ALL or _NONE (rects
 * ignored), or VIS_OPAQUE_RECTS with a copy of rects[0 … n). Returns 0, or -1 with ENOMEM, or
 * EINVAL for an input-only window or an unknown mode (nothing changes then). O(n), as
 * vis_wtree_set_shape().
 */
int vis_wtree_set_opaque(struct vis_window *window, enum vis_opaque mode,
			 const struct vis_rect *rects, uint32_t n);

/*
 * Gives a window the external ID (ext_namespace ≠ 0, external), which it keeps for its life; the
 * pair leaves the index when the window is destroyed. Returns 0, or -1 with EEXIST when another
 * window carries the pair, EINVAL when ext_namespace is 0 or the window has an external ID
 * already, ENOMEM (nothing changes then). Expected O(1).
 */
int vis_wtree_set_external(struct vis_wtree *tree, struct vis_window *window,
			   uint32_t ext_namespace, uint64_t external);

/* The window carrying the external ID, or NULL (always for namespace 0). Expected O(1). */
struct vis_window *vis_wtree_find_external(const struct vis_wtree *tree, uint32_t ext_namespace,
					   uint64_t external);

/*
 * The window's look cut into its pieces for its size now (look.h), kept until the look or the size
 * changes, so that recomputes place the pieces instead of cutting the look again; only for a
 * window whose look has a shape or opaque rectangles (window->cut is not NULL). NULL with errno
 * EINVAL for another window, or ENOMEM. O(1) when kept, else O(k log k + b) for the look's k
 * rectangles and its b pieces.
 */
const struct vis_look_cut *vis_wtree_cut(const struct vis_window *window);

/*
 * Gives a window with a cut the one made for its look and size now (vis_look_cut_fill()), which
 * saves cutting it again; cut's array is the window's then (a window without a cut frees it), and
 * cut is left zero. O(1).
 */
void vis_wtree_keep_cut(struct vis_window *window, struct vis_look_cut *cut);

/*
 * The protocol's translucent flag: whether some pixel of the window hides nothing
 * (vis_look_translucent()), from the pieces it keeps. O(1) when they are kept for its size, else
 * as vis_wtree_cut().
 */
bool vis_wtree_translucent(const struct vis_window *window);

/* Makes a window input-only: no pixels, no state; only right after creating it. O(1). */
void vis_wtree_set_input_only(struct vis_window *window);

/* Puts window just above sibling (above = true) or just below it. O(1). */
void vis_wtree_restack(struct vis_window *window, struct vis_window *sibling, bool above);

/* Puts window on top of (or below) all its siblings. O(1). */
void vis_wtree_raise(struct vis_window *window);
void vis_wtree_lower(struct vis_window *window);

/* Whether a is b or one of b's ancestors. O(depth). */
bool vis_wtree_is_ancestor(const struct vis_window *a, const struct vis_window *b);

/*
 * Moves window under parent (not the window itself or a descendant) at x, y, on top of its new
 * siblings, and updates the subtree's depths. O(size of the subtree).
 */
void vis_wtree_reparent(struct vis_window *window, struct vis_window *parent, int32_t x, int32_t y);

/*
 * The window after w in pre-order (stacking order, parents before children) over every window,
 * mapped or not; NULL after the last. Start from tree->root.bottom. O(depth) at worst.
 */
struct vis_window *vis_wtree_next(const struct vis_window *w);

/* As vis_wtree_next(), staying inside top's subtree (top: its first window; NULL: the whole
 * tree): NULL past its last window. O(depth) at worst. */
struct vis_window *vis_wtree_next_within(const struct vis_window *w, const struct vis_window *top);

/*
 * The viewable window after w in pre-order (w viewable; NULL: the first), or NULL after the last:
 * stacking order, unmapped subtrees skipped. O(depth + unmapped siblings) at worst.
 */
struct vis_window *vis_wtree_next_viewable(const struct vis_wtree *tree,
					   const struct vis_window *w);

/*
 * The window's border box in screen coordinates from its own and its ancestors' positions (and
 * their borders), viewable or not: its subtree's pixels lie inside it, as children are clipped to
 * their parent's inside. O(depth).
 */
struct vis_box vis_wtree_box(const struct vis_window *window);

/*
 * Sets a viewable window's boxes (box, clip, inner) from its own geometry and its parent's boxes,
 * which must be set: as a recompute places it. O(1).
 */
void vis_wtree_place(struct vis_window *window);

/* Whether the window and all its ancestors are mapped. O(depth). */
bool vis_wtree_viewable(const struct vis_window *window);

/*
 * Recomputes every window's state with X.Org's VisibilityNotify semantics over the window's own
 * pixels (its look's: its shape in its border box, look.h): a pixel is hidden by an opaque pixel
 * of a later sibling of the window or of its ancestors (or of their descendants), never by its own
 * descendants, and clipped by its ancestors' inner boxes and the screen. Unobscured when every
 * pixel is seen (so none clipped), fully obscured when none is (a window without pixels is),
 * else partially obscured; input-only windows keep VIS_WTREE_STATE_NONE, and hide nothing.
 * Moves each state to old_state first, so that callers can see what changed.
 * Returns 0, or -1 with errno ENOMEM (states are then unchanged).
 * O((1 + D) · n log n) with the sweep, where D is the number of depths holding a viewable window
 * with viewable children: the sweep over the flattened tree (pre-order, each window clipped to
 * its ancestors) is exact for windows without children; one over the windows at depth ≤ d, each
 * one at depth d above its descendants, is exact for those at depth d (a descendant is left out
 * when its parent's pixels, all opaque, hold it: always, without looks). The sweeps start at the
 * highest top-level window, opaque and unshaped, that covers the screen, if any: the windows below
 * it are fully obscured, so a desktop with a maximized window near the top costs O(n) and the
 * sweep over the windows above. While no viewable window is shaped, translucent in part or
 * input-only, each window is one rectangle for the engine (a border only makes it larger); else
 * such windows are cut into pieces (look.h), and n counts the pieces.
 */
int vis_wtree_compute(struct vis_wtree *tree);

/*
 * As vis_wtree_compute(), with the same result, knowing where the tree changed since the last
 * recompute: damage[0 … n_damage − 1] holds, for every change (creating, mapping, unmapping,
 * moving, resizing, restacking, reparenting or destroying a window, or changing its border,
 * shape or opaque region), the changed window's box as vis_wtree_box() gives it just before and
 * just after the change (once when the two are equal).
 *
 * The rule: only the viewable windows new to the order (created, mapped, or under an ancestor
 * newly mapped), or whose box or clip moved, or whose clip meets a damage box have their states
 * recomputed; every other window keeps its state. It is exact: a change of window c changes
 * clips, viewability, stacking order, ancestry and pixels only inside c's subtree and between it
 * and other windows, and c's subtree lies in c's box before and after the change. So on every
 * pixel outside the damage, the windows that cover it, their looks, their order and their ancestry
 * are those of the last recompute, and a window whose clip stayed and misses the damage has the
 * same pixels covered. Of those that meet it, the ones last fully obscured below a top-level
 * window, opaque and unshaped, whose clip holds all the damage stay fully obscured (most windows
 * of a desktop) and are left out too.
 *
 * How: the windows recomputed are classified inside one box, within, by the sweeps of
 * vis_wtree_compute() over the windows that meet it, each clipped to it (and over the depths of
 * those of them with children only). within is the hull of the damage on the screen and of the
 * clips of the new and moved windows, and of the shaped ones (whose pixels might all lie on one
 * side of within's edge). Outside within, a window's pixels are covered as at the last
 * recompute: one last unobscured or fully obscured was so there too; for one last partially
 * obscured, the windows above it are looked up (a box test each for those opaque and unshaped,
 * the engine when none settles it, with the others' pieces) within a budget of 4 visits per
 * viewable window in all, highest windows first, past which their clips join within instead; and
 * so do the clips of those whose lookups might hand the engine windows with a look once such
 * lookups would take more than n / 4 windows in all (cutting and sweeping them costs as much as
 * the full recompute's sweep does for as many windows).
 * A window's state is its state inside within if it is the same outside, else partially obscured.
 *
 * Returns 0, or -1 with errno ENOMEM (states are then unchanged, and the next recompute is full).
 * O(n · d) for flattening and the damage tests (n viewable windows, d damage boxes; past 4 boxes
 * their hull is tested first), O(n) for the lookups with the engine over at most 4n boxes (n / 4
 * windows when some have a look, cut into their pieces), and the sweeps over the m windows that
 * meet within: O(n · d + (1 + D) · m log m + n log n) at worst.
 * As within grows towards the screen, this becomes vis_wtree_compute(): no separate fall-back to
 * it is needed, and the worst case stays within a constant of it, but for the damage tests.
 */
int vis_wtree_compute_damaged(struct vis_wtree *tree, const struct vis_box *damage,
			      size_t n_damage);

/*
 * Notes that window is about to change or has changed, for vis_wtree_update(): call it for every
 * change the damage of vis_wtree_compute_damaged() is recorded for, at the same times (before and
 * after a move, a resize or a reparent, before a destruction, after the others). O(1) amortized;
 * without memory the next update recomputes everything.
 */
void vis_wtree_note(struct vis_wtree *tree, struct vis_window *window);

/*
 * Recomputes the states after the changes noted since the last recompute, with the result of
 * vis_wtree_compute(), at a cost that follows the windows the changes can affect, not the tree.
 *
 * It keeps, from one recompute to the next, every viewable window's key (growing in pre-order,
 * keys spaced so that a change renumbers only its own subtree), a grid of the windows' clips in
 * key order (zgrid.h; its entries index a dense array of the clips), and the viewable windows
 * that are not fully obscured with what they saw: their seen region (the clip less the clips of
 * the windows after their subtree), as up to eight boxes or a box holding it (with the edges of
 * that box known to hold pixels of it, when it is the region's extents), and a grid of those
 * boxes without order (sgrid.h: which windows saw pixels of a region, from its cells alone). A
 * window's state follows from its seen region: none, fully obscured; its whole box, unobscured;
 * else partially obscured.
 *
 * The rule: let the changed subtrees be those of the noted windows (a change of a window moves
 * or re-stacks its subtree with it). Recomputed are (1) the windows of the changed subtrees;
 * (2) for each of those that sees pixels now, walking the grid down from its key, the unchanged
 * windows whose clip meets what is left of those pixels and whose last seen region meets it,
 * with their ancestors whose last seen region does, each unchanged window's clip taken off what
 * is left; (3) for each window of the changed subtrees (and each one destroyed) that saw pixels,
 * walking the grid down from its old key, the windows whose clip meets what is left of those
 * pixels, and their ancestors, each one's clip taken off what is left. Every other window keeps
 * its state and seen region. Where a walk of (2) would pass over more clips than 512 and a
 * sixteenth of the boxes the seen grid holds in the cells of its pixels, it stops, and the
 * unchanged windows below its key whose last seen region (as kept) meets those pixels are taken
 * instead.
 * It is exact: a window w outside the changed subtrees keeps its clip and its place among the
 * others. If it sees fewer pixels, the pixel p it lost is now hidden by windows after w's
 * subtree; the highest of them, h, is in a changed subtree, or it would have hidden p before.
 * Nothing after h covers p, so h sees p, and w's subtree lies below h's key. Walking down from
 * it, the windows whose clips hold p before w or its descendants are reached hide w at p now
 * (unless they are w's descendants): were one unchanged, it would have hidden p before. So only
 * changed windows are passed over at p, p is still left when w or a descendant is reached, and
 * as w saw p, w is taken, (2); or, w's last seen region holding p, one of h's pixels, and w
 * lying below h's key, the seen grid takes it (those the walk took before it stopped stay
 * taken: taking a window more only recomputes it). If w sees more, the pixel p it gained was
 * hidden by windows after its subtree; the highest of them, h, is in a changed subtree or
 * destroyed, or it would still hide p. Nothing after h covered p, so h saw p, and w's subtree
 * lies below h's old key. Walking down from that key, the windows whose clips hold p before w
 * or its descendants are reached hide w at p now, unless they are w's descendants: so p is
 * still left when w or a descendant is reached, and w is taken, (3). In both walks a window reached at p takes off p for the windows
 * below it, but for its ancestors, which its pixels never hide and which are taken with it.
 * The argument is pixel by pixel, so a walk may go over its pixels in pieces, each from where
 * the whole stood: a box at a time, or, once they fragment, a grid cell at a time.
 * Pixels a changed window h saw before and sees now need no walk, unless its changed subtree
 * has a new parent: if w lost such a pixel p to h, h was not above w's subtree before (or w
 * would not have seen p) nor below it (w would have hidden p from h), so h was w's descendant
 * and is not now; if w gained p, h hid it before and, seeing p now above w, would hide it still
 * unless it has just become w's descendant. So rule 2 walks over what h sees less what it saw,
 * rule 3 over what h saw less what it sees, where those are exact (kept as boxes, not a box
 * holding them); a destroyed window's walk is over all it saw. The pixels walked in rule 3,
 * exposed, hold every pixel any window gains.
 * The changed windows get their seen regions exactly, by walking the grid over the windows
 * after their subtree from both ends of that range, until their pixels are all hidden or the
 * walks meet; so do the others whose last seen region is not exact. A lone changed window
 * without descendants (none destroyed) whose old key lies between the keys of the windows now
 * before and after it has the same windows above it: it sees what it saw inside its new clip,
 * and the walks go over the rest of its clip alone; one lowered, its clip as it was, has above
 * it the windows that were and those between its keys: it sees what it saw less their clips,
 * found by one walk over what it saw, down from its old key to its new one, which also takes the
 * windows rule 3 would and stands for that walk: the pixels it no longer sees are each hidden by
 * a window between its keys, so rule 3's walk over them ends above its new key, and the windows
 * between never meet the pixels it still sees, so walking those too takes none more and lists
 * no other gains. Another window w, whose
 * last seen region s is exact, sees s less the clips of the changed windows now after its
 * subtree (no unchanged window there hid s before, and none hides it now), plus, if rule 3 took
 * it, what it sees of exposed (it gains no pixel elsewhere): without viewable descendants, the
 * pixels its clip holds of what was left of exact walks over it, less those changed clips (the
 * windows above the walk's start did not hide those pixels, and those between are cut off what
 * is left), else what a grid walk over exposed alone finds. One whose last seen region is a box
 * with edges known to hold pixels it saw, taken by rule 2 alone, is partially obscured still
 * while one such edge meets no changed clip now after its subtree: the pixel it saw there is
 * hidden by no window that did not hide it before, and a box kept so was never its whole box;
 * the box still holds what it sees. Seen regions start exact when the structures are built, by
 * the region method from the top of the order down, a grid cell at a time (a cell once covered
 * is passed over below), within a bound.
 * A window with a look has for pixels its look's pieces in its clip, and only its opaque pieces
 * hide: the argument holds with "hides p" meaning an opaque piece holds p, the walks testing
 * clips (which hold the pieces) and cutting by opaque pieces. The rest takes a window's pixels
 * to be its clip, all opaque, and is kept from windows with looks: the pixels seen before and
 * now are walked too while any window with a look is indexed (h moved above or below a
 * see-through pixel of another window hides it, or stops hiding it, where both are seen) or when
 * h had or has a look, and a lowered lone window exposes all it saw (one it went below may see
 * through to it); a lone window with a look, then or now, gets its query; an unchanged one's
 * gains are found by a walk over its pieces in exposed, not listed, and it is unobscured when it
 * sees all its pieces; and loose boxes are not
 * narrowed while looks are indexed (a changed window not yet out of the grid would cut by
 * pieces for its new size at its old place). The unit test holds the result to vis_wtree_compute()'s
 * after every batch of edits on random trees, and the structures to their invariants.
 *
 * Where the live structures do not apply, it recomputes through the tree instead, with the same
 * result: below vis_wtree_live_from()'s windows, the first time, after a failed recompute, keys
 * used up where a subtree goes, or a viewable window under a shaped ancestor (whose shape also
 * clips it); vis_wtree_compute_damaged() with the notes' boxes when it can (up to 64),
 * else vis_wtree_compute(). The structures are then built again once 64 updates have gone
 * through the tree in a row. Positions (order, pos) are kept only by the recomputes through the
 * tree: n_order is 0 after a live one.
 *
 * Returns 0, or -1 with errno ENOMEM (states are then unchanged, and the next recompute is full).
 * Cost, live: O(r · log n) per window recomputed and per walk, r the clips the walk passes over
 * (those in the grid cells its pixels meet, between its key and the first that hide them; for
 * rule 2, at most 512 and a sixteenth of the seen boxes in those cells, then read once), plus
 * the subtrees changed. Past a budget of n + 256 steps in all (a walk step costs about what the
 * recompute through the tree spends on 0.3 to 2.5 windows), or more changed windows than 4 + n / 32
 * (4 + n / 512 below 2,048 windows), the states come from vis_wtree_compute_damaged() instead,
 * the structures kept up to date.
 */
int vis_wtree_update(struct vis_wtree *tree);

/*
 * For a caller that keeps the states itself for a while, changing the tree without notes
 * (libvis's tallies): drops the live structures and the notes taken, so that the next
 * vis_wtree_update() recomputes everything. O(notes).
 */
void vis_wtree_drop_live(struct vis_wtree *tree);

/*
 * Sets the windows from which vis_wtree_update() goes live (default 64: below, the damaged
 * recompute costs less; 0: always). 0, or -1 with ENOMEM.
 */
int vis_wtree_live_from(struct vis_wtree *tree, size_t windows);

/*
 * After a recompute, the windows whose state or visible region it may have changed (every one
 * whose state differs from old_state among them): true with them in *windows[0 … *n), or false
 * when that may be any window (the recompute went through the tree).
 */
bool vis_wtree_changes(const struct vis_wtree *tree, struct vis_window *const **windows,
		       size_t *n);

/*
 * The window's own visible pixels (its shape inside its clip, not covered by an opaque pixel of
 * any later window in pre-order, descendants included, as X's clip list) as rectangles in window
 * coordinates, relative to its inside's top-left corner as shapes are (its border lies at
 * −border … 0 and width … width + border), y-x banded, into a pixman region
 * (pixman_region32_t *, initialized by the caller); empty for input-only windows. Needs a
 * computed tree. 0 or -1 (ENOMEM).
 * O(n + r log r) for r pieces of the window and of the later windows that overlap it; while the
 * live structures are built, a walk over the later windows there.
 */
int vis_wtree_visible_region(const struct vis_wtree *tree, const struct vis_window *window,
			     void *region);

/*
 * Appends a viewable window's pixels inside the screen box c to pieces, numbered num, as the
 * recomputes cut them (look.h): its look's pieces, opaque then see-through (none for an
 * input-only window), within its shaped ancestors' shapes, each clipped to c; a plain window's
 * is c itself, opaque. For queries over a computed tree (libvis's repaint). 0, or -1 with ENOMEM
 * or EOVERFLOW. O(k log k + b) for the look's k rectangles and its b pieces out, O(b) when kept.
 */
int vis_wtree_add_pieces(struct vis_pieces *pieces, const struct vis_window *window,
			 struct vis_box c, uint32_t num);

/*
 * The windows that show pixels of their own inside the screen box damage, bottom to top: the
 * sweep over the flattened tree, every window clipped to damage; a window shows where no opaque
 * pixel of a later window covers it, so translucent ones and those seen through them are listed,
 * input-only ones never. Writes at most count windows to out and returns how many, or -1 with
 * ENOMEM. Needs a computed tree. O(n log n), n counting pieces as vis_wtree_compute() does.
 */
long vis_wtree_repaint(const struct vis_wtree *tree, struct vis_box damage,
		       struct vis_window **out);

#endif
