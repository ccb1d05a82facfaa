/*
 * Notices on their way to a connection, and the bound on what may wait for it. A connection that
 * reads slowly gets its notices coalesced (the latest state of each window, the union of its
 * exposures); one that falls further behind loses them for an overflow notice and a resync of
 * everything it subscribed to. Serials are given as notices are written, so they stay gapless.
 */
#include <stdlib.h>
#include <string.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"
#include "wire.h"

/* Encoded sizes: header, serial, fields (an exposure's count, then 16 bytes a rectangle). */
#define VISIBILITY_BYTES (VIS_MSG_HEADER + 8u + 4 * 4u)
#define EXPOSURE_BYTES (VIS_MSG_HEADER + 8u + 4 * 4u)
#define STACK_BYTES (VIS_MSG_HEADER + 8u + 4 * SERVER_STACK_WORDS)

void server_output_init(struct client *c)
{
	vis_idmap_init(&c->out.held_index);
}

/* Forgets everything held. */
static void drop_held(struct output *o)
{
	for (size_t i = 0; i < o->n_held; i++)
		pixman_region32_fini(&o->held[i].exposed);
	o->n_held = 0;
	o->n_stack = 0;
	o->held_bytes = 0;
	vis_idmap_finish(&o->held_index);
	vis_idmap_init(&o->held_index);
}

void server_output_finish(struct client *c)
{
	drop_held(&c->out);
	free(c->out.held);
	free(c->out.stack);
	vis_idmap_finish(&c->out.held_index);
}

size_t server_output_pending(const struct client *c)
{
	return server_io_pending(c);
}

/* Past the bound: what is held goes, counted, and the connection waits for its resync. */
static void overflow(struct client *c)
{
	struct output *o = &c->out;
	uint64_t lost = o->n_stack;
	for (size_t i = 0; i < o->n_held; i++)
		lost += o->held[i].visibility_count + o->held[i].exposure_count;
	log_info("client %u: %zu bytes wait to be written and %zu are held, over the bound of %u; "
		 "dropping its notices until it catches up",
		 c->id, server_output_pending(c), o->held_bytes, c->server->opt.max_pending);
	drop_held(o);
	o->dropped = lost > UINT32_MAX ? UINT32_MAX : (uint32_t)lost;
	o->overflowed = true;
	o->lagging = false;
}

/*
 * Whether a notice to c must not be written now: true when it was counted as dropped, or when c
 * lags and the notice is to be held.
 */
static bool must_hold(struct client *c)
{
	struct output *o = &c->out;
	if (o->overflowed) {
		if (o->dropped < UINT32_MAX)
			o->dropped++;
		return true;
	}
	if (!o->lagging && server_output_pending(c) < c->server->opt.max_pending / 2)
		return false;
	o->lagging = true;
	return true;
}

/* Checks the bound after holding more. */
static void check_bound(struct client *c)
{
	if (server_output_pending(c) + c->out.held_bytes > c->server->opt.max_pending)
		overflow(c);
}

/* The held entry of window w, created empty when there is none; NULL when memory runs out. */
static struct held *held_for(struct client *c, uint32_t window)
{
	struct output *o = &c->out;
	uintptr_t i = (uintptr_t)vis_idmap_get(&o->held_index, window);
	if (i)
		return &o->held[i - 1];
	if (o->n_held == o->cap_held) {
		size_t cap = o->cap_held ? 2 * o->cap_held : 16;
		struct held *more = realloc(o->held, cap * sizeof *more);
		if (!more)
			return NULL;
		o->held = more;
		o->cap_held = cap;
	}
	if (vis_idmap_put(&o->held_index, window, (void *)(uintptr_t)(o->n_held + 1)) < 0)
		return NULL;
	struct held *h = &o->held[o->n_held++];
	*h = (struct held){ .window = window };
	pixman_region32_init(&h->exposed);
	return h;
}

/* Memory ran out while holding: treat it as an overflow, which needs no memory. */
static void hold_failed(struct client *c)
{
	log_error("client %u: out of memory holding notices", c->id);
	overflow(c);
}

/* The held entry of window for a notice to hold, or NULL when the notice is dropped instead. */
static struct held *held_entry(struct client *c, uint32_t window)
{
	if (c->out.overflowed)
		return NULL;
	struct held *h = held_for(c, window);
	if (!h)
		hold_failed(c);
	return h;
}

/*
 * Lays out a notice of n fixed words after the serial at p, by hand, and returns its size: the
 * fan-out's hot path, where the generic encoder's walk of the signature cost a third of the
 * daemon's time. Every suite that talks to visd decodes what this writes with the generic decoder.
 */
static uint32_t encode_words(uint8_t *p, uint32_t opcode, uint64_t serial, const uint32_t *words,
			     size_t n)
{
	uint32_t size = VIS_MSG_HEADER + 8 + 4 * (uint32_t)n;
	vis_wire_put_u32(p, size);
	vis_wire_put_u16(p + 4, (uint16_t)opcode);
	vis_wire_put_u16(p + 6, 0);
	vis_wire_put_u64(p + 8, serial);
	for (size_t i = 0; i < n; i++)
		vis_wire_put_u32(p + 16 + 4 * i, words[i]);
	return size;
}

/* Writes a notice of fixed words after the serial to c alone. */
static void write_words(struct client *c, uint32_t opcode, const uint32_t *words, size_t n)
{
	uint8_t *p;
	if (!c->closing && (p = server_io_reserve(c, VIS_MSG_HEADER + 8 + 4 * n)))
		encode_words(p, opcode, ++c->serial, words, n);
}

/*
 * Writes a copy of a notice encoded once for the fan-out, with c's own serial: the rest is the
 * same for every connection, and copying 32 to 68 bytes costs less than laying them out again
 * (or than sharing one buffer among the connections' output, reference-counted).
 */
static void write_copy(struct client *c, const uint8_t *bytes, size_t size)
{
	uint8_t *p;
	if (c->closing || !(p = server_io_reserve(c, size)))
		return;
	memcpy(p, bytes, size);
	vis_wire_put_u64(p + 8, ++c->serial);
}

static void write_visibility(struct client *c, uint32_t window, uint32_t state, uint32_t previous,
			     uint32_t coalesced)
{
	const uint32_t words[4] = { window, state, previous, coalesced };
	write_words(c, VIS_OP_VISIBILITY, words, 4);
}

/*
 * Encodes an exposure notice (serial 0) into out: the rectangles, or their bounding box when
 * collapse. 0, or -1 when memory ran out.
 */
static int encode_exposure(struct vis_buf *out, uint32_t window, bool collapse,
			   const uint32_t *words, uint32_t n, uint32_t coalesced)
{
	/* Collapsed: the rectangles' bounding box (words of int32 x, y; n > 0). */
	int64_t x1 = 0, y1 = 0, x2 = 0, y2 = 0;
	for (uint32_t i = 0; collapse && i < n; i++) {
		int64_t x = (int32_t)words[4 * i], y = (int32_t)words[4 * i + 1];
		int64_t xe = x + words[4 * i + 2], ye = y + words[4 * i + 3];
		x1 = i == 0 || x < x1 ? x : x1;
		y1 = i == 0 || y < y1 ? y : y1;
		x2 = i == 0 || xe > x2 ? xe : x2;
		y2 = i == 0 || ye > y2 ? ye : y2;
	}
	const uint32_t extents[4] = { (uint32_t)x1, (uint32_t)y1, (uint32_t)(x2 - x1),
				      (uint32_t)(y2 - y1) };
	union vis_arg a[5];
	a[0].q = 0;
	a[1].u = window;
	a[2].u = collapse ? VIS_EXPOSURE_COLLAPSED : 0;
	a[3].u = coalesced;
	a[4].a.words = collapse ? extents : words;
	a[4].a.n = collapse ? 1 : n;
	a[4].a.raw = NULL;
	return vis_msg_encode(out, VIS_OP_EXPOSURE, a);
}

/* Writes one exposure notice now: the rectangles, or their bounding box past the limit. */
static void write_exposure(struct client *c, uint32_t window, uint32_t rect_limit,
			   const uint32_t *words, uint32_t n, uint32_t coalesced)
{
	struct vis_buf *b = &c->server->scratch;
	b->len = 0;
	if (c->closing)
		return;
	if (encode_exposure(b, window, n > rect_limit, words, n, coalesced) < 0) {
		log_error("client %u: cannot encode an exposure notice", c->id);
		server_client_close(c);
		return;
	}
	write_copy(c, b->data, b->len);
}

/*
 * As write_exposure(), for w's rectangles as c's protocol version reads them, from a region
 * (today's window coordinates) or from n words (exposed NULL), left as they are.
 */
static void write_region(struct client *c, const struct vis_window *w, uint32_t rect_limit,
			 pixman_region32_t *exposed, const uint32_t *from, uint32_t n,
			 uint32_t coalesced)
{
	uint32_t *words = exposed ? server_region_words(exposed, &n)
				  : malloc(((size_t)n + 1) * 4 * sizeof *words);
	if (!words) {
		log_error("client %u: out of memory for an exposure notice", c->id);
		server_client_close(c);
		return;
	}
	if (!exposed)
		memcpy(words, from, (size_t)n * 4 * sizeof *words);
	server_compat_rects(c, w, words, n);
	write_exposure(c, w->id, rect_limit, words, n, coalesced);
	free(words);
}

static void write_stack(struct client *c, const uint32_t words[SERVER_STACK_WORDS])
{
	write_words(c, VIS_OP_STACK, words, SERVER_STACK_WORDS);
}

void server_notice_visibility(struct client *c, const struct vis_window *w,
			      struct server_notice *once)
{
	if (!must_hold(c)) {
		if (!once->size) {
			const uint32_t words[4] = { w->id, w->state, w->old_state, 0 };
			once->size = encode_words(once->bytes, VIS_OP_VISIBILITY, 0, words, 4);
		}
		write_copy(c, once->bytes, once->size);
		return;
	}
	struct held *h = held_entry(c, w->id);
	if (!h)
		return;
	if (!h->visibility) {
		h->visibility = true;
		h->previous = w->old_state;
		c->out.held_bytes += VISIBILITY_BYTES;
	} else if (w->old_state == VIS_VISIBILITY_NONE) {
		h->previous = VIS_VISIBILITY_NONE; /* it became viewable again meanwhile */
	}
	h->state = w->state;
	h->visibility_count++;
	check_bound(c);
}

void server_notice_initial(struct client *c, const struct vis_window *w)
{
	if (!must_hold(c)) {
		write_visibility(c, w->id, w->state, VIS_VISIBILITY_INITIAL, 0);
		return;
	}
	struct held *h = held_entry(c, w->id);
	if (!h)
		return;
	if (!h->visibility)
		c->out.held_bytes += VISIBILITY_BYTES;
	/* What the connection will be told first is this state, whatever it held before. */
	h->visibility = true;
	h->previous = VIS_VISIBILITY_INITIAL;
	h->state = w->state;
	h->visibility_count++;
	check_bound(c);
}

/* The bytes an exposure notice of region r would take, as held (before any collapsing). */
static size_t exposure_bytes(pixman_region32_t *r)
{
	return EXPOSURE_BYTES + 16u * (size_t)pixman_region32_n_rects(r);
}

void server_exposure_finish(struct server_exposure *e)
{
	vis_buf_finish(&e->encoded[0]);
	vis_buf_finish(&e->encoded[1]);
	if (e->built)
		pixman_region32_fini(&e->region);
}

/* The exposure's region, made of its rectangles on first use; NULL when memory runs out. */
static pixman_region32_t *exposure_region(struct server_exposure *e)
{
	if (e->built)
		return &e->region;
	pixman_box32_t *boxes = malloc((size_t)e->n * sizeof *boxes);
	if (!boxes)
		return NULL;
	for (uint32_t i = 0; i < e->n; i++) {
		const struct vis_rect32 *r = &e->rects[i];
		boxes[i] = (pixman_box32_t){ r->x, r->y, (int32_t)((int64_t)r->x + r->width),
					     (int32_t)((int64_t)r->y + r->height) };
	}
	e->built = pixman_region32_init_rects(&e->region, boxes, (int)e->n);
	free(boxes);
	return e->built ? &e->region : NULL;
}

void server_notice_exposure(struct client *c, const struct sub *s, const struct vis_window *w,
			    struct server_exposure *once)
{
	if (!must_hold(c)) {
		if (server_compat_rects_differ(c, w)) {
			/* An older version's rectangles: this connection's own copy. */
			write_region(c, w, s->rect_limit, NULL, once->words, once->n, 0);
			return;
		}
		bool collapse = once->n > s->rect_limit;
		struct vis_buf *b = &once->encoded[collapse];
		if (!b->len && encode_exposure(b, w->id, collapse, once->words, once->n, 0) < 0) {
			log_error("client %u: cannot encode an exposure notice", c->id);
			server_client_close(c);
			return;
		}
		write_copy(c, b->data, b->len);
		return;
	}
	pixman_region32_t *exposed = exposure_region(once);
	if (!exposed) {
		hold_failed(c);
		return;
	}
	struct held *h = held_entry(c, w->id);
	if (!h)
		return;
	if (h->exposure)
		c->out.held_bytes -= exposure_bytes(&h->exposed);
	h->exposure = true;
	h->exposure_count++;
	if (!pixman_region32_union(&h->exposed, &h->exposed, exposed)) {
		hold_failed(c);
		return;
	}
	c->out.held_bytes += exposure_bytes(&h->exposed);
	check_bound(c);
}

void server_notice_stack(struct client *c, const uint32_t words[SERVER_STACK_WORDS],
			 struct server_notice *once)
{
	if (!must_hold(c)) {
		if (!once) {
			write_stack(c, words);
			return;
		}
		if (!once->size)
			once->size = encode_words(once->bytes, VIS_OP_STACK, 0, words,
						  SERVER_STACK_WORDS);
		write_copy(c, once->bytes, once->size);
		return;
	}
	struct output *o = &c->out;
	if (o->overflowed)
		return;
	if (o->n_stack == o->cap_stack) {
		size_t cap = o->cap_stack ? 2 * o->cap_stack : 16;
		struct held_stack *more = realloc(o->stack, cap * sizeof *more);
		if (!more) {
			hold_failed(c);
			return;
		}
		o->stack = more;
		o->cap_stack = cap;
	}
	memcpy(o->stack[o->n_stack].words, words, sizeof o->stack[o->n_stack].words);
	o->n_stack++;
	o->held_bytes += STACK_BYTES;
	check_bound(c);
}

/* The stacking position of a held window, for sending in stacking order; destroyed ones last. */
struct held_order {
	uint64_t key;
	struct held *h;
};

static int by_position(const void *a, const void *b)
{
	const struct held_order *x = a, *y = b;
	if (x->key != y->key)
		return x->key < y->key ? -1 : 1;
	return x->h->window < y->h->window ? -1 : x->h->window > y->h->window;
}

/* Sends the held notices: stack notices in order, then each window's, in stacking order. */
static void release_held(struct client *c)
{
	struct server *server = c->server;
	struct output *o = &c->out;
	for (size_t i = 0; i < o->n_stack; i++)
		write_stack(c, o->stack[i].words);
	struct held_order *order = malloc((o->n_held + 1) * sizeof *order);
	if (!order) {
		hold_failed(c);
		return;
	}
	for (size_t i = 0; i < o->n_held; i++) {
		struct vis_window *w = vis_wtree_find(&server->vis->core, o->held[i].window);
		order[i].key = w && w->state != VIS_WTREE_STATE_NONE ? w->key : UINT64_MAX;
		order[i].h = &o->held[i];
	}
	qsort(order, o->n_held, sizeof *order, by_position);
	for (size_t i = 0; i < o->n_held && !c->closing; i++) {
		struct held *h = order[i].h;
		struct vis_window *w = vis_wtree_find(&server->vis->core, h->window);
		if (!w)
			continue; /* destroyed: the stack notice says so */
		if (h->visibility && h->state != h->previous &&
		    server_client_sub_for(c, w, VIS_NOTICE_VISIBILITY))
			write_visibility(c, h->window, h->state, h->previous,
					 h->visibility_count - 1);
		const struct sub *s;
		if (h->exposure && (s = server_client_sub_for(c, w, VIS_NOTICE_EXPOSURE)))
			write_region(c, w, s->rect_limit, &h->exposed, NULL, 0,
				     h->exposure_count - 1);
	}
	free(order);
	drop_held(o);
	o->lagging = false;
}

/*
 * Goes over what c's subscriptions cover, counting the resync notices, and writes them when
 * write is true: each window in stacking order, its stack notice, its state, its visible region.
 */
static uint32_t resync(struct client *c, bool write)
{
	struct server *server = c->server;
	uint32_t n = 0;
	for (struct vis_window *w = server->vis->core.root.bottom; w && !c->closing;
	     w = vis_wtree_next(w)) {
		if (!server_may_see(c, w))
			continue;
		if (server_client_sub_for(c, w, VIS_NOTICE_STACK)) {
			n++;
			if (write) {
				uint32_t words[SERVER_STACK_WORDS];
				server_stack_words(c, w, VIS_STACK_RESYNC, words);
				write_stack(c, words);
			}
		}
		/* State NONE also covers windows mapped since the last recompute, which follows. */
		if (w->state == VIS_WTREE_STATE_NONE)
			continue;
		if (server_client_sub_for(c, w, VIS_NOTICE_VISIBILITY)) {
			n++;
			if (write)
				write_visibility(c, w->id, w->state, VIS_VISIBILITY_NONE, 0);
		}
		const struct sub *s = server_client_sub_for(c, w, VIS_NOTICE_EXPOSURE);
		/* What it showed at the last recompute, while libvis tracks its exposures. */
		struct vis_win *win = w->data;
		if (s && win->tracked && pixman_region32_not_empty(&win->region)) {
			n++;
			if (write)
				write_region(c, w, s->rect_limit, &win->region, NULL, 0, 0);
		}
	}
	return n;
}

/* After an overflow: the overflow notice, then every subscription restated. */
static void send_resync(struct client *c)
{
	struct output *o = &c->out;
	server_flush(c->server); /* restate the states as they are now */
	o->overflowed = false;
	union vis_arg a[3];
	a[0].q = ++c->serial;
	a[1].u = o->dropped;
	a[2].u = resync(c, false);
	log_info("client %u caught up: %u notices were dropped, %u restate its subscriptions",
		 c->id, a[1].u, a[2].u);
	o->dropped = 0;
	server_client_write(c, VIS_OP_OVERFLOW, a);
	resync(c, true);
}

void server_output_release(struct client *c)
{
	if (c->out.overflowed)
		send_resync(c);
	else if (c->out.lagging)
		release_held(c);
}
