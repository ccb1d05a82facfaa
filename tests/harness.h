/*
 * A test harness for suites that face a real visd with raw bytes: it starts the daemon on a
 * private socket (a mkdtemp directory) with its stderr in a file, connects without libvisclient,
 * sends bytes, reads and decodes the daemon's messages, waiting as long as the daemon works
 * (progress.h) or within a timeout, and stops the daemon, checking that it exits with status 0
 * and that no sanitizer wrote a report.
 *
 * Failures print where, the current context and the seed (when one is set), kill the daemons
 * started, and exit with status 1.
 */
#ifndef VIS_TESTS_HARNESS_H
#define VIS_TESTS_HARNESS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

#include "codec.h"
#include "progress.h"

/* A visd started by the harness. */
struct harness_daemon {
	pid_t pid;
	char dir[64];	/* mkdtemp, mode 0700 */
	char sock[96];	/* dir/sock */
	char rsock[96]; /* dir/restricted, the --restricted-socket */
	char log[96];	/* dir/stderr: what the daemon wrote to stderr */
	int nofile;	/* set before harness_start: the daemon's descriptor limit (0: ours) */
};

/*
 * A raw connection. seq is the number of the last request sent (the daemon numbers every request
 * it receives, malformed ones included, from 1); in holds received bytes not yet returned.
 */
struct harness_conn {
	int fd;
	uint32_t seq;
	uint32_t id;	      /* from hello-reply */
	uint32_t max_request; /* from hello-reply */
	struct vis_buf in;
	size_t taken; /* bytes at the start of in that the last message returned occupies */
	/* Called with each notice harness_next_reply() skips; NULL: they are only counted. */
	void (*on_notice)(void *data, const struct vis_msg *m);
	void *notice_data;
};

void harness_fail(const char *file, int line, const char *fmt, ...)
	__attribute__((format(printf, 3, 4), noreturn));
#define CHECK(cond, ...)                                                                           \
	do {                                                                                       \
		if (!(cond))                                                                       \
			harness_fail(__FILE__, __LINE__, __VA_ARGS__);                             \
	} while (0)

/* What failures name: the case running now, and the seed of a seeded run (0: none). */
void harness_context(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void harness_seed(uint64_t seed);

/*
 * Starts visd at path with --socket, --restricted-socket and the extra options (NULL-terminated,
 * may be NULL), and waits for both sockets to exist.
 */
void harness_start(struct harness_daemon *d, const char *visd, const char *const *extra);
/* SIGTERM, then checks the exit status (0), the log (no sanitizer report) and the clean-up. */
void harness_stop(struct harness_daemon *d);
/* Fails unless the daemon is still running and its log holds no sanitizer report. */
void harness_check_alive(struct harness_daemon *d);
/* The descriptors the daemon holds now (-1 if /proc cannot tell). */
int harness_count_fds(const struct harness_daemon *d);
/* Waits until the daemon holds exactly want descriptors (while it works: progress.h). */
void harness_wait_fds(const struct harness_daemon *d, int want);
/*
 * A wait for something the daemon d (NULL: every daemon started) is working towards, as a loop:
 *   for (struct progress p = harness_working(d); !done(); harness_still_working(&p, "what"));
 * harness_still_working() fails, naming what, when a daemon of the wait died or none has used CPU
 * time for PROGRESS_STALL_MS (or the ceiling passed); else it naps 10 ms.
 */
struct progress harness_working(const struct harness_daemon *d);
void harness_still_working(struct progress *p, const char *what);

/* A connected Unix socket, or -1 with errno set. */
int harness_connect(const char *path);
void harness_open(struct harness_conn *c, const char *path);
/* Opens a connection and, unless role is -1, makes the handshake for role. */
void harness_open_as(struct harness_conn *c, const char *path, int role);
void harness_close(struct harness_conn *c);
/* Writes all of p; 0, or -1 with errno set (the daemon may have closed the connection). */
int harness_send(struct harness_conn *c, const void *p, size_t n);

/*
 * Encodes a request of words (host order, as many as its signature has fields) into out, a
 * buffer of at least VIS_MSG_HEADER + 4 * n bytes; returns its size.
 */
size_t harness_build(uint8_t *out, uint32_t opcode, const uint32_t *words, size_t n);
/* harness_build() with the words as arguments. */
#define harness_put(out, op, ...)                                                                  \
	harness_build(out, op, (const uint32_t[]){ __VA_ARGS__ },                                  \
		      sizeof((const uint32_t[]){ __VA_ARGS__ }) / sizeof(uint32_t))
/* Sends a request of n words and returns its sequence number. */
uint32_t harness_request(struct harness_conn *c, uint32_t opcode, const uint32_t *words, size_t n);
#define harness_req(c, op, ...)                                                                    \
	harness_request(c, op, (const uint32_t[]){ __VA_ARGS__ },                                  \
			sizeof((const uint32_t[]){ __VA_ARGS__ }) / sizeof(uint32_t))
/* Sends raw bytes that the daemon counts as one request; returns its sequence number. */
uint32_t harness_request_raw(struct harness_conn *c, const void *p, size_t n);

/*
 * The next message from the daemon: 1 (in *m, valid until the next call), 0 at the end of the
 * connection, -1 when nothing came within timeout_ms. A message that does not decode fails.
 * timeout_ms HARNESS_WORKING waits as long as the daemons started make progress (progress.h):
 * it fails, never returns -1, when one dies or they stop working.
 */
#define HARNESS_WORKING (-1)
int harness_recv(struct harness_conn *c, int timeout_ms, struct vis_msg *m);
/* The next reply or error, skipping notices (counted in *notices when not NULL, and given to
 * on_notice). */
void harness_next_reply(struct harness_conn *c, struct vis_msg *m, size_t *notices);
/* Sends hello for role and expects hello-reply granting it; sets c->id and c->max_request. */
void harness_hello(struct harness_conn *c, uint32_t role);
/* Expects the reply to request seq to be of opcode (notices skipped); fails on an error. */
void harness_expect(struct harness_conn *c, uint32_t seq, uint32_t opcode, struct vis_msg *m);
/*
 * Expects an error for request seq of that opcode with code, its message holding reason (when
 * not NULL). With fatal, the error must be the connection's last message before the end.
 */
void harness_expect_error(struct harness_conn *c, uint32_t seq, uint32_t opcode, uint32_t code,
			  const char *reason, bool fatal);
/*
 * Sends bytes as one request on a new connection to path (after the handshake for role unless
 * role is -1) and expects the error that ends it.
 */
void harness_expect_fatal(const char *path, const void *bytes, size_t n, int role, uint32_t opcode,
			  uint32_t code, const char *reason);
/* How many errors harness_expect_error() has checked. */
int harness_errors_checked(void);
/* A round trip: sync, and the notices that came before synced (when not NULL). */
void harness_sync(struct harness_conn *c, size_t *notices);
/* Sends n copies of one request of size bytes, as fast as the socket takes them. */
void harness_send_copies(struct harness_conn *c, const void *req, size_t size, uint32_t n);
/* Creates n unmapped 5 × 5 top-level windows at x, y, pipelined, and reads their replies. */
void harness_create_many(struct harness_conn *c, uint32_t n, int32_t x, int32_t y);
/* Milliseconds on the monotonic clock. */
double harness_clock_ms(void);
/*
 * Sends set-shape or set-opaque (op) for window with mode (shaped, or the opaque mode) and n
 * rectangles, rects[4k … 4k + 4) their x, y, width and height; returns its sequence number.
 */
uint32_t harness_look(struct harness_conn *c, uint32_t op, uint32_t window, uint32_t mode,
		      const uint32_t *rects, uint32_t n);
/* Creates a window; returns its ID. */
uint32_t harness_create(struct harness_conn *c, uint32_t parent, int32_t x, int32_t y, uint32_t w,
			uint32_t h, uint32_t flags);

/* One field of a message's signature (messages.h). */
struct harness_field {
	char type; /* u, i, q, s, or an array's record letter */
	char name[16];
};
/* The fields of a message type, at most VIS_MSG_MAX_ARGS; returns how many. */
size_t harness_fields(const struct vis_msg_type *t, struct harness_field *f);

/* A tree reply's node: the fields of the T record. */
struct harness_node {
	uint32_t window, parent;
	int32_t x, y;
	uint32_t width, height, border, flags, state;
};
/* Every window the connection may see, in stacking order (malloc'd; *n nodes). */
struct harness_node *harness_get_tree(struct harness_conn *c, size_t *n);
/* A states reply's record. */
struct harness_state {
	uint32_t window, state;
};
/* Every viewable window the connection may see, ascending ID (malloc'd; *n records). */
struct harness_state *harness_get_states(struct harness_conn *c, size_t *n);

#endif
