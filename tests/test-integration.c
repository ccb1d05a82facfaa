/*
 * Integration tests: a real visd on a private socket, driven through libvisclient. Every request
 * and notice, errors and refusals, batches, child clipping, roles, disconnect cleanup, retained
 * windows, many clients, and the key property: after random changes, the daemon's states equal
 * the core's on the same scene, and the notices seen by an observer add up to those states.
 * Usage: test-integration VISD [SEED]
 */
#include <dirent.h>
#include <stdbool.h>
#include <errno.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include "engine.h"
#include "look.h"
#include "progress.h"
#include "rng.h"
#include "vis/visclient.h"

#define SCREEN_W 200
#define SCREEN_H 100

static char dir[64], sock[128], rsock[128];
static pid_t daemon_pid;
static const char *current = "start";

static void fail(int line, const char *fmt, ...) __attribute__((format(printf, 2, 3), noreturn));
static void fail(int line, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	fprintf(stderr, "test-integration.c:%d: %s: ", line, current);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
	if (daemon_pid > 0)
		kill(daemon_pid, SIGKILL);
	exit(1);
}
#define CHECK(cond, ...)                          \
	do {                                      \
		if (!(cond))                      \
			fail(__LINE__, __VA_ARGS__); \
	} while (0)

/* Naps 10 ms in a wait for the daemon's work; fails with what when it died or stopped working. */
static void still_working(struct progress *p, int line, const char *what)
{
	if (progress_stopped(p))
		fail(line, "%s: %s", what, p->why);
	usleep(10000);
}

/* A wait on the daemon's work (progress.h). */
static struct progress daemon_working(void)
{
	struct progress p;
	progress_begin(&p, &daemon_pid, 1);
	return p;
}

/* Recorded notices, with exposure rectangles copied. */
struct rec {
	struct vis_notice n;
	struct vis_rect32 rects[32];
};
struct log {
	struct rec *v;
	size_t n, cap;
};

static void on_notice(void *data, const struct vis_notice *n)
{
	struct log *l = data;
	if (l->n == l->cap) {
		l->cap = l->cap ? 2 * l->cap : 64;
		l->v = realloc(l->v, l->cap * sizeof *l->v);
	}
	struct rec *r = &l->v[l->n++];
	r->n = *n;
	if (n->kind == VIS_NOTICE_KIND_EXPOSURE) {
		size_t k = n->exposure.n_rects < 32 ? n->exposure.n_rects : 32;
		memcpy(r->rects, n->exposure.rects, k * sizeof *r->rects);
		r->n.exposure.rects = r->rects;
	}
}

static struct vis_client *connect_to(const char *path, uint32_t role, struct log *log)
{
	struct vis_client *c = vis_client_connect(path, role);
	CHECK(c && !vis_client_error(c), "connect as role %u: %s", role,
	      c ? vis_client_error_message(c) : "out of memory");
	if (log)
		vis_client_set_notice_handler(c, on_notice, log);
	return c;
}

static int count_fds(pid_t pid)
{
	char path[64];
	snprintf(path, sizeof path, "/proc/%d/fd", (int)pid);
	DIR *d = opendir(path);
	if (!d)
		return -1;
	int n = 0;
	while (readdir(d))
		n++;
	closedir(d);
	return n;
}

static void start_daemon(const char *visd)
{
	snprintf(dir, sizeof dir, "/tmp/visd-test-XXXXXX");
	CHECK(mkdtemp(dir), "mkdtemp: %s", strerror(errno));
	snprintf(sock, sizeof sock, "%s/sock", dir);
	snprintf(rsock, sizeof rsock, "%s/restricted", dir);
	daemon_pid = fork();
	CHECK(daemon_pid >= 0, "fork");
	if (daemon_pid == 0) {
		execl(visd, visd, "--socket", sock, "--restricted-socket", rsock, "--screen", "200x100",
		      (char *)NULL);
		perror(visd);
		_exit(127);
	}
	for (struct progress p = daemon_working();
	     access(sock, F_OK) < 0 || access(rsock, F_OK) < 0;)
		still_working(&p, __LINE__, "visd did not create its sockets");
}

static void stop_daemon(void)
{
	kill(daemon_pid, SIGTERM);
	int status;
	waitpid(daemon_pid, &status, 0);
	CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0, "visd exited with status %#x", status);
	CHECK(access(sock, F_OK) < 0 && access(rsock, F_OK) < 0, "visd left its sockets behind");
	char lock[160];
	snprintf(lock, sizeof lock, "%s.lock", sock);
	CHECK(access(lock, F_OK) < 0, "visd left its lock behind");
	rmdir(dir);
}

static uint32_t create(struct vis_client *c, uint32_t parent, int32_t x, int32_t y, uint32_t w,
		       uint32_t h, uint32_t flags)
{
	uint32_t id = 0;
	CHECK(vis_client_create(c, parent, x, y, w, h, flags, &id) == 0, "create failed");
	return id;
}

static uint32_t state_of(struct vis_client *c, uint32_t w)
{
	uint32_t s = 99;
	CHECK(vis_client_get_state(c, w, &s) == 0, "get-state %u failed", w);
	return s;
}

static void on_state(void *data, const struct vis_error *err, uint32_t window, uint32_t state)
{
	(void)window;
	if (!err)
		*(uint32_t *)data = state;
}

static void on_created(void *data, const struct vis_error *err, uint32_t window)
{
	if (!err)
		*(uint32_t *)data = window;
}

/* Expects the last protocol error to be code for request seq. */
static void expect_error(struct vis_client *c, uint32_t seq, uint32_t code, int line)
{
	vis_client_roundtrip(c);
	struct vis_error e;
	if (!vis_client_last_error(c, &e) || e.seq != seq || e.code != code)
		fail(line, "request %u: wanted error %s, got %s (seq %u: %s)", seq,
		     vis_error_code_name(code), vis_client_last_error(c, &e) ? vis_error_code_name(e.code) : "none",
		     e.seq, e.message);
}

/*
 * Bad looks: every way a border, shape or opaque region can be wrong gets its error, and nothing
 * changes; overlapping and repeated rectangles are a union, not an error.
 */
static void test_look_errors(struct vis_client *a, uint32_t p, uint32_t q)
{
	struct vis_window_info *before, *after;
	size_t nb, na;
	CHECK(vis_client_get_tree(a, &before, &nb) == 0, "tree");
	uint32_t io;
	CHECK(vis_client_create_window(a, 0, 0, 0, 5, 5, 0, VIS_CREATE_INPUT_ONLY, &io) == 0,
	      "an input-only window");
	const struct vis_rect32 ok[3] = { { 0, 0, 5, 5 }, { 0, 0, 5, 5 }, { 2, 2, 10, 10 } };
	const struct vis_rect32 zero[2] = { { 0, 0, 5, 5 }, { 0, 0, 0, 5 } };
	const struct vis_rect32 huge[1] = { { 0, 0, 0x80000000u, 5 } };
	/* Borders: past the 32-bit range (with the size), on an input-only window. */
	expect_error(a, vis_client_create_window_async(a, 0, 0, 0, 5, 5, 0x40000000u, 0, NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_create_window_async(a, 0, 0, 0, 0x7ffffff0u, 5, 8, 0, NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_create_window_async(a, 0, 0, 0, 5, 5, 1, VIS_CREATE_INPUT_ONLY,
						       NULL, NULL),
		     VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_configure(a, p, 0, 0, 0x7ffffff0u, 5, 8), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_configure(a, p, 0, 0, 0, 5, 0), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_configure(a, io, 0, 0, 5, 5, 1), VIS_ERROR_MATCH, __LINE__);
	/* Shapes and opaque regions: zero or too large sizes, unknown modes, rectangles a mode
	 * does not take, input-only windows. */
	expect_error(a, vis_client_set_shape(a, q, 1, zero, 2), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_set_shape(a, q, 1, huge, 1), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_set_shape(a, q, 2, ok, 1), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_set_shape(a, q, 0, ok, 1), VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_set_shape(a, io, 1, ok, 1), VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_set_opaque(a, q, 3, NULL, 0), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_set_opaque(a, q, VIS_OPAQUE_MODE_NONE, ok, 1), VIS_ERROR_MATCH,
		     __LINE__);
	expect_error(a, vis_client_set_opaque(a, q, VIS_OPAQUE_MODE_RECTS, zero, 2), VIS_ERROR_VALUE,
		     __LINE__);
	expect_error(a, vis_client_set_opaque(a, io, VIS_OPAQUE_MODE_NONE, NULL, 0), VIS_ERROR_MATCH,
		     __LINE__);
	/* A list longer than the daemon's largest request (65,536 bytes by default): refused by
	 * the library before anything is sent. */
	uint32_t n_big = 65536 / 16 + 1;
	struct vis_rect32 *big = calloc(n_big, sizeof *big);
	CHECK(big, "out of memory");
	for (uint32_t i = 0; i < n_big; i++)
		big[i] = (struct vis_rect32){ (int32_t)i, 0, 1, 1 };
	errno = 0;
	CHECK(vis_client_set_shape(a, q, 1, big, n_big) == 0 && errno == EMSGSIZE &&
		      vis_client_error(a) == 0,
	      "a shape larger than a request was not refused with EMSGSIZE");
	free(big);
	vis_client_destroy_window(a, io);
	CHECK(vis_client_sync(a) == 0 || vis_client_error(a) == 0, "sync after the errors");
	CHECK(vis_client_get_tree(a, &after, &na) == 0 && na == nb &&
		      memcmp(before, after, nb * sizeof *before) == 0,
	      "the refused looks changed the tree");
	free(before);
	free(after);
	/* Overlapping and repeated rectangles are a union: accepted, and the tree says shaped. */
	vis_client_set_shape(a, q, 1, ok, 3);
	CHECK(vis_client_sync(a) == 0, "an overlapping shape was refused");
	CHECK(vis_client_get_tree(a, &after, &na) == 0, "tree");
	for (size_t i = 0; i < na; i++)
		if (after[i].window == q)
			CHECK(after[i].flags & VIS_WINDOW_SHAPED, "window %u is not shaped", q);
	free(after);
	/* get-look gives back what was set, rectangles and all. */
	const struct vis_rect32 shadow = { 2, 2, 6, 6 };
	vis_client_set_opaque(a, q, VIS_OPAQUE_MODE_RECTS, &shadow, 1);
	struct vis_look_info look;
	CHECK(vis_client_get_look(a, q, &look) == 0, "get-look");
	CHECK(look.window == q && look.shaped == 1 && look.n_shape == 3 &&
		      memcmp(look.shape, ok, sizeof ok) == 0 && look.mode == VIS_OPAQUE_MODE_RECTS &&
		      look.n_opaque == 1 && memcmp(look.opaque, &shadow, sizeof shadow) == 0,
	      "get-look: not what was set");
	free(look.shape);
	free(look.opaque);
	vis_client_set_shape(a, q, 0, NULL, 0);
	vis_client_set_opaque(a, q, VIS_OPAQUE_MODE_ALL, NULL, 0);
	CHECK(vis_client_get_look(a, q, &look) == 0 && look.shaped == 0 && look.n_shape == 0 &&
		      look.mode == VIS_OPAQUE_MODE_ALL && !look.shape && !look.opaque,
	      "get-look after unshaping");
	expect_error(a, vis_client_get_look_async(a, 999999, NULL, NULL), VIS_ERROR_WINDOW, __LINE__);
	CHECK(vis_client_get_look(a, 999999, &look) < 0 && vis_client_error(a) == 0 && !look.shape &&
		      !look.opaque,
	      "a synchronous get-look of no window");
	CHECK(vis_client_sync(a) == 0 || vis_client_error(a) == 0, "unshaping failed");
}

/* The last visibility notice for w in a log, or NULL. */
static const struct vis_notice *last_visibility(const struct log *l, uint32_t w)
{
	for (size_t i = l->n; i-- > 0;)
		if (l->v[i].n.kind == VIS_NOTICE_KIND_VISIBILITY && l->v[i].n.window == w)
			return &l->v[i].n;
	return NULL;
}

static void check_serials(const struct log *l)
{
	for (size_t i = 0; i < l->n; i++)
		CHECK(l->v[i].n.serial == i + 1, "notice %zu has serial %llu", i + 1,
		      (unsigned long long)l->v[i].n.serial);
}

/* Requests and notices on one connection: states, regions, occlusion, exposure, stack notices. */
static void test_requests(void)
{
	current = "requests";
	struct log log = { 0 };
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, &log);
	vis_client_subscribe(a, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	uint32_t w1 = create(a, 0, 0, 0, 100, 50, VIS_CREATE_MAP);
	const struct vis_notice *n = last_visibility(&log, w1);
	CHECK(n && n->visibility.state == VIS_VISIBILITY_UNOBSCURED &&
		      n->visibility.previous == VIS_VISIBILITY_NONE,
	      "no first visibility notice after mapping");
	CHECK(log.n == 4 && log.v[0].n.kind == VIS_NOTICE_KIND_STACK &&
		      log.v[0].n.stack.change == VIS_STACK_CREATE &&
		      log.v[1].n.stack.change == VIS_STACK_MAP &&
		      log.v[3].n.kind == VIS_NOTICE_KIND_EXPOSURE,
	      "create+map: wanted create, map, visibility, exposure; got %zu notices", log.n);
	CHECK(log.v[3].n.exposure.n_rects == 1 && log.v[3].rects[0].width == 100 &&
		      log.v[3].rects[0].height == 50,
	      "the first exposure is not the whole window");

	uint32_t w2 = create(a, 0, 50, 25, 100, 50, VIS_CREATE_MAP);
	CHECK(state_of(a, w1) == VIS_VISIBILITY_PARTIALLY_OBSCURED, "w1 not partially obscured");
	CHECK(last_visibility(&log, w1)->visibility.previous == VIS_VISIBILITY_UNOBSCURED,
	      "w1's notice has the wrong previous state");
	struct vis_window_state *st;
	size_t n_st;
	/* Ascending ID, which says nothing of the order they were created in. */
	size_t i2 = w1 < w2 ? 1 : 0;
	CHECK(vis_client_get_states(a, &st, &n_st) == 0 && n_st == 2 && st[0].window < st[1].window &&
		      st[1 - i2].window == w1 && st[i2].window == w2 &&
		      st[i2].state == VIS_VISIBILITY_UNOBSCURED,
	      "get-states");
	free(st);
	struct vis_rect32 *r;
	size_t n_r;
	CHECK(vis_client_get_region(a, w1, &r, &n_r) == 0 && n_r == 2 && r[0].x == 0 &&
		      r[0].y == 0 && r[0].width == 100 && r[0].height == 25 && r[1].x == 0 &&
		      r[1].y == 25 && r[1].width == 50 && r[1].height == 25,
	      "get-region of w1");
	free(r);
	uint32_t *ids;
	size_t n_ids;
	CHECK(vis_client_get_repaint(a, (struct vis_rect32){ 0, 0, 40, 40 }, &ids, &n_ids) == 0 &&
		      n_ids == 1 && ids[0] == w1,
	      "get-repaint of a corner only w1 shows in");
	free(ids);

	/* Cover w1 exactly: the occlusion notice. Then raise it: all of it is exposed again. */
	vis_client_move(a, w2, 0, 0);
	vis_client_resize(a, w2, 100, 50);
	CHECK(vis_client_sync(a) == 0, "move/resize failed");
	n = last_visibility(&log, w1);
	CHECK(n->visibility.state == VIS_VISIBILITY_FULLY_OBSCURED, "no occlusion notice");
	size_t before = log.n;
	vis_client_raise(a, w1);
	CHECK(vis_client_sync(a) == 0, "raise failed");
	CHECK(state_of(a, w1) == VIS_VISIBILITY_UNOBSCURED && state_of(a, w2) == 2, "raise");
	/* Notices of the raise: stack, then in stacking order w2's visibility, w1's visibility and
	 * exposure. */
	CHECK(log.n == before + 4 && log.v[before].n.stack.change == VIS_STACK_RESTACK &&
		      log.v[before].n.stack.sibling == w2 && log.v[before + 1].n.window == w2 &&
		      log.v[before + 2].n.kind == VIS_NOTICE_KIND_VISIBILITY &&
		      log.v[before + 2].n.window == w1 &&
		      log.v[before + 3].n.kind == VIS_NOTICE_KIND_EXPOSURE &&
		      log.v[before + 3].n.window == w1 && log.v[before + 3].rects[0].width == 100,
	      "raise: wanted stack, visibility of w2, visibility and exposure of w1");
	vis_client_restack(a, w1, VIS_RESTACK_BELOW, w2);
	vis_client_lower(a, w2);
	CHECK(vis_client_sync(a) == 0 && state_of(a, w1) == 0 && state_of(a, w2) == 2,
	      "restack/lower");

	/* Unmapping sends no visibility notice; mapping again always does. */
	before = log.n;
	vis_client_unmap(a, w1);
	CHECK(vis_client_sync(a) == 0 && state_of(a, w1) == VIS_VISIBILITY_NONE, "unmap");
	CHECK(last_visibility(&log, w2)->visibility.state == 0, "unmap: w2 not unobscured");
	for (size_t i = before; i < log.n; i++)
		CHECK(!(log.v[i].n.kind == VIS_NOTICE_KIND_VISIBILITY && log.v[i].n.window == w1),
		      "unmap sent a visibility notice");
	vis_client_map(a, w1);
	CHECK(vis_client_sync(a) == 0, "map");
	n = last_visibility(&log, w1);
	CHECK(n->visibility.state == 0 && n->visibility.previous == VIS_VISIBILITY_NONE,
	      "map: no first-state notice");

	/* A window partly off-screen is never unobscured. */
	vis_client_move(a, w1, 150, 0);
	CHECK(vis_client_sync(a) == 0 && state_of(a, w1) == 1, "off-screen part");
	vis_client_move(a, w1, 1000, 1000);
	CHECK(vis_client_sync(a) == 0 && state_of(a, w1) == 2, "wholly off-screen");

	vis_client_destroy_window(a, w2);
	CHECK(vis_client_sync(a) == 0, "destroy");
	uint32_t seq = vis_client_get_state_async(a, w2, NULL, NULL);
	expect_error(a, seq, VIS_ERROR_WINDOW, __LINE__);
	check_serials(&log);
	vis_client_destroy(a);
	free(log.v);
}

/* Exposures past the subscription's rectangle limit collapse to their bounding box. */
static void test_exposure_limit(void)
{
	current = "exposure limit";
	struct log log = { 0 };
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, &log);
	uint32_t w = create(a, 0, 0, 0, 60, 60, VIS_CREATE_MAP);
	uint32_t top = create(a, 0, 20, 20, 20, 20, VIS_CREATE_MAP);
	uint32_t cover = create(a, 0, 0, 0, 60, 60, VIS_CREATE_MAP);
	vis_client_subscribe(a, w, VIS_NOTICE_EXPOSURE, 1);
	/* Uncovering w leaves a frame around top: 3 bands of rectangles, over the limit of 1. */
	vis_client_destroy_window(a, cover);
	CHECK(vis_client_sync(a) == 0, "destroy");
	CHECK(log.n == 1 && log.v[0].n.kind == VIS_NOTICE_KIND_EXPOSURE &&
		      log.v[0].n.exposure.flags == VIS_EXPOSURE_COLLAPSED &&
		      log.v[0].n.exposure.n_rects == 1 && log.v[0].rects[0].width == 60 &&
		      log.v[0].rects[0].height == 60,
	      "wanted one collapsed exposure of 60x60, got %zu notices", log.n);
	/* Within the limit: the exact rectangles. */
	vis_client_subscribe(a, w, VIS_NOTICE_EXPOSURE, 0);
	vis_client_destroy_window(a, top);
	CHECK(vis_client_sync(a) == 0, "destroy top");
	CHECK(log.n == 2 && log.v[1].n.exposure.flags == 0 && log.v[1].n.exposure.n_rects == 1 &&
		      log.v[1].rects[0].x == 20 && log.v[1].rects[0].width == 20,
	      "uncovering the middle");
	/* A move keeps the contents: nothing new shows. A resize forgets them: all of it. */
	vis_client_move(a, w, 5, 5);
	CHECK(vis_client_sync(a) == 0 && log.n == 2, "a move exposed something");
	vis_client_resize(a, w, 60, 61);
	CHECK(vis_client_sync(a) == 0 && log.n == 3 && log.v[2].rects[0].height == 61,
	      "a resize did not expose the whole window");
	vis_client_destroy(a);
	free(log.v);
}

/* Errors and refusals, each naming its request; roles and the restricted socket. */
static void test_errors_and_roles(void)
{
	current = "errors and roles";
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	struct vis_client *b = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	struct vis_client *obs = connect_to(sock, VIS_ROLE_OBSERVER, NULL);
	struct vis_client *mgr = connect_to(sock, VIS_ROLE_MANAGER, NULL);
	CHECK(vis_client_role(obs) == VIS_ROLE_OBSERVER && vis_client_role(mgr) == VIS_ROLE_MANAGER,
	      "roles not granted");
	uint32_t sw, sh;
	vis_client_screen(a, &sw, &sh);
	CHECK(sw == SCREEN_W && sh == SCREEN_H, "screen %ux%u", sw, sh);

	uint32_t p = create(a, 0, 0, 0, 50, 50, VIS_CREATE_MAP);
	uint32_t q = create(a, 0, 10, 10, 50, 50, VIS_CREATE_MAP);
	uint32_t child = create(a, p, 1, 1, 5, 5, VIS_CREATE_MAP);

	expect_error(a, vis_client_get_state_async(a, 9999, NULL, NULL), VIS_ERROR_WINDOW, __LINE__);
	uint32_t id;
	CHECK(vis_client_create(a, 0, 0, 0, 0, 5, 0, &id) < 0, "a zero width was accepted");
	struct vis_error e;
	CHECK(vis_client_last_error(a, &e) && e.code == VIS_ERROR_VALUE && e.opcode == 2 &&
		      strstr(e.message, "width"),
	      "a zero width: wrong error");
	expect_error(a, vis_client_create_async(a, 0, 0, 0, 5, 5, 8, NULL, NULL), VIS_ERROR_VALUE,
		     __LINE__);
	expect_error(a, vis_client_create_async(a, 0, 0, 0, 0x80000000u, 5, 0, NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_restack(a, child, VIS_RESTACK_ABOVE, q), VIS_ERROR_MATCH,
		     __LINE__);
	expect_error(a, vis_client_restack(a, q, 7, p), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_restack(a, q, 0, q), VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_reparent(a, p, child, 0, 0), VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_reparent(a, p, p, 0, 0), VIS_ERROR_MATCH, __LINE__);
	expect_error(a, vis_client_batch_commit(a), VIS_ERROR_STATE, __LINE__);
	expect_error(a, vis_client_unsubscribe(a, p), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_subscribe(a, p, 0, 0), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_subscribe(a, p, 8, 0), VIS_ERROR_VALUE, __LINE__);
	expect_error(a, vis_client_get_repaint_async(a, (struct vis_rect32){ 0, 0, 0, 1 }, NULL,
						     NULL),
		     VIS_ERROR_VALUE, __LINE__);
	test_look_errors(a, p, q);
	/* Inside a batch everything is held: replies keep request order, and queries run after the
	 * batch's changes, answering for the states after it; synchronous calls would wait forever
	 * and are refused. */
	vis_client_batch_begin(a);
	vis_client_unmap(a, q);
	uint32_t held_state = 99;
	uint32_t s1 = vis_client_get_state_async(a, q, on_state, &held_state);
	uint32_t nested = vis_client_batch_begin(a);
	uint32_t s2 = vis_client_create_async(a, 0, 0, 0, 5, 5, 0, on_created, &id);
	CHECK(s1 && s2 && vis_client_get_state(a, q, &held_state) < 0 && errno == EDEADLK,
	      "a synchronous call inside a batch was not refused");
	vis_client_batch_commit(a);
	expect_error(a, nested, VIS_ERROR_STATE, __LINE__);
	CHECK(held_state == VIS_VISIBILITY_NONE && id && id != child && id != p && id != q,
	      "held query and create");
	CHECK(state_of(a, q) == VIS_VISIBILITY_NONE, "batch commit");
	vis_client_destroy_window(a, id);
	vis_client_map(a, q);
	vis_client_roundtrip(a);

	/* Another client sees none of a's windows; an observer sees but changes nothing. */
	expect_error(b, vis_client_map(b, p), VIS_ERROR_WINDOW, __LINE__);
	expect_error(b, vis_client_subscribe(b, p, 1, 0), VIS_ERROR_WINDOW, __LINE__);
	expect_error(b, vis_client_get_region_async(b, p, NULL, NULL), VIS_ERROR_WINDOW, __LINE__);
	expect_error(b, vis_client_create_async(b, p, 0, 0, 5, 5, 0, NULL, NULL), VIS_ERROR_WINDOW,
		     __LINE__);
	uint32_t bw = create(b, 0, 0, 0, 5, 5, 0);
	expect_error(b, vis_client_restack(b, bw, 0, q), VIS_ERROR_WINDOW, __LINE__);
	struct vis_window_state *st;
	size_t n;
	CHECK(vis_client_get_states(b, &st, &n) == 0 && n == 0, "b sees %zu states", n);
	free(st);
	CHECK(state_of(obs, p) == VIS_VISIBILITY_PARTIALLY_OBSCURED, "observer reads a state");
	CHECK(vis_client_get_states(obs, &st, &n) == 0 && n == 3, "observer sees %zu states", n);
	free(st);
	expect_error(obs, vis_client_unmap(obs, p), VIS_ERROR_ACCESS, __LINE__);
	expect_error(obs, vis_client_create_async(obs, 0, 0, 0, 5, 5, 0, NULL, NULL),
		     VIS_ERROR_ACCESS, __LINE__);
	/* The manager changes anyone's windows. */
	vis_client_unmap(mgr, q);
	CHECK(vis_client_sync(mgr) == 0 && state_of(a, q) == VIS_VISIBILITY_NONE, "manager unmap");

	/* One manager at a time; no roles on the restricted socket. */
	struct vis_client *m2 = vis_client_connect(sock, VIS_ROLE_MANAGER);
	CHECK(m2 && vis_client_error(m2), "a second manager was accepted");
	vis_client_destroy(m2);
	struct vis_client *r = vis_client_connect(rsock, VIS_ROLE_OBSERVER);
	CHECK(r && vis_client_error(r), "a role was granted on the restricted socket");
	vis_client_destroy(r);
	r = connect_to(rsock, VIS_ROLE_CLIENT, NULL);
	CHECK(create(r, 0, 0, 0, 5, 5, VIS_CREATE_MAP) > 0, "restricted client create");
	vis_client_destroy(r);
	/* Once the manager goes, another may take the role. */
	vis_client_destroy(mgr);
	for (struct progress p = daemon_working();;) {
		m2 = vis_client_connect(sock, VIS_ROLE_MANAGER);
		if (!vis_client_error(m2))
			break;
		vis_client_destroy(m2);
		still_working(&p, __LINE__, "the manager role was not released");
	}
	vis_client_destroy(m2);
	vis_client_destroy(a);
	vis_client_destroy(b);
	vis_client_destroy(obs);
}

/* Little-endian 32-bit word at p. */
static uint32_t le32(const uint8_t *p)
{
	return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/*
 * Sends raw bytes on a fresh connection and reads until the daemon hangs up: it must answer with
 * exactly one error, of code, for request seq, then close.
 */
static void expect_fatal(const uint8_t *bytes, size_t len, uint32_t seq, uint32_t code, int line)
{
	int fd = socket(AF_UNIX, SOCK_STREAM, 0);
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	memcpy(addr.sun_path, sock, strlen(sock) + 1); /* mkdtemp paths are short */
	if (fd < 0 || connect(fd, (struct sockaddr *)&addr, sizeof addr) < 0 ||
	    write(fd, bytes, len) != (ssize_t)len)
		fail(line, "raw connection: %s", strerror(errno));
	uint8_t in[512];
	size_t got = 0;
	for (struct progress work = daemon_working();;) {
		struct pollfd p = { fd, POLLIN, 0 };
		if (poll(&p, 1, 10) == 0) {
			still_working(&work, line, "the daemon did not close the connection");
			continue;
		}
		ssize_t r = read(fd, in + got, sizeof in - got);
		if (r <= 0)
			break;
		got += (size_t)r;
	}
	close(fd);
	/* Skip a hello reply; the error must be the last message. */
	size_t at = 0;
	while (at + 8 <= got && le32(in + at) >= 8 && at + le32(in + at) < got)
		at += le32(in + at);
	if (got - at < 20 || le32(in + at) != got - at || (le32(in + at + 4) & 0xffff) != 96 ||
	    le32(in + at + 8) != seq || le32(in + at + 16) != code)
		fail(line, "wanted an error %s for request %u, then the end; got %zu bytes",
		     vis_error_code_name(code), seq, got);
}

/* Bytes that cannot be parsed end their connection after an error; nobody else notices. */
static void test_fatal(void)
{
	current = "fatal errors";
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	uint32_t w = create(a, 0, 0, 0, 10, 10, VIS_CREATE_MAP);
	/* sync (opcode 21) before hello; an unknown opcode; a size under the header; a wrong magic;
	 * hello then a map (opcode 4) whose payload lacks its window. */
	static const uint8_t early[] = { 8, 0, 0, 0, 21, 0, 0, 0 };
	static const uint8_t unknown[] = { 8, 0, 0, 0, 99, 0, 0, 0 };
	static const uint8_t tiny[] = { 4, 0, 0, 0, 1, 0, 0, 0 };
	static const uint8_t magic[] = { 20, 0, 0, 0, 1, 0, 0, 0, 1, 2, 3, 4, 2, 0, 0, 0, 0, 0, 0, 0 };
	static const uint8_t truncated[] = { 20, 0, 0, 0, 1, 0, 0, 0, 'V', 'I', 'S', 'D', VIS_PROTOCOL_VERSION, 0,
					     0,  0, 0, 0, 0, 0, 8, 0, 0, 0,   4,   0,   0,   0 };
	expect_fatal(early, sizeof early, 1, VIS_ERROR_HANDSHAKE, __LINE__);
	expect_fatal(unknown, sizeof unknown, 1, VIS_ERROR_OPCODE, __LINE__);
	expect_fatal(tiny, sizeof tiny, 1, VIS_ERROR_MALFORMED, __LINE__);
	expect_fatal(magic, sizeof magic, 1, VIS_ERROR_HANDSHAKE, __LINE__);
	expect_fatal(truncated, sizeof truncated, 2, VIS_ERROR_MALFORMED, __LINE__);
	CHECK(state_of(a, w) == VIS_VISIBILITY_UNOBSCURED, "another client noticed");
	vis_client_destroy(a);
}

/* Waits until the observer sees exactly `want` windows (disconnects are handled asynchronously). */
static void wait_windows(struct vis_client *obs, size_t want)
{
	char what[80];
	for (struct progress p = daemon_working();;) {
		struct vis_window_info *t;
		size_t n;
		CHECK(vis_client_get_tree(obs, &t, &n) == 0, "get-tree");
		free(t);
		if (n == want)
			return;
		snprintf(what, sizeof what, "the observer sees %zu windows, not %zu", n, want);
		still_working(&p, __LINE__, what);
	}
}

/* A batch is one recompute: changes that cancel out inside it send no visibility notice. */
static void test_batch(void)
{
	current = "batch";
	struct log log = { 0 };
	struct vis_client *obs = connect_to(sock, VIS_ROLE_OBSERVER, &log);
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	uint32_t w = create(a, 0, 0, 0, 50, 50, VIS_CREATE_MAP);
	vis_client_subscribe(obs, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0);
	CHECK(vis_client_sync(obs) == 0, "subscribe");
	/* A subscription begins with the state of each window it covers, created before it. */
	const struct vis_notice *first = last_visibility(&log, w);
	CHECK(first && first->visibility.state == VIS_VISIBILITY_UNOBSCURED &&
		      first->visibility.previous == VIS_VISIBILITY_INITIAL,
	      "no initial state for window %u", w);
	log.n = 0;
	vis_client_batch_begin(a);
	uint32_t cover = 0;
	vis_client_create_async(a, 0, 0, 0, 50, 50, VIS_CREATE_MAP, NULL, NULL);
	vis_client_move(a, w, 100, 0);
	vis_client_move(a, w, 0, 0);
	vis_client_batch_commit(a);
	CHECK(vis_client_sync(a) == 0, "batch failed");
	vis_client_roundtrip(obs);
	/* Only the new window's first state and w's occlusion: no state in between. */
	struct vis_window_info *t;
	size_t n;
	CHECK(vis_client_get_tree(a, &t, &n) == 0 && n == 2, "tree after batch");
	cover = t[1].window;
	free(t);
	CHECK(log.n == 2 && log.v[0].n.window == w && log.v[0].n.visibility.state == 2 &&
		      log.v[1].n.window == cover && log.v[1].n.visibility.state == 0,
	      "batch: wanted 2 notices, got %zu", log.n);
	/* Inside a batch, an unmap then a map leaves nothing to notice. */
	vis_client_batch_begin(a);
	vis_client_unmap(a, cover);
	vis_client_map(a, cover);
	vis_client_batch_commit(a);
	CHECK(vis_client_sync(a) == 0 && (vis_client_roundtrip(obs), log.n == 2),
	      "unmap+map in a batch sent notices");
	vis_client_destroy(a);
	vis_client_destroy(obs);
	free(log.v);
}

/*
 * A newcomer's program: the default socket named by "" (as an unset variable passed on would be),
 * then a subscription and a create that nobody flushes, and a poll for reading: the requests must
 * have gone out when they were made, or the poll waits forever.
 */
static void test_newcomer(void)
{
	current = "newcomer";
	struct log log = { 0 };
	CHECK(setenv("VISD_SOCKET", sock, 1) == 0, "setenv");
	struct vis_client *c = connect_to("", VIS_ROLE_CLIENT, &log);
	unsetenv("VISD_SOCKET");
	uint32_t w = 0;
	CHECK(vis_client_subscribe(c, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0) &&
		      vis_client_create_async(c, 0, 10, 10, 20, 20, VIS_CREATE_MAP, on_created, &w),
	      "queueing requests");
	struct pollfd p = { .fd = vis_client_fd(c), .events = POLLIN };
	/* Before any dispatch (which would write what waits): the daemon must have answered. */
	for (struct progress work = daemon_working(); poll(&p, 1, 0) == 0;)
		still_working(&work, __LINE__, "nothing to read: the requests were never sent");
	for (struct progress work = daemon_working(); !last_visibility(&log, w);) {
		CHECK(poll(&p, 1, 0) >= 0 && vis_client_dispatch(c) >= 0, "dispatch");
		if (!last_visibility(&log, w))
			still_working(&work, __LINE__, "no visibility notice");
	}
	CHECK(w && last_visibility(&log, w), "no reply or notice without a flush: created %u", w);
	vis_client_destroy(c);
	free(log.v);
	/* Neither a path nor a variable: a clear error, not a connection to "". */
	const char *xdg = getenv("XDG_RUNTIME_DIR");
	char *saved = xdg ? strdup(xdg) : NULL;
	unsetenv("XDG_RUNTIME_DIR");
	c = vis_client_connect("", VIS_ROLE_CLIENT);
	CHECK(c && vis_client_error(c) == ENOENT, "connect(\"\") without variables: %s",
	      c ? vis_client_error_message(c) : "out of memory");
	vis_client_destroy(c);
	if (saved)
		setenv("XDG_RUNTIME_DIR", saved, 1);
	free(saved);
}

/* Children: clipped by the parent, never obscuring it, unviewable with it. */
static void test_children(void)
{
	current = "children";
	struct log log = { 0 };
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, &log);
	uint32_t p = create(a, 0, 10, 10, 50, 50, VIS_CREATE_MAP);
	uint32_t out = create(a, p, 40, 40, 30, 30, VIS_CREATE_MAP);
	uint32_t in = create(a, p, 5, 5, 10, 10, VIS_CREATE_MAP);
	uint32_t all = create(a, p, 0, 0, 50, 50, 0);
	CHECK(state_of(a, p) == 0, "a parent is not obscured by its children");
	CHECK(state_of(a, out) == 1, "a child cut by its parent is partially obscured");
	CHECK(state_of(a, in) == 0, "an inner child is unobscured");
	CHECK(state_of(a, all) == VIS_VISIBILITY_NONE, "unmapped child has a state");
	vis_client_map(a, all);
	CHECK(vis_client_sync(a) == 0 && state_of(a, p) == 0 && state_of(a, in) == 2 &&
		      state_of(a, out) == 2,
	      "a child covering its parent");
	struct vis_rect32 *r;
	size_t n;
	CHECK(vis_client_get_region(a, p, &r, &n) == 0 && n == 0, "parent's own region not empty");
	free(r);
	uint32_t s = create(a, 0, 0, 0, 20, 20, VIS_CREATE_MAP);
	CHECK(state_of(a, p) == 1 && state_of(a, all) == 1, "a sibling over the parent");
	vis_client_subscribe(a, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0);
	vis_client_unmap(a, p);
	CHECK(vis_client_sync(a) == 0 && state_of(a, in) == VIS_VISIBILITY_NONE, "unmapped parent");
	size_t before = log.n;
	vis_client_map(a, p);
	CHECK(vis_client_sync(a) == 0, "map parent");
	CHECK(log.n == before + 4, "mapping the parent: %zu notices, wanted 4 (p, out, in, all)",
	      log.n - before);
	for (size_t i = before; i < log.n; i++)
		CHECK(log.v[i].n.visibility.previous == VIS_VISIBILITY_NONE, "previous not none");
	/* Reparent the covering child to the top level: it now obscures the parent. */
	vis_client_reparent(a, all, 0, 10, 10);
	CHECK(vis_client_sync(a) == 0 && state_of(a, p) == 2 && state_of(a, s) == 1,
	      "reparent to the screen");
	vis_client_destroy(a);
	free(log.v);
}

/* Disconnects destroy a client's windows, except retained ones; fds are not leaked. */
static void test_disconnect(void)
{
	current = "disconnect";
	struct log log = { 0 };
	struct vis_client *obs = connect_to(sock, VIS_ROLE_OBSERVER, &log);
	wait_windows(obs, 0);
	int fds = count_fds(daemon_pid);
	vis_client_subscribe(obs, VIS_WINDOW_ALL, VIS_NOTICE_STACK, 0);
	vis_client_roundtrip(obs);
	struct vis_client *a = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	uint32_t w = create(a, 0, 0, 0, 10, 10, VIS_CREATE_MAP);
	uint32_t kept = create(a, 0, 0, 0, 10, 10, VIS_CREATE_MAP | VIS_CREATE_RETAIN);
	uint32_t child = create(a, kept, 0, 0, 5, 5, VIS_CREATE_MAP);
	vis_client_destroy(a);
	wait_windows(obs, 1);
	vis_client_roundtrip(obs);
	size_t destroyed = 0;
	for (size_t i = 0; i < log.n; i++)
		if (log.v[i].n.kind == VIS_NOTICE_KIND_STACK &&
		    log.v[i].n.stack.change == VIS_STACK_DESTROY)
			destroyed += log.v[i].n.window == w || log.v[i].n.window == child;
	CHECK(destroyed == 2, "destroy notices for %zu of 2 windows", destroyed);
	struct vis_window_info *t;
	size_t n;
	CHECK(vis_client_get_tree(obs, &t, &n) == 0 && n == 1 && t[0].window == kept &&
		      (t[0].flags & VIS_WINDOW_RETAINED),
	      "the retained window is gone");
	free(t);
	/* 64 clients at once, then all gone: the daemon is back to its descriptors. */
	struct vis_client *many[64];
	for (int i = 0; i < 64; i++) {
		many[i] = connect_to(sock, VIS_ROLE_CLIENT, NULL);
		create(many[i], 0, i, i, 20, 20, VIS_CREATE_MAP);
	}
	wait_windows(obs, 65);
	for (int i = 0; i < 64; i++)
		vis_client_destroy(many[i]);
	wait_windows(obs, 1);
	struct vis_client *mgr = connect_to(sock, VIS_ROLE_MANAGER, NULL);
	vis_client_destroy_window(mgr, kept);
	CHECK(vis_client_sync(mgr) == 0, "manager destroys the retained window");
	vis_client_destroy(mgr);
	wait_windows(obs, 0);
	CHECK(count_fds(daemon_pid) == fds, "the daemon holds %d descriptors, %d before",
	      count_fds(daemon_pid), fds);
	vis_client_destroy(obs);
	free(log.v);
}

/* The last stack notice of change about window w in l, or NULL. */
static const struct vis_notice *last_stack(const struct log *l, uint32_t w, uint32_t change)
{
	for (size_t i = l->n; i-- > 0;)
		if (l->v[i].n.kind == VIS_NOTICE_KIND_STACK && l->v[i].n.window == w &&
		    l->v[i].n.stack.change == change)
			return &l->v[i].n;
	return NULL;
}

/* The tree record of window w as c sees it (CHECKs that there is one). */
static struct vis_window_info tree_record(struct vis_client *c, uint32_t w)
{
	struct vis_window_info *t, found = { 0 };
	size_t n;
	CHECK(vis_client_get_tree(c, &t, &n) == 0, "get-tree");
	for (size_t i = 0; i < n; i++)
		if (t[i].window == w)
			found = t[i];
	free(t);
	CHECK(found.window == w, "window %u is not in the tree", w);
	return found;
}

/*
 * External IDs: only the manager sets them, unique among the windows that exist, found by lookup
 * as far as the connection may see, carried by tree records and stack notices, freed by destroy
 * (with an ancestor too) and by the manager's hang-up.
 */
static void test_external(void)
{
	current = "external IDs";
	struct log log = { 0 };
	struct vis_client *obs = connect_to(sock, VIS_ROLE_OBSERVER, &log);
	wait_windows(obs, 0);
	vis_client_subscribe(obs, VIS_WINDOW_ALL, VIS_NOTICE_STACK, 0);
	vis_client_roundtrip(obs);
	struct vis_client *mgr = connect_to(sock, VIS_ROLE_MANAGER, NULL);
	struct vis_client *cl = connect_to(sock, VIS_ROLE_CLIENT, NULL);
	const uint64_t big = 0xfedcba9800000001ull; /* both halves of the tag count */
	uint32_t frame = 0, xw = 0, wl = 0, plain = 0, w = 0;
	CHECK(vis_client_create_external(mgr, 0, 10, 10, 50, 40, 2, VIS_CREATE_MAP,
					 VIS_EXTERNAL_X11, 0x1e00003, &frame) == 0,
	      "the manager creates a window with an X ID");
	CHECK(vis_client_create_external(mgr, frame, 0, 0, 20, 20, 0, VIS_CREATE_MAP,
					 VIS_EXTERNAL_X11, big, &xw) == 0,
	      "the manager creates a child with an X ID");
	/* The same tag in another namespace is another ID. */
	CHECK(vis_client_create_external(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_WAYLAND, 0x1e00003,
					 &wl) == 0,
	      "the same tag in another namespace");
	plain = create(cl, 0, 100, 0, 5, 5, VIS_CREATE_MAP);

	/* Refusals: a client or an observer may not set one; a pair in use; a tag without a
	 * namespace (also for the manager); nothing was created by any of them. */
	expect_error(cl,
		     vis_client_create_external_async(cl, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_X11,
						      0x99, NULL, NULL),
		     VIS_ERROR_ACCESS, __LINE__);
	expect_error(obs,
		     vis_client_create_external_async(obs, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_X11,
						      0x99, NULL, NULL),
		     VIS_ERROR_ACCESS, __LINE__);
	expect_error(mgr,
		     vis_client_create_external_async(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_X11,
						      0x1e00003, NULL, NULL),
		     VIS_ERROR_MATCH, __LINE__);
	expect_error(mgr,
		     vis_client_create_external_async(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_NONE, 5,
						      NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	expect_error(cl,
		     vis_client_create_external_async(cl, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_NONE, 5,
						      NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	vis_client_sync(mgr); /* fails for the errors above; later syncs count only later ones */
	wait_windows(obs, 4);

	/* Lookups: observers and the manager see every window; a client sees only its own. */
	CHECK(vis_client_lookup(obs, VIS_EXTERNAL_X11, 0x1e00003, &w) == 0 && w == frame,
	      "lookup of the frame's X ID: %u", w);
	CHECK(vis_client_lookup(mgr, VIS_EXTERNAL_X11, big, &w) == 0 && w == xw,
	      "lookup of a 64-bit tag: %u", w);
	CHECK(vis_client_lookup(obs, VIS_EXTERNAL_WAYLAND, 0x1e00003, &w) == 0 && w == wl,
	      "lookup in another namespace: %u", w);
	expect_error(cl, vis_client_lookup_async(cl, VIS_EXTERNAL_X11, 0x1e00003, NULL, NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	expect_error(obs, vis_client_lookup_async(obs, VIS_EXTERNAL_X11, 0x42, NULL, NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	expect_error(obs, vis_client_lookup_async(obs, VIS_EXTERNAL_X11, big & 0xffffffffu, NULL,
						  NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	expect_error(obs, vis_client_lookup_async(obs, VIS_EXTERNAL_NONE, 0, NULL, NULL),
		     VIS_ERROR_VALUE, __LINE__);
	CHECK(vis_client_lookup(obs, VIS_EXTERNAL_NONE, 0, &w) < 0 && vis_client_error(obs) == 0,
	      "a synchronous lookup of no ID fails, the connection kept");

	/* Tree records and stack notices carry the pair; windows without one say 0, 0. */
	struct vis_window_info r = tree_record(obs, xw);
	CHECK(r.ext_namespace == VIS_EXTERNAL_X11 && r.external == big && r.parent == frame,
	      "tree record of the child: %u:%#llx", r.ext_namespace, (unsigned long long)r.external);
	r = tree_record(obs, wl);
	CHECK(r.ext_namespace == VIS_EXTERNAL_WAYLAND && r.external == 0x1e00003, "tree record");
	r = tree_record(obs, plain);
	CHECK(r.ext_namespace == VIS_EXTERNAL_NONE && r.external == 0, "a plain window's record");
	vis_client_move(mgr, xw, 3, 4);
	vis_client_unmap(mgr, frame);
	CHECK(vis_client_sync(mgr) == 0, "move and unmap");
	vis_client_roundtrip(obs);
	uint32_t changes[] = { VIS_STACK_CREATE, VIS_STACK_MAP, VIS_STACK_CONFIGURE };
	for (size_t i = 0; i < sizeof changes / sizeof *changes; i++) {
		const struct vis_notice *n = last_stack(&log, xw, changes[i]);
		CHECK(n && n->stack.ext_namespace == VIS_EXTERNAL_X11 && n->stack.external == big,
		      "stack notice %u of the child without its X ID", changes[i]);
	}
	const struct vis_notice *n = last_stack(&log, frame, VIS_STACK_UNMAP);
	CHECK(n && n->stack.ext_namespace == VIS_EXTERNAL_X11 && n->stack.external == 0x1e00003,
	      "unmap notice of the frame without its X ID");
	n = last_stack(&log, plain, VIS_STACK_CREATE);
	CHECK(n && n->stack.ext_namespace == 0 && n->stack.external == 0,
	      "a plain window's create notice");

	/* Destroying the frame destroys the child: both pairs are free, the notices still say them. */
	vis_client_destroy_window(mgr, frame);
	CHECK(vis_client_sync(mgr) == 0, "destroy");
	vis_client_roundtrip(obs);
	n = last_stack(&log, xw, VIS_STACK_DESTROY);
	CHECK(n && n->stack.external == big, "the child's destroy notice without its X ID");
	expect_error(obs, vis_client_lookup_async(obs, VIS_EXTERNAL_X11, 0x1e00003, NULL, NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	expect_error(mgr, vis_client_lookup_async(mgr, VIS_EXTERNAL_X11, big, NULL, NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	CHECK(vis_client_create_external(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_X11, big, &w) == 0 &&
		      w != xw,
	      "a destroyed window's pair taken again");

	/* The manager hangs up: its windows go, and their pairs with them. */
	vis_client_destroy(mgr);
	wait_windows(obs, 1);
	expect_error(obs, vis_client_lookup_async(obs, VIS_EXTERNAL_WAYLAND, 0x1e00003, NULL, NULL),
		     VIS_ERROR_WINDOW, __LINE__);
	mgr = connect_to(sock, VIS_ROLE_MANAGER, NULL);
	CHECK(vis_client_create_external(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_WAYLAND, 0x1e00003,
					 &w) == 0 &&
		      vis_client_create_external(mgr, 0, 0, 0, 5, 5, 0, 0, VIS_EXTERNAL_X11, big,
						 &w) == 0,
	      "the pairs of a gone manager's windows taken again");
	vis_client_destroy(mgr);
	vis_client_destroy(cl);
	wait_windows(obs, 0);
	vis_client_destroy(obs);
	free(log.v);
}

/*
 * The key property: after random changes by a manager, the daemon's states equal the core's on
 * the same scene (the tree, read back, as a stack), and the last visibility notice an observer got
 * for each viewable window is its state.
 */
static int checks;

static void test_random(uint64_t seed, int steps)
{
	char name[64];
	snprintf(name, sizeof name, "random (seed %llu)", (unsigned long long)seed);
	current = name;
	struct vis_rng rng = { seed };
	struct log log = { 0 };
	struct vis_client *mgr = connect_to(sock, VIS_ROLE_MANAGER, NULL);
	struct vis_client *obs = connect_to(sock, VIS_ROLE_OBSERVER, &log);
	vis_client_subscribe(obs, VIS_WINDOW_ALL, VIS_NOTICE_VISIBILITY, 0);
	vis_client_roundtrip(obs);
	/* The model: the stack as the test expects it, bottom to top, with each window's look (its
	 * rectangles kept beside it: the look's pointers are set when the stack is made). */
	struct model {
		uint32_t id;
		struct vis_rect r;
		bool mapped;
		struct vis_look look;
		struct vis_rect shape[4], opaque[4];
	} m[64], tmp;
	size_t n = 0;
	for (int step = 0; step < steps; step++) {
		int op = (int)vis_rng_below(&rng, 13);
		int32_t x = (int32_t)vis_rng_range(&rng, -20, SCREEN_W);
		int32_t y = (int32_t)vis_rng_range(&rng, -20, SCREEN_H);
		uint32_t w = 1 + (uint32_t)vis_rng_below(&rng, vis_rng_below(&rng, 4) ? 60 : 220);
		uint32_t h = 1 + (uint32_t)vis_rng_below(&rng, vis_rng_below(&rng, 4) ? 40 : 120);
		if (n < 2 || (op == 0 && n < 64)) {
			bool map = vis_rng_below(&rng, 5) != 0;
			bool input_only = vis_rng_below(&rng, 10) == 0;
			uint32_t border = input_only ? 0 : (uint32_t)vis_rng_below(&rng, 3);
			memset(&m[n], 0, sizeof m[n]);
			uint32_t id = 0;
			CHECK(vis_client_create_window(mgr, 0, x, y, w, h, border,
						       (map ? VIS_CREATE_MAP : 0) |
							       (input_only ? VIS_CREATE_INPUT_ONLY : 0),
						       &id) == 0,
			      "create failed");
			m[n].id = id;
			m[n].r = (struct vis_rect){ x, y, (int32_t)w, (int32_t)h };
			m[n].look.border = (int32_t)border;
			m[n].look.input_only = input_only;
			m[n++].mapped = map;
			continue;
		}
		size_t k = (size_t)vis_rng_below(&rng, n), j = (size_t)vis_rng_below(&rng, n);
		uint32_t id = m[k].id;
		tmp = m[k];
		switch (op) {
		case 1:
			vis_client_destroy_window(mgr, id);
			memmove(&m[k], &m[k + 1], (n - k - 1) * sizeof *m);
			n--;
			break;
		case 2:
		case 3:
			op == 2 ? vis_client_map(mgr, id) : vis_client_unmap(mgr, id);
			m[k].mapped = op == 2;
			break;
		case 4:
			vis_client_move(mgr, id, x, y);
			m[k].r.x = x;
			m[k].r.y = y;
			break;
		case 5:
			vis_client_resize(mgr, id, w, h);
			m[k].r.w = (int32_t)w;
			m[k].r.h = (int32_t)h;
			break;
		case 6:
		case 7:
			op == 6 ? vis_client_raise(mgr, id) : vis_client_lower(mgr, id);
			memmove(&m[k], &m[k + 1], (n - k - 1) * sizeof *m);
			if (op == 6) {
				m[n - 1] = tmp;
			} else {
				memmove(&m[1], &m[0], (n - 1) * sizeof *m);
				m[0] = tmp;
			}
			break;
		default: {
			if (j == k)
				break;
			uint32_t sib = m[j].id;
			vis_client_restack(mgr, id, op == 8 ? VIS_RESTACK_ABOVE : VIS_RESTACK_BELOW, sib);
			memmove(&m[k], &m[k + 1], (n - k - 1) * sizeof *m);
			size_t at = 0;
			while (m[at].id != sib)
				at++;
			at += op == 8;
			memmove(&m[at + 1], &m[at], (n - 1 - at) * sizeof *m);
			m[at] = tmp;
			break;
		}
		case 10: { /* configure: a new place, size and border at once */
			if (m[k].look.input_only)
				break;
			uint32_t b = (uint32_t)vis_rng_below(&rng, 4);
			vis_client_configure(mgr, id, x, y, w, h, b);
			m[k].r = (struct vis_rect){ x, y, (int32_t)w, (int32_t)h };
			m[k].look.border = (int32_t)b;
			break;
		}
		case 11:
		case 12: { /* a shape, or an opaque region: rectangles in window coordinates */
			if (m[k].look.input_only)
				break;
			uint32_t count = (uint32_t)vis_rng_below(&rng, 5), mode = 1;
			struct vis_rect32 r32[4];
			struct vis_rect *r = op == 11 ? m[k].shape : m[k].opaque;
			if (op == 12)
				mode = count == 4 ? VIS_OPAQUE_MODE_ALL
				     : count == 0 ? VIS_OPAQUE_MODE_NONE : VIS_OPAQUE_MODE_RECTS;
			else if (count == 4)
				mode = 0; /* back to the border box */
			uint32_t nr = (op == 11 && mode == 1) || (op == 12 && mode == 2) ? count : 0;
			for (uint32_t q = 0; q < nr; q++) {
				r[q] = (struct vis_rect){ (int32_t)vis_rng_range(&rng, -3, m[k].r.w),
							  (int32_t)vis_rng_range(&rng, -3, m[k].r.h),
							  (int32_t)vis_rng_range(&rng, 1, m[k].r.w),
							  (int32_t)vis_rng_range(&rng, 1, m[k].r.h) };
				r32[q] = (struct vis_rect32){ r[q].x, r[q].y, (uint32_t)r[q].w,
							      (uint32_t)r[q].h };
			}
			if (op == 11) {
				vis_client_set_shape(mgr, id, mode, r32, nr);
				m[k].look.shaped = mode == 1;
				m[k].look.n_shape = nr;
			} else {
				vis_client_set_opaque(mgr, id, mode, r32, nr);
				m[k].look.opaque = (uint8_t)mode;
				m[k].look.n_opaque = nr;
			}
			break;
		}
		}
		if (step % 7)
			continue;
		CHECK(vis_client_sync(mgr) == 0, "a change failed at step %d", step);
		struct vis_window_info *t;
		size_t nt;
		struct vis_window_state *st;
		size_t ns;
		CHECK(vis_client_get_tree(mgr, &t, &nt) == 0 && vis_client_get_states(mgr, &st, &ns) == 0,
		      "queries");
		CHECK(nt == n, "step %d: the daemon has %zu windows, the model %zu", step, nt, n);
		struct vis_rect rects[64];
		struct vis_look looks[64];
		uint32_t of[64];
		uint8_t want[64];
		size_t mapped = 0, stateless = 0;
		for (size_t i = 0; i < n; i++) {
			struct vis_look look = m[i].look;
			look.shape = m[i].shape;
			look.opaque_rects = m[i].opaque;
			uint32_t look_flags = (m[i].look.shaped ? VIS_WINDOW_SHAPED : 0) |
					      (vis_look_translucent(&look, m[i].r.w, m[i].r.h) > 0
						       ? VIS_WINDOW_TRANSLUCENT : 0) |
					      (m[i].look.input_only ? VIS_WINDOW_INPUT_ONLY : 0);
			CHECK(t[i].window == m[i].id && t[i].x == m[i].r.x && t[i].y == m[i].r.y &&
				      t[i].width == (uint32_t)m[i].r.w &&
				      t[i].height == (uint32_t)m[i].r.h &&
				      t[i].border == (uint32_t)m[i].look.border &&
				      (t[i].flags & (VIS_WINDOW_SHAPED | VIS_WINDOW_TRANSLUCENT |
						     VIS_WINDOW_INPUT_ONLY)) == look_flags &&
				      !!(t[i].flags & VIS_WINDOW_MAPPED) == m[i].mapped,
			      "step %d: window %zu of the stack is %u, the model says %u", step, i,
			      t[i].window, m[i].id);
			if (m[i].mapped) {
				rects[mapped] = m[i].r;
				looks[mapped] = m[i].look;
				looks[mapped].shape = m[i].shape;
				looks[mapped].opaque_rects = m[i].opaque;
				stateless += m[i].look.input_only;
				of[mapped++] = m[i].id;
			}
		}
		struct vis_stack stack = { rects, mapped, true, SCREEN_W, SCREEN_H, NULL, looks };
		CHECK(vis_compute(VIS_ENGINE_BRUTE, &stack, want) == 0, "brute force");
		CHECK(ns == mapped - stateless, "step %d: %zu states for %zu mapped windows with pixels",
		      step, ns, mapped - stateless);
		vis_client_roundtrip(obs);
		for (size_t i = 0; i < mapped; i++) {
			if (want[i] == VIS_NO_STATE)
				continue; /* input-only: no state, no notice */
			uint32_t got = 99;
			for (size_t q = 0; q < ns; q++)
				if (st[q].window == of[i])
					got = st[q].state;
			CHECK(got == want[i], "step %d: window %u is %s, the core says %s", step, of[i],
			      vis_visibility_name(got), vis_visibility_name(want[i]));
			const struct vis_notice *v = last_visibility(&log, of[i]);
			CHECK(v && v->visibility.state == got,
			      "step %d: the observer's last notice for %u says %s, the state is %s", step,
			      of[i], v ? vis_visibility_name(v->visibility.state) : "nothing",
			      vis_visibility_name(got));
		}
		free(t);
		free(st);
		checks++;
	}
	check_serials(&log);
	vis_client_destroy(mgr);
	vis_client_destroy(obs);
	free(log.v);
}

int main(int argc, char **argv)
{
	if (argc < 2) {
		fprintf(stderr, "usage: test-integration VISD [SEED]\n");
		return 2;
	}
	signal(SIGPIPE, SIG_IGN);
	start_daemon(argv[1]);
	if (argc > 2) {
		test_random(strtoull(argv[2], NULL, 10), 700);
	} else {
		test_requests();
		test_exposure_limit();
		test_errors_and_roles();
		test_fatal();
		test_batch();
		test_newcomer();
		test_children();
		test_disconnect();
		test_external();
		for (uint64_t seed = 1; seed <= 12; seed++)
			test_random(seed, 700);
	}
	current = "shutdown";
	stop_daemon();
	printf("integration: every request, notice and refusal as documented; %d random stacks "
	       "agree with the model and the core\n", checks);
	return 0;
}
