/*
 * wl-hostile: a Wayland client that misbehaves on purpose, for viscomp's fault tests
 * (tests/test-viscomp-hostile.sh). One mode a run:
 *   (none)            one toplevel with one opaque buffer, drawn once: a cover
 *   --no-ack          a toplevel that never acks a configure and commits a buffer anyway
 *                     (xdg-shell makes that a protocol error: the compositor must drop it)
 *   --ack-once        acks the first configure only, ignores the later ones (resizes,
 *                     activation) and keeps drawing at its frame callbacks' pace
 *   --flood           commits as fast as the socket takes it, never waiting for a frame
 *                     callback (it keeps one requested, only to count those answered)
 *   --surfaces N      N toplevels, each with one opaque buffer
 *   --subsurfaces N   a toplevel with a chain of N subsurfaces, each the child of the one
 *                     before (N deep), desynchronized, each drawing at its own frame pace
 *   --churn N         one toplevel that stays, and N more toplevels created and destroyed as
 *                     fast as the compositor takes them, 8 at a time: one in four before its
 *                     configure comes, one in four as soon as it has committed its buffer, the
 *                     others once a frame callback says the compositor has shown it (or after
 *                     CHURN_PATIENCE turns, covered); a subsurface of the first created and
 *                     destroyed in the same turns; then "churned N" and it stays
 *   --shadow M        one toplevel drawn once like a window with a client-side shadow: its
 *                     buffer (ARGB8888) translucent black (alpha 1/4) in a margin M pixels
 *                     wide, opaque inside, and its opaque region only the inside (the buffer
 *                     inset by M), as toolkits that draw their own shadow set it
 * --size WxH sets the toplevels' size (default 200x200; 32x32 with --surfaces). Subsurface k
 * (1 … N) is SUB_SIZE square at SUB_STEP, SUB_STEP from its parent's corner: with the defaults,
 * 6, 7 and 8 stick out of the toplevel at its bottom-right corner. Every buffer but --shadow's is
 * XRGB8888 with the whole surface as its opaque region.
 *
 * Output, on stdout, a line at a time:
 *   ready pid=PID surfaces=ID,ID,...   once every surface has its first buffer (the wl_surface
 *                                      protocol IDs: toplevels first, then subsurfaces 1 … N)
 *   commits=N frames=F,F,... ms=T      N commits so far, F frame callbacks answered for each
 *                                      surface, T ms since ready: at each answer, and with
 *                                      --flood every 1,000 commits (not with --surfaces)
 *   protocol-error interface=I code=C  the compositor ended the connection so (exit status 3)
 * Exit status 1 for a broken connection or a bad command line, 3 for a protocol error.
 */
#include <errno.h>
#include <poll.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include <wayland-client.h>

#include "xdg-shell-client-protocol.h"

#define SUB_SIZE 100
#define SUB_STEP 20
#define MAX_DEPTH 64
#define MAX_SURFACES 100000

enum mode { PLAIN, NO_ACK, ACK_ONCE, FLOOD, SURFACES, SUBSURFACES, CHURN, SHADOW };

/* The toplevels --churn has at once, and the turns one waits for a frame callback at most. */
#define CHURN_SLOTS 8
#define CHURN_PATIENCE 200

struct buffer {
	struct wl_buffer *wl;
	bool busy;
};

/* One surface: a toplevel or a subsurface; two buffers to draw from in turn (one when static). */
struct surf {
	struct wl_surface *wl;
	struct xdg_surface *xdg;
	struct xdg_toplevel *toplevel;
	struct wl_subsurface *sub;
	struct buffer buffers[2];
	int n_buffers, next;
	int32_t width, height;
	bool acked_once, drawn, animate, no_frames;
	struct wl_callback *frame;
	uint64_t frames;
};

static struct {
	enum mode mode;
	struct wl_display *display;
	struct wl_compositor *compositor;
	struct wl_subcompositor *subcompositor;
	struct wl_shm *shm;
	struct xdg_wm_base *wm_base;
	struct surf *surfs;
	int n_surfs, n_toplevels, drawn;
	int32_t margin; /* --shadow's */
	bool ready;
	uint64_t commits, ready_ms;
} c;

static uint64_t now_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (uint64_t)t.tv_sec * 1000u + (uint64_t)t.tv_nsec / 1000000u;
}

/* Says how far it got: commits, each surface's frame callbacks answered, the time since ready. */
static void report(void)
{
	if (c.mode == SURFACES || c.mode == CHURN)
		return; /* a thousand counts a line helps no one */
	printf("commits=%llu frames=", (unsigned long long)c.commits);
	for (int i = 0; i < c.n_surfs; i++)
		printf("%s%llu", i ? "," : "", (unsigned long long)c.surfs[i].frames);
	printf(" ms=%llu\n", (unsigned long long)(now_ms() - c.ready_ms));
}

static void buffer_release(void *data, struct wl_buffer *wl)
{
	(void)wl;
	struct buffer *b = data;
	b->busy = false;
}

static const struct wl_buffer_listener buffer_listener = { buffer_release };

static void frame_done(void *data, struct wl_callback *cb, uint32_t time);
static const struct wl_callback_listener frame_listener = { frame_done };

/* Attaches a buffer (one the compositor released, if any), damages all, commits; asks for a
 * frame callback when none is pending. */
static void draw(struct surf *s)
{
	struct buffer *b = &s->buffers[s->next];
	if (b->busy && s->n_buffers == 2 && !s->buffers[!s->next].busy)
		b = &s->buffers[!s->next];
	s->next = (int)(b - s->buffers + 1) % s->n_buffers;
	b->busy = true;
	wl_surface_attach(s->wl, b->wl, 0, 0);
	wl_surface_damage_buffer(s->wl, 0, 0, s->width, s->height);
	if (s->frame == NULL && !s->no_frames) {
		s->frame = wl_surface_frame(s->wl);
		wl_callback_add_listener(s->frame, &frame_listener, s);
	}
	wl_surface_commit(s->wl);
	c.commits++;
	if (!s->drawn) {
		s->drawn = true;
		c.drawn++;
	}
}

/* Once every surface has drawn: "ready" and the surfaces' IDs. */
static void check_ready(void)
{
	if (c.ready || c.drawn < c.n_surfs)
		return;
	c.ready = true;
	c.ready_ms = now_ms();
	printf("ready pid=%d surfaces=", (int)getpid());
	for (int i = 0; i < c.n_surfs; i++)
		printf("%s%u", i ? "," : "", wl_proxy_get_id((struct wl_proxy *)c.surfs[i].wl));
	printf("\n");
}

static void frame_done(void *data, struct wl_callback *cb, uint32_t time)
{
	(void)time;
	struct surf *s = data;
	wl_callback_destroy(cb);
	s->frame = NULL;
	s->frames++;
	if (s->animate)
		draw(s);
	report();
}

static void xdg_surface_configure(void *data, struct xdg_surface *xdg, uint32_t serial)
{
	struct surf *s = data;
	bool ack = c.mode != NO_ACK && !(c.mode == ACK_ONCE && s->acked_once);
	if (ack) {
		xdg_surface_ack_configure(xdg, serial);
		s->acked_once = true;
	}
	/* The first buffer, acked or not; an ack takes effect at a commit. */
	if (!s->drawn || ack)
		draw(s);
	check_ready();
}

static const struct xdg_surface_listener xdg_surface_listener = { xdg_surface_configure };

static void toplevel_configure(void *data, struct xdg_toplevel *t, int32_t w, int32_t h,
			       struct wl_array *states)
{
	(void)data, (void)t, (void)w, (void)h, (void)states; /* the size stays ours */
}

static void toplevel_close(void *data, struct xdg_toplevel *t)
{
	(void)data, (void)t;
	exit(0);
}

/* xdg_wm_base version 1: no configure_bounds, no wm_capabilities. */
static const struct xdg_toplevel_listener toplevel_listener = {
	.configure = toplevel_configure,
	.close = toplevel_close,
};

static void ping(void *data, struct xdg_wm_base *wm_base, uint32_t serial)
{
	(void)data;
	xdg_wm_base_pong(wm_base, serial);
}

static const struct xdg_wm_base_listener wm_base_listener = { ping };

static void global(void *data, struct wl_registry *registry, uint32_t name, const char *iface,
		   uint32_t version)
{
	(void)data, (void)version;
	if (strcmp(iface, wl_compositor_interface.name) == 0)
		c.compositor = wl_registry_bind(registry, name, &wl_compositor_interface, 4);
	else if (strcmp(iface, wl_subcompositor_interface.name) == 0)
		c.subcompositor = wl_registry_bind(registry, name, &wl_subcompositor_interface, 1);
	else if (strcmp(iface, wl_shm_interface.name) == 0)
		c.shm = wl_registry_bind(registry, name, &wl_shm_interface, 1);
	else if (strcmp(iface, xdg_wm_base_interface.name) == 0)
		c.wm_base = wl_registry_bind(registry, name, &xdg_wm_base_interface, 1);
}

static void global_remove(void *data, struct wl_registry *registry, uint32_t name)
{
	(void)data, (void)registry, (void)name;
}

static const struct wl_registry_listener registry_listener = { global, global_remove };

/* Exits after a broken connection, saying which protocol error ended it, if one did. */
static void die_connection(void)
{
	int err = wl_display_get_error(c.display);
	if (err == EPROTO) {
		const struct wl_interface *iface = NULL;
		uint32_t id;
		uint32_t code = wl_display_get_protocol_error(c.display, &iface, &id);
		printf("protocol-error interface=%s code=%u\n", iface ? iface->name : "?", code);
		exit(3);
	}
	fprintf(stderr, "wl-hostile: connection: %s\n", strerror(err ? err : errno));
	exit(1);
}

/* --shadow's margin: translucent black (premultiplied, alpha 0x40) around the opaque inside. */
static void draw_shadow(uint32_t *pixels, int32_t width, int32_t height)
{
	for (int32_t y = 0; y < height; y++)
		for (int32_t x = 0; x < width; x++)
			if (x < c.margin || y < c.margin || x >= width - c.margin ||
			    y >= height - c.margin)
				pixels[(size_t)y * (size_t)width + (size_t)x] = 0x40000000u;
}

/* Every surface's buffers from one shared-memory pool, each surface in a colour of its own. */
static void create_buffers(void)
{
	size_t size = 0;
	for (int i = 0; i < c.n_surfs; i++)
		size += (size_t)c.surfs[i].n_buffers * (size_t)c.surfs[i].width * 4u *
			(size_t)c.surfs[i].height;
	int fd = memfd_create("wl-hostile", MFD_CLOEXEC);
	if (fd < 0 || ftruncate(fd, (off_t)size) < 0) {
		perror("wl-hostile: memfd");
		exit(1);
	}
	uint32_t *pixels = mmap(NULL, size, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
	if (pixels == MAP_FAILED) {
		perror("wl-hostile: mmap");
		exit(1);
	}
	struct wl_shm_pool *pool = wl_shm_create_pool(c.shm, fd, (int32_t)size);
	size_t offset = 0;
	for (int i = 0; i < c.n_surfs; i++) {
		struct surf *s = &c.surfs[i];
		size_t n = (size_t)s->width * (size_t)s->height;
		for (int k = 0; k < s->n_buffers; k++) {
			uint32_t rgb = (uint32_t)(i * 0x3b5a7 + k * 0x101010) & 0xffffffu;
			uint32_t colour = 0xff000000u | rgb;
			for (size_t p = 0; p < n; p++)
				pixels[offset / 4 + p] = colour;
			if (c.margin > 0)
				draw_shadow(pixels + offset / 4, s->width, s->height);
			uint32_t format = c.margin > 0 ? WL_SHM_FORMAT_ARGB8888 : WL_SHM_FORMAT_XRGB8888;
			s->buffers[k].wl = wl_shm_pool_create_buffer(pool, (int32_t)offset, s->width,
								     s->height, s->width * 4, format);
			wl_buffer_add_listener(s->buffers[k].wl, &buffer_listener, &s->buffers[k]);
			offset += n * 4;
		}
	}
	wl_shm_pool_destroy(pool);
	munmap(pixels, size);
	close(fd);
}

/* The surface, its opaque region (all of it; --shadow: inside the margin), and its role. */
static void create_surface(struct surf *s, struct surf *parent, int index)
{
	s->wl = wl_compositor_create_surface(c.compositor);
	struct wl_region *opaque = wl_compositor_create_region(c.compositor);
	int32_t m = parent == NULL ? c.margin : 0;
	wl_region_add(opaque, m, m, s->width - 2 * m, s->height - 2 * m);
	wl_surface_set_opaque_region(s->wl, opaque);
	wl_region_destroy(opaque);
	if (parent != NULL) {
		s->sub = wl_subcompositor_get_subsurface(c.subcompositor, s->wl, parent->wl);
		wl_subsurface_set_position(s->sub, SUB_STEP, SUB_STEP);
		wl_subsurface_set_desync(s->sub);
		return;
	}
	s->xdg = xdg_wm_base_get_xdg_surface(c.wm_base, s->wl);
	xdg_surface_add_listener(s->xdg, &xdg_surface_listener, s);
	s->toplevel = xdg_surface_get_toplevel(s->xdg);
	xdg_toplevel_add_listener(s->toplevel, &toplevel_listener, s);
	char title[32];
	snprintf(title, sizeof(title), "wl-hostile %d", index);
	xdg_toplevel_set_title(s->toplevel, title);
	xdg_toplevel_set_app_id(s->toplevel, "wl-hostile");
}

/* Commits as fast as the socket takes it, reading what comes in between; never returns. */
static void flood(struct surf *s)
{
	int fd = wl_display_get_fd(c.display);
	bool blocked = false;
	for (;;) {
		while (wl_display_prepare_read(c.display) != 0)
			if (wl_display_dispatch_pending(c.display) < 0)
				die_connection();
		struct pollfd p = { fd, POLLIN | (blocked ? POLLOUT : 0), 0 };
		if (poll(&p, 1, blocked ? -1 : 0) < 0 && errno != EINTR) {
			wl_display_cancel_read(c.display);
			die_connection();
		}
		if (p.revents & (POLLIN | POLLHUP | POLLERR)) {
			if (wl_display_read_events(c.display) < 0)
				die_connection();
		} else {
			wl_display_cancel_read(c.display);
		}
		if (wl_display_dispatch_pending(c.display) < 0)
			die_connection();
		if (blocked) {
			if (wl_display_flush(c.display) < 0 && errno != EAGAIN)
				die_connection();
			blocked = wl_display_flush(c.display) < 0;
			continue;
		}
		draw(s);
		if (c.commits % 1000 == 0)
			report();
		if (wl_display_flush(c.display) < 0) {
			if (errno != EAGAIN)
				die_connection();
			blocked = true;
		}
	}
}

/* Destroys a surface and its role objects (not its buffers). */
static void destroy_surface(struct surf *s)
{
	if (s->toplevel != NULL)
		xdg_toplevel_destroy(s->toplevel);
	if (s->xdg != NULL)
		xdg_surface_destroy(s->xdg);
	if (s->sub != NULL)
		wl_subsurface_destroy(s->sub);
	wl_surface_destroy(s->wl);
	memset(s, 0, sizeof(*s));
}

/* --churn: toplevels (and a subsurface of the first) created and destroyed as fast as they are
 * configured; the first toplevel's buffer serves them all. */
static void churn(int rounds)
{
	struct surf slots[CHURN_SLOTS], sub = { 0 };
	int serial[CHURN_SLOTS], turns[CHURN_SLOTS];
	memset(slots, 0, sizeof(slots));
	struct surf *first = &c.surfs[0];
	int started = 0, done = 0;
	while (done < rounds) {
		for (int i = 0; i < CHURN_SLOTS; i++) {
			struct surf *s = &slots[i];
			int kind = serial[i] % 4;
			bool go = kind == 0 || (kind == 1 && s->drawn) ||
				  (s->drawn && (s->frames > 0 || ++turns[i] > CHURN_PATIENCE));
			if (s->wl != NULL && go) {
				if (s->frame != NULL)
					wl_callback_destroy(s->frame);
				destroy_surface(s);
				done++;
			}
			if (s->wl == NULL && started < rounds) {
				s->width = s->height = 32;
				s->n_buffers = 1;
				s->buffers[0].wl = first->buffers[0].wl;
				create_surface(s, NULL, c.n_surfs + started);
				wl_surface_commit(s->wl);
				serial[i] = started++;
				turns[i] = 0;
			}
		}
		if (sub.wl != NULL)
			destroy_surface(&sub);
		sub.width = sub.height = first->width;
		sub.n_buffers = 1;
		sub.buffers[0].wl = first->buffers[0].wl;
		sub.no_frames = true;
		create_surface(&sub, first, 0);
		draw(&sub);
		if (wl_display_dispatch(c.display) < 0)
			die_connection();
	}
	printf("churned %d\n", rounds);
}

static void usage(void)
{
	fprintf(stderr, "usage: wl-hostile [--no-ack | --ack-once | --flood | --surfaces N |"
			" --subsurfaces N | --churn N | --shadow M] [--size WxH]\n");
	exit(1);
}

int main(int argc, char **argv)
{
	setvbuf(stdout, NULL, _IOLBF, 0);
	int count = 1;
	int32_t width = 0, height = 0;
	c.mode = PLAIN;
	for (int i = 1; i < argc; i++) {
		if (strcmp(argv[i], "--no-ack") == 0)
			c.mode = NO_ACK;
		else if (strcmp(argv[i], "--ack-once") == 0)
			c.mode = ACK_ONCE;
		else if (strcmp(argv[i], "--flood") == 0)
			c.mode = FLOOD;
		else if (strcmp(argv[i], "--surfaces") == 0 && i + 1 < argc)
			c.mode = SURFACES, count = atoi(argv[++i]);
		else if (strcmp(argv[i], "--subsurfaces") == 0 && i + 1 < argc)
			c.mode = SUBSURFACES, count = atoi(argv[++i]);
		else if (strcmp(argv[i], "--churn") == 0 && i + 1 < argc)
			c.mode = CHURN, count = atoi(argv[++i]);
		else if (strcmp(argv[i], "--shadow") == 0 && i + 1 < argc)
			c.mode = SHADOW, c.margin = atoi(argv[++i]);
		else if (strcmp(argv[i], "--size") == 0 && i + 1 < argc &&
			 sscanf(argv[++i], "%dx%d", &width, &height) == 2 && width > 0 && height > 0)
			;
		else
			usage();
	}
	if (count < 1 || count > MAX_SURFACES || (c.mode == SUBSURFACES && count > MAX_DEPTH))
		usage();
	if (width == 0)
		width = height = c.mode == SURFACES ? 32 : 200;
	/* The shadow leaves an opaque inside. */
	if (c.mode == SHADOW && (c.margin < 1 || 2 * c.margin >= width || 2 * c.margin >= height))
		usage();

	c.display = wl_display_connect(NULL);
	if (c.display == NULL) {
		fprintf(stderr, "wl-hostile: cannot connect to the compositor\n");
		return 1;
	}
	struct wl_registry *registry = wl_display_get_registry(c.display);
	wl_registry_add_listener(registry, &registry_listener, NULL);
	if (wl_display_roundtrip(c.display) < 0)
		die_connection();
	if (c.compositor == NULL || c.shm == NULL || c.wm_base == NULL ||
	    (c.mode == SUBSURFACES && c.subcompositor == NULL)) {
		fprintf(stderr, "wl-hostile: the compositor lacks a global it needs\n");
		return 1;
	}
	xdg_wm_base_add_listener(c.wm_base, &wm_base_listener, NULL);

	c.n_toplevels = c.mode == SURFACES ? count : 1;
	c.n_surfs = c.n_toplevels + (c.mode == SUBSURFACES ? count : 0);
	c.surfs = calloc((size_t)c.n_surfs, sizeof(*c.surfs));
	if (c.surfs == NULL)
		return 1;
	bool animate = c.mode == ACK_ONCE || c.mode == SUBSURFACES;
	for (int i = 0; i < c.n_surfs; i++) {
		struct surf *s = &c.surfs[i];
		bool sub = i >= c.n_toplevels;
		s->width = sub ? SUB_SIZE : width;
		s->height = sub ? SUB_SIZE : height;
		s->n_buffers = c.mode == SURFACES || c.mode == PLAIN || c.mode == SHADOW ? 1 : 2;
		s->animate = animate;
	}
	create_buffers();
	for (int i = 0; i < c.n_surfs; i++)
		create_surface(&c.surfs[i], i > c.n_toplevels - 1 ? &c.surfs[i - 1] : NULL, i);
	/* Subsurfaces first, deepest first: each parent's commit applies its child's position. */
	for (int i = c.n_surfs - 1; i >= c.n_toplevels; i--)
		draw(&c.surfs[i]);
	/* The toplevels' initial commits, without a buffer: the configure follows. */
	for (int i = 0; i < c.n_toplevels; i++)
		wl_surface_commit(c.surfs[i].wl);

	while (!c.ready) {
		if (wl_display_dispatch(c.display) < 0)
			die_connection();
	}
	if (c.mode == FLOOD)
		flood(&c.surfs[0]);
	if (c.mode == CHURN)
		churn(count);
	for (;;)
		if (wl_display_dispatch(c.display) < 0)
			die_connection();
}
