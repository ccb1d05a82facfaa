#include <stdlib.h>
#include <time.h>

#include <vis/vis.h>
#include <wlr/backend.h>
#include <wlr/render/wlr_renderer.h>
#include <wlr/types/wlr_matrix.h>
#include <wlr/types/wlr_output.h>
#include <wlr/types/wlr_output_damage.h>
#include <wlr/types/wlr_output_layout.h>
#include <wlr/types/wlr_surface.h>
#include <wlr/types/wlr_xdg_shell.h>
#include <wlr/util/log.h>

#include "output.h"
#include "server.h"
#include "view.h"

static const float background[4] = { 0.18f, 0.20f, 0.22f, 1.0f };

uint64_t server_now_ms(void)
{
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	return (uint64_t)now.tv_sec * 1000u + (uint64_t)now.tv_nsec / 1000000u;
}

/* The output's box in the layout; false when it is not in it. */
static bool output_box(struct output *output, struct wlr_box *box)
{
	struct wlr_box *b = wlr_output_layout_get_box(output->server->layout, output->wlr_output);
	if (b == NULL || b->width <= 0)
		return false;
	*box = *b;
	return true;
}

void server_damage_box(struct server *server, int32_t x, int32_t y, int32_t width, int32_t height)
{
	struct output *output;
	wl_list_for_each(output, &server->outputs, link) {
		struct wlr_box box;
		if (!output_box(output, &box))
			continue;
		struct wlr_box damage = { x - box.x, y - box.y, width, height };
		wlr_output_damage_add_box(output->damage, &damage);
	}
}

void server_damage_whole(struct server *server)
{
	struct output *output;
	wl_list_for_each(output, &server->outputs, link)
		wlr_output_damage_add_whole(output->damage);
}

void server_schedule_frames(struct server *server, int32_t x, int32_t y, int32_t width,
			    int32_t height)
{
	struct output *output;
	wl_list_for_each(output, &server->outputs, link) {
		struct wlr_box box;
		if (!output_box(output, &box))
			continue;
		if (x < box.x + box.width && box.x < x + width && y < box.y + box.height &&
		    box.y < y + height)
			wlr_output_schedule_frame(output->wlr_output);
	}
}

void server_outputs_changed(struct server *server)
{
	pixman_region32_t shown;
	pixman_region32_init(&shown);
	struct output *output;
	wl_list_for_each(output, &server->outputs, link) {
		struct wlr_box box;
		if (output_box(output, &box))
			pixman_region32_union_rect(&shown, &shown, box.x, box.y,
						   (unsigned)box.width, (unsigned)box.height);
		wlr_output_damage_add_whole(output->damage);
	}
	model_set_shown(&server->model, &shown);
	pixman_region32_fini(&shown);
}

/* Draws one damaged rectangle (output coordinates): the background, then the repaint set libvis
 * gives for it, bottom to top, each surface clipped to what of it shows there. */
static void render_rect(struct output *output, const struct wlr_box *box, const struct wlr_box *rect,
			uint64_t *work_ns)
{
	struct server *server = output->server;
	struct wlr_renderer *renderer = server->renderer;
	struct wlr_output *wlr_output = output->wlr_output;
	struct wlr_box clip = *rect;
	wlr_renderer_scissor(renderer, &clip);
	wlr_renderer_clear(renderer, background);

	struct vis_rect32 damage = {
		.x = box->x + rect->x,
		.y = box->y + rect->y,
		.width = (uint32_t)rect->width,
		.height = (uint32_t)rect->height,
	};
	const struct vis_repaint *repaint;
	size_t n;
	uint64_t t0 = stats_now_ns();
	int rc = vis_tree_repaint(server->model.tree, &damage, &repaint, &n);
	*work_ns += stats_now_ns() - t0;
	if (rc < 0) {
		wlr_log_errno(WLR_ERROR, "vis_tree_repaint");
		return;
	}
	for (size_t i = 0; i < n; i++) {
		struct model_surface *ms = repaint[i].data;
		if (ms == NULL)
			continue; /* the outside is never drawn */
		struct wlr_texture *texture = wlr_surface_get_texture(ms->surface);
		if (texture == NULL)
			continue;
		/* The buffer scaled to the surface's size, where the surface lies on this output. */
		struct wlr_box where = {
			.x = (int)(repaint[i].x - box->x),
			.y = (int)(repaint[i].y - box->y),
			.width = ms->width,
			.height = ms->height,
		};
		float matrix[9];
		wlr_matrix_project_box(matrix, &where, WL_OUTPUT_TRANSFORM_NORMAL, 0,
				       wlr_output->transform_matrix);
		for (uint32_t r = 0; r < repaint[i].n_rects; r++) {
			const struct vis_rect32 *part = &repaint[i].rects[r];
			struct wlr_box scissor = {
				.x = where.x + part->x,
				.y = where.y + part->y,
				.width = (int)part->width,
				.height = (int)part->height,
			};
			wlr_renderer_scissor(renderer, &scissor);
			wlr_render_texture_with_matrix(renderer, texture, matrix, 1.0f);
		}
	}
}

/* The latency of a surface's flip, when a control command made one and its first callback since
 * is being withheld (covered) or sent (uncovered): stats.h. */
static void time_flip(struct stats *stats, struct model_surface *ms, bool sent)
{
	if (ms->flip_ns == 0 || ms->flip_covered == sent)
		return;
	uint64_t frames = stats->frames - ms->flip_frames;
	if (frames > UINT32_MAX)
		frames = UINT32_MAX;
	stats_add_latency(ms->flip_covered ? &stats->cover : &stats->uncover,
			  stats_now_ns() - ms->flip_ns, (uint32_t)frames);
	ms->flip_ns = 0;
}

/* Answers the frame callbacks of the surfaces with a visible pixel on this output; the others
 * keep theirs until they can be seen (model_update()). */
static void send_frame_done(struct output *output, const struct wlr_box *box)
{
	struct server *server = output->server;
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	uint64_t now_ms = server_now_ms();
	struct model_surface *ms;
	wl_list_for_each(ms, &server->model.surfaces, link) {
		if (!ms->mapped)
			continue;
		if (ms->x >= box->x + box->width || box->x >= ms->x + ms->width ||
		    ms->y >= box->y + box->height || box->y >= ms->y + ms->height)
			continue;
		if (wl_list_empty(&ms->surface->current.frame_callback_list))
			continue;
		bool visible = model_surface_visible(ms);
		time_flip(&server->stats, ms, visible);
		if (!visible)
			continue;
		if (ms->view != NULL && ms->view->xdg->surface == ms->surface) {
			rate_add(&ms->view->frames, now_ms);
			ms->view->frames_total++;
		}
		wlr_surface_send_frame_done(ms->surface, &now);
	}
}

/* An output's frame: update the states, draw the damage from the repaint sets, commit, and
 * answer the frame callbacks of what shows on it. */
static void handle_frame(struct wl_listener *listener, void *data)
{
	(void)data;
	struct output *output = wl_container_of(listener, output, frame);
	struct server *server = output->server;
	struct wlr_output *wlr_output = output->wlr_output;
	struct wlr_box box;
	if (!output_box(output, &box))
		return;
	server->stats.frames++; /* this frame is the count's (stats.h) */
	/* States first: both what to draw and who gets a frame callback follow from them. */
	model_update(&server->model);
	uint64_t work_ns = server->model.update_ns;

	bool needs_frame;
	pixman_region32_t damage;
	pixman_region32_init(&damage);
	if (!wlr_output_damage_attach_render(output->damage, &needs_frame, &damage)) {
		pixman_region32_fini(&damage);
		return;
	}
	if (needs_frame) {
		struct wlr_renderer *renderer = server->renderer;
		wlr_renderer_begin(renderer, (uint32_t)wlr_output->width, (uint32_t)wlr_output->height);
		int n = 0;
		const pixman_box32_t *rects = pixman_region32_rectangles(&damage, &n);
		for (int i = 0; i < n; i++) {
			struct wlr_box rect = { rects[i].x1, rects[i].y1, rects[i].x2 - rects[i].x1,
						rects[i].y2 - rects[i].y1 };
			render_rect(output, &box, &rect, &work_ns);
		}
		wlr_renderer_scissor(renderer, NULL);
		wlr_output_render_software_cursors(wlr_output, &damage);
		wlr_renderer_end(renderer);
		/* What changed on the screen since the last frame (not the buffer's age). */
		pixman_region32_t frame_damage;
		pixman_region32_init(&frame_damage);
		pixman_region32_copy(&frame_damage, &output->damage->current);
		wlr_output_set_damage(wlr_output, &frame_damage);
		pixman_region32_fini(&frame_damage);
		output->frames++;
		if (!wlr_output_commit(wlr_output))
			wlr_log(WLR_DEBUG, "output %s: commit failed", wlr_output->name);
	} else {
		wlr_output_rollback(wlr_output);
	}
	pixman_region32_fini(&damage);
	stats_add(&server->stats.frame, work_ns);
	send_frame_done(output, &box);
}

/* An output went: the outside grows by it. */
static void handle_destroy(struct wl_listener *listener, void *data)
{
	(void)data;
	struct output *output = wl_container_of(listener, output, destroy);
	struct server *server = output->server;
	wl_list_remove(&output->frame.link);
	wl_list_remove(&output->destroy.link);
	wl_list_remove(&output->link);
	free(output);
	server_outputs_changed(server);
}

/* A new output: enabled in its preferred mode, laid out, drawn from then on. */
static void handle_new_output(struct wl_listener *listener, void *data)
{
	struct server *server = wl_container_of(listener, server, new_output);
	struct wlr_output *wlr_output = data;
	if (!wlr_output_init_render(wlr_output, server->allocator, server->renderer)) {
		wlr_log(WLR_ERROR, "output %s: cannot render to it", wlr_output->name);
		return;
	}
	struct wlr_output_mode *mode = wlr_output_preferred_mode(wlr_output);
	if (mode != NULL)
		wlr_output_set_mode(wlr_output, mode);
	wlr_output_enable(wlr_output, true);
	if (!wlr_output_commit(wlr_output)) {
		wlr_log(WLR_ERROR, "output %s: cannot enable it", wlr_output->name);
		return;
	}
	struct output *output = calloc(1, sizeof(*output));
	if (output == NULL) {
		wlr_log(WLR_ERROR, "out of memory for an output");
		return;
	}
	output->server = server;
	output->wlr_output = wlr_output;
	/* Our destroy handler first: the damage tracker frees itself on the same signal, and our
	 * frame listener must leave its list before. */
	output->destroy.notify = handle_destroy;
	wl_signal_add(&wlr_output->events.destroy, &output->destroy);
	output->damage = wlr_output_damage_create(wlr_output);
	if (output->damage == NULL) {
		wlr_log(WLR_ERROR, "output %s: no damage tracking", wlr_output->name);
		wl_list_remove(&output->destroy.link);
		free(output);
		return;
	}
	output->frame.notify = handle_frame;
	wl_signal_add(&output->damage->events.frame, &output->frame);
	wl_list_insert(server->outputs.prev, &output->link);
	wlr_output_layout_add_auto(server->layout, wlr_output);
	wlr_output_create_global(wlr_output);
	server_outputs_changed(server);
	wlr_log(WLR_INFO, "output %s: %dx%d", wlr_output->name, wlr_output->width,
		wlr_output->height);
}

void output_init(struct server *server)
{
	server->new_output.notify = handle_new_output;
	wl_signal_add(&server->backend->events.new_output, &server->new_output);
}
