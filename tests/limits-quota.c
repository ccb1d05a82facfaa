/*
 * The limits suite's cases on connections that others hold: another uid flooding the restricted
 * socket cannot lock the daemon's owner out, each bound on connections refuses with its option's
 * name, and a connection that never completes hello is closed after --hello-timeout. The cases of
 * other uids run in children that setuid to them, so only as root; otherwise they are skipped
 * with a note.
 */
#include <errno.h>
#include <grp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "limits.h"
#include "vis/protocol.h"

/* More connections than any case's bound allows: a flood that gets them all was never refused. */
#define FLOOD_MAX 64

/* A child that holds connections of another uid open until killed. */
struct flood {
	pid_t pid;
	int accepted;
};

/*
 * Forks a child that becomes uid (and its gid) and connects to sock until refused, with a refusal
 * naming reason (any when NULL); it reports how many it holds and keeps them until killed.
 * False, with nothing started, when it cannot become uid (not root).
 */
static bool flood_as(struct flood *f, uid_t uid, const char *sock, const char *reason)
{
	int report[2];
	CHECK(pipe(report) == 0, "pipe: %s", strerror(errno));
	fflush(NULL);
	f->pid = fork();
	CHECK(f->pid >= 0, "fork: %s", strerror(errno));
	if (f->pid == 0) {
		close(report[0]);
		if (setgroups(0, NULL) < 0 || setgid(uid) < 0 || setuid(uid) < 0)
			_exit(77);
		/* A failing test must not leave it behind; after setuid(), which clears this. */
		prctl(PR_SET_PDEATHSIG, SIGKILL);
		static struct harness_conn conn[FLOOD_MAX + 1];
		int n = 0;
		while (limits_try_hello(&conn[n], sock, reason))
			CHECK(++n <= FLOOD_MAX, "uid %u: %d connections and never refused",
			      (unsigned)uid, n);
		CHECK(write(report[1], &n, sizeof n) == sizeof n, "write: %s", strerror(errno));
		for (;;)
			pause();
	}
	close(report[1]);
	ssize_t got = read(report[0], &f->accepted, sizeof f->accepted);
	close(report[0]);
	if (got == sizeof f->accepted)
		return true;
	int status;
	CHECK(waitpid(f->pid, &status, 0) == f->pid, "waitpid: %s", strerror(errno));
	CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 77,
	      "the flood as uid %u failed (status %#x)", (unsigned)uid, status);
	return false;
}

/* Ends a flood: its connections close with it. */
static void flood_stop(struct flood *f)
{
	kill(f->pid, SIGKILL);
	CHECK(waitpid(f->pid, NULL, 0) == f->pid, "waitpid: %s", strerror(errno));
}

/* Lets other uids reach both sockets, as a daemon serving them would (the harness's are 0600). */
static void open_sockets(const struct harness_daemon *d)
{
	CHECK(chmod(d->dir, 0711) == 0 && chmod(d->sock, 0666) == 0 && chmod(d->rsock, 0666) == 0,
	      "chmod: %s", strerror(errno));
}

/* Opens connections of the daemon's uid to sock until refused for reason; returns how many. */
static int fill(struct harness_conn *conn, int max, const char *sock, const char *reason)
{
	int n = 0;
	while (limits_try_hello(&conn[n], sock, reason))
		CHECK(++n < max, "%d connections and never refused", n);
	return n;
}

static void close_all(struct harness_conn *conn, int n)
{
	for (int i = 0; i < n; i++)
		harness_close(&conn[i]);
}

/*
 * The lockout: another uid opens connections on the restricted socket until refused; the owner
 * must still get in on the main socket. Only --max-clients is given, which every visd takes: the
 * case is the attack itself, whichever bound stops it (here the default reserve, half of 40).
 */
void limits_quota_lockout(void)
{
	harness_context("another uid floods the restricted socket");
	if (geteuid() != 0) {
		printf("limits: not root: the other-uid flood is skipped\n");
		return;
	}
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, (const char *[]){ "--max-clients", "40", NULL });
	open_sockets(&d);
	struct flood f;
	CHECK(flood_as(&f, 65534, d.rsock, NULL), "cannot run as uid 65534");
	struct harness_conn c;
	CHECK(limits_try_hello(&c, d.sock, NULL),
	      "uid 65534 holds %d connections and the owner is refused", f.accepted);
	harness_create(&c, 0, 0, 0, 10, 10, VIS_CREATE_MAP);
	printf("limits: uid 65534 got %d of 40 slots; the owner got in\n", f.accepted);
	harness_close(&c);
	flood_stop(&f);
	harness_stop(&d);
}

/*
 * Each bound on connections refuses with its option's name: the restricted socket's (24) for the
 * owner too; then, as root, one uid's (16), the restricted socket's again across uids, the owner's
 * reserve (the last 8 of 40) against a third uid on the main socket, and --max-clients for the
 * owner, who alone may fill the reserve.
 */
void limits_quota_connections(void)
{
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd,
		      (const char *[]){ "--max-clients", "40", "--owner-reserve", "8",
					"--max-clients-per-uid", "16", "--max-restricted-clients",
					"24", NULL });
	static struct harness_conn conn[41];
	int base_fds = harness_count_fds(&d);

	harness_context("connections on the restricted socket");
	int n = fill(conn, 41, d.rsock, "--max-restricted-clients");
	CHECK(n == 24, "the restricted socket took %d connections, not 24", n);
	CHECK(strstr(limits_read_log(&d), "--max-restricted-clients"), "the refusal is not logged");
	close_all(conn, n);
	harness_wait_fds(&d, base_fds);

	harness_context("connections per uid and the owner's reserve");
	open_sockets(&d);
	struct flood a, b, c;
	if (!flood_as(&a, 65534, d.rsock, "--max-clients-per-uid")) {
		printf("limits: not root: the per-uid bounds are skipped\n");
		harness_stop(&d);
		return;
	}
	CHECK(a.accepted == 16, "uid 65534 got %d connections, not 16", a.accepted);
	CHECK(flood_as(&b, 65533, d.rsock, "--max-restricted-clients") && b.accepted == 8,
	      "uid 65533 got %d connections on the restricted socket, not the 8 left", b.accepted);
	CHECK(flood_as(&c, 65532, d.sock, "--owner-reserve") && c.accepted == 8,
	      "uid 65532 got %d connections on the main socket, not 8 before the reserve",
	      c.accepted);
	n = fill(conn, 41, d.sock, "--max-clients");
	CHECK(n == 8, "the owner got %d of the reserve's 8 slots", n);
	harness_sync(&conn[0], NULL);
	close_all(conn, n);
	flood_stop(&a);
	flood_stop(&b);
	flood_stop(&c);
	harness_wait_fds(&d, base_fds);
	/* Every count went back: each uid gets its share again. */
	CHECK(flood_as(&a, 65534, d.rsock, "--max-clients-per-uid") && a.accepted == 16,
	      "after the floods, uid 65534 got %d connections, not 16", a.accepted);
	flood_stop(&a);
	harness_stop(&d);
}

static double now_s(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec + t.tv_nsec / 1e9;
}

/*
 * --hello-timeout 1: a connection that sends nothing, and one that sends half a hello, get a
 * handshake error naming the option after a second, then the end; one that completed hello
 * before them and idles since is served still.
 */
void limits_quota_hello_timeout(void)
{
	harness_context("hello timeout");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, (const char *[]){ "--hello-timeout", "1", NULL });
	struct harness_conn idle, silent, partial;
	harness_open(&idle, d.sock);
	harness_hello(&idle, VIS_ROLE_CLIENT);
	double start = now_s();
	harness_open(&silent, d.sock);
	harness_open(&partial, d.rsock);
	uint8_t hello[VIS_MSG_HEADER + 12];
	harness_build(hello, VIS_OP_HELLO,
		      (const uint32_t[]){ VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, 0 }, 3);
	CHECK(harness_send(&partial, hello, 10) == 0, "send: %s", strerror(errno));
	harness_expect_error(&silent, 1, VIS_OP_HELLO, VIS_ERROR_HANDSHAKE,
			     "no hello within 1 s (visd --hello-timeout)", true);
	double waited = now_s() - start;
	CHECK(waited > 0.9, "a silent connection was closed after %.2f s, before its deadline",
	      waited);
	harness_expect_error(&partial, 1, VIS_OP_HELLO, VIS_ERROR_HANDSHAKE, "--hello-timeout",
			     true);
	/* Its deadline passed before theirs: it would have been closed by now. */
	harness_create(&idle, 0, 0, 0, 10, 10, VIS_CREATE_MAP);
	CHECK(strstr(limits_read_log(&d), "no hello within 1 s (visd --hello-timeout)"),
	      "the timeout is not logged");
	harness_close(&silent);
	harness_close(&partial);
	harness_close(&idle);
	harness_stop(&d);
}

/* Waits until the manager sees n windows: the daemon has dropped a departed client's windows. */
static void wait_windows(struct harness_conn *m, size_t n)
{
	char what[80];
	for (struct progress p = harness_working(NULL);;) {
		size_t k;
		free(harness_get_tree(m, &k));
		if (k == n)
			return;
		snprintf(what, sizeof what, "the manager sees %zu windows, not %zu", k, n);
		harness_still_working(&p, what);
	}
}

/* Expects a retained window's creation on c to be refused for reason, and c to go on. */
static void refused_retain(struct harness_conn *c, const char *reason)
{
	uint32_t seq = harness_req(c, VIS_OP_CREATE, 0, 500, 0, 5, 5, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	limits_expect_limit(c, seq, VIS_OP_CREATE, reason);
}

/* The socket another uid's case connects to. */
static const char *other_sock;

/*
 * Runs a case as uid 65534 in a child, on d's restricted socket (opened to others): false when
 * it was skipped (not root), with a note naming what.
 */
static bool as_other_uid(const struct harness_daemon *d, void (*run)(void), const char *what)
{
	open_sockets(d);
	other_sock = d->rsock;
	fflush(NULL);
	pid_t pid = fork();
	CHECK(pid >= 0, "fork: %s", strerror(errno));
	if (pid == 0) {
		if (setgroups(0, NULL) < 0 || setgid(65534) < 0 || setuid(65534) < 0)
			_exit(77);
		run();
		_exit(0);
	}
	int status;
	CHECK(waitpid(pid, &status, 0) == pid, "waitpid: %s", strerror(errno));
	CHECK(WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 77),
	      "the case as uid 65534 failed (status %#x)", status);
	if (WEXITSTATUS(status) == 77)
		printf("limits: not root: %s of another uid are skipped\n", what);
	return WEXITSTATUS(status) == 0;
}

/* As uid 65534: two retained windows fill the total of 8, a third is refused for it. */
static void retain_as_other(void)
{
	struct harness_conn c;
	harness_open_as(&c, other_sock, VIS_ROLE_CLIENT);
	harness_create(&c, 0, 600, 0, 5, 5, VIS_CREATE_RETAIN);
	harness_create(&c, 0, 610, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&c, "8 retained windows exist, the limit (visd --max-retained)");
	harness_close(&c);
}

/*
 * Retained windows outlive their connections, so they are bounded per uid and in all, whether
 * their connections are alive or gone: with --max-retained-per-uid 6 --max-retained 8, the
 * owner's connections come and go, leaving retained windows, until one is refused; destroying
 * some, alone or as part of a subtree, makes room again. As root, another uid is refused once
 * the total is reached. Then, with --max-retained 3 alone, the total for one uid.
 */
void limits_quota_retained(void)
{
	harness_context("retained windows per uid");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd,
		      (const char *[]){ "--max-retained-per-uid", "6", "--max-retained", "8", NULL });
	const char *per_uid = "has 6 retained windows, the limit (visd --max-retained-per-uid)";
	struct harness_conn m, a, b;
	harness_open_as(&m, d.sock, VIS_ROLE_MANAGER);
	harness_open_as(&a, d.sock, VIS_ROLE_CLIENT);
	uint32_t r1 = harness_create(&a, 0, 0, 0, 50, 50, VIS_CREATE_RETAIN);
	harness_create(&a, r1, 0, 0, 5, 5, VIS_CREATE_RETAIN);
	uint32_t r3 = harness_create(&a, 0, 60, 0, 5, 5, VIS_CREATE_RETAIN);
	harness_create(&a, 0, 70, 0, 5, 5, VIS_CREATE_RETAIN);
	harness_create(&a, 0, 80, 0, 5, 5, 0); /* not retained: counts for nothing */
	harness_close(&a);
	wait_windows(&m, 4);
	harness_open_as(&b, d.sock, VIS_ROLE_CLIENT);
	harness_create(&b, 0, 100, 0, 5, 5, VIS_CREATE_RETAIN);
	harness_create(&b, 0, 110, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&b, per_uid);
	harness_create(&b, 0, 120, 0, 5, 5, VIS_CREATE_MAP);

	harness_context("destroyed retained windows make room");
	harness_req(&m, VIS_OP_DESTROY, r1); /* and its retained child */
	harness_sync(&m, NULL);
	harness_create(&b, 0, 130, 0, 5, 5, VIS_CREATE_RETAIN);
	uint32_t b4 = harness_create(&b, 0, 140, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&b, per_uid);
	harness_req(&b, VIS_OP_DESTROY, b4);
	harness_create(&b, 0, 150, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&b, per_uid);
	harness_close(&b);
	wait_windows(&m, 6);
	harness_open_as(&b, d.sock, VIS_ROLE_CLIENT);
	refused_retain(&b, per_uid);

	harness_context("retained windows in all, across uids");
	if (!as_other_uid(&d, retain_as_other, "retained windows")) {
		wait_windows(&m, 8); /* its retained windows stay */
		harness_req(&m, VIS_OP_DESTROY, r3);
		harness_create(&b, 0, 160, 0, 5, 5, VIS_CREATE_RETAIN);
		refused_retain(&b, per_uid);
	}
	harness_close(&b);
	harness_close(&m);
	harness_stop(&d);

	harness_context("retained windows in all");
	harness_start(&d, limits_visd, (const char *[]){ "--max-retained", "3", NULL });
	const char *total = "3 retained windows exist, the limit (visd --max-retained)";
	harness_open_as(&m, d.sock, VIS_ROLE_MANAGER);
	harness_open_as(&a, d.sock, VIS_ROLE_CLIENT);
	harness_create(&a, 0, 0, 0, 5, 5, VIS_CREATE_RETAIN);
	uint32_t gone = harness_create(&a, 0, 10, 0, 5, 5, VIS_CREATE_RETAIN);
	harness_close(&a);
	wait_windows(&m, 2);
	harness_open_as(&b, d.sock, VIS_ROLE_CLIENT);
	harness_create(&b, 0, 20, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&b, total);
	harness_req(&m, VIS_OP_DESTROY, gone);
	harness_sync(&m, NULL);
	harness_create(&b, 0, 30, 0, 5, 5, VIS_CREATE_RETAIN);
	refused_retain(&b, total);
	harness_close(&b);
	harness_close(&m);
	harness_stop(&d);
}

/* Eight squares apart, a piece each: a shape of the first n has n pieces. */
static const uint32_t squares[] = { 0, 0, 1, 1, 2, 0, 1, 1, 4, 0, 1, 1, 6, 0, 1, 1,
				    8, 0, 1, 1, 10, 0, 1, 1, 12, 0, 1, 1, 14, 0, 1, 1 };

/* Expects a shape of n squares on c's window w to be refused for reason, one of fits to pass. */
static void shape_refused(struct harness_conn *c, uint32_t w, uint32_t n, const char *reason,
			  uint32_t fits)
{
	uint32_t seq = harness_look(c, VIS_OP_SET_SHAPE, w, 1, squares, n);
	limits_expect_limit(c, seq, VIS_OP_SET_SHAPE, reason);
	harness_look(c, VIS_OP_SET_SHAPE, w, 1, squares, fits);
	harness_sync(c, NULL);
}

/* As uid 65534, on other_sock: two connections of 8 look pieces each, where the uid has 10. */
static void look_pieces_as_other(void)
{
	struct harness_conn a, b;
	harness_open_as(&a, other_sock, VIS_ROLE_CLIENT);
	harness_open_as(&b, other_sock, VIS_ROLE_CLIENT);
	uint32_t wa = harness_create(&a, 0, 0, 0, 20, 20, VIS_CREATE_MAP);
	uint32_t wb = harness_create(&b, 0, 0, 0, 20, 20, VIS_CREATE_MAP);
	harness_look(&a, VIS_OP_SET_SHAPE, wa, 1, squares, 8);
	harness_sync(&a, NULL);
	shape_refused(&b, wb, 8,
		      "the windows of uid 65534 would have 16 look pieces, past the limit of 10 "
		      "(visd --max-look-pieces)",
		      2);
	harness_close(&a);
	harness_close(&b);
}

/*
 * Look pieces are the cost of every recompute, so what one party holds is bounded however it
 * spreads them: retained windows left behind count against the connections of their uid that
 * follow (else a client could leave looks behind and connect again, without end), until they are
 * destroyed; and, as root, another uid's connections share one allowance.
 */
void limits_quota_look_pieces(void)
{
	harness_context("look pieces of retained windows left behind");
	struct harness_daemon d = { 0 };
	harness_start(&d, limits_visd, (const char *[]){ "--max-look-pieces", "10", NULL });
	struct harness_conn m, a, b;
	harness_open_as(&m, d.sock, VIS_ROLE_MANAGER);
	harness_open_as(&a, d.sock, VIS_ROLE_CLIENT);
	uint32_t left = harness_create(&a, 0, 0, 0, 20, 20, VIS_CREATE_RETAIN | VIS_CREATE_MAP);
	harness_look(&a, VIS_OP_SET_SHAPE, left, 1, squares, 8);
	harness_close(&a);
	wait_windows(&m, 1);
	harness_open_as(&b, d.sock, VIS_ROLE_CLIENT);
	uint32_t w = harness_create(&b, 0, 30, 0, 20, 20, VIS_CREATE_MAP);
	shape_refused(&b, w, 4,
		      "(with those its uid left retained) would have 12 look pieces, past the limit "
		      "of 10 (visd --max-look-pieces)",
		      2);
	harness_req(&m, VIS_OP_DESTROY, left);
	harness_sync(&m, NULL);
	harness_look(&b, VIS_OP_SET_SHAPE, w, 1, squares, 8);
	harness_sync(&b, NULL);
	harness_close(&b);

	harness_context("look pieces of the manager's windows: the desktop's own");
	uint32_t desk = harness_create(&m, 0, 0, 40, 20, 20, VIS_CREATE_MAP);
	harness_look(&m, VIS_OP_SET_SHAPE, desk, 1, squares, 8);
	desk = harness_create(&m, 0, 0, 40, 20, 20, VIS_CREATE_MAP);
	harness_look(&m, VIS_OP_SET_SHAPE, desk, 1, squares, 8);
	harness_sync(&m, NULL);

	harness_context("look pieces of another uid's connections");
	as_other_uid(&d, look_pieces_as_other, "look pieces");
	harness_close(&m);
	harness_stop(&d);
}
