#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include <vis/vis.h>
#include <wlr/types/wlr_surface.h>
#include <wlr/util/log.h>

#include "mirror.h"
#include "model.h"
#include "server.h"
#include "view.h"

/* The most opaque rectangles a surface's region is given in; past it the surface counts as hiding
 * nothing, which can only cost frames, never show a stale pixel. */
#define MAX_OPAQUE_RECTS 256

int model_init(struct model *model, struct server *server)
{
	model->server = server;
	wl_list_init(&model->surfaces);
	model->tree = vis_tree_create(MODEL_SCREEN_SIZE, MODEL_SCREEN_SIZE);
	if (model->tree == NULL)
		return -1;
	/* Until an output comes, nothing is shown: the outside is the whole screen. */
	model->outside = vis_win_create(model->tree, NULL, 0, 0, MODEL_SCREEN_SIZE,
					MODEL_SCREEN_SIZE, 0, 0);
	if (model->outside == NULL || vis_win_map(model->outside) < 0) {
		vis_tree_destroy(model->tree);
		return -1;
	}
	return 0;
}

void model_finish(struct model *model)
{
	/* The surfaces are gone with the display (their destroy handlers ran). */
	vis_tree_destroy(model->tree);
	model->tree = NULL;
	free(model->outside_rects);
	model->outside_rects = NULL;
}

static void surface_addon_destroy(struct wlr_addon *addon)
{
	(void)addon; /* the surface's destroy signal does the work, before its addons go */
}

static const struct wlr_addon_interface surface_addon = {
	.name = "viscomp-model-surface",
	.destroy = surface_addon_destroy,
};

struct model_surface *model_surface_from_wlr(struct wlr_surface *surface)
{
	struct wlr_addon *addon = wlr_addon_find(&surface->addons, &surface_addon, &surface_addon);
	if (addon == NULL)
		return NULL;
	struct model_surface *ms = wl_container_of(addon, ms, addon);
	return ms;
}

/* A surface committed: its view places its surfaces again (view.c). */
static void handle_commit(struct wl_listener *listener, void *data)
{
	(void)data;
	struct model_surface *ms = wl_container_of(listener, ms, commit);
	view_surface_committed(ms->model->server, ms);
}

/* A surface is destroyed: its window, its damage and its record go. */
static void handle_destroy(struct wl_listener *listener, void *data)
{
	(void)data;
	struct model_surface *ms = wl_container_of(listener, ms, destroy);
	if (ms->mapped)
		server_damage_box(ms->model->server, ms->x, ms->y, ms->width, ms->height);
	view_surface_destroyed(ms->model->server, ms);
	mirror_surface_gone(ms->model->server->mirror, ms);
	wl_list_remove(&ms->view_link);
	wl_list_remove(&ms->link);
	wl_list_remove(&ms->commit.link);
	wl_list_remove(&ms->destroy.link);
	wlr_addon_finish(&ms->addon);
	vis_win_destroy(ms->win);
	pixman_region32_fini(&ms->opaque);
	free(ms);
}

struct model_surface *model_surface_create(struct model *model, struct wlr_surface *surface)
{
	struct model_surface *ms = calloc(1, sizeof(*ms));
	if (ms == NULL) {
		wlr_log(WLR_ERROR, "out of memory for a surface");
		return NULL;
	}
	ms->model = model;
	ms->surface = surface;
	pixman_region32_init(&ms->opaque);
	wl_list_insert(&model->surfaces, &ms->link);
	wl_list_init(&ms->view_link);
	/* One model a process: the interface itself is the owner. */
	wlr_addon_init(&ms->addon, &surface->addons, &surface_addon, &surface_addon);
	ms->commit.notify = handle_commit;
	wl_signal_add(&surface->events.commit, &ms->commit);
	ms->destroy.notify = handle_destroy;
	wl_signal_add(&surface->events.destroy, &ms->destroy);
	return ms;
}

/* A pixman box as libvis's rectangle (the boxes here lie well inside 32 bits). */
static struct vis_rect32 rect_of(const pixman_box32_t *b)
{
	return (struct vis_rect32){ b->x1, b->y1, (uint32_t)(b->x2 - b->x1), (uint32_t)(b->y2 - b->y1) };
}

/* Gives the window the surface's opaque region, when it changed. */
static int set_opaque(struct model_surface *ms)
{
	pixman_region32_t *opaque = &ms->surface->opaque_region;
	if (pixman_region32_equal(opaque, &ms->opaque))
		return 0;
	int n = 0;
	const pixman_box32_t *boxes = pixman_region32_rectangles(opaque, &n);
	pixman_box32_t *extents = pixman_region32_extents(opaque);
	int rc;
	if (n == 0 || n > MAX_OPAQUE_RECTS) {
		rc = vis_win_set_opaque(ms->win, VIS_OPAQUE_MODE_NONE, NULL, 0);
	} else if (n == 1 && extents->x1 <= 0 && extents->y1 <= 0 &&
		   extents->x2 >= ms->width && extents->y2 >= ms->height) {
		rc = vis_win_set_opaque(ms->win, VIS_OPAQUE_MODE_ALL, NULL, 0);
	} else {
		struct vis_rect32 rects[MAX_OPAQUE_RECTS];
		for (int i = 0; i < n; i++)
			rects[i] = rect_of(&boxes[i]);
		rc = vis_win_set_opaque(ms->win, VIS_OPAQUE_MODE_RECTS, rects, (uint32_t)n);
	}
	if (rc < 0) {
		wlr_log_errno(WLR_ERROR, "vis_win_set_opaque");
		return -1;
	}
	pixman_region32_copy(&ms->opaque, opaque);
	return 1;
}

int model_surface_place(struct model_surface *ms, int32_t x, int32_t y, bool mapped)
{
	struct model *model = ms->model;
	struct wlr_surface *surface = ms->surface;
	int32_t width = surface->current.width, height = surface->current.height;
	if (!wlr_surface_has_buffer(surface) || width <= 0 || height <= 0)
		mapped = false;
	if (width <= 0 || height <= 0)
		width = height = 1; /* a window has at least a pixel; unmapped, it shows none */

	if (ms->win == NULL) {
		ms->win = vis_win_create(model->tree, NULL, x, y, width, height, 0, 0);
		if (ms->win == NULL || vis_win_restack(ms->win, model->outside, 0) < 0) {
			wlr_log_errno(WLR_ERROR, "vis_win_create");
			vis_win_destroy(ms->win);
			ms->win = NULL;
			return -1;
		}
		vis_win_set_data(ms->win, ms);
		ms->x = x, ms->y = y, ms->width = width, ms->height = height;
		/* A new window hides everything (libvis' default); set_opaque() corrects it. */
		pixman_region32_fini(&ms->opaque);
		pixman_region32_init_rect(&ms->opaque, 0, 0, (unsigned)width, (unsigned)height);
	}

	bool moved = x != ms->x || y != ms->y || width != ms->width || height != ms->height;
	if (moved && ms->mapped)
		server_damage_box(model->server, ms->x, ms->y, ms->width, ms->height);
	if (moved && vis_win_configure(ms->win, x, y, width, height, 0) < 0) {
		wlr_log_errno(WLR_ERROR, "vis_win_configure");
		return -1;
	}
	ms->x = x, ms->y = y, ms->width = width, ms->height = height;
	int opaque = set_opaque(ms);
	if (opaque < 0)
		return -1;
	/* Less opaque, it shows what is below; more, it hides it: the screen changes either way
	 * (view.c adds no damage for a covered surface's commits, which this may uncover). */
	if (opaque > 0 && ms->mapped)
		server_damage_box(model->server, x, y, width, height);
	if (mapped != ms->mapped) {
		if ((mapped ? vis_win_map(ms->win) : vis_win_unmap(ms->win)) < 0) {
			wlr_log_errno(WLR_ERROR, "vis_win_map");
			return -1;
		}
		if (!mapped)
			server_damage_box(model->server, x, y, width, height);
		ms->mapped = mapped;
	}
	if (moved && mapped)
		server_damage_box(model->server, x, y, width, height);
	return 0;
}

int model_surface_state(const struct model_surface *ms)
{
	if (ms->win == NULL)
		return VIS_VISIBILITY_NONE;
	int state = vis_win_state(ms->win);
	return state < 0 ? VIS_VISIBILITY_NONE : state;
}

bool model_surface_visible(const struct model_surface *ms)
{
	int state = model_surface_state(ms);
	return state == VIS_VISIBILITY_UNOBSCURED || state == VIS_VISIBILITY_PARTIALLY_OBSCURED;
}

int model_set_shown(struct model *model, const pixman_region32_t *shown)
{
	pixman_region32_t outside;
	pixman_region32_init_rect(&outside, 0, 0, MODEL_SCREEN_SIZE, MODEL_SCREEN_SIZE);
	pixman_region32_subtract(&outside, &outside, (pixman_region32_t *)shown);
	int n = 0;
	const pixman_box32_t *boxes = pixman_region32_rectangles(&outside, &n);
	struct vis_rect32 *rects = calloc(n > 0 ? (size_t)n : 1, sizeof(*rects));
	if (rects == NULL) {
		pixman_region32_fini(&outside);
		return -1;
	}
	for (int i = 0; i < n; i++)
		rects[i] = rect_of(&boxes[i]);
	int rc = vis_win_set_shape(model->outside, 1, rects, (uint32_t)n);
	if (rc < 0) {
		wlr_log_errno(WLR_ERROR, "vis_win_set_shape (the outside)");
		free(rects);
	} else {
		free(model->outside_rects);
		model->outside_rects = rects;
		model->n_outside = (size_t)n;
		mirror_outside_changed(model->server->mirror);
	}
	pixman_region32_fini(&outside);
	return rc;
}

int model_update(struct model *model)
{
	const struct vis_change *changes;
	size_t n;
	/* visd gets the model's changes at the same pace as libvis: once a frame, in one batch. */
	mirror_sync(model->server->mirror);
	struct stats *stats = &model->server->stats;
	uint64_t t0 = stats_now_ns();
	int rc = vis_tree_update(model->tree, &changes, &n);
	model->update_ns = stats_now_ns() - t0;
	if (rc < 0) {
		wlr_log_errno(WLR_ERROR, "vis_tree_update");
		return -1;
	}
	for (size_t i = 0; i < n; i++) {
		struct model_surface *ms = changes[i].data;
		if (ms == NULL)
			continue; /* the outside */
		bool was = changes[i].previous == VIS_VISIBILITY_UNOBSCURED ||
			   changes[i].previous == VIS_VISIBILITY_PARTIALLY_OBSCURED;
		bool is = changes[i].state == VIS_VISIBILITY_UNOBSCURED ||
			  changes[i].state == VIS_VISIBILITY_PARTIALLY_OBSCURED;
		if (is != was && stats->change_ns != 0) {
			ms->flip_ns = stats->change_ns;
			ms->flip_frames = stats->change_frames;
			ms->flip_covered = !is;
		}
		/* Its callbacks waited while nothing of it could be seen: answer them now. */
		if (is && !was)
			server_schedule_frames(model->server, ms->x, ms->y, ms->width, ms->height);
	}
	/* The command's flips are all in this update: later ones are not its. */
	stats->change_ns = 0;
	return 0;
}
