/*
 * A session of libvisclient calls that every recording under tests/compat/ was made with (README
 * there): create, map, configure, shapes, opaque regions, subscriptions, regions and exposures of
 * bordered windows, a batch, a protocol error. It is not built here: it is compiled against the
 * libvisclient of the release whose protocol a recording keeps, and run through
 * `test-compat --record`. It prints what it was told, for whoever records, and exits 0 when every
 * call did what it should.
 */
#include <stdio.h>
#include <stdlib.h>

#include <vis/visclient.h>

static int failures;

/* Fails the session unless ok, naming the call. */
static void must(struct vis_client *c, int ok, const char *what)
{
	if (!ok) {
		fprintf(stderr, "session: %s failed: %s\n", what,
			vis_client_error(c) ? vis_client_error_message(c) : "protocol error");
		failures++;
	}
}

static void on_notice(void *data, const struct vis_notice *n)
{
	(void)data;
	printf("notice %llu: kind %d window %u", (unsigned long long)n->serial, (int)n->kind,
	       n->window);
	if (n->kind == VIS_NOTICE_KIND_EXPOSURE)
		for (uint32_t i = 0; i < n->exposure.n_rects; i++)
			printf(" %d,%d,%u,%u", n->exposure.rects[i].x, n->exposure.rects[i].y,
			       n->exposure.rects[i].width, n->exposure.rects[i].height);
	printf("\n");
}

static void region(struct vis_client *c, uint32_t w)
{
	struct vis_rect32 *r = NULL;
	size_t n = 0;
	must(c, vis_client_get_region(c, w, &r, &n) == 0, "get-region");
	printf("region %u:", w);
	for (size_t i = 0; i < n; i++)
		printf(" %d,%d,%u,%u", r[i].x, r[i].y, r[i].width, r[i].height);
	printf("\n");
	free(r);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: session SOCKET\n");
		return 2;
	}
	struct vis_client *c = vis_client_connect(argv[1], VIS_ROLE_CLIENT);
	if (!c || vis_client_error(c)) {
		fprintf(stderr, "session: cannot connect: %s\n",
			c ? vis_client_error_message(c) : "out of memory");
		return 1;
	}
	vis_client_set_notice_handler(c, on_notice, NULL);
	must(c, vis_client_subscribe(c, 0, VIS_NOTICE_ALL, 0) != 0, "subscribe");

	/* Two bordered top-level windows, overlapping; a bordered child of the first. */
	uint32_t a = 0, b = 0, k = 0, d = 0;
	must(c, vis_client_create_window(c, 0, 10, 10, 200, 100, 5, 0, &a) == 0, "create a");
	must(c, vis_client_map(c, a) != 0, "map a");
	must(c, vis_client_create_window(c, 0, 150, 60, 100, 80, 3, VIS_CREATE_MAP, &b) == 0,
	     "create b");
	must(c, vis_client_create_window(c, a, 20, 20, 40, 30, 2, VIS_CREATE_MAP, &k) == 0,
	     "create k");
	must(c, vis_client_sync(c) == 0, "sync");
	region(c, a);
	region(c, b);
	region(c, k);

	/* Move b off a, then back: a's border and inside exposed. */
	must(c, vis_client_move(c, b, 400, 300) != 0, "move b");
	must(c, vis_client_sync(c) == 0, "sync");
	must(c, vis_client_move(c, b, 150, 60) != 0, "move b back");
	must(c, vis_client_sync(c) == 0, "sync");

	/* A new border and size for a, a shape reaching into b's border, an opaque region. */
	must(c, vis_client_configure(c, a, 20, 20, 220, 120, 7) != 0, "configure a");
	const struct vis_rect32 shape[] = { { -3, -3, 60, 40 }, { 20, 20, 83, 63 } };
	must(c, vis_client_set_shape(c, b, 1, shape, 2) != 0, "set-shape b");
	const struct vis_rect32 opaque[] = { { 0, 0, 50, 50 } };
	must(c, vis_client_set_opaque(c, b, VIS_OPAQUE_MODE_RECTS, opaque, 1) != 0, "set-opaque b");
	must(c, vis_client_sync(c) == 0, "sync");
	region(c, a);
	region(c, b);
	struct vis_look_info look;
	must(c, vis_client_get_look(c, b, &look) == 0, "get-look b");
	free(look.shape);
	free(look.opaque);

	/* Unmapping b exposes what it hid of a; a subscription with a rect_limit of 2 collapses
	 * the exposures that have more rectangles. */
	must(c, vis_client_subscribe(c, 0, VIS_NOTICE_ALL, 2) != 0, "subscribe again");
	must(c, vis_client_unmap(c, b) != 0, "unmap b");
	must(c, vis_client_sync(c) == 0, "sync");
	must(c, vis_client_map(c, b) != 0, "map b");
	must(c, vis_client_raise(c, a) != 0, "raise a");
	must(c, vis_client_sync(c) == 0, "sync");
	region(c, b);

	/* A batch: moves and a restack, one recompute. */
	must(c, vis_client_batch_begin(c) != 0, "batch-begin");
	must(c, vis_client_move(c, a, 30, 25) != 0, "move a");
	must(c, vis_client_restack(c, b, VIS_RESTACK_ABOVE, a) != 0, "restack b");
	must(c, vis_client_resize(c, k, 60, 50) != 0, "resize k");
	must(c, vis_client_batch_commit(c) != 0, "batch-commit");
	must(c, vis_client_sync(c) == 0, "sync");

	struct vis_window_info *tree = NULL;
	size_t n = 0;
	must(c, vis_client_get_tree(c, &tree, &n) == 0 && n == 3, "get-tree");
	free(tree);
	struct vis_window_state *states = NULL;
	must(c, vis_client_get_states(c, &states, &n) == 0, "get-states");
	free(states);

	/* A protocol error: a window that does not exist. */
	uint32_t state;
	must(c, vis_client_get_state(c, 0xdead, &state) < 0 && !vis_client_error(c),
	     "get-state of no window");
	vis_client_sync(c); /* -1: it reports that error again */

	/* A window made and destroyed; then a is destroyed with its child. */
	must(c, vis_client_create_window(c, 0, 100, 100, 30, 30, 1, VIS_CREATE_MAP, &d) == 0,
	     "create d");
	must(c, vis_client_sync(c) == 0, "sync");
	must(c, vis_client_destroy_window(c, d) != 0, "destroy d");
	must(c, vis_client_destroy_window(c, a) != 0, "destroy a");
	must(c, vis_client_sync(c) == 0, "sync");
	region(c, b);
	vis_client_destroy(c);
	return failures ? 1 : 0;
}
