/* The daemon's shared state: listeners, the window tree, recomputes and the notice fan-out. */
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
	server->dirty = true;
	vis_wtree_note(&server->tree, w);
	if (server->damage_all)
		return;
	if (server->n_damage == SERVER_DAMAGE_BOXES) {
		server->damage_all = true;
		return;
	}
	/* Children are clipped by their parent: its box covers the subtree. */
	server->damage[server->n_damage++] = vis_wtree_box(w);
}

/* A box in pixman's 32-bit coordinates: clamped, as the screen lies well inside them. */
static pixman_box32_t clamp_box(struct vis_box b)
{
	const int64_t lo = INT32_MIN, hi = INT32_MAX;
	return (pixman_box32_t){ (int32_t)(b.x1 < lo ? lo : b.x1 > hi ? hi : b.x1),
				 (int32_t)(b.y1 < lo ? lo : b.y1 > hi ? hi : b.y1),
				 (int32_t)(b.x2 < lo ? lo : b.x2 > hi ? hi : b.x2),
				 (int32_t)(b.y2 < lo ? lo : b.y2 > hi ? hi : b.y2) };
}

/*
 * Whether w's visible region may have changed since the last recompute: a pixel that it gained or
 * lost lies in its new clip box and in the box of some change (its own, an ancestor's, or that of
 * a window that covered or uncovered it), or else its state changed. damage: the union of the
 * changes' boxes, or NULL for everywhere.
 */
static bool maybe_exposed(pixman_region32_t *damage, const struct vis_window *w)
{
	if (!damage || w->state != w->old_state)
		return true;
	if (vis_box_empty(w->clip))
		return false;
	pixman_box32_t b = clamp_box(w->clip);
	return pixman_region32_contains_rectangle(damage, &b) != PIXMAN_REGION_OUT;
}

/*
 * The union of the damage boxes, built on first use in a recompute (only exposure tracking needs
 * it); NULL for everywhere: too many changes, or no memory for the region.
 */
struct damage {
	bool built, ok;
	pixman_region32_t region;
};

static pixman_region32_t *damage_region(struct server *server, struct damage *d)
{
	if (!d->built) {
		d->built = true;
		if (!server->damage_all) {
			static pixman_box32_t boxes[SERVER_DAMAGE_BOXES];
			for (size_t i = 0; i < server->n_damage; i++)
				boxes[i] = clamp_box(server->damage[i]);
			d->ok = pixman_region32_init_rects(&d->region, boxes, (int)server->n_damage);
		}
	}
	return d->ok ? &d->region : NULL;
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
	if (server->dirty && !server->deferring)
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
	vis_wtree_init(&server->tree, opt->screen_width, opt->screen_height);
	vis_wtree_set_id_key(&server->tree, opt->id_key);
	if (vis_wtree_live_from(&server->tree, opt->live_from) < 0)
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

/*
 * Starts or stops tracking a window's visible region, keeping server->tracked. false when there
 * is no memory to track it (it stays untracked).
 */
static bool set_tracked(struct server *server, struct vis_window *w, struct window_data *d, bool on)
{
	if (on == d->tracked)
		return true;
	if (on) {
		if (server->n_tracked == server->cap_tracked) {
			size_t cap = server->cap_tracked ? 2 * server->cap_tracked : 64;
			struct vis_window **t = realloc(server->tracked, cap * sizeof *t);
			if (!t)
				return false;
			server->tracked = t;
			server->cap_tracked = cap;
		}
		server->tracked[server->n_tracked++] = w;
		d->tracked_slot = (uint32_t)server->n_tracked;
	} else {
		size_t at = d->tracked_slot - 1;
		server->tracked[at] = server->tracked[--server->n_tracked];
		if (at < server->n_tracked)
			((struct window_data *)server->tracked[at]->data)->tracked_slot = (uint32_t)(at + 1);
		d->tracked_slot = 0;
	}
	d->tracked = on;
	return true;
}

/* Frees a window's daemon data (at shutdown, server is NULL: the tracked list goes too). */
static void free_window_data(struct server *server, struct vis_window *w)
{
	struct window_data *d = w->data;
	if (d) {
		if (server)
			set_tracked(server, w, d, false);
		pixman_region32_fini(&d->region);
		free(d);
		w->data = NULL;
	}
}

/* The tree's callback at shutdown. */
static void forget_window_data(void *data, struct vis_window *w)
{
	(void)data;
	free_window_data(NULL, w);
}

void server_finish(struct server *server)
{
	struct client *c;
	server->deferring = true; /* no recomputes or notices while everything goes */
	while ((c = TAILQ_FIRST(&server->clients)))
		server_client_free(c);
	while (server->tree.root.top)
		vis_wtree_destroy(&server->tree, server->tree.root.top, forget_window_data, NULL);
	if (server->listener)
		evconnlistener_free(server->listener);
	if (server->restricted_listener)
		evconnlistener_free(server->restricted_listener);
	if (server->listener_retry)
		event_free(server->listener_retry);
	if (server->turn_event)
		event_free(server->turn_event);
	vis_wtree_finish(&server->tree);
	free(server->tracked);
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
	if (!w->data) {
		struct window_data *d = calloc(1, sizeof *d);
		if (!d)
			return NULL;
		pixman_region32_init(&d->region);
		w->data = d;
	}
	return w->data;
}

/* Whether some subscription asks for w's exposures. */
static bool wants_exposure(const struct server *server, const struct vis_window *w)
{
	const struct window_data *d = w->data;
	if (server->role_all_exposure || (d && d->exposure_subs))
		return true;
	/* The owner's subscription to all of its own windows. */
	const struct client *owner = vis_idmap_get(&server->clients_by_id, w->owner);
	return owner && owner->all_exposure;
}

void server_track(struct vis_window *w, struct server *server)
{
	struct window_data *d = server_window_data(w);
	if (!d || d->tracked)
		return;
	if (!set_tracked(server, w, d, true)) {
		log_error("out of memory for exposure tracking");
		return;
	}
	if (vis_wtree_visible_region(&server->tree, w, &d->region) < 0)
		pixman_region32_clear(&d->region);
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

/* Sends the exposure notice of w (rectangles in window coordinates) to its subscribers. */
static void notify_exposure(struct server *server, struct vis_window *w, pixman_region32_t *exposed)
{
	uint32_t n;
	uint32_t *words = server_region_words(exposed, &n);
	if (!words) {
		log_error("out of memory for an exposure notice");
		return;
	}
	struct server_exposure once = { .exposed = exposed, .words = words, .n = n };
	struct client *c;
	TAILQ_FOREACH(c, &server->clients, link) {
		const struct sub *s;
		if (!c->closing && (s = server_client_sub_for(c, w, VIS_NOTICE_EXPOSURE)))
			server_notice_exposure(c, s, w, &once);
	}
	server_exposure_finish(&once);
	free(words);
}

/* Orders windows by stacking (keys grow with it; 0 for those not viewable), then address. */
static int by_stacking(const void *a, const void *b)
{
	const struct vis_window *x = *(struct vis_window *const *)a, *y = *(struct vis_window *const *)b;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return x < y ? -1 : x > y;
}

/*
 * The notices of one window after a recompute: its visibility if its state changed, its exposure
 * if it is tracked and its visible region may have grown.
 */
static void flush_window(struct server *server, struct vis_window *w, struct damage *damage,
			 pixman_region32_t *now, pixman_region32_t *exposed)
{
	if (w->state != w->old_state && w->state != VIS_WTREE_STATE_NONE)
		notify_visibility(server, w);
	struct window_data *d = w->data;
	if (!wants_exposure(server, w)) {
		if (d && d->tracked) {
			set_tracked(server, w, d, false);
			pixman_region32_clear(&d->region);
		}
		return;
	}
	if (d && d->tracked && !maybe_exposed(damage_region(server, damage), w))
		return;
	/* A window first tracked now was created since the last recompute: it showed nothing. */
	if (!(d = server_window_data(w)) || !set_tracked(server, w, d, true)) {
		log_error("out of memory for exposure tracking");
		return;
	}
	if (vis_wtree_visible_region(&server->tree, w, now) < 0) {
		log_error("out of memory for a visible region");
		return;
	}
	pixman_region32_subtract(exposed, now, &d->region);
	pixman_region32_copy(&d->region, now);
	if (pixman_region32_not_empty(exposed))
		notify_exposure(server, w, exposed);
}

void server_flush(struct server *server)
{
	if (!server->dirty || server->deferring)
		return;
	/* The tree decides how: live from the changes noted, or through the tree. */
	if (vis_wtree_update(&server->tree) < 0) {
		log_error("recompute: out of memory; states stay as they were");
		return;
	}
	server->dirty = false;
	server->recomputes++;
	pixman_region32_t now, exposed;
	pixman_region32_init(&now);
	pixman_region32_init(&exposed);
	struct damage damage = { 0 };
	struct vis_window *const *changed;
	size_t n;
	/*
	 * A live recompute lists the windows it may have changed; a window it did not keeps its
	 * state and visible region, so that a tracked one has no new exposure. Else every window.
	 */
	struct vis_window **list = NULL;
	if (vis_wtree_changes(&server->tree, &changed, &n) &&
	    (list = malloc((n + server->n_tracked + 1) * sizeof *list))) {
		/*
		 * The windows the recompute may have changed, and the tracked ones: a tracked
		 * window's region also counts its descendants as hiding it (X's clip list), so it
		 * may change with no change of state; maybe_exposed() tells. In stacking order, as
		 * notices go out, each once.
		 */
		size_t m = 0;
		for (size_t i = 0; i < n; i++)
			list[m++] = changed[i];
		for (size_t i = 0; i < server->n_tracked; i++)
			list[m++] = server->tracked[i];
		qsort(list, m, sizeof *list, by_stacking);
		for (size_t i = 0; i < m; i++)
			if (i == 0 || list[i] != list[i - 1])
				flush_window(server, list[i], &damage, &now, &exposed);
		free(list);
	} else {
		for (struct vis_window *w = server->tree.root.bottom; w; w = vis_wtree_next(w))
			flush_window(server, w, &damage, &now, &exposed);
	}
	pixman_region32_fini(&now);
	pixman_region32_fini(&exposed);
	if (damage.ok)
		pixman_region32_fini(&damage.region);
	server->n_damage = 0;
	server->damage_all = false;
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
	server_quota_look(server, w, -(int64_t)((uint64_t)w->look.n_shape + w->look.n_opaque),
			  -(int64_t)server_look_charged(w));
	if (w->retained)
		server_quota_release(server, w);
	struct window_data *d = w->data;
	if (d && d->subs) {
		struct client *c;
		TAILQ_FOREACH(c, &server->clients, link)
			for (size_t i = 0; i < c->n_subs;)
				if (c->subs[i].window == w->id)
					c->subs[i] = c->subs[--c->n_subs];
				else
					i++;
	}
	free_window_data(server, w);
}

void server_destroy_window(struct server *server, struct vis_window *w)
{
	server_damage(server, w);
	vis_wtree_destroy(&server->tree, w, window_gone, server);
}
