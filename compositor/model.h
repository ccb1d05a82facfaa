/*
 * The model: what can be seen, kept by libvis. Every wl_surface viscomp shows (a toplevel, its
 * subsurfaces, its popups) is one top-level window of one libvis tree whose screen is the
 * output layout; the tree answers which surfaces have a visible pixel (frame callbacks go only to
 * those, output.c) and what to draw of each for a damaged area (the repaint set).
 *
 * Invariants:
 * - A model_surface exists from wlr_surface creation to its destruction; its libvis window from
 *   the first time a view places it (model_surface_place()) until the surface is destroyed.
 * - The window is mapped exactly while the surface is placed, has a buffer and its view is mapped;
 *   its box is the surface's on the screen (layout coordinates, x, y inclusive; x + width,
 *   y + height exclusive), its opaque region wlroots' (the client's set_opaque_region, or the
 *   whole surface when its buffer format has no alpha); no opaque region: it hides nothing
 *   (Wayland's rule, where X's windows hide everything below them).
 * - Subsurfaces and popups are not clipped by their parent in Wayland, so they are top-level
 *   windows too, stacked just above (or below) their toplevel's window in the order wlroots
 *   draws them (view.c keeps it); libvis children would be clipped as X clips them.
 * - The outside window, always on top, covers what no output shows: a surface is fully obscured
 *   when no output shows a pixel of it, exactly as when other windows cover it.
 */
#ifndef VISCOMP_MODEL_H
#define VISCOMP_MODEL_H

#include <pixman.h>
#include <stdbool.h>
#include <stdint.h>
#include <wayland-server-core.h>
#include <wlr/util/addon.h>

struct mirror_win;
struct view;
struct server;
struct vis_rect32;
struct vis_tree;
struct vis_win;
struct wlr_surface;

struct model_surface {
	struct model *model;
	struct wlr_surface *surface;
	struct view *view; /* the view that placed it last, or NULL */
	struct vis_win *win; /* NULL until first placed */
	struct wlr_addon addon; /* on the wlr_surface, to find this from it */
	struct wl_list link; /* model.surfaces */
	struct wl_list view_link; /* view.surfaces, bottom to top; empty when not in one */
	struct wl_listener commit;
	struct wl_listener destroy;

	bool mapped;
	int32_t x, y, width, height; /* on the screen, as the window was last configured */
	pixman_region32_t opaque; /* the opaque region the window was last given */
	uint32_t stamp; /* the view sync that placed it last (view.c) */
	/* Where view.c last restacked the window: just above (or below) this one of its view's;
	 * unchanged, the window is still there (view.c says why). */
	struct model_surface *stack_ref;
	bool stack_above;
	struct mirror_win *mirror; /* its visd window (mirror.c), or NULL */
	/* A visibility flip a control command made, not yet timed (stats.h): when the command
	 * arrived (0: none), the output frames handled then, and whether the surface was covered
	 * (else uncovered). */
	uint64_t flip_ns;
	uint64_t flip_frames;
	bool flip_covered;
};

struct model {
	struct server *server;
	struct vis_tree *tree;
	struct vis_win *outside;
	struct vis_rect32 *outside_rects; /* the outside's shape, as last set */
	size_t n_outside;
	struct wl_list surfaces; /* model_surface.link */
	uint64_t update_ns; /* how long the last vis_tree_update() took */
};

/* The tree's screen: large enough for any layout of outputs; what lies outside them is covered. */
#define MODEL_SCREEN_SIZE 16384

/* Creates the tree and the outside window (covering the whole screen until outputs come).
 * 0, or -1 with errno. */
int model_init(struct model *model, struct server *server);
void model_finish(struct model *model);

/* Tracks a new wlr_surface: its commits and its destruction. NULL on failure (logged). */
struct model_surface *model_surface_create(struct model *model, struct wlr_surface *surface);

/* The model_surface of a wlr_surface, or NULL. */
struct model_surface *model_surface_from_wlr(struct wlr_surface *surface);

/*
 * Places a surface on the screen with its origin at x, y, mapped or not (a surface without a
 * buffer is never mapped), taking its size and opaque region from its current state; damages
 * what it covered and covers when anything changed. Creates its window (just below the outside,
 * on top of every view) on first use. 0, or -1 (logged).
 */
int model_surface_place(struct model_surface *ms, int32_t x, int32_t y, bool mapped);

/* The window's state at the last update (enum vis_visibility). */
int model_surface_state(const struct model_surface *ms);

/* Whether the surface had a visible pixel at the last update. */
bool model_surface_visible(const struct model_surface *ms);

/* Sets which screen rectangles outputs show: the outside window becomes the rest. */
int model_set_shown(struct model *model, const pixman_region32_t *shown);

/*
 * Recomputes the states after the changes made since the last update (vis_tree_update()); asks
 * a frame of the outputs showing a surface that has just become visible, so that its pending
 * frame callbacks are answered within that frame; marks the surfaces whose visibility the last
 * move, raise or lower flipped, for stats.h. 0, or -1 (logged; tried again next time).
 */
int model_update(struct model *model);

#endif
