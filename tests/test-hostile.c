/*
 * Hostile clients against a real visd, with raw bytes: every class of malformed input gets an
 * error naming the request (its sequence number and opcode) and the reason, then the end of that
 * connection; bad and foreign window IDs get a window error and the connection stays; clients
 * without a role can neither change nor see another client's windows; no role on the restricted
 * socket or for another uid; no message to a client names a window it may not see (seeded random
 * runs: a failure prints the seed; `test-hostile VISD --seed S` reruns one alone). After each case
 * an innocent client, whose windows have known states, must find them unchanged and get no
 * notice, a new connection must work, the daemon must hold its descriptors of before (the dropped
 * connections are freed), and its stderr must hold no sanitizer report.
 * Usage: test-hostile VISD [--seed S]
 */
#include <errno.h>
#include <grp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "hostile.h"
#include "vis/protocol.h"
#include "wire.h"

struct harness_daemon hostile_visd;
struct harness_conn hostile_innocent;
uint32_t hostile_win[HOSTILE_WINDOWS];
static struct harness_node *base; /* the innocent's tree as it must stay */
static size_t n_base;
static int base_fds; /* the daemon's descriptors with the innocent connected */

/* The innocent's windows and their states; the hostile ones stay right of x = 200 or unmapped. */
static const struct {
	int parent; /* index in win, or -1 for the screen */
	int32_t x, y;
	uint32_t w, h, flags, state;
} layout[HOSTILE_WINDOWS] = {
	{ -1, 0, 0, 100, 50, VIS_CREATE_MAP, VIS_VISIBILITY_PARTIALLY_OBSCURED },
	{ -1, 50, 25, 100, 50, VIS_CREATE_MAP, VIS_VISIBILITY_UNOBSCURED },
	{ 0, 10, 10, 20, 20, VIS_CREATE_MAP, VIS_VISIBILITY_UNOBSCURED },
	{ -1, 0, 100, 30, 30, 0, VIS_VISIBILITY_NONE },
	{ -1, 1000, 1000, 10, 10, VIS_CREATE_MAP | VIS_CREATE_RETAIN,
	  VIS_VISIBILITY_FULLY_OBSCURED },
};

bool hostile_is_window_field(const char *name)
{
	return !strcmp(name, "window") || !strcmp(name, "parent") || !strcmp(name, "sibling");
}

size_t hostile_request_words(const struct vis_msg_type *t, uint32_t own, uint32_t sibling,
			     uint32_t *words)
{
	struct harness_field f[VIS_MSG_MAX_ARGS];
	size_t n = harness_fields(t, f), at = 0;
	for (size_t k = 0; k < n; k++) {
		static const struct {
			const char *name;
			uint32_t value;
		} plain[] = { { "magic", VIS_PROTOCOL_MAGIC },
			      { "version", VIS_PROTOCOL_VERSION },
			      { "role", VIS_ROLE_CLIENT },
			      { "parent", VIS_WINDOW_ROOT },
			      { "x", 300 },
			      { "y", 200 },
			      { "width", 10 },
			      { "height", 10 },
			      { "flags", 0 },
			      { "border", 0 },
			      { "shaped", 0 },
			      { "rects", 0 }, /* an empty array: its count */
			      { "mode", 0 },
			      { "mask", VIS_NOTICE_ALL },
			      { "rect_limit", 0 },
			      { "namespace", VIS_EXTERNAL_NONE } };
		/* Every request's fields are words, but arrays, sent empty: a count of 0, and 64-bit
		 * ones (an external ID, 0), two words after every other field, so that word k is
		 * still field k for the others. */
		if (f[k].type == 'q') {
			words[at++] = 0;
			words[at++] = 0;
			continue;
		}
		CHECK(at == k && (f[k].type == 'u' || f[k].type == 'i' || f[k].type == 'R'),
		      "%s: field %s of type %c", t->name, f[k].name, f[k].type);
		at++;
		bool known = true;
		if (!strcmp(f[k].name, "window"))
			words[k] = own;
		else if (!strcmp(f[k].name, "sibling"))
			words[k] = sibling;
		else
			known = false;
		for (size_t i = 0; !known && i < sizeof plain / sizeof *plain; i++)
			if (!strcmp(f[k].name, plain[i].name)) {
				words[k] = plain[i].value;
				known = true;
			}
		CHECK(known, "%s: no value for field %s", t->name, f[k].name);
	}
	return at;
}

void hostile_check_unaffected(void)
{
	harness_check_alive(&hostile_visd);
	harness_wait_fds(&hostile_visd, base_fds);
	struct harness_conn c;
	size_t notices = 0, n;
	/* Connections still in the listening backlog run what they sent once accepted: wait. */
	char what[80];
	for (struct progress p = harness_working(&hostile_visd);;) {
		harness_open_as(&c, hostile_visd.sock, VIS_ROLE_OBSERVER);
		free(harness_get_tree(&c, &n));
		harness_close(&c);
		if (n == HOSTILE_WINDOWS)
			break;
		snprintf(what, sizeof what, "%zu windows, only the innocent's %d should be left", n,
			 HOSTILE_WINDOWS);
		harness_still_working(&p, what);
	}
	harness_sync(&hostile_innocent, &notices);
	CHECK(notices == 0, "the innocent client got %zu notices", notices);
	struct harness_node *t = harness_get_tree(&hostile_innocent, &n);
	CHECK(n == n_base && !memcmp(t, base, n * sizeof *t), "the innocent's windows changed");
	free(t);
	struct harness_state *s = harness_get_states(&hostile_innocent, &n);
	size_t k = 0;
	for (size_t i = 0; i < HOSTILE_WINDOWS; i++) {
		if (layout[i].state == VIS_VISIBILITY_NONE)
			continue;
		size_t j = 0; /* ascending ID, not the order they were created in */
		while (j < n && s[j].window != hostile_win[i])
			j++;
		CHECK(j < n && s[j].state == layout[i].state, "the innocent's window %u is not %u",
		      hostile_win[i], layout[i].state);
		k++;
	}
	CHECK(k == n, "the innocent has %zu viewable windows, not %zu", n, k);
	free(s);
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint32_t w = harness_create(&c, 0, 300, 200, 10, 10, 0);
	struct vis_msg m;
	harness_expect(&c, harness_req(&c, VIS_OP_GET_STATE, w), VIS_OP_STATE, &m);
	CHECK(m.args[2].u == VIS_VISIBILITY_NONE, "a new window's state is %u", m.args[2].u);
	harness_close(&c);
	harness_wait_fds(&hostile_visd, base_fds);
}

void hostile_destroy_leftovers(void)
{
	struct harness_conn mgr;
	harness_open_as(&mgr, hostile_visd.sock, VIS_ROLE_MANAGER);
	size_t n;
	struct harness_node *t = harness_get_tree(&mgr, &n);
	for (size_t i = 0; i < n; i++) {
		bool ours = false;
		for (size_t k = 0; k < HOSTILE_WINDOWS; k++)
			ours |= t[i].window == hostile_win[k];
		if (!ours && t[i].parent == VIS_WINDOW_ROOT)
			harness_req(&mgr, VIS_OP_DESTROY, t[i].window);
	}
	free(t);
	harness_sync(&mgr, NULL);
	harness_close(&mgr);
}

static void setup(void)
{
	harness_context("setup");
	harness_open_as(&hostile_innocent, hostile_visd.sock, VIS_ROLE_CLIENT);
	for (size_t i = 0; i < HOSTILE_WINDOWS; i++)
		hostile_win[i] = harness_create(
			&hostile_innocent, layout[i].parent < 0 ? 0 : hostile_win[layout[i].parent],
			layout[i].x, layout[i].y, layout[i].w, layout[i].h, layout[i].flags);
	harness_req(&hostile_innocent, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	harness_sync(&hostile_innocent, NULL);
	base = harness_get_tree(&hostile_innocent, &n_base);
	base_fds = harness_count_fds(&hostile_visd);
	hostile_check_unaffected();
}

/* Declared sizes: under the header, the header, past the fields, the maximum and past it. */
static void test_lengths(const char *path, uint32_t max)
{
	harness_context("declared lengths, maximum %u", max);
	/* body: send the declared size in full (the daemon must wait for it); else the header alone
	 * (the daemon must decide on the header, before reading or allocating anything). */
	const struct {
		uint32_t size;
		bool body;
		const char *reason;
	} table[] = {
		{ 0, false, "declared size %u is less than the 8-byte header" },
		{ 1, false, "declared size %u is less than the 8-byte header" },
		{ VIS_MSG_HEADER - 1, false, "declared size %u is less than the 8-byte header" },
		{ VIS_MSG_HEADER, true, "map: %u bytes declared, too few for its fields" },
		{ 13, false, "declared size %u is not a multiple of 4" },
		{ 16, true, "map: %u bytes declared, the fields take 12" },
		{ max, true, "map: %u bytes declared, the fields take 12" },
		{ max + 1, false, "declared size %u is over the maximum" },
		{ max + 4, false, "declared size %u is over the maximum" },
		{ UINT32_MAX - 3, false, "declared size %u is over the maximum" },
		{ UINT32_MAX, false, "declared size %u is over the maximum" },
	};
	uint8_t *buf = calloc(1, max);
	CHECK(buf, "out of memory");
	for (size_t i = 0; i < sizeof table / sizeof *table; i++) {
		harness_put(buf, VIS_OP_MAP, hostile_win[0]);
		vis_wire_put_u32(buf, table[i].size);
		char reason[120];
		snprintf(reason, sizeof reason, table[i].reason, table[i].size);
		struct harness_conn c;
		harness_open_as(&c, path, VIS_ROLE_CLIENT);
		CHECK(c.max_request == max, "hello-reply says the maximum is %u", c.max_request);
		uint32_t seq = harness_request_raw(&c, buf,
						   table[i].body ? table[i].size : VIS_MSG_HEADER);
		harness_expect_error(&c, seq, VIS_OP_MAP, VIS_ERROR_MALFORMED, reason, true);
		harness_close(&c);
	}
	free(buf);
	/* Before the handshake too: the size comes first. */
	harness_expect_fatal(path, (const uint8_t[]){ 0, 0, 0, 0, 1, 0, 0, 0 }, VIS_MSG_HEADER, -1,
			     VIS_OP_HELLO, VIS_ERROR_MALFORMED, "less than the 8-byte header");
}

/* Every request of the table, 4 bytes short and 4 bytes long (zero bytes or not). */
static void test_truncated_extended(void)
{
	harness_context("every request truncated and extended");
	size_t count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *t = &types[i];
		if (t->dir != VIS_DIR_REQUEST)
			continue;
		uint32_t words[VIS_MSG_MAX_ARGS + 1];
		uint8_t b[VIS_MSG_HEADER + 4 * (VIS_MSG_MAX_ARGS + 1)];
		size_t n = hostile_request_words(t, hostile_win[0], hostile_win[1], words);
		words[n] = 0xdeadbeef;
		int role = t->opcode == VIS_OP_HELLO ? -1 : VIS_ROLE_CLIENT;
		uint32_t size = (uint32_t)harness_build(b, t->opcode, words, n + 1) - 4;
		char reason[120];
		vis_wire_put_u32(b, size - 4);
		if (size - 4 < VIS_MSG_HEADER)
			snprintf(reason, sizeof reason, "declared size %u is less than", size - 4);
		else
			snprintf(reason, sizeof reason,
				 "%s: %u bytes declared, too few for its fields", t->name,
				 size - 4);
		harness_expect_fatal(hostile_visd.sock, b,
				     size - 4 < VIS_MSG_HEADER ? VIS_MSG_HEADER : size - 4, role,
				     t->opcode, VIS_ERROR_MALFORMED, reason);
		vis_wire_put_u32(b, size + 4);
		snprintf(reason, sizeof reason, "%s: %u bytes declared, the fields take %u",
			 t->name, size + 4, size);
		harness_expect_fatal(hostile_visd.sock, b, size + 4, role, t->opcode,
				     VIS_ERROR_MALFORMED, reason);
		vis_wire_put_u32(b + size, 0);
		harness_expect_fatal(hostile_visd.sock, b, size + 4, role, t->opcode,
				     VIS_ERROR_MALFORMED, reason);
	}
	/* Inside a batch: refused at once, not held; the held requests die with the connection. */
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	harness_req(&c, VIS_OP_CREATE, 0, 300, 200, 10, 10, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	uint8_t b[16];
	harness_put(b, VIS_OP_MOVE, hostile_win[0], 0);
	uint32_t seq = harness_request_raw(&c, b, 16);
	harness_expect_error(&c, seq, VIS_OP_MOVE, VIS_ERROR_MALFORMED,
			     "move: 16 bytes declared, too few for its fields", true);
	harness_close(&c);
	hostile_check_unaffected();
}

/* Unknown opcodes and the daemon's own, before and after the handshake; a non-zero header pad. */
static void test_opcodes(void)
{
	harness_context("unknown opcodes");
	/* The daemon's own: 64 hello-reply, 72 look, 73 found, 96 error, 128 visibility, 130 stack. */
	static const uint32_t ops[] = {
		0, 27, 63, 64, 72, 73, 96, 97, 127, 128, 130, 131, 1000, 0xffff
	};
	for (size_t i = 0; i < sizeof ops / sizeof *ops; i++) {
		uint8_t b[24] = { 0 };
		harness_put(b, ops[i]);
		char reason[60];
		snprintf(reason, sizeof reason, "unknown opcode %u", ops[i]);
		harness_expect_fatal(hostile_visd.sock, b, VIS_MSG_HEADER, -1, ops[i],
				     VIS_ERROR_OPCODE, reason);
		vis_wire_put_u32(b, sizeof b); /* with a body, read whole and then refused */
		harness_expect_fatal(hostile_visd.sock, b, sizeof b, VIS_ROLE_CLIENT, ops[i],
				     VIS_ERROR_OPCODE, reason);
	}
	uint8_t b[12];
	harness_put(b, VIS_OP_MAP, hostile_win[0]);
	b[6] = 1;
	harness_expect_fatal(hostile_visd.sock, b, sizeof b, VIS_ROLE_CLIENT, VIS_OP_MAP,
			     VIS_ERROR_MALFORMED, "map: header padding is not zero");
	b[6] = 0;
	b[7] = 0x80;
	harness_expect_fatal(hostile_visd.sock, b, sizeof b, VIS_ROLE_CLIENT, VIS_OP_MAP,
			     VIS_ERROR_MALFORMED, "map: header padding is not zero");
	hostile_check_unaffected();
}

/* Sizes that lie: what they swallow or leave behind is never read as a request. */
static void test_lying_lengths(void)
{
	harness_context("lengths that lie about the payload");
	struct harness_conn c;
	uint8_t b[64];
	/* Longer than the payload: it takes the next request's first bytes. */
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	size_t n = harness_put(b, VIS_OP_MAP, hostile_win[0]);
	vis_wire_put_u32(b, 16);
	n += harness_put(b + n, VIS_OP_SYNC);
	CHECK(harness_send(&c, b, n) == 0, "send: %s", strerror(errno));
	harness_expect_error(&c, c.seq + 1, VIS_OP_MAP, VIS_ERROR_MALFORMED,
			     "map: 16 bytes declared, the fields take 12", true);
	harness_close(&c);
	/* Shorter: the rest would read as a request of 300 bytes, opcode 200. */
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	n = harness_put(b, VIS_OP_MOVE, hostile_win[0], 300, 200);
	vis_wire_put_u32(b, 12);
	harness_request_raw(&c, b, n);
	harness_expect_error(&c, c.seq, VIS_OP_MOVE, VIS_ERROR_MALFORMED,
			     "move: 12 bytes declared, too few for its fields", true);
	harness_close(&c);
	/* A set-shape whose rectangle count lies: 1,000 rectangles said, one sent. */
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	n = harness_put(b, VIS_OP_SET_SHAPE, hostile_win[0], 1, 1000, 0, 0, 5, 5);
	harness_request_raw(&c, b, n);
	harness_expect_error(&c, c.seq, VIS_OP_SET_SHAPE, VIS_ERROR_MALFORMED,
			     "set-shape: field 3: 1000 records need 16000 bytes, only 16 left in the "
			     "message", true);
	harness_close(&c);
	hostile_check_unaffected();
	/* A short map after a create must not take the create's window from stale bytes. */
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint32_t w = harness_create(&c, 0, 300, 200, 10, 10, VIS_CREATE_RETAIN);
	harness_put(b, VIS_OP_MAP);
	harness_request_raw(&c, b, VIS_MSG_HEADER);
	harness_expect_error(&c, c.seq, VIS_OP_MAP, VIS_ERROR_MALFORMED,
			     "map: 8 bytes declared, too few for its fields", true);
	harness_close(&c);
	/* Bytes sent after a fatal error are never read: the retained window after it is not made.
	 */
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint8_t flood[2 * 48 + VIS_MSG_HEADER];
	n = harness_put(flood, VIS_OP_CREATE, 0, 310, 200, 10, 10, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	size_t at = n;
	n += harness_put(flood + n, VIS_OP_MAP);
	vis_wire_put_u32(flood + at, 4);
	n += harness_put(flood + n, VIS_OP_CREATE, 0, 320, 200, 10, 10, VIS_CREATE_RETAIN, 0, 0, 0, 0);
	CHECK(harness_send(&c, flood, n) == 0, "send: %s", strerror(errno));
	harness_expect_error(&c, c.seq + 2, VIS_OP_MAP, VIS_ERROR_MALFORMED,
			     "declared size 4 is less than the 8-byte header", true);
	harness_close(&c);
	struct harness_conn obs;
	harness_open_as(&obs, hostile_visd.sock, VIS_ROLE_OBSERVER);
	harness_wait_fds(&hostile_visd, base_fds + 1);
	struct harness_node *t = harness_get_tree(&obs, &n);
	size_t found = 0;
	for (size_t i = 0; i < n; i++) {
		if (t[i].window == w)
			CHECK(!(t[i].flags & VIS_WINDOW_MAPPED), "a short map mapped the window");
		CHECK(t[i].x != 320, "a request after a fatal error was run");
		found += t[i].window == w || t[i].x == 310;
	}
	CHECK(found == 2, "%zu of the 2 retained windows are left", found);
	free(t);
	harness_close(&obs);
	hostile_destroy_leftovers();
	hostile_check_unaffected();
}

void hostile_expect_no_role(const char *path, const char *reason)
{
	uint8_t b[VIS_MSG_HEADER + 12];
	for (uint32_t role = VIS_ROLE_OBSERVER; role <= VIS_ROLE_MANAGER; role++)
		harness_expect_fatal(path, b,
				     harness_put(b, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC,
						 VIS_PROTOCOL_VERSION, role),
				     -1, VIS_OP_HELLO, VIS_ERROR_ACCESS, reason);
}

/* Wrong handshakes, requests before it, a second one; roles refused. */
static void test_handshake(void)
{
	harness_context("handshakes");
	const struct {
		uint32_t magic, version, role;
		const char *reason;
	} table[] = {
		{ 0, VIS_PROTOCOL_VERSION, 0, "not a visd client" },
		{ 0x56495344, VIS_PROTOCOL_VERSION, 0, "not a visd client" }, /* byte-swapped */
		{ VIS_PROTOCOL_MAGIC, 0, 0, "protocol version 0 is not supported" },
		{ VIS_PROTOCOL_MAGIC, 1, 0, "protocol version 1 is not supported" },
		{ VIS_PROTOCOL_MAGIC, 2, 0, "protocol version 2 is not supported" },
		{ VIS_PROTOCOL_MAGIC, 5, 0, "protocol version 5 is not supported" },
		{ VIS_PROTOCOL_MAGIC, UINT32_MAX, 0, "version 4294967295 is not supported" },
		{ VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, 3, "unknown role 3" },
		{ VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, UINT32_MAX, "unknown role 4294967295" },
	};
	uint8_t b[VIS_MSG_HEADER + 4 * VIS_MSG_MAX_ARGS];
	for (size_t i = 0; i < sizeof table / sizeof *table; i++)
		harness_expect_fatal(hostile_visd.sock, b,
				     harness_put(b, VIS_OP_HELLO, table[i].magic, table[i].version,
						 table[i].role),
				     -1, VIS_OP_HELLO, VIS_ERROR_HANDSHAKE, table[i].reason);
	/* Every other request, well formed, before the handshake. */
	size_t count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *t = &types[i];
		if (t->dir != VIS_DIR_REQUEST || t->opcode == VIS_OP_HELLO)
			continue;
		uint32_t words[VIS_MSG_MAX_ARGS];
		size_t n = hostile_request_words(t, hostile_win[0], hostile_win[1], words);
		char reason[80];
		snprintf(reason, sizeof reason, "%s before the handshake", t->name);
		harness_expect_fatal(hostile_visd.sock, b, harness_build(b, t->opcode, words, n),
				     -1, t->opcode, VIS_ERROR_HANDSHAKE, reason);
	}
	/* A second hello, also inside a batch. */
	size_t n = harness_put(b, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION,
			       VIS_ROLE_CLIENT);
	harness_expect_fatal(hostile_visd.sock, b, n, VIS_ROLE_CLIENT, VIS_OP_HELLO,
			     VIS_ERROR_HANDSHAKE, "a second hello");
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_BATCH_BEGIN);
	harness_expect_error(&c, harness_request_raw(&c, b, n), VIS_OP_HELLO, VIS_ERROR_HANDSHAKE,
			     "a second hello", true);
	harness_close(&c);
	/* No role on the restricted socket; one manager at a time. */
	hostile_expect_no_role(hostile_visd.rsock, "clients of the restricted socket get no role");
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_MANAGER);
	harness_expect_fatal(hostile_visd.sock, b,
			     harness_put(b, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION,
					 VIS_ROLE_MANAGER),
			     -1, VIS_OP_HELLO, VIS_ERROR_STATE, "the manager role is taken");
	harness_close(&c);
	harness_wait_fds(&hostile_visd, base_fds);
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_MANAGER); /* released with its connection */
	harness_close(&c);
	hostile_check_unaffected();
}

/* Connects, sends the first n bytes of script and hangs up without reading anything. */
static void hang_up_after(const char *path, const uint8_t *script, size_t n)
{
	struct harness_conn c;
	harness_open(&c, path);
	CHECK(harness_send(&c, script, n) == 0, "send: %s", strerror(errno));
	harness_close(&c);
}

/* Clients that hang up at every byte of a session, and one that sends a byte at a time. */
static void test_mid_message(void)
{
	harness_context("disconnects mid-message");
	/* hello, a subscription and windows (notices and replies the client never reads), a batch
	 * left open, then a request of the largest size, cut short. */
	uint8_t script[512];
	size_t n = harness_put(script, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION,
			       VIS_ROLE_CLIENT);
	n += harness_put(script + n, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	n += harness_put(script + n, VIS_OP_CREATE, 0, 300, 200, 50, 50, VIS_CREATE_MAP, 0, 0, 0, 0);
	n += harness_put(script + n, VIS_OP_CREATE, 0, 310, 210, 50, 50, VIS_CREATE_MAP, 0, 0, 0, 0);
	n += harness_put(script + n, VIS_OP_GET_TREE);
	n += harness_put(script + n, VIS_OP_BATCH_BEGIN);
	n += harness_put(script + n, VIS_OP_CREATE, 0, 320, 220, 50, 50, VIS_CREATE_MAP, 0, 0, 0, 0);
	n += harness_put(script + n, VIS_OP_GET_STATES);
	n += harness_put(script + n, VIS_OP_MAP, 0);
	vis_wire_put_u32(script + n - 12, 65536);
	n += 100;
	CHECK(n <= sizeof script, "the script is too long");
	for (size_t cut = 0; cut <= n; cut++)
		hang_up_after(hostile_visd.sock, script, cut);
	harness_wait_fds(&hostile_visd, base_fds);
	hostile_check_unaffected();

	/* A byte at a time, the innocent served between them. */
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	uint8_t b[48];
	n = harness_put(b, VIS_OP_CREATE, 0, 300, 200, 5, 5, 0, 0, 0, 0, 0);
	for (size_t i = 0; i < n; i++) {
		CHECK(harness_send(&c, b + i, 1) == 0, "send: %s", strerror(errno));
		harness_sync(&hostile_innocent, NULL);
	}
	struct vis_msg m;
	harness_expect(&c, ++c.seq, VIS_OP_CREATED, &m);
	harness_close(&c);
	hostile_check_unaffected();
}

/*
 * Valid requests at the edges of the ranges: positions at INT32_MIN and INT32_MAX, sizes of
 * INT32_MAX, nested so that absolute edges pass 2^32, damage rectangles as large; every query on
 * them. Right and below the innocent's windows, so that their states stay. (UBSan and ASan judge.)
 */
static void test_extremes(void)
{
	harness_context("extreme coordinates and sizes");
	const uint32_t lo = (uint32_t)INT32_MIN, hi = INT32_MAX;
	struct harness_conn c;
	harness_open_as(&c, hostile_visd.sock, VIS_ROLE_CLIENT);
	harness_req(&c, VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, UINT32_MAX);
	uint32_t w[8];
	w[0] = harness_create(&c, 0, INT32_MIN, INT32_MIN, hi, hi, VIS_CREATE_MAP);
	w[1] = harness_create(&c, 0, 200, 150, hi, hi, VIS_CREATE_MAP);
	w[2] = harness_create(&c, w[1], INT32_MAX, INT32_MAX, hi, hi, VIS_CREATE_MAP);
	w[3] = harness_create(&c, w[2], INT32_MAX, INT32_MAX, hi, hi, VIS_CREATE_MAP);
	w[4] = harness_create(&c, w[1], INT32_MIN, INT32_MIN, hi, hi, VIS_CREATE_MAP);
	w[5] = harness_create(&c, w[4], INT32_MAX, INT32_MAX, 1, 1, VIS_CREATE_MAP);
	w[6] = harness_create(&c, w[5], INT32_MIN, INT32_MIN, hi, hi, VIS_CREATE_MAP);
	w[7] = harness_create(&c, 0, 250, 200, 1, 1, VIS_CREATE_MAP);
	harness_req(&c, VIS_OP_MOVE, w[0], hi, hi);
	harness_req(&c, VIS_OP_MOVE, w[0], lo, lo);
	harness_req(&c, VIS_OP_REPARENT, w[3], w[0], lo, hi);
	harness_req(&c, VIS_OP_RESIZE, w[1], hi, 1);
	harness_req(&c, VIS_OP_RESIZE, w[1], hi, hi);
	harness_req(&c, VIS_OP_RESTACK, w[7], VIS_RESTACK_BELOW, w[0]);
	const uint32_t damage[][4] = { { lo, lo, hi, hi }, { hi, hi, hi, hi }, { 0, 0, hi, hi },
				       { lo, 0, hi, 1 },   { hi, lo, 1, hi },  { 199, 149, 2, 2 } };
	for (size_t i = 0; i < sizeof damage / sizeof *damage; i++) {
		struct vis_msg m;
		uint32_t seq = harness_req(&c, VIS_OP_GET_REPAINT, damage[i][0], damage[i][1],
					   damage[i][2], damage[i][3]);
		harness_expect(&c, seq, VIS_OP_REPAINT, &m);
	}
	for (size_t i = 0; i < 8; i++) {
		struct vis_msg m;
		harness_expect(&c, harness_req(&c, VIS_OP_GET_REGION, w[i]), VIS_OP_REGION, &m);
		harness_expect(&c, harness_req(&c, VIS_OP_GET_STATE, w[i]), VIS_OP_STATE, &m);
	}
	size_t n;
	free(harness_get_tree(&c, &n));
	free(harness_get_states(&c, &n));
	harness_sync(&c, NULL);
	harness_close(&c);
	hostile_check_unaffected();
}

int main(int argc, char **argv)
{
	if (argc != 2 && (argc != 4 || strcmp(argv[2], "--seed") || !atoll(argv[3]))) {
		fprintf(stderr, "usage: test-hostile VISD [--seed S]\n");
		return 2;
	}
	signal(SIGPIPE, SIG_IGN);
	if (argc == 4) {
		/* A failure of the hidden windows' random runs, again on its own. */
		hostile_hidden_windows(argv[1], strtoull(argv[3], NULL, 10));
		printf("hostile: hidden windows, seed %s: the client saw none\n", argv[3]);
		return 0;
	}
	harness_start(&hostile_visd, argv[1], (const char *const[]){ "--screen", "400x300", NULL });
	setup();
	test_lengths(hostile_visd.sock, 65536);
	hostile_check_unaffected();
	struct harness_daemon small = { 0 };
	harness_start(&small, argv[1], (const char *const[]){ "--max-request", "64", NULL });
	test_lengths(small.sock, 64);
	harness_stop(&small);
	test_truncated_extended();
	test_opcodes();
	test_lying_lengths();
	hostile_access_window_ids();
	test_handshake();
	test_mid_message();
	hostile_access_isolation();
	hostile_access_stack_notices();
	hostile_access_other_uid();
	test_extremes();
	hostile_batch();
	hostile_hangup();
	hostile_hidden_windows(argv[1], 0);
	harness_context("shutdown");
	harness_close(&hostile_innocent);
	harness_stop(&hostile_visd);
	printf("hostile: %d errors checked; each malformed request got its error and lost its "
	       "connection, the others were refused as documented; the innocent client's states "
	       "never "
	       "changed\n",
	       harness_errors_checked());
	return 0;
}
