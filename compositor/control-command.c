#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include <wayland-server-core.h>
#include <wlr/types/wlr_output.h>
#include <wlr/types/wlr_output_layout.h>
#include <wlr/types/wlr_xdg_shell.h>

#include "control.h"
#include "output.h"
#include "server.h"
#include "stack.h" /* vis_state_name(): the names visctl states prints */
#include "view.h"

/* Parses a decimal int32; false when text is not one. */
static bool parse_int(const char *text, int32_t *out)
{
	char *end;
	errno = 0;
	long v = strtol(text, &end, 10);
	if (end == text || *end != '\0' || errno != 0 || v < INT32_MIN || v > INT32_MAX)
		return false;
	*out = (int32_t)v;
	return true;
}

/* Writes a JSON string: quotes, backslashes and control characters escaped. */
static void json_string(struct control_reply *reply, const char *text)
{
	control_reply_printf(reply, "\"");
	for (const unsigned char *p = (const unsigned char *)(text ? text : ""); *p; p++) {
		if (*p == '"' || *p == '\\')
			control_reply_printf(reply, "\\%c", *p);
		else if (*p < 0x20)
			control_reply_printf(reply, "\\u%04x", *p);
		else
			control_reply_printf(reply, "%c", *p);
	}
	control_reply_printf(reply, "\"");
}

/* A text field of the plain list: "-" for none, spaces kept (the title is the line's last),
 * control characters (a newline would start a line of its own) as '?'. */
static void text_field(struct control_reply *reply, const char *text)
{
	if (text == NULL || *text == '\0') {
		control_reply_printf(reply, "-");
		return;
	}
	for (const unsigned char *p = (const unsigned char *)text; *p; p++)
		control_reply_printf(reply, "%c", *p < 0x20 || *p == 0x7f ? '?' : *p);
}

/* The pid of the view's client (0 when the socket cannot say). */
static pid_t view_pid(const struct view *view)
{
	pid_t pid = 0;
	struct wl_client *client = wl_resource_get_client(view->xdg->resource);
	wl_client_get_credentials(client, &pid, NULL, NULL);
	return pid;
}

/* list [--json]: the mapped views, top first, with their states and rates. */
static void list(struct server *server, bool json, struct control_reply *reply)
{
	/* Changes since the last frame count: the states are those of now. */
	model_update(&server->model);
	uint64_t now = server_now_ms();
	struct view *view;
	wl_list_for_each_reverse(view, &server->views, link) {
		if (!view->mapped)
			continue;
		int32_t x, y, width, height;
		view_box(view, &x, &y, &width, &height);
		const char *state = vis_state_name((enum vis_state)view_state(view));
		const char *app_id = view->xdg->toplevel->app_id;
		const char *title = view->xdg->toplevel->title;
		uint32_t commits = rate_get(&view->commits, now);
		uint32_t frames = rate_get(&view->frames, now);
		if (!json) {
			control_reply_printf(reply, "%u %d,%d %dx%d %s commits=%u frames=%u pid=%d ",
					     view->id, x, y, width, height, state, commits, frames,
					     (int)view_pid(view));
			text_field(reply, app_id);
			control_reply_printf(reply, " ");
			text_field(reply, title);
			control_reply_printf(reply, "\n");
			continue;
		}
		control_reply_printf(reply, "{\"id\":%u,\"app_id\":", view->id);
		json_string(reply, app_id);
		control_reply_printf(reply, ",\"title\":");
		json_string(reply, title);
		control_reply_printf(reply,
				     ",\"pid\":%d,\"x\":%d,\"y\":%d,\"width\":%d,\"height\":%d,"
				     "\"state\":\"%s\",\"focused\":%s,\"frames\":%u,\"commits\":%u,"
				     "\"frames_total\":%llu,\"commits_total\":%llu}\n",
				     (int)view_pid(view), x, y, width, height, state,
				     view == server->focused ? "true" : "false", frames, commits,
				     (unsigned long long)view->frames_total,
				     (unsigned long long)view->commits_total);
	}
	control_reply_printf(reply, "ok\n");
}

/* outputs: each output's place in the layout and the frames drawn on it: what clients' commits
 * cost the screen (a covered client's should cost nothing). */
static void outputs(struct server *server, struct control_reply *reply)
{
	struct output *output;
	wl_list_for_each(output, &server->outputs, link) {
		struct wlr_box *box = wlr_output_layout_get_box(server->layout, output->wlr_output);
		if (box == NULL)
			continue;
		control_reply_printf(reply, "%s %d,%d %dx%d frames=%llu\n", output->wlr_output->name,
				     box->x, box->y, box->width, box->height,
				     (unsigned long long)output->frames);
	}
	control_reply_printf(reply, "ok\n");
}

void control_command_run(struct server *server, int argc, char **argv, struct control_reply *reply)
{
	/* When the command arrived: a move, raise or lower is timed from it (stats.h); those made
	 * at once in the model, unlike resize and close, which the client carries out. */
	uint64_t arrived = stats_now_ns();
	if (argc == 0) {
		control_reply_printf(reply, "error: no command\n");
		return;
	}
	const char *cmd = argv[0];
	if (strcmp(cmd, "list") == 0) {
		bool json = argc == 2 && strcmp(argv[1], "--json") == 0;
		if (argc > 2 || (argc == 2 && !json))
			control_reply_printf(reply, "error: usage: list [--json]\n");
		else
			list(server, json, reply);
		return;
	}
	if (strcmp(cmd, "outputs") == 0) {
		if (argc > 1)
			control_reply_printf(reply, "error: usage: outputs\n");
		else
			outputs(server, reply);
		return;
	}
	if (strcmp(cmd, "redraw") == 0) {
		if (argc != 1) {
			control_reply_printf(reply, "error: usage: redraw\n");
			return;
		}
		server_damage_whole(server);
		control_reply_printf(reply, "ok\n");
		return;
	}
	if (strcmp(cmd, "stats") == 0) {
		bool reset = argc == 2 && strcmp(argv[1], "--reset") == 0;
		if (argc > 2 || (argc == 2 && !reset)) {
			control_reply_printf(reply, "error: usage: stats [--reset]\n");
			return;
		}
		stats_report(&server->stats, reply);
		if (reset)
			stats_reset(&server->stats);
		control_reply_printf(reply, "ok\n");
		return;
	}
	int want;
	if (strcmp(cmd, "move") == 0 || strcmp(cmd, "resize") == 0)
		want = 4;
	else if (strcmp(cmd, "raise") == 0 || strcmp(cmd, "lower") == 0 || strcmp(cmd, "close") == 0)
		want = 2;
	else {
		control_reply_printf(reply, "error: unknown command %s\n", cmd);
		return;
	}
	int32_t id, a = 0, b = 0;
	if (argc != want || !parse_int(argv[1], &id) ||
	    (want == 4 && (!parse_int(argv[2], &a) || !parse_int(argv[3], &b)))) {
		control_reply_printf(reply, "error: usage: %s ID%s\n", cmd,
				     want == 2 ? "" : strcmp(cmd, "move") == 0 ? " X Y" : " W H");
		return;
	}
	struct view *view = id > 0 ? view_from_id(server, (uint32_t)id) : NULL;
	if (view == NULL || !view->mapped) {
		control_reply_printf(reply, "error: no window %s\n", argv[1]);
		return;
	}
	if (strcmp(cmd, "move") == 0) {
		/* Within the libvis screen, where a window's pixels can be: no overflow past it. */
		if (a < -MODEL_SCREEN_SIZE || a > MODEL_SCREEN_SIZE || b < -MODEL_SCREEN_SIZE ||
		    b > MODEL_SCREEN_SIZE) {
			control_reply_printf(reply, "error: move: X and Y lie in -%d … %d\n",
					     MODEL_SCREEN_SIZE, MODEL_SCREEN_SIZE);
			return;
		}
		stats_mark_change(&server->stats, arrived);
		view_move(view, a, b);
	} else if (strcmp(cmd, "resize") == 0) {
		if (a < 1 || b < 1 || a > MODEL_SCREEN_SIZE || b > MODEL_SCREEN_SIZE) {
			control_reply_printf(reply, "error: resize: W and H lie in 1 … %d\n",
					     MODEL_SCREEN_SIZE);
			return;
		}
		view_resize(view, a, b);
	} else if (strcmp(cmd, "raise") == 0) {
		stats_mark_change(&server->stats, arrived);
		view_raise(view);
	} else if (strcmp(cmd, "lower") == 0) {
		stats_mark_change(&server->stats, arrived);
		view_lower(view);
	} else {
		view_close(view);
	}
	control_reply_printf(reply, "ok\n");
}
