#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include <vis/visclient.h>
#include <wayland-server-core.h>
#include <wlr/types/wlr_surface.h>
#include <wlr/util/log.h>

#include "mirror.h"
#include "model.h"
#include "server.h"
#include "view.h"

/* The most opaque rectangles sent for a surface, as model.c gives libvis. */
#define MAX_OPAQUE_RECTS 256

/* After visd went away: the first attempt to connect again, and the longest wait between two
 * (each failed attempt doubles the wait up to it). */
#define RETRY_FIRST_MS 100
#define RETRY_MAX_MS 5000

/*
 * One model surface's visd window. Lives from the create request until both the surface is gone
 * (ms NULL) and visd's answer has come (id set, or the create failed), since the answer may come
 * after the surface went.
 */
struct mirror_win {
	struct mirror *mirror;
	struct model_surface *ms; /* NULL once the surface is gone */
	uint32_t id;              /* visd's ID, 0 until the create's answer */
	struct wl_list link;      /* mirror.wins */
	/* What visd has: */
	int32_t x, y, width, height;
	bool mapped;
	pixman_region32_t opaque;
};

struct mirror {
	struct server *server;
	char *path;                   /* visd's socket */
	struct vis_client *client;    /* NULL while visd is away */
	struct wl_event_source *source;
	struct wl_event_source *retry; /* the timer that connects again while client is NULL */
	int retry_ms;                 /* the wait before the next attempt */
	unsigned attempts;            /* attempts since the connection ended */
	struct wl_event_source *idle; /* a sync due at idle (answers came), or NULL */
	struct wl_list wins;  /* mirror_win.link */
	uint32_t outside;     /* the outside's visd window */
	bool outside_dirty;
	uint32_t *order;      /* the IDs as last stacked, bottom to top */
	size_t n_order, cap_order;
};

static void win_free(struct mirror_win *mw);

/* Forgets what visd had: its windows went with the connection (they are not retained), and
 * the answers still awaited will never come. The next connection mirrors everything anew. */
static void forget(struct mirror *mirror)
{
	struct mirror_win *mw, *tmp;
	wl_list_for_each_safe(mw, tmp, &mirror->wins, link) {
		if (mw->ms != NULL)
			mw->ms->mirror = NULL;
		win_free(mw);
	}
	free(mirror->order);
	mirror->order = NULL;
	mirror->n_order = mirror->cap_order = 0;
	mirror->outside = 0;
}

/* Drops the connection after a failure; viscomp goes on without a mirror and tries to connect
 * again, first after RETRY_FIRST_MS. */
static void disconnect(struct mirror *mirror, const char *why)
{
	if (mirror->client == NULL)
		return;
	wlr_log(WLR_ERROR, "visd mirror: %s: %s; going on without it, connecting again (every "
		"%d ms at first, at most every %d ms)", why,
		vis_client_error_message(mirror->client), RETRY_FIRST_MS, RETRY_MAX_MS);
	wl_event_source_remove(mirror->source);
	mirror->source = NULL;
	vis_client_destroy(mirror->client);
	mirror->client = NULL;
	forget(mirror);
	mirror->retry_ms = RETRY_FIRST_MS;
	mirror->attempts = 0;
	wl_event_source_timer_update(mirror->retry, mirror->retry_ms);
}

/* A sync at idle: for what visd's answers made possible (a created window to map, place and
 * stack) when no frame would come to send it. */
static void sync_idle(void *data)
{
	struct mirror *mirror = data;
	mirror->idle = NULL;
	mirror_sync(mirror);
}

static void schedule_sync(struct mirror *mirror)
{
	if (mirror->idle == NULL)
		mirror->idle = wl_event_loop_add_idle(mirror->server->loop, sync_idle, mirror);
}

/* Polls for writing only while the socket has not taken everything. */
static void flush(struct mirror *mirror)
{
	int rc = vis_client_flush(mirror->client);
	if (rc < 0)
		disconnect(mirror, "write");
	else
		wl_event_source_fd_update(mirror->source,
					  WL_EVENT_READABLE | (rc > 0 ? WL_EVENT_WRITABLE : 0));
}

/* visd's answers and errors, and writing what the socket did not take. */
static int handle_fd(int fd, uint32_t mask, void *data)
{
	(void)fd;
	struct mirror *mirror = data;
	if (vis_client_dispatch(mirror->client) < 0 || (mask & (WL_EVENT_HANGUP | WL_EVENT_ERROR))) {
		disconnect(mirror, "the connection ended");
		return 0;
	}
	flush(mirror);
	return 0;
}

/* Logs a request visd refused: the mirror may then differ until the window changes again. */
static void handle_error(void *data, const struct vis_error *error)
{
	(void)data;
	wlr_log(WLR_ERROR, "visd mirror: request %u (%s) failed: %s", error->seq,
		vis_request_name(error->opcode), error->message);
}

/* Frees a window record (not visd's window). */
static void win_free(struct mirror_win *mw)
{
	wl_list_remove(&mw->link);
	pixman_region32_fini(&mw->opaque);
	free(mw);
}

/* Sends what differs between the surface and what visd has of it. */
static void push(struct mirror *mirror, struct mirror_win *mw)
{
	struct vis_client *c = mirror->client;
	struct model_surface *ms = mw->ms;
	if (ms->x != mw->x || ms->y != mw->y || ms->width != mw->width || ms->height != mw->height) {
		vis_client_configure(c, mw->id, ms->x, ms->y, (uint32_t)ms->width,
				     (uint32_t)ms->height, 0);
		mw->x = ms->x, mw->y = ms->y, mw->width = ms->width, mw->height = ms->height;
	}
	if (!pixman_region32_equal(&ms->opaque, &mw->opaque)) {
		/* The same rule as model.c's set_opaque(), from the region libvis was given. */
		int n = 0;
		const pixman_box32_t *boxes = pixman_region32_rectangles(&ms->opaque, &n);
		pixman_box32_t *e = pixman_region32_extents(&ms->opaque);
		if (n == 0 || n > MAX_OPAQUE_RECTS) {
			vis_client_set_opaque(c, mw->id, VIS_OPAQUE_MODE_NONE, NULL, 0);
		} else if (n == 1 && e->x1 <= 0 && e->y1 <= 0 && e->x2 >= ms->width &&
			   e->y2 >= ms->height) {
			vis_client_set_opaque(c, mw->id, VIS_OPAQUE_MODE_ALL, NULL, 0);
		} else {
			struct vis_rect32 rects[MAX_OPAQUE_RECTS];
			for (int i = 0; i < n; i++)
				rects[i] = (struct vis_rect32){ boxes[i].x1, boxes[i].y1,
								(uint32_t)(boxes[i].x2 - boxes[i].x1),
								(uint32_t)(boxes[i].y2 - boxes[i].y1) };
			vis_client_set_opaque(c, mw->id, VIS_OPAQUE_MODE_RECTS, rects, (uint32_t)n);
		}
		pixman_region32_copy(&mw->opaque, &ms->opaque);
	}
	if (ms->mapped != mw->mapped) {
		if (ms->mapped)
			vis_client_map(c, mw->id);
		else
			vis_client_unmap(c, mw->id);
		mw->mapped = ms->mapped;
	}
}

/* visd's answer to a create: the window's ID, or it is gone already. */
static void created(void *data, const struct vis_error *err, uint32_t window)
{
	struct mirror_win *mw = data;
	struct mirror *mirror = mw->mirror;
	if (err != NULL) {
		wlr_log(WLR_ERROR, "visd mirror: create failed: %s", err->message);
		if (mw->ms != NULL)
			mw->ms->mirror = NULL;
		win_free(mw);
		return;
	}
	mw->id = window;
	if (mw->ms == NULL) {
		vis_client_destroy_window(mirror->client, window);
		win_free(mw);
		return;
	}
	/* What changed while the create was on its way, its mapping and its place in the stack:
	 * at the next sync, which an idle desktop would not bring. */
	schedule_sync(mirror);
}

/* Asks visd for a window for a surface, with the surface as it is now. */
static void create(struct mirror *mirror, struct model_surface *ms)
{
	struct mirror_win *mw = calloc(1, sizeof(*mw));
	if (mw == NULL)
		return;
	mw->mirror = mirror;
	mw->ms = ms;
	mw->x = ms->x, mw->y = ms->y, mw->width = ms->width, mw->height = ms->height;
	/* visd's windows hide everything until told otherwise, as libvis'. */
	pixman_region32_init_rect(&mw->opaque, 0, 0, (unsigned)ms->width, (unsigned)ms->height);
	wl_list_insert(&mirror->wins, &mw->link);
	struct wl_client *client = wl_resource_get_client(ms->surface->resource);
	pid_t pid = 0;
	wl_client_get_credentials(client, &pid, NULL, NULL);
	uint64_t tag = (uint64_t)(uint32_t)pid << 32 | wl_resource_get_id(ms->surface->resource);
	if (vis_client_create_external_async(mirror->client, VIS_WINDOW_ROOT, ms->x, ms->y,
					     (uint32_t)ms->width, (uint32_t)ms->height, 0, 0,
					     VIS_EXTERNAL_WAYLAND, tag, created, mw) == 0) {
		win_free(mw);
		return;
	}
	ms->mirror = mw;
}

/* Appends a window to the order being built; false when memory ran out. */
static bool order_add(uint32_t **order, size_t *n, size_t *cap, uint32_t id)
{
	if (*n == *cap) {
		size_t grown = *cap ? *cap * 2 : 64;
		uint32_t *bigger = realloc(*order, grown * sizeof(**order));
		if (bigger == NULL)
			return false;
		*order = bigger, *cap = grown;
	}
	(*order)[(*n)++] = id;
	return true;
}

/* Stacks visd's windows as the model's: the views bottom to top, each view's surfaces in order,
 * the outside on top. Only the part from the first difference is sent again. */
static void restack(struct mirror *mirror)
{
	uint32_t *order = NULL;
	size_t n = 0, cap = 0;
	bool ok = true;
	struct view *view;
	wl_list_for_each(view, &mirror->server->views, link) {
		struct model_surface *ms;
		wl_list_for_each(ms, &view->surfaces, view_link)
			if (ms->mirror != NULL && ms->mirror->id != 0 && ms->mirror->mapped)
				ok = ok && order_add(&order, &n, &cap, ms->mirror->id);
	}
	ok = ok && order_add(&order, &n, &cap, mirror->outside);
	if (!ok) {
		free(order);
		return; /* tried again at the next sync */
	}
	size_t same = 0;
	while (same < n && same < mirror->n_order && order[same] == mirror->order[same])
		same++;
	for (size_t i = same; i < n; i++) {
		if (i == 0)
			vis_client_lower(mirror->client, order[0]);
		else
			vis_client_restack(mirror->client, order[i], VIS_RESTACK_ABOVE, order[i - 1]);
	}
	free(mirror->order);
	mirror->order = order, mirror->n_order = n, mirror->cap_order = cap;
}

/* Sends the outside's shape. */
static void send_outside(struct mirror *mirror)
{
	struct model *model = &mirror->server->model;
	vis_client_set_shape(mirror->client, mirror->outside, 1, model->outside_rects,
			     (uint32_t)model->n_outside);
	mirror->outside_dirty = false;
}

void mirror_sync(struct mirror *mirror)
{
	if (mirror == NULL || mirror->client == NULL)
		return;
	vis_client_batch_begin(mirror->client);
	if (mirror->outside_dirty)
		send_outside(mirror);
	struct model_surface *ms;
	wl_list_for_each(ms, &mirror->server->model.surfaces, link) {
		if (ms->win == NULL)
			continue; /* never placed */
		if (ms->mirror == NULL)
			create(mirror, ms);
		else if (ms->mirror->id != 0)
			push(mirror, ms->mirror);
	}
	/* A restack in the model (view.c) leaves no trace here: the order is compared each time. */
	restack(mirror);
	vis_client_batch_commit(mirror->client);
	if (vis_client_error(mirror->client) != 0)
		disconnect(mirror, "send");
	else
		flush(mirror);
}

void mirror_surface_gone(struct mirror *mirror, struct model_surface *ms)
{
	struct mirror_win *mw = ms->mirror;
	ms->mirror = NULL;
	if (mw == NULL)
		return;
	mw->ms = NULL;
	if (mw->id == 0)
		return; /* created() destroys it */
	if (mirror != NULL && mirror->client != NULL)
		vis_client_destroy_window(mirror->client, mw->id);
	win_free(mw);
}

void mirror_outside_changed(struct mirror *mirror)
{
	if (mirror != NULL)
		mirror->outside_dirty = true;
}

/*
 * Connects to visd as its manager and creates the outside; the model's surfaces follow at the
 * next sync. Synchronous: the handshake and the outside's creation wait for visd's answers.
 * 0, or -1 with the reason logged at level (the first failure of a series is an error, the
 * others only the verbose log's).
 */
static int attach(struct mirror *mirror, enum wlr_log_importance level)
{
	struct vis_client *c = vis_client_connect(mirror->path, VIS_ROLE_MANAGER);
	if (c == NULL || vis_client_error(c) != 0) {
		wlr_log(level, "visd mirror: cannot connect to %s as the manager: %s", mirror->path,
			c ? vis_client_error_message(c) : "no memory");
		vis_client_destroy(c);
		return -1;
	}
	vis_client_set_error_handler(c, handle_error, mirror);
	uint32_t width, height;
	vis_client_screen(c, &width, &height);
	if (vis_client_create_window(c, VIS_WINDOW_ROOT, 0, 0, width, height, 0, VIS_CREATE_MAP,
				     &mirror->outside) < 0) {
		wlr_log(level, "visd mirror: cannot create the outside: %s",
			vis_client_error_message(c));
		vis_client_destroy(c);
		return -1;
	}
	mirror->source = wl_event_loop_add_fd(mirror->server->loop, vis_client_fd(c),
					      WL_EVENT_READABLE, handle_fd, mirror);
	if (mirror->source == NULL) {
		wlr_log(level, "visd mirror: cannot watch the connection");
		vis_client_destroy(c);
		return -1;
	}
	mirror->client = c;
	mirror->outside_dirty = true;
	wlr_log(WLR_INFO, "visd mirror: connected to %s (screen %ux%u)", mirror->path, width,
		height);
	return 0;
}

/* The reconnection timer: one attempt; on success the whole model goes to the new visd, else
 * the next attempt waits twice as long (up to RETRY_MAX_MS). */
static int retry(void *data)
{
	struct mirror *mirror = data;
	if (mirror->client != NULL)
		return 0;
	mirror->attempts++;
	if (attach(mirror, mirror->attempts == 1 ? WLR_ERROR : WLR_INFO) < 0) {
		mirror->retry_ms = mirror->retry_ms * 2 < RETRY_MAX_MS ? mirror->retry_ms * 2
								       : RETRY_MAX_MS;
		/* Logged before the timer is set: the next attempt's line is at least that late. */
		wlr_log(WLR_INFO, "visd mirror: attempt %u failed; the next in %d ms",
			mirror->attempts, mirror->retry_ms);
		wl_event_source_timer_update(mirror->retry, mirror->retry_ms);
		return 0;
	}
	wlr_log(WLR_ERROR, "visd mirror: connected again to %s after %u attempt%s; mirroring "
		"every window anew", mirror->path, mirror->attempts, mirror->attempts > 1 ? "s" : "");
	mirror_sync(mirror);
	return 0;
}

struct mirror *mirror_create(struct server *server, const char *path)
{
	struct mirror *mirror = calloc(1, sizeof(*mirror));
	if (mirror == NULL)
		return NULL;
	mirror->server = server;
	wl_list_init(&mirror->wins);
	mirror->path = strdup(path);
	mirror->retry = wl_event_loop_add_timer(server->loop, retry, mirror);
	if (mirror->path == NULL || mirror->retry == NULL || attach(mirror, WLR_ERROR) < 0) {
		mirror_destroy(mirror);
		return NULL;
	}
	return mirror;
}

void mirror_destroy(struct mirror *mirror)
{
	if (mirror == NULL)
		return;
	if (mirror->source != NULL)
		wl_event_source_remove(mirror->source);
	if (mirror->retry != NULL)
		wl_event_source_remove(mirror->retry);
	if (mirror->idle != NULL)
		wl_event_source_remove(mirror->idle);
	vis_client_destroy(mirror->client);
	forget(mirror);
	free(mirror->path);
	free(mirror);
}
