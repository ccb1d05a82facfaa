/* The daemon's state: the window tree, the connections, and what ties them together. */
#ifndef VISD_SERVER_H
#define VISD_SERVER_H

#include <event2/event.h>
#include <event2/listener.h>
#include <pixman.h>
#include <stdbool.h>
#include <sys/queue.h>
#include <sys/types.h>

#include "codec.h"
#include "wtree.h"

struct server_options {
	const char *socket_path;
	const char *restricted_path; /* NULL: none */
	int32_t screen_width, screen_height;
	uint32_t max_request;   /* bytes, header included */
	uint32_t max_batch;     /* bytes held by one open batch */
	uid_t allowed_uid;      /* peers with this uid may take roles */
};

/* A subscription: window 0 means every window the connection may see. */
struct sub {
	uint32_t window;
	uint32_t mask;       /* enum vis_notice_mask */
	uint32_t rect_limit; /* exposure rectangles before collapsing to the bounding box */
};

/*
 * One connection. Invariants: requests are numbered from 1 in arrival order (seq is the last one
 * received); serial is the last notice's number; while in_batch, requests wait in batch, each
 * prefixed with its number, until batch-commit; once closing, nothing more is read and the
 * connection ends when its output has drained.
 */
struct client {
	struct server *server;
	struct bufferevent *bev;
	TAILQ_ENTRY(client) link;
	uint32_t id;
	uid_t uid;
	bool restricted, hello_done, in_batch, closing;
	uint32_t role;
	uint32_t seq;
	uint64_t serial;
	struct evbuffer *batch;
	struct sub *subs;
	size_t n_subs, cap_subs;
	bool all_exposure; /* holds a subscription to every window with exposures */
};

TAILQ_HEAD(client_list, client);

/* What the daemon keeps for a window (vis_window.data). */
struct window_data {
	uint32_t exposure_subs; /* subscriptions naming this window with exposures */
	uint32_t subs;          /* subscriptions naming this window */
	bool tracked;           /* region holds the visible region last reported */
	pixman_region32_t region;
};

struct server {
	struct event_base *base;
	struct server_options opt;
	struct evconnlistener *listener, *restricted_listener;
	struct event *listener_retry;
	struct vis_wtree tree;
	struct client_list clients;
	struct vis_idmap clients_by_id; /* window owners' connections, by ID */
	uint32_t next_client;
	struct client *manager;
	uint32_t role_all_exposure; /* observers and managers with exposures of every window */
	bool dirty;     /* the tree changed since the last recompute */
	bool deferring; /* replaying a batch: recompute once at its end */
	struct vis_buf scratch;
};

/* Sets up the server and its listening sockets. 0, or -1 after logging why. */
int server_init(struct server *server, struct event_base *base, const struct server_options *opt);
/* Closes every connection and listener and frees everything. */
void server_finish(struct server *server);

/* Whether a connection may see / change a window. */
bool server_may_see(const struct client *c, const struct vis_window *w);
bool server_may_change(const struct client *c, const struct vis_window *w);

/* Recomputes the states if the tree changed, and sends the notices that follow. */
void server_flush(struct server *server);

/* Sends a stack notice about w to the connections subscribed to it. */
void server_notify_stack(struct server *server, struct vis_window *w, uint32_t change);

/* The window's daemon data, allocated on first use; NULL when memory runs out. */
struct window_data *server_window_data(struct vis_window *w);

/* A region's rectangles as x, y, w, h words (malloc'd; *count rectangles), or NULL. */
uint32_t *server_region_words(pixman_region32_t *region, uint32_t *count);

/* Starts exposure tracking of w from its current region (the tree must be computed). */
void server_track(struct vis_window *w, struct server *server);

/* Destroys w and its subtree, with notices. */
void server_destroy_window(struct server *server, struct vis_window *w);

/* Connections: accepting, dispatch and replies (server-client.c). */
void server_client_accept(struct server *server, int fd, bool restricted);
void server_client_free(struct client *c);
/* Encodes and queues one message to c; on failure the connection is closed. */
void server_client_send(struct client *c, uint32_t opcode, const union vis_arg *args);
/* Ends the connection once what is queued has been written. */
void server_client_close(struct client *c);
/* Sends an error reply; fatal ones close the connection once the error is written. */
void server_client_error(struct client *c, uint32_t seq, uint32_t opcode, uint32_t code,
			 const char *fmt, ...) __attribute__((format(printf, 5, 6)));
/* The subscription of c that covers w with some of mask, or NULL. */
const struct sub *server_client_sub_for(const struct client *c, const struct vis_window *w,
					uint32_t mask);
/* Runs subscribe or unsubscribe (server-subscribe.c). */
void server_subscription(struct client *c, uint32_t seq, uint32_t op, const union vis_arg *a);
/* Ends every subscription of c. */
void server_unsubscribe_all(struct client *c);
/* Runs one decoded request. */
void server_client_dispatch(struct client *c, uint32_t seq, const struct vis_msg *m);

#endif
