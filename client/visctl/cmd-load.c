/*
 * `visctl load`: a scene file becomes live windows, all created in one batch so that the daemon
 * recomputes once. The scene is parsed completely before connecting: a bad scene changes nothing.
 */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "live.h"
#include "scene.h"
#include "visctl.h"

/* Requests queued between two waits for the socket, so that a large scene never piles up. */
#define LOAD_DRAIN_EVERY 4096

/* Called with each created reply; they come in request order, hence in scene order. */
static void on_created(void *data, const struct vis_error *err, uint32_t window)
{
	struct load *ld = data;
	if (err && !ld->failed) {
		ld->failed = true;
		ld->failed_at = ld->created;
		ld->error = *err;
	}
	ld->windows[ld->created++] = window;
}

/* Reads and parses the scene: 1 when it cannot be read, 2 for bad input, as compute does. */
static int read_scene(struct live *l, const char *path, struct vis_scene *scene)
{
	const char *shown = strcmp(path, "-") == 0 ? "<stdin>" : path;
	char *text;
	size_t len;
	if (visctl_read_all(path, &text, &len) < 0)
		return live_error(l, "%s: cannot read: %s", shown, strerror(errno)); /* runtime: 1 */
	struct vis_scene_error err;
	int r = vis_scene_parse(scene, text, len, &err);
	free(text);
	if (r == 0)
		return VISCTL_EXIT_OK;
	if (l->in_script)
		fprintf(stderr, "%s: ", l->where);
	if (err.line == 0) {
		fprintf(stderr, "%s: %s\n", shown, err.reason);
		return VISCTL_EXIT_FAILURE;
	}
	fprintf(stderr, "%s:%zu: %s\n", shown, err.line, err.reason);
	return VISCTL_EXIT_USAGE;
}

/* Whether a window's look needs requests of its own after create: a shape or opaque region. */
static bool needs_look_requests(const struct vis_look *look)
{
	return look->shaped || look->opaque != VIS_OPAQUE_ALL;
}

/* Sends a window's shape and opaque region, its rectangles as the protocol's. */
static bool send_look(struct vis_client *c, uint32_t window, const struct vis_look *look)
{
	const struct vis_rect *r[2] = { look->shape, look->opaque_rects };
	uint32_t n[2] = { look->n_shape, look->n_opaque };
	for (int k = 0; k < 2; k++) {
		if ((k == 0 && !look->shaped) || (k == 1 && look->opaque == VIS_OPAQUE_ALL))
			continue;
		struct vis_rect32 *v = malloc((n[k] ? n[k] : 1) * sizeof(*v));
		if (!v)
			return false;
		for (uint32_t i = 0; i < n[k]; i++)
			v[i] = (struct vis_rect32){ r[k][i].x, r[k][i].y, (uint32_t)r[k][i].w,
						    (uint32_t)r[k][i].h };
		uint32_t seq = k == 0 ? vis_client_set_shape(c, window, 1, v, n[k])
				      : vis_client_set_opaque(c, window, look->opaque, v, n[k]);
		free(v);
		if (!seq)
			return false;
	}
	return true;
}

/*
 * Creates the scene's windows. Borders and input-only go with create; shapes and opaque regions
 * need the windows' IDs, which come at the batch's commit: then the windows are created unmapped
 * and a second batch gives them their looks and maps them, so that no recompute sees them half
 * made.
 */
int cmd_load_batch(struct vis_client *c, const struct vis_scene *scene, uint32_t flags,
		   struct load *ld)
{
	bool second = false;
	for (size_t i = 0; scene->looks && i < scene->n && !second; i++)
		second = needs_look_requests(&scene->looks[i]);
	uint32_t create_flags = second ? flags & ~(uint32_t)VIS_CREATE_MAP : flags;
	uint32_t begin = vis_client_batch_begin(c);
	if (!begin)
		return -1;
	for (size_t i = 0; i < scene->n; i++) {
		const struct vis_rect *r = &scene->rects[i];
		const struct vis_look *look = scene->looks ? &scene->looks[i] : NULL;
		uint32_t f = create_flags | (look && look->input_only ? VIS_CREATE_INPUT_ONLY : 0);
		if (!vis_client_create_window_async(c, VIS_WINDOW_ROOT, r->x, r->y, (uint32_t)r->w,
						    (uint32_t)r->h, look ? (uint32_t)look->border : 0,
						    f, on_created, ld))
			return -1;
		if ((i + 1) % LOAD_DRAIN_EVERY == 0 && live_drain(c) < 0)
			return -1;
	}
	if (!vis_client_batch_commit(c))
		return -1;
	struct vis_error e;
	if (vis_client_roundtrip(c) < 0 || ld->failed)
		return -1;
	/* batch-begin or batch-commit may have failed without a reply to carry it. */
	if (vis_client_last_error(c, &e) && e.seq >= begin)
		return -1;
	if (!second)
		return 0;
	if (!(begin = vis_client_batch_begin(c)))
		return -1;
	for (size_t i = 0; i < scene->n; i++) {
		if (needs_look_requests(&scene->looks[i]) &&
		    !send_look(c, ld->windows[i], &scene->looks[i]))
			return -1;
		if ((flags & VIS_CREATE_MAP) && !vis_client_map(c, ld->windows[i]))
			return -1;
		if ((i + 1) % LOAD_DRAIN_EVERY == 0 && live_drain(c) < 0)
			return -1;
	}
	if (!vis_client_batch_commit(c) || vis_client_roundtrip(c) < 0)
		return -1;
	/* A shape, opaque region or map of the second batch failed: the error says which. */
	if (vis_client_last_error(c, &e) && e.seq >= begin)
		return -1;
	return 0;
}

int cmd_load(struct live *l, int argc, char **argv)
{
	uint32_t flags = VIS_CREATE_MAP;
	bool any_screen = false, json = false;
	const char *path = NULL;
	struct load ld = { 0 };
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
			printf("usage: visctl load [--retain] [--any-screen] [--json] SCENE\n"
			       "  Creates the scene's windows, mapped, in one batch (file order is bottom\n"
			       "  to top) and prints 'SCENE_ID WINDOW_ID' for each (--json: one object a\n"
			       "  line, {\"scene_id\":ID,\"window\":ID}). SCENE is a path or '-'.\n"
			       "  A scene whose screen line differs from the daemon's screen is refused\n"
			       "  (exit status 1): its states would not be visctl compute's. --any-screen\n"
			       "  loads it on the daemon's screen all the same. Borders, shapes, opaque\n"
			       "  regions and input-only windows load as the scene gives them.\n");
			return fflush(stdout) == 0 ? VISCTL_EXIT_OK : VISCTL_EXIT_FAILURE;
		}
		if (strcmp(a, "--retain") == 0)
			flags |= VIS_CREATE_RETAIN;
		else if (strcmp(a, "--any-screen") == 0)
			any_screen = true;
		else if (strcmp(a, "--json") == 0)
			json = true;
		else if (a[0] == '-' && a[1] != '\0')
			return live_usage(l, argv[0], "unknown option '%s'", a);
		else if (path)
			return live_usage(l, argv[0], "unexpected argument '%s'", a);
		else
			path = a;
	}
	if (!path)
		return live_usage(l, argv[0], "missing SCENE");

	struct vis_scene scene;
	vis_scene_init(&scene);
	int ret = read_scene(l, path, &scene);
	if (ret != VISCTL_EXIT_OK)
		goto out;
	ld.windows = malloc((scene.n ? scene.n : 1) * sizeof(uint32_t));
	if (!ld.windows) {
		ret = live_error(l, "load: %s", strerror(ENOMEM));
		goto out;
	}
	ret = VISCTL_EXIT_FAILURE;
	if (!live_connect(l))
		goto out;
	uint32_t sw, sh;
	vis_client_screen(l->client, &sw, &sh);
	if (scene.has_screen && !any_screen &&
	    ((uint32_t)scene.screen_w != sw || (uint32_t)scene.screen_h != sh)) {
		live_error(l,
			   "load %s: the scene's screen is %dx%d, the daemon's %ux%u: its states "
			   "would not be visctl compute's (--any-screen loads it all the same)",
			   path, scene.screen_w, scene.screen_h, sw, sh);
		goto out;
	}
	if (cmd_load_batch(l->client, &scene, flags, &ld) < 0) {
		char what[256];
		if (ld.failed && !vis_client_error(l->client))
			live_error(l, "load %s: create of window %u: %s: %s", path,
				   scene.ids[ld.failed_at], vis_error_code_name(ld.error.code),
				   ld.error.message);
		else
			live_failed(l, live_describe(argc, argv, what, sizeof(what)));
		goto out;
	}
	for (size_t i = 0; i < scene.n; i++)
		printf(json ? "{\"scene_id\":%u,\"window\":%u}\n" : "%u %u\n", scene.ids[i],
		       ld.windows[i]);
	ret = VISCTL_EXIT_OK;
out:
	free(ld.windows);
	vis_scene_finish(&scene);
	return ret;
}
