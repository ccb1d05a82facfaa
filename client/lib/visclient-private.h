/*
 * libvisclient's insides, shared by the connection (visclient.c) and the typed requests
 * (visclient-requests.c). Nothing here is exported: the library is built with hidden visibility
 * and only VIS_EXPORT names leave it.
 */
#ifndef VIS_VISCLIENT_PRIVATE_H
#define VIS_VISCLIENT_PRIVATE_H

#include <stddef.h>
#include <stdint.h>

#include "codec.h"
#include "vis/visclient.h"

/* What a request expects back; every kind but none waits in the connection's pending queue. */
enum vis_reply_kind {
	VIS_REPLY_NONE,
	VIS_REPLY_HELLO,
	VIS_REPLY_CREATED,
	VIS_REPLY_STATE,
	VIS_REPLY_STATES,
	VIS_REPLY_TREE,
	VIS_REPLY_REGION,
	VIS_REPLY_REPAINT,
	VIS_REPLY_SYNCED,
	VIS_REPLY_LOOK,
	VIS_REPLY_FOUND, /* lookup's: a window, to the create callback's type */
};

/*
 * A request waiting for its reply. Chunked replies (more = 1) gather their records in items
 * until the last chunk, so callbacks always see the whole answer at once.
 */
struct vis_pending {
	uint32_t seq;
	uint32_t opcode; /* the request's */
	enum vis_reply_kind kind;
	uint32_t window; /* get-state and get-region: the window asked about, for checking */
	union {
		vis_create_cb create; /* and found */
		vis_state_cb state;
		vis_states_cb states;
		vis_tree_cb tree;
		vis_rects_cb rects;
		vis_windows_cb windows;
		vis_done_cb done;
		vis_look_cb look;
	} cb;
	void *data;
	void *items; /* malloc'ed records of the chunks so far */
	size_t n, cap;
};

/*
 * Invariants: requests sent number 1 … next_seq - 1; every request still owed a reply is in
 * pending[head, len), in request order; answered is the number of the last request answered (by a
 * reply or an error), and answers only go forward. Bytes in[in_off, in.len) are received but not
 * yet handled.
 */
struct vis_client {
	int fd;
	int error; /* sticky: an errno value, 0 while the connection is good */
	char error_message[320];

	struct vis_error last_error;
	int has_last_error;
	unsigned long error_count, sync_mark;

	int connected; /* the handshake succeeded */
	uint32_t role, id, screen_width, screen_height, max_request;
	uint32_t next_seq, answered;
	int in_batch; /* batch-begin sent, batch-commit not yet: the daemon holds requests */
	uint64_t next_serial;

	struct vis_buf out, in;
	size_t in_off;

	struct vis_pending *pending;
	size_t head, len, cap;

	vis_notice_handler notice;
	void *notice_data;
	vis_error_handler on_error;
	void *error_data;
};

/* Makes the connection's error sticky (an errno value and why); the first error wins. */
void vis_client_fail(struct vis_client *c, int err, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/*
 * Handles every complete message received (visclient-dispatch.c). Returns how many. The offset
 * moves past a message before it is handled, so a callback that dispatches (a synchronous call
 * inside a handler) carries on from the next one.
 */
int vis_client_process(struct vis_client *c);

/*
 * Encodes a request with args, gives it the next request number, and queues it (flushing when
 * the queue is long). When pending is not NULL the request expects a reply: the entry is copied
 * into the pending queue with its seq filled in. Returns the request number, or 0 (a connection
 * error, or errno EMSGSIZE for a request over the daemon's maximum).
 */
uint32_t vis_client_send(struct vis_client *c, uint32_t opcode, const union vis_arg *args,
			 const struct vis_pending *pending);

/* Blocks until *done is set by a callback or the connection fails. Returns 0 or -1. */
int vis_client_wait(struct vis_client *c, const int *done);

/*
 * Whether a synchronous call must be refused: inside a batch the daemon holds every request until
 * batch-commit, so waiting for a reply would wait forever. Sets errno to EDEADLK then.
 */
int vis_client_refuse_in_batch(const struct vis_client *c);

/*
 * Makes a connection around fd, a connected stream socket, that has sent nothing yet: the caller
 * sends hello (vis_client_hello) and reads the reply like any other. The connection owns fd from
 * then on. For the tests and the fuzzer, which play the daemon's side over a socketpair: what is
 * read from fd goes through the same read and dispatch path as on a connection to visd. NULL when
 * memory runs out.
 */
struct vis_client *vis_client_adopt(int fd);

/*
 * Queues the handshake asking for role; the reply makes the connection usable (or fails it).
 * Returns the request number (1), or 0 on a connection error.
 */
uint32_t vis_client_hello(struct vis_client *c, uint32_t role);

/* How many protocol errors the connection has received, to tell whether a sync saw new ones. */
unsigned long vis_client_error_count(const struct vis_client *c);

#endif
