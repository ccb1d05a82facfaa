/*
 * The hostile suite's access cases: window IDs that do not exist for a connection (bad, destroyed,
 * another client's), what a client without a role sees of others, what an observer may do, the
 * restricted socket, the socket's mode, and another uid (when the tests run as root).
 */
#include <errno.h>
#include <grp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hostile.h"
#include "vis/protocol.h"

/*
 * Sends every request with each of its window fields set to bad in turn (the other fields valid),
 * inside a batch if asked, and expects for each a window error (value for unsubscribe, which
 * names a subscription), then that the connection goes on.
 */
static void send_bad_ids(struct harness_conn *c, uint32_t own, uint32_t sibling, uint32_t bad,
			 bool batch)
{
	struct {
		uint32_t seq, op;
	} sent[64];
	size_t n_sent = 0, count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	if (batch)
		harness_req(c, VIS_OP_BATCH_BEGIN);
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *t = &types[i];
		struct harness_field f[VIS_MSG_MAX_ARGS];
		size_t n = harness_fields(t, f);
		if (t->dir != VIS_DIR_REQUEST || t->opcode == VIS_OP_HELLO)
			continue;
		for (size_t k = 0; k < n; k++) {
			/* 0 is the screen as a parent, every window in a subscription. */
			if (!hostile_is_window_field(f[k].name) ||
			    (bad == 0 &&
			     (!strcmp(f[k].name, "parent") || t->opcode == VIS_OP_SUBSCRIBE ||
			      t->opcode == VIS_OP_UNSUBSCRIBE)))
				continue;
			uint32_t words[VIS_MSG_MAX_ARGS];
			size_t nw = hostile_request_words(t, own, sibling, words);
			words[k] = bad;
			CHECK(n_sent < sizeof sent / sizeof *sent, "too many requests");
			sent[n_sent].seq = harness_request(c, t->opcode, words, nw);
			sent[n_sent++].op = t->opcode;
		}
	}
	if (batch)
		harness_req(c, VIS_OP_BATCH_COMMIT);
	for (size_t i = 0; i < n_sent; i++) {
		char reason[60];
		bool unsub = sent[i].op == VIS_OP_UNSUBSCRIBE;
		snprintf(reason, sizeof reason,
			 unsub ? "no subscription to window %u" : "no such window %u", bad);
		harness_expect_error(c, sent[i].seq, sent[i].op,
				     unsub ? VIS_ERROR_VALUE : VIS_ERROR_WINDOW, reason, false);
	}
	harness_sync(c, NULL);
}

/* Window IDs that do not exist for the connection: not fatal, and nothing changes. */
void hostile_access_window_ids(void)
{
	harness_context("bad and foreign window IDs");
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint32_t own = harness_create(&c, 0, 300, 200, 10, 10, VIS_CREATE_MAP);
	uint32_t sibling = harness_create(&c, 0, 320, 200, 10, 10, 0);
	uint32_t gone = harness_create(&c, own, 0, 0, 5, 5, 0);
	harness_req(&c, VIS_OP_DESTROY, gone);
	size_t n_before, n_after;
	struct harness_node *before = harness_get_tree(&c, &n_before);
	/* 0, the largest, a destroyed one, one never made, and the innocent's windows. */
	uint32_t bad[4 + HOSTILE_WINDOWS] = { 0, UINT32_MAX, gone, gone + 1000000 };
	memcpy(bad + 4, hostile_win, sizeof hostile_win);
	for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
		harness_context("bad window ID %u", bad[i]);
		send_bad_ids(&c, own, sibling, bad[i], false);
		send_bad_ids(&c, own, sibling, bad[i], true);
	}
	struct harness_node *after = harness_get_tree(&c, &n_after);
	CHECK(n_after == n_before && !memcmp(before, after, n_after * sizeof *after),
	      "refused requests changed the client's own windows");
	free(before);
	free(after);
	harness_close(&c);
	hostile_check_unaffected();
}

/* Reads replies up to the one to request seq, failing on any error. */
static void expect_no_error(struct harness_conn *c, uint32_t seq)
{
	struct vis_msg m;
	do {
		harness_next_reply(c, &m, NULL);
		CHECK(m.type->opcode != VIS_OP_ERROR, "request %u: error %u: %.*s", m.args[0].u,
		      m.args[2].u, (int)m.args[3].s.len, m.args[3].s.p);
	} while (m.args[0].u != seq);
}

/*
 * Isolation. A client without a role: every request naming another client's window is refused as
 * if it did not exist (hostile_access_window_ids(), with the innocent's windows); here, what it
 * sees in lists, repaints and notices. An observer: sees every window, changes none. The restricted
 * socket.
 */
void hostile_access_isolation(void)
{
	harness_context("isolation");
	struct harness_conn a;
	harness_open_as(&a, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&a, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	uint32_t own = harness_create(&a, 0, 300, 200, 10, 10, VIS_CREATE_MAP);
	size_t n, notices = 0;
	harness_sync(&a, NULL);
	struct harness_node *t = harness_get_tree(&a, &n);
	CHECK(n == 1 && t[0].window == own, "a client sees %zu windows", n);
	free(t);
	struct harness_state *s = harness_get_states(&a, &n);
	CHECK(n == 1 && s[0].window == own, "a client has %zu states", n);
	free(s);
	struct vis_msg m;
	uint32_t seq = harness_req(&a, VIS_OP_GET_REPAINT, 0, 0, 400, 300);
	harness_expect(&a, seq, VIS_OP_REPAINT, &m);
	CHECK(m.args[2].a.n == 1 && vis_arg_word(&m.args[2], 'W', 0, 0) == own,
	      "a client's repaint lists %u windows", m.args[2].a.n);
	/* The innocent changes a window and changes it back: a's subscription hears nothing. */
	harness_req(&hostile_innocent, VIS_OP_MAP, hostile_win[3]);
	harness_req(&hostile_innocent, VIS_OP_MOVE, hostile_win[1], 60, 25);
	harness_sync(&hostile_innocent, &notices);
	harness_req(&hostile_innocent, VIS_OP_UNMAP, hostile_win[3]);
	harness_req(&hostile_innocent, VIS_OP_MOVE, hostile_win[1], 50, 25);
	harness_sync(&hostile_innocent, &notices);
	CHECK(notices >= 4, "the innocent's own changes sent it %zu notices", notices);
	notices = 0;
	harness_sync(&a, &notices);
	CHECK(notices == 0, "a client heard %zu notices about another's windows", notices);
	harness_close(&a);
	hostile_check_unaffected(); /* and a's window gone */

	/* An observer: every request naming the innocent's windows; changes refused. */
	struct harness_conn o;
	harness_open_as(&o, hostile_visd.sock, VIS_ROLE_OBSERVER);
	size_t count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *ty = &types[i];
		struct harness_field f[VIS_MSG_MAX_ARGS];
		size_t nf = harness_fields(ty, f);
		uint32_t words[VIS_MSG_MAX_ARGS];
		bool named = false;
		if (ty->dir != VIS_DIR_REQUEST)
			continue;
		size_t nw = hostile_request_words(ty, hostile_win[0], hostile_win[1], words);
		for (size_t k = 0; k < nf; k++)
			if (!strcmp(f[k].name, "parent")) {
				words[k] = hostile_win[2];
				named = true;
			} else {
				named |= hostile_is_window_field(f[k].name);
			}
		if (!named)
			continue;
		seq = harness_request(&o, ty->opcode, words, nw);
		if ((ty->opcode >= VIS_OP_CREATE && ty->opcode <= VIS_OP_REPARENT) ||
		    (ty->opcode >= VIS_OP_CONFIGURE && ty->opcode <= VIS_OP_SET_OPAQUE))
			harness_expect_error(&o, seq, ty->opcode, VIS_ERROR_ACCESS,
					     "is not yours to change", false);
		else
			expect_no_error(&o, harness_req(&o, VIS_OP_SYNC));
	}
	seq = harness_req(&o, VIS_OP_CREATE, 0, 300, 200, 5, 5, 0, 0, 0, 0, 0);
	harness_expect_error(&o, seq, VIS_OP_CREATE, VIS_ERROR_ACCESS, "observers change nothing",
			     false);
	s = harness_get_states(&o, &n);
	CHECK(n == 4, "an observer sees %zu viewable windows, not 4", n);
	free(s);
	harness_close(&o);

	/* The restricted socket: a client like any other, seeing only its own. */
	struct harness_conn r;
	harness_open_as(&r, hostile_visd.rsock, VIS_ROLE_CLIENT);
	seq = harness_req(&r, VIS_OP_GET_STATE, hostile_win[0]);
	harness_expect_error(&r, seq, VIS_OP_GET_STATE, VIS_ERROR_WINDOW, "no such window", false);
	t = harness_get_tree(&r, &n);
	CHECK(n == 0, "a restricted client sees %zu windows", n);
	free(t);
	harness_close(&r);

	/* The sockets and locks: the owner's only. */
	const char *paths[] = { hostile_visd.sock, hostile_visd.rsock };
	for (size_t i = 0; i < 2; i++) {
		char lock[128];
		snprintf(lock, sizeof lock, "%s.lock", paths[i]);
		struct stat st, sl;
		CHECK(stat(paths[i], &st) == 0 && stat(lock, &sl) == 0, "stat %s: %s", paths[i],
		      strerror(errno));
		CHECK(S_ISSOCK(st.st_mode) && !(st.st_mode & 077) && !(sl.st_mode & 077) &&
			      st.st_uid == geteuid(),
		      "%s has mode %o, its lock %o", paths[i], st.st_mode & 07777,
		      sl.st_mode & 07777);
	}
	hostile_check_unaffected();
}

/* A stack notice as a client got it. */
struct stack_seen {
	uint32_t change, window, parent, sibling;
	int32_t x, y;
};

static struct stack_seen stack_seen[16];
static size_t n_stack_seen;

/* The notice hook of the stack cases: keeps the stack notices. */
static void keep_stack(void *data, const struct vis_msg *m)
{
	(void)data;
	if (m->type->opcode != VIS_OP_STACK)
		return;
	CHECK(n_stack_seen < sizeof stack_seen / sizeof *stack_seen, "too many stack notices");
	const union vis_arg *a = m->args;
	stack_seen[n_stack_seen++] =
		(struct stack_seen){ a[1].u, a[2].u, a[3].u, a[8].u, a[4].i, a[5].i };
}

/* Syncs c and expects the stack notices it got since the last call to be want[0 … n − 1]. */
static void expect_stack(struct harness_conn *c, const struct stack_seen *want, size_t n)
{
	harness_sync(c, NULL);
	CHECK(n_stack_seen == n, "%zu stack notices, wanted %zu", n_stack_seen, n);
	for (size_t i = 0; i < n; i++) {
		const struct stack_seen *g = &stack_seen[i], *w = &want[i];
		CHECK(g->change == w->change && g->window == w->window && g->parent == w->parent &&
			      g->sibling == w->sibling && g->x == w->x && g->y == w->y,
		      "stack notice %zu: change %u window %u parent %u at %d,%d sibling %u; wanted "
		      "change %u window %u parent %u at %d,%d sibling %u",
		      i, g->change, g->window, g->parent, g->x, g->y, g->sibling, w->change,
		      w->window, w->parent, w->x, w->y, w->sibling);
	}
	n_stack_seen = 0;
}

static void expect_one(struct harness_conn *c, struct stack_seen want)
{
	expect_stack(c, &want, 1);
}

/*
 * A client's stack notices and tree name no window it may not see: its sibling is the window
 * just below if that is its own, its parent 0 when the parent is not its own (x, y still
 * relative to it). The innocent's windows lie below a new top-level window, the manager's
 * between a client's windows under the manager's frame and under the client's own window; and
 * the frame's destruction destroys the client's windows in it, top one first.
 */
void hostile_access_stack_notices(void)
{
	const char *paths[] = { hostile_visd.sock, hostile_visd.rsock };
	for (size_t i = 0; i < 2; i++) {
		harness_context("stack notices name no other client's window%s",
				i ? " (restricted socket)" : "");
		struct harness_conn b, mgr;
		harness_open_as(&b, paths[i], VIS_ROLE_CLIENT);
		b.on_notice = keep_stack;
		n_stack_seen = 0;
		harness_req(&b, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_STACK, 0);
		/* Above the innocent's top-level windows: none of them is b's sibling. */
		uint32_t b1 = harness_create(&b, 0, 300, 200, 10, 10, VIS_CREATE_MAP);
		expect_stack(&b,
			     (const struct stack_seen[]){ { VIS_STACK_CREATE, b1, 0, 0, 300, 200 },
							  { VIS_STACK_MAP, b1, 0, 0, 300, 200 } },
			     2);
		uint32_t seq = harness_req(&b, VIS_OP_GET_STATE, hostile_win[4]);
		harness_expect_error(&b, seq, VIS_OP_GET_STATE, VIS_ERROR_WINDOW, "no such window",
				     false);
		uint32_t b2 = harness_create(&b, 0, 320, 200, 10, 10, 0);
		expect_one(&b, (struct stack_seen){ VIS_STACK_CREATE, b2, 0, b1, 320, 200 });
		harness_req(&b, VIS_OP_LOWER, b2);
		expect_one(&b, (struct stack_seen){ VIS_STACK_RESTACK, b2, 0, 0, 320, 200 });

		/* The manager's frame, with b2 in it above a window of the manager's. */
		harness_open_as(&mgr, hostile_visd.sock, VIS_ROLE_MANAGER);
		uint32_t frame = harness_create(&mgr, 0, 340, 200, 40, 40, VIS_CREATE_MAP);
		uint32_t b3 = harness_create(&b, 0, 360, 200, 10, 10, 0);
		harness_create(&mgr, frame, 0, 0, 5, 5, VIS_CREATE_MAP);
		harness_req(&mgr, VIS_OP_REPARENT, b2, frame, 1, 2);
		harness_create(&mgr, frame, 0, 0, 5, 5, 0);
		harness_req(&mgr, VIS_OP_REPARENT, b3, frame, 3, 4);
		harness_sync(&mgr, NULL);
		expect_stack(&b,
			     (const struct stack_seen[]){ { VIS_STACK_CREATE, b3, 0, 0, 360, 200 },
							  { VIS_STACK_REPARENT, b2, 0, 0, 1, 2 },
							  { VIS_STACK_REPARENT, b3, 0, 0, 3, 4 } },
			     3);
		/* A window of the manager's under b1, then one of b's above it. */
		harness_create(&mgr, b1, 0, 0, 5, 5, VIS_CREATE_MAP);
		uint32_t b4 = harness_create(&b, b1, 1, 1, 2, 2, 0);
		expect_one(&b, (struct stack_seen){ VIS_STACK_CREATE, b4, b1, 0, 1, 1 });
		size_t n;
		struct harness_node *t = harness_get_tree(&b, &n);
		const uint32_t hid = VIS_WINDOW_PARENT_HIDDEN;
		CHECK(n == 4 && t[0].window == b1 && t[0].parent == 0 && !(t[0].flags & hid) &&
			      t[1].window == b4 && t[1].parent == b1 && !(t[1].flags & hid) &&
			      t[2].window == b2 && t[2].parent == 0 && t[2].x == 1 &&
			      (t[2].flags & hid) && t[3].window == b3 && t[3].parent == 0 &&
			      t[3].y == 4 && (t[3].flags & hid),
		      "the client's tree: %zu windows, %u (parent %u), %u (parent %u), …", n,
		      n ? t[0].window : 0, n ? t[0].parent : 0, n > 1 ? t[1].window : 0,
		      n > 1 ? t[1].parent : 0);
		free(t);
		/* The frame goes: its windows with it, the top one first. */
		harness_req(&mgr, VIS_OP_DESTROY, frame);
		harness_sync(&mgr, NULL);
		expect_stack(&b,
			     (const struct stack_seen[]){ { VIS_STACK_DESTROY, b3, 0, 0, 3, 4 },
							  { VIS_STACK_DESTROY, b2, 0, 0, 1, 2 } },
			     2);
		harness_close(&mgr);
		expect_stack(&b, NULL, 0); /* the manager's window under b1 went: nothing to say */
		harness_close(&b);
		hostile_check_unaffected();
	}
}

/* Runs check in a child process under another uid; returns false if it cannot switch. */
static bool as_other_uid(void (*check)(void))
{
	const uid_t nobody = 65534;
	fflush(NULL);
	pid_t pid = fork();
	CHECK(pid >= 0, "fork: %s", strerror(errno));
	if (pid == 0) {
		if (setgroups(0, NULL) < 0 || setgid(nobody) < 0 || setuid(nobody) < 0)
			_exit(77);
		check(); /* a failed CHECK exits the child with status 1 */
		_exit(0);
	}
	int status;
	CHECK(waitpid(pid, &status, 0) == pid, "waitpid: %s", strerror(errno));
	CHECK(WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 77),
	      "the check under another uid failed (status %#x)", status);
	return WEXITSTATUS(status) == 0;
}

/* Another uid cannot reach the socket: its directory and the socket are the owner's only. */
static void cannot_connect(void)
{
	int fd = harness_connect(hostile_visd.sock);
	CHECK(fd < 0 && errno == EACCES, "another uid connected (%s)", strerror(errno));
}

/* Another uid that reaches the socket (opened up by hand) gets no role: SO_PEERCRED. */
static void gets_no_role(void)
{
	hostile_expect_no_role(hostile_visd.sock, "the peer's uid is not allowed roles");
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint32_t seq = harness_req(&c, VIS_OP_GET_STATE, hostile_win[0]);
	harness_expect_error(&c, seq, VIS_OP_GET_STATE, VIS_ERROR_WINDOW, "no such window", false);
	harness_close(&c);
}

void hostile_access_other_uid(void)
{
	harness_context("another uid");
	if (geteuid() != 0 || !as_other_uid(cannot_connect)) {
		printf("hostile: cannot run as another uid (not root): other-uid cases skipped\n");
		return;
	}
	CHECK(chmod(hostile_visd.dir, 0711) == 0 && chmod(hostile_visd.sock, 0666) == 0,
	      "chmod: %s", strerror(errno));
	as_other_uid(gets_no_role);
	CHECK(chmod(hostile_visd.dir, 0700) == 0 && chmod(hostile_visd.sock, 0600) == 0,
	      "chmod: %s", strerror(errno));
	hostile_check_unaffected();
}
