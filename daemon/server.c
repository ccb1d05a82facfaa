/* The daemon's shared state: listeners, the libvis tree, recomputes and the notice fan-out. */
#include <errno.h>
#include <fcntl.h>
#include <stdbool.h>
#include <event2/event.h>
#include <stdlib.h>
#include <string.h>
#include <stdio.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"

/* Accepts one connection on either socket. */
static void on_accept(struct evconnlistener *l, evutil_socket_t fd, struct sockaddr *sa, int len,
		      void *data)
{
	(void)sa;
	(void)len;
	struct server *server = data;
	server_client_accept(server, fd, l == server->restricted_listener);
}

/* Re-enables accepting after running out of descriptors. */
static void on_listener_retry(evutil_socket_t fd, short what, void *data)
{
	(void)fd;
	(void)what;
	struct server *server = data;
	evconnlistener_enable(server->listener);
	if (server->restricted_listener)
		evconnlistener_enable(server->restricted_listener);
}

/* Holds a descriptor in reserve, to refuse connections cleanly once the others run out. */
static void take_reserve(struct server *server)
{
	if (server->reserve_fd < 0)
		server->reserve_fd = open("/dev/null", O_RDONLY | O_CLOEXEC);
}

/*
 * accept() failed. Out of descriptors must not end the daemon: the reserve descriptor makes room to
 * accept each waiting connection and refuse it with an error; without one, accepting pauses for
 * 100 ms.
 */
static void on_accept_error(struct evconnlistener *l, void *data)
{
	struct server *server = data;
	int err = EVUTIL_SOCKET_ERROR();
	if ((err == EMFILE || err == ENFILE) && server->reserve_fd >= 0) {
		close(server->reserve_fd);
		server->reserve_fd = -1;
		int fd, n = 0;
		/* At most a backlog's worth a call: a flood must not hold the event loop. */
		while (n++ < 64 &&
		       (fd = accept4(evconnlistener_get_fd(l), NULL, NULL, SOCK_CLOEXEC)) >= 0)
			server_refuse(server, fd, "the daemon is out of file descriptors (%s)",
				      strerror(err));
		take_reserve(server);
		if (server->reserve_fd >= 0)
			return;
	}
	log_warn("accept: %s; refusing connections for 100 ms", strerror(err));
	evconnlistener_disable(l);
	struct timeval delay = { 0, 100000 };
	evtimer_add(server->listener_retry, &delay);
}

/* Whether something listens at the socket path: a live socket, not a stale one. */
static bool socket_answers(const char *path)
{
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	strcpy(addr.sun_path, path);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
	if (fd < 0)
		return true; /* cannot tell: leave it */
	bool live = connect(fd, (struct sockaddr *)&addr, sizeof addr) == 0 || errno == EAGAIN;
	close(fd);
	return live;
}

/*
 * Binds fd to the temporary name tmp, unless it is too long or taken: only a socket nobody listens
 * on there is a stale one of ours, and anything else (a file, another daemon's socket) is left
 * alone.
 */
static bool bind_staged(int fd, const char *tmp, int len)
{
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	struct stat st;
	if (len < 0 || len >= (int)sizeof addr.sun_path)
		return false;
	if (lstat(tmp, &st) == 0 &&
	    (!S_ISSOCK(st.st_mode) || socket_answers(tmp) || unlink(tmp) < 0))
		return false;
	strcpy(addr.sun_path, tmp);
	return bind(fd, (struct sockaddr *)&addr, sizeof addr) == 0;
}

/*
 * Binds fd under a temporary name, path + ".new" or, if that is taken, path + ".PID.new", to be
 * renamed to path once listening; else, at path itself. Returns the name bound (path or tmp), or
 * NULL after logging why.
 */
static const char *bind_at(int fd, const char *path, char *tmp, size_t tmp_size)
{
	unlink(path); /* stale: the lock says no other daemon serves it */
	if (bind_staged(fd, tmp, snprintf(tmp, tmp_size, "%s.new", path)) ||
	    bind_staged(fd, tmp, snprintf(tmp, tmp_size, "%s.%ld.new", path, (long)getpid())))
		return tmp;
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	strcpy(addr.sun_path, path);
	if (bind(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
		log_error("cannot bind '%s': %s", path, strerror(errno));
		return NULL;
	}
	return path;
}

/*
 * Accepts connections on fd, a listening socket, with a backlog of 64 (0: fd listens already).
 * Accepted sockets are close-on-exec; fd is closed with the listener.
 */
static struct evconnlistener *new_listener(struct server *server, int fd, int backlog)
{
	struct evconnlistener *l = evconnlistener_new(server->base, on_accept, server,
		LEV_OPT_CLOSE_ON_FREE | LEV_OPT_CLOSE_ON_EXEC, backlog, fd);
	if (l)
		evconnlistener_set_error_cb(l, on_accept_error);
	return l;
}

/*
 * Opens one listening socket at an already-locked path. bind() creates the socket's file and only
 * listen() makes it answer: a client that connects as soon as the path appears (as scripts that
 * start visd do) would be refused in between. So the socket is bound under a temporary name and
 * renamed into place once it listens, when such a name fits and is free.
 */
static struct evconnlistener *listen_at(struct server *server, const char *path)
{
	char tmp[sizeof((struct sockaddr_un *)0)->sun_path];
	if (strlen(path) >= sizeof tmp) {
		log_error("socket path '%s' is longer than %zu bytes", path, sizeof tmp - 1);
		return NULL;
	}
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
	if (fd < 0) {
		log_error("socket: %s", strerror(errno));
		return NULL;
	}
	const char *bound = bind_at(fd, path, tmp, sizeof tmp);
	if (!bound) {
		close(fd);
		return NULL;
	}
	struct evconnlistener *l = new_listener(server, fd, 64);
	if (!l) {
		log_error("cannot listen on '%s': %s", path, strerror(errno));
		close(fd);
		unlink(bound);
		return NULL;
	}
	if (bound == tmp && rename(tmp, path) < 0) {
		log_error("cannot rename '%s' to '%s': %s", tmp, path, strerror(errno));
		evconnlistener_free(l);
		unlink(tmp);
		return NULL;
	}
	return l;
}

/*
 * Serves a listening socket the service manager passed (activation.c made it non-blocking): it
 * listens already, and its file, if any, belongs to the manager, which alone may remove it.
 */
static struct evconnlistener *listen_passed(struct server *server, int fd, const char *name)
{
	struct evconnlistener *l = new_listener(server, fd, 0);
	if (!l)
		log_error("cannot serve the socket passed, %s (fd %d): %s", name, fd, strerror(errno));
	return l;
}

void server_damage(struct server *server, struct vis_window *w)
{
	libvis_damage(server->vis, w->data);
}

bool server_dirty(const struct server *server)
{
	return server->vis->dirty;
}

/*
 * The end of the turn, after every request read in it: the deferred recompute, then one write to
 * each connection with output, its replies and notices together. Events activated while others
 * run come after those the turn's epoll_wait and timers made ready, so this runs last.
 */
static void on_turn_end(evutil_socket_t fd, short what, void *data)
{
	(void)fd;
	(void)what;
	struct server *server = data;
	server->turn_due = false;
	server_flush(server);
	server_io_write_all(server);
}

void server_schedule_turn_end(struct server *server)
{
	/* Once a turn: the fan-out would otherwise ask libevent for it once per subscriber. */
	if (!server->turn_due) {
		server->turn_due = true;
		event_active(server->turn_event, EV_TIMEOUT, 0);
	}
}

void server_schedule_flush(struct server *server)
{
	if (server->vis->dirty && !server->deferring)
		server_schedule_turn_end(server);
}

int server_init(struct server *server, struct event_base *base, const struct server_options *opt)
{
	memset(server, 0, sizeof *server);
	server->base = base;
	server->opt = *opt;
	server->next_client = 1;
	server->reserve_fd = -1;
	server->walk_left = UINT64_MAX;
	take_reserve(server);
	TAILQ_INIT(&server->clients);
	TAILQ_INIT(&server->to_write);
	vis_idmap_init(&server->clients_by_id);
	vis_idmap_init(&server->quotas);
	vis_buf_init(&server->scratch);
	if (!(server->vis = vis_tree_create(opt->screen_width, opt->screen_height)))
		return -1;
	vis_wtree_set_id_key(&server->vis->core, opt->id_key);
	/* The requests change the core itself (server_damage()): no walks around them keep tallies. */
	libvis_tally_below(server->vis, 0);
	if (vis_wtree_live_from(&server->vis->core, opt->live_from) < 0)
		return -1;
	server->listener_retry = evtimer_new(base, on_listener_retry, server);
	server->turn_event = event_new(base, -1, 0, on_turn_end, server);
	if (!server->listener_retry || !server->turn_event)
		return -1;
	server->listener = opt->socket_fd >= 0
				   ? listen_passed(server, opt->socket_fd, opt->socket_path)
				   : listen_at(server, opt->socket_path);
	if (!server->listener)
		return -1;
	if (opt->restricted_fd >= 0)
		server->restricted_listener =
			listen_passed(server, opt->restricted_fd, opt->restricted_path);
	else if (opt->restricted_path)
		server->restricted_listener = listen_at(server, opt->restricted_path);
	if (opt->restricted_path && !server->restricted_listener)
		return -1;
	return 0;
}

/* Frees a window's daemon data. */
static void free_window_data(struct vis_window *w)
{
	struct vis_win *win = w->data;
	if (win) {
		free(vis_win_get_data(win));
		vis_win_set_data(win, NULL);
	}
}

/* The tree's callback for a window that goes with no notices (shutdown, a failed create). */
static void forget_window(void *data, struct vis_window *w)
{
	(void)data;
	free_window_data(w);
	libvis_forget(w);
}

void server_finish(struct server *server)
{
	struct client *c;
	server->deferring = true; /* no recomputes or notices while everything goes */
	while ((c = TAILQ_FIRST(&server->clients)))
		server_client_free(c);
	if (server->vis)
		while (server->vis->core.root.top)
			vis_wtree_destroy(&server->vis->core, server->vis->core.root.top,
					  forget_window, NULL);
	if (server->listener)
		evconnlistener_free(server->listener);
	if (server->restricted_listener)
		evconnlistener_free(server->restricted_listener);
	if (server->listener_retry)
		event_free(server->listener_retry);
	if (server->turn_event)
		event_free(server->turn_event);
	vis_tree_destroy(server->vis);
	vis_idmap_finish(&server->clients_by_id);
	server_quota_finish(server);
	if (server->reserve_fd >= 0)
		close(server->reserve_fd);
	vis_buf_finish(&server->scratch);
}

bool server_may_see(const struct client *c, const struct vis_window *w)
{
	return c->role != VIS_ROLE_CLIENT || w->owner == c->id;
}

bool server_may_change(const struct client *c, const struct vis_window *w)
{
	return c->role == VIS_ROLE_MANAGER || (c->role == VIS_ROLE_CLIENT && w->owner == c->id);
}

struct window_data *server_window_data(struct vis_window *w)
{
	struct window_data *d = server_data_of(w);
	if (!d && (d = calloc(1, sizeof *d)))
		vis_win_set_data(w->data, d);
	return d;
}

/* Whether some subscription asks for w's exposures. */
static bool wants_exposure(const struct server *server, const struct vis_window *w)
{
	const struct window_data *d = server_data_of(w);
	if (server->role_all_exposure || (d && d->exposure_subs))
		return true;
	/* The owner's subscription to all of its own windows. */
	const struct client *owner = vis_idmap_get(&server->clients_by_id, w->owner);
	return owner && owner->all_exposure;
}

void server_track(struct vis_window *w, struct server *server)
{
	if (w && wants_exposure(server, w) && vis_win_track_exposure(w->data, 1) < 0)
		log_error("out of memory for exposure tracking");
}

/*
 * Stops tracking the exposures of the windows no subscription wants them of any more, once one
 * ended: libvis then spends nothing on them. From the end, as untracking moves the last one into
 * the place it leaves.
 */
static void untrack_unwanted(struct server *server)
{
	struct vis_tree *vis = server->vis;
	server->untrack_due = false;
	for (size_t i = vis->n_tracked; i-- > 0;)
		if (!wants_exposure(server, vis->tracked[i]->core))
			libvis_untrack(vis->tracked[i]);
}

/* Sends the visibility notice of w to every connection subscribed to it. */
static void notify_visibility(struct server *server, struct vis_window *w)
{
	struct server_notice once = { 0 };
	struct client *c;
	TAILQ_FOREACH(c, &server->clients, link)
		if (!c->closing && server_client_sub_for(c, w, VIS_NOTICE_VISIBILITY))
			server_notice_visibility(c, w, &once);
}

uint32_t *server_region_words(pixman_region32_t *region, uint32_t *count)
{
	int n;
	const pixman_box32_t *b = pixman_region32_rectangles(region, &n);
	uint32_t *words = malloc(((size_t)n + 1) * 4 * sizeof *words);
	if (!words)
		return NULL;
	for (int i = 0; i < n; i++) {
		words[4 * i] = (uint32_t)b[i].x1;
		words[4 * i + 1] = (uint32_t)b[i].y1;
		words[4 * i + 2] = (uint32_t)(b[i].x2 - b[i].x1);
		words[4 * i + 3] = (uint32_t)(b[i].y2 - b[i].y1);
	}
	*count = (uint32_t)n;
	return words;
}

/*
 * Sends the exposure notice of w to its subscribers: rects[0 … n), n > 0, window coordinates, as
 * libvis lists them (a pixman region's rectangles: the region made of them has the same ones,
 * for the connections that hold it).
 */
static void notify_exposure(struct server *server, struct vis_window *w,
			    const struct vis_rect32 *rects, uint32_t n)
{
	uint32_t *words = malloc((size_t)n * 4 * sizeof *words);
	if (!words) {
		log_error("out of memory for an exposure notice");
		return;
	}
	for (uint32_t i = 0; i < n; i++) {
		words[4 * i] = (uint32_t)rects[i].x;
		words[4 * i + 1] = (uint32_t)rects[i].y;
		words[4 * i + 2] = rects[i].width;
		words[4 * i + 3] = rects[i].height;
	}
	struct server_exposure once = { .rects = rects, .words = words, .n = n };
	struct client *c;
	TAILQ_FOREACH(c, &server->clients, link) {
		const struct sub *s;
		if (!c->closing && (s = server_client_sub_for(c, w, VIS_NOTICE_EXPOSURE)))
			server_notice_exposure(c, s, w, &once);
	}
	server_exposure_finish(&once);
	free(words);
}

/*
 * The recompute and its notices, from what libvis lists (stacking order): a visibility notice
 * for each window whose state changed, but to not viewable (its stack notice said so); an
 * exposure notice for each tracked window with newly visible pixels.
 */
void server_flush(struct server *server)
{
	if (!server->vis->dirty || server->deferring)
		return;
	if (server->untrack_due)
		untrack_unwanted(server);
	const struct vis_change *changes;
	size_t n;
	/* libvis decides how: live from the changes noted, or through the tree. */
	if (vis_tree_update(server->vis, &changes, &n) < 0) {
		log_error("recompute: out of memory; states stay as they were");
		return;
	}
	server->recomputes++;
	for (size_t i = 0; i < n; i++) {
		const struct vis_change *ch = &changes[i];
		struct vis_window *w = ch->win->core;
		if (ch->state != ch->previous && ch->state != VIS_VISIBILITY_NONE)
			notify_visibility(server, w);
		if (ch->n_exposed)
			notify_exposure(server, w, ch->exposed, ch->n_exposed);
	}
}

uint32_t server_seen_id(const struct client *viewer, const struct vis_window *w)
{
	return w && (!viewer || server_may_see(viewer, w)) ? w->id : 0;
}

void server_stack_words(const struct client *viewer, const struct vis_window *w, uint32_t change,
			uint32_t words[SERVER_STACK_WORDS])
{
	if (viewer && viewer->role != VIS_ROLE_CLIENT)
		viewer = NULL; /* sees every window: the shared words */
	words[0] = change;
	words[1] = w->id;
	words[2] = server_seen_id(viewer, w->parent); /* the root's ID is 0 */
	words[3] = (uint32_t)w->x;
	words[4] = (uint32_t)w->y;
	words[5] = (uint32_t)w->width;
	words[6] = (uint32_t)w->height;
	words[7] = server_seen_id(viewer, w->below); /* O(1): no walk past others' windows */
	words[8] = server_window_flags(w, words[2]);
	words[9] = (uint32_t)w->look.border;
	words[10] = w->ext_namespace;
	words[11] = (uint32_t)w->external;
	words[12] = (uint32_t)(w->external >> 32);
}

uint32_t server_window_flags(const struct vis_window *w, uint32_t seen_parent)
{
	return (w->mapped ? VIS_WINDOW_MAPPED : 0) |
	       (vis_wtree_viewable(w) ? VIS_WINDOW_VIEWABLE : 0) |
	       (w->retained ? VIS_WINDOW_RETAINED : 0) |
	       (!seen_parent && w->parent && w->parent->id ? VIS_WINDOW_PARENT_HIDDEN : 0) |
	       (w->look.shaped ? VIS_WINDOW_SHAPED : 0) |
	       (vis_wtree_translucent(w) ? VIS_WINDOW_TRANSLUCENT : 0) |
	       (w->look.input_only ? VIS_WINDOW_INPUT_ONLY : 0);
}

/*
 * The fan-out is a hot path: the words are made once for all observers and managers; a client
 * (only the window's owner may be subscribed to it) gets words of its own, made only when it is.
 */
void server_notify_stack(struct server *server, struct vis_window *w, uint32_t change)
{
	uint32_t shared[SERVER_STACK_WORDS], own[SERVER_STACK_WORDS];
	struct server_notice once = { 0 };
	bool made = false;
	struct client *c;
	TAILQ_FOREACH(c, &server->clients, link) {
		if (c->closing || !server_client_sub_for(c, w, VIS_NOTICE_STACK))
			continue;
		if (c->role == VIS_ROLE_CLIENT) {
			server_stack_words(c, w, change, own);
			server_notice_stack(c, own, NULL);
			continue;
		}
		if (!made)
			server_stack_words(NULL, w, change, shared);
		made = true;
		server_notice_stack(c, shared, &once);
	}
}

/* The tree's callback for each window destroyed: notices, subscriptions, daemon data. */
static void window_gone(void *data, struct vis_window *w)
{
	struct server *server = data;
	server_notify_stack(server, w, VIS_STACK_DESTROY);
	struct client *owner = vis_idmap_get(&server->clients_by_id, w->owner);
	if (owner)
		owner->n_windows--;
	server_quota_look(server, w, -(int64_t)server_look_rects(w),
			  -(int64_t)server_look_charged(w));
	if (w->retained)
		server_quota_release(server, w);
	struct window_data *d = server_data_of(w);
	if (d && d->subs) {
		struct client *c;
		TAILQ_FOREACH(c, &server->clients, link)
			for (size_t i = 0; i < c->n_subs;)
				if (c->subs[i].window == w->id)
					c->subs[i] = c->subs[--c->n_subs];
				else
					i++;
	}
	free_window_data(w);
	libvis_forget(w);
}

void server_destroy_window(struct server *server, struct vis_window *w)
{
	server_damage(server, w);
	vis_wtree_destroy(&server->vis->core, w, window_gone, server);
}

int server_wrap_window(struct server *server, struct vis_window *w)
{
	return libvis_wrap(server->vis, w) ? 0 : -1;
}

void server_discard_window(struct server *server, struct vis_window *w)
{
	vis_wtree_destroy(&server->vis->core, w, forget_window, NULL);
}
