/*
 * Writes the hand-made seeds of the fuzz targets' corpora: gen-corpus DIR writes DIR/codec,
 * DIR/scene and DIR/client (which must exist), every file named seed-*. The committed corpora are
 * these seeds plus what fuzzing added (files named by their SHA-1). Messages are made by the
 * codec itself, so the seeds follow messages.h; the client seeds answer the requests of
 * fuzz-client.h.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "fuzz-client.h"
#include "vis/protocol.h"
#include "wire.h"

static const char *out_dir;
static int written;

/* Writes one seed: the control byte (none if ctl < 0), then n bytes. */
static void seed(const char *target, const char *name, int ctl, const void *p, size_t n)
{
	char path[512];
	snprintf(path, sizeof(path), "%s/%s/seed-%s", out_dir, target, name);
	FILE *fp = fopen(path, "wb");
	if (!fp || (ctl >= 0 && fputc(ctl, fp) == EOF) || fwrite(p, 1, n, fp) != n || fclose(fp)) {
		perror(path);
		exit(1);
	}
	written++;
}

/* Appends a message; the arguments must be valid. */
static void put(struct vis_buf *b, uint32_t opcode, const union vis_arg *args)
{
	if (vis_msg_encode(b, opcode, args) < 0) {
		fprintf(stderr, "gen-corpus: cannot encode opcode %u\n", opcode);
		exit(1);
	}
}

static const uint32_t words[24] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12,
				    0, 0x7fffffff, 0x80000000, 0xffffffff, 1, 1, 1, 1, 2, 0, 3, 2 };

/* Arguments for a type: ordinary values, or edge ones (edge 1) for every field. */
static void fill(const struct vis_msg_type *t, union vis_arg *args, int edge)
{
	static const uint32_t edges[] = { 0, 0xffffffff, 0x80000000, 0x7fffffff, 1 };
	static const char *strings[] = { "", "x", "ab", "abc", "no such window 9" };
	memset(args, 0, sizeof(union vis_arg) * VIS_MSG_MAX_ARGS);
	const char *sig = t->signature;
	for (int k = 0; *sig; k++) {
		while (*sig == ' ')
			sig++;
		char c = sig[0] == 'a' ? sig[1] : sig[0];
		if (c == 'q')
			args[k].q = edge ? UINT64_MAX - (uint64_t)k : 1;
		else if (c == 's') {
			args[k].s.p = strings[edge ? k % 4 : 4];
			args[k].s.len = (uint32_t)strlen(args[k].s.p);
		} else if (c == 'u' || c == 'i')
			args[k].u = edge ? edges[k % 5] : (uint32_t)k + 1;
		else {
			args[k].a.words = words;
			args[k].a.n = edge ? 0 : 24 / vis_msg_record_words(c);
		}
		sig += strcspn(sig, " ");
	}
}

/* The codec seeds: every message, edge values, damaged copies, streams, every maximum. */
static void codec_seeds(void)
{
	size_t count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	struct vis_buf all[2];
	vis_buf_init(&all[0]);
	vis_buf_init(&all[1]);
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *t = &types[i];
		int req = t->dir == VIS_DIR_REQUEST;
		for (int edge = 0; edge < 2; edge++) {
			union vis_arg args[VIS_MSG_MAX_ARGS];
			struct vis_buf b;
			char name[64];
			vis_buf_init(&b);
			fill(t, args, edge);
			put(&b, t->opcode, args);
			snprintf(name, sizeof(name), "%s%s", t->name, edge ? "-edge" : "");
			seed("codec", name, req, b.data, b.len);
			if (!edge) {
				vis_buf_append(&all[req], b.data, b.len);
				/* Cut short, and with a word more than its fields. */
				snprintf(name, sizeof(name), "%s-short", t->name);
				seed("codec", name, req, b.data, b.len - 4);
				vis_wire_put_u32(b.data, (uint32_t)b.len + 4);
				vis_buf_append(&b, "\0\0\0\0", 4);
				snprintf(name, sizeof(name), "%s-long", t->name);
				seed("codec", name, req, b.data, b.len);
			}
			vis_buf_finish(&b);
		}
	}
	seed("codec", "replies", 0, all[0].data, all[0].len);
	seed("codec", "requests", 1, all[1].data, all[1].len);
	/* The requests against every maximum the target knows. */
	for (int m = 1; m < 8; m++) {
		char name[32];
		snprintf(name, sizeof(name), "requests-max-%d", m);
		seed("codec", name, 1 | m << 1, all[1].data, all[1].len);
	}
	vis_buf_finish(&all[0]);
	vis_buf_finish(&all[1]);

	/* Headers that lie, and fields that do. */
	static const struct {
		const char *name;
		uint32_t w[8];
		size_t n;
	} bad[] = {
		{ "size-0", { 0, 21 }, 2 },
		{ "size-7", { 7, 21 }, 2 },
		{ "size-odd", { 10, 21, 0 }, 3 },
		{ "size-huge", { 0xfffffffc, 21 }, 2 },
		{ "size-over-max", { VIS_PROTOCOL_MAX_MESSAGE + 4, 21 }, 2 },
		{ "opcode-unknown", { 8, 200 }, 2 },
		{ "opcode-reply", { 12, 71, 1 }, 3 },
		{ "header-pad", { 8, 21 | 1u << 16 }, 2 },
		{ "header-only", { 8, 21 }, 2 },
		{ "string-over", { 24, 96, 1, 2, 3, 0xffffffff }, 6 },
		{ "string-nul", { 28, 96, 1, 2, 3, 3, 0x00616161 }, 7 },
		{ "string-pad", { 28, 96, 1, 2, 3, 2, 0x01006161 }, 7 },
		{ "count-over", { 20, 67, 1, 0, 1000 }, 5 },
		{ "count-wrap", { 20, 68, 1, 0, 0x20000000 }, 5 },
	};
	for (size_t i = 0; i < sizeof(bad) / sizeof(bad[0]); i++) {
		uint8_t b[32];
		for (size_t k = 0; k < bad[i].n; k++)
			vis_wire_put_u32(b + 4 * k, bad[i].w[k]);
		/* Requests (21: sync) for the daemon's side, the rest for a client's. */
		seed("codec", bad[i].name, (bad[i].w[1] & 0xffff) < 64, b, 4 * bad[i].n);
	}
}

/* The scene seeds: every record, every way of writing one, every refusal. */
static void scene_seeds(void)
{
	static const char *const scenes[][2] = {
		{ "empty", "" },
		{ "blank", "\n\n  \t\n" },
		{ "one", "window 1 0 0 10 10\n" },
		{ "screen", "screen 1920 1080\nwindow 1 0 0 100 100\nwindow 2 50 50 100 100\n" },
		{ "crlf", "screen 640 480\r\nwindow 1 0 0 10 10\r\nwindow 2 -5 -5 10 10\r\n" },
		{ "comments", "# a desktop\nscreen 64 48 # small\n\n#window 1 0 0 1 1\nwindow 7 1 2 3 4#x\n" },
		{ "tabs", "\twindow\t3\t-1\t-2\t3\t4\t\nwindow 4  0  0  1  1" },
		{ "limits", "screen 2147483647 2147483647\nwindow 0 -2147483648 -2147483648 2147483647 "
			    "2147483647\nwindow 4294967295 2147483647 2147483647 1 1\n" },
		{ "no-newline", "window 1 0 0 1 1" },
		{ "minus-zero", "window 1 -0 -0 1 1\n" },
		{ "stack", "window 3 0 0 50 50\nwindow 1 10 10 50 50\nwindow 2 20 20 50 50\n"
			   "window 9 -30 -30 100 100\nwindow 5 0 0 1 1\n" },
		{ "dup", "window 1 0 0 1 1\nwindow 2 0 0 1 1\nwindow 1 0 0 1 1\n" },
		{ "dup-then-junk", "window 1 0 0 1 1\nwindow 1 0 0 1 1\njunk\n" },
		{ "screen-twice", "screen 1 1\nscreen 2 2\n" },
		{ "screen-late", "window 1 0 0 1 1\nscreen 10 10\n" },
		{ "screen-zero", "screen 0 10\n" },
		{ "screen-fields", "screen 10\n" },
		{ "unknown", "windows 1 0 0 1 1\n" },
		{ "fields-few", "window 1 0 0 1\n" },
		{ "fields-many", "window 1 0 0 1 1 1 1 1\n" },
		{ "width-zero", "window 1 0 0 0 1\n" },
		{ "height-neg", "window 1 0 0 1 -1\n" },
		{ "id-neg", "window -1 0 0 1 1\n" },
		{ "id-over", "window 4294967296 0 0 1 1\n" },
		{ "x-over", "window 1 2147483648 0 1 1\n" },
		{ "y-under", "window 1 0 -2147483649 1 1\n" },
		{ "huge", "window 1 99999999999999999999999 0 1 1\n" },
		{ "plus", "window +1 0 0 1 1\n" },
		{ "hex", "window 0x10 0 0 1 1\n" },
		{ "trailing", "window 1 0 0 1 1x\n" },
		{ "minus-only", "window 1 - 0 1 1\n" },
		{ "cr-inside", "window 1 0\r0 1 1\n" },
		{ "binary", "window \x01\xff\x7f 0 0 1 1\n" },
		{ "long-field", "window 123456789012345678901234567890123456789012345678901234567890 0 0 1 1\n" },
	};
	for (size_t i = 0; i < sizeof(scenes) / sizeof(scenes[0]); i++)
		seed("scene", scenes[i][0], -1, scenes[i][1], strlen(scenes[i][1]));
	static const char nul[] = "window 1 0 0 1 1\nwindow 2\0 0 0 1 1\n";
	seed("scene", "nul", -1, nul, sizeof(nul) - 1);
}

#define U(v) { .u = (v) }
#define A(w, n) { .a = { NULL, (w), (n) } }

/* Appends an error reply. */
static void put_error(struct vis_buf *b, uint32_t seq, uint32_t opcode, uint32_t code)
{
	union vis_arg a[4] = { U(seq), U(opcode), U(code), { .s = { "refused", 7 } } };
	put(b, VIS_OP_ERROR, a);
}

/* Appends the answers to every request of fuzz-client.h, and notices among them. */
static void put_session(struct vis_buf *b, uint64_t *serial)
{
	static const uint32_t states[] = { 5, 0, 6, 2 }, node[] = { 5, 0, 1, 2, 30, 40, 0, 3, 1,
										    1, 0x1e00003, 0 };
	static const uint32_t rects[] = { 0, 0, 10, 5, (uint32_t)-3, 5, 20, 1 }, ids[] = { 5, 6 };
	put(b, VIS_OP_VISIBILITY, (union vis_arg[]){ { .q = (*serial)++ }, U(5), U(0), U(3), U(0) });
	put(b, VIS_OP_CREATED, (union vis_arg[]){ U(FUZZ_SEQ_CREATE), U(5) });
	put_error(b, FUZZ_SEQ_MAP, VIS_OP_MAP, VIS_ERROR_WINDOW);
	put(b, VIS_OP_STATE, (union vis_arg[]){ U(FUZZ_SEQ_GET_STATE), U(FUZZ_WINDOW), U(1) });
	put(b, VIS_OP_STATES, (union vis_arg[]){ U(FUZZ_SEQ_GET_STATES), U(1), A(states, 1) });
	put(b, VIS_OP_EXPOSURE,
	    (union vis_arg[]){ { .q = (*serial)++ }, U(5), U(1), U(2), A(rects, 2) });
	put(b, VIS_OP_STATES, (union vis_arg[]){ U(FUZZ_SEQ_GET_STATES), U(0), A(states + 2, 1) });
	put(b, VIS_OP_TREE, (union vis_arg[]){ U(FUZZ_SEQ_GET_TREE), U(0), A(node, 1) });
	put(b, VIS_OP_REGION,
	    (union vis_arg[]){ U(FUZZ_SEQ_GET_REGION), U(FUZZ_WINDOW), U(1), A(rects, 1) });
	put(b, VIS_OP_STACK, (union vis_arg[]){ { .q = (*serial)++ }, U(VIS_STACK_RESTACK), U(5),
						 U(0), { .i = -4 }, U(6), U(7), U(8), U(6), U(3), U(0),
						 U(VIS_EXTERNAL_X11), { .q = 0x1e00003 } });
	put(b, VIS_OP_OVERFLOW, (union vis_arg[]){ { .q = (*serial)++ }, U(40), U(1) });
	put(b, VIS_OP_STACK, (union vis_arg[]){ { .q = (*serial)++ }, U(VIS_STACK_RESYNC), U(5),
						 U(0), { .i = -4 }, U(6), U(7), U(8), U(6), U(3), U(2),
						 U(0), { .q = 0 } });
	put(b, VIS_OP_REGION,
	    (union vis_arg[]){ U(FUZZ_SEQ_GET_REGION), U(FUZZ_WINDOW), U(0), A(rects + 4, 1) });
	put(b, VIS_OP_REPAINT, (union vis_arg[]){ U(FUZZ_SEQ_GET_REPAINT), U(0), A(ids, 2) });
	put(b, VIS_OP_SYNCED, (union vis_arg[]){ U(FUZZ_SEQ_SYNC) });
}

/* The client seeds: good sessions read in every chunk size, errors, and broken daemons. */
static void client_seeds(void)
{
	struct vis_buf b;
	uint64_t serial = 1;
	char name[64];
	vis_buf_init(&b);
	put_session(&b, &serial);
	for (int ctl = 0; ctl < 16; ctl++) {
		snprintf(name, sizeof(name), "session-%d", ctl);
		seed("client", name, ctl, b.data, b.len);
	}
	/* Every sync the target sends, answered: its queue grows while it is read. */
	for (uint32_t s = FUZZ_SEQ_SYNC + 1; s < FUZZ_SEQ_SYNC + FUZZ_SYNCS; s++)
		put(&b, VIS_OP_SYNCED, (union vis_arg[]){ U(s) });
	seed("client", "syncs", 0, b.data, b.len);
	vis_buf_finish(&b);

	/* The handshake in the daemon's bytes: granted, refused every way, broken. */
	static const uint32_t hello[7] = { 1, VIS_PROTOCOL_VERSION, FUZZ_CLIENT_ID, VIS_ROLE_CLIENT,
					   100, 200, 65536 };
	for (int k = 0; k < 3; k++) {
		union vis_arg a[7];
		for (int j = 0; j < 7; j++)
			a[j].u = hello[j];
		a[1].u += k == 1;       /* another version */
		a[3].u += 3 * (k == 2); /* a role that does not exist */
		vis_buf_init(&b);
		put(&b, VIS_OP_HELLO_REPLY, a);
		serial = 1;
		put_session(&b, &serial);
		seed("client", k == 0 ? "handshake" : k == 1 ? "hello-version" : "hello-role",
		     FUZZ_HANDSHAKE, b.data, b.len);
		vis_buf_finish(&b);
	}
	for (uint32_t code = VIS_ERROR_MALFORMED; code <= VIS_ERROR_STATE; code++) {
		vis_buf_init(&b);
		put_error(&b, 1, VIS_OP_HELLO, code);
		snprintf(name, sizeof(name), "hello-refused-%u", code);
		seed("client", name, FUZZ_HANDSHAKE, b.data, b.len);
		vis_buf_finish(&b);
	}
	vis_buf_init(&b);
	put(&b, VIS_OP_VISIBILITY, (union vis_arg[]){ { .q = 1 }, U(5), U(0), U(3), U(0) });
	seed("client", "hello-notice-first", FUZZ_HANDSHAKE, b.data, b.len);
	vis_buf_finish(&b);
	vis_buf_init(&b);
	put(&b, VIS_OP_CREATED, (union vis_arg[]){ U(FUZZ_SEQ_CREATE), U(5) });
	seed("client", "hello-reply-first", FUZZ_HANDSHAKE, b.data, b.len);
	vis_buf_finish(&b);

	/* Every request refused, the fatal way last. */
	static const uint32_t ops[] = { VIS_OP_CREATE,	   VIS_OP_MAP,	    VIS_OP_GET_STATE,
					VIS_OP_GET_STATES, VIS_OP_GET_TREE, VIS_OP_GET_REGION,
					VIS_OP_GET_REPAINT, VIS_OP_SYNC };
	vis_buf_init(&b);
	for (uint32_t i = 0; i < 8; i++)
		put_error(&b, FUZZ_SEQ_CREATE + i, ops[i], i == 7 ? VIS_ERROR_MALFORMED : 4 + i % 5);
	seed("client", "errors", FUZZ_REENTER, b.data, b.len);
	vis_buf_finish(&b);

	/* Broken daemons: each a message the library must refuse with EPROTO. */
	static const uint32_t bad_state[] = { 5, 3 },
			      bad_node[] = { 5, 0, 0, 0, 1, 1, 0, 0, 4, 0, 0, 0 },
			      bad_external[] = { 5, 0, 0, 0, 1, 1, 0, 0, 3, 0, 7, 0 };
	static const struct {
		const char *name;
		uint32_t op;
		union vis_arg a[VIS_MSG_MAX_ARGS];
	} broken[] = {
		{ "wrong-seq", VIS_OP_CREATED, { U(99), U(5) } },
		{ "wrong-reply", VIS_OP_SYNCED, { U(FUZZ_SEQ_CREATE) } },
		{ "created-0", VIS_OP_CREATED, { U(FUZZ_SEQ_CREATE), U(0) } },
		{ "hello-again", VIS_OP_HELLO_REPLY, { U(1), U(1), U(7), U(0), U(1), U(1), U(64) } },
		{ "error-later", VIS_OP_ERROR, { U(FUZZ_SEQ_SYNC), U(VIS_OP_SYNC), U(4) } },
		{ "error-unsent", VIS_OP_ERROR, { U(1000), U(VIS_OP_MAP), U(1) } },
		{ "error-opcode", VIS_OP_ERROR, { U(FUZZ_SEQ_CREATE), U(VIS_OP_MAP), U(4) } },
		{ "serial-gap", VIS_OP_VISIBILITY, { { .q = 2 }, U(5), U(0), U(3), U(0) } },
		{ "notice-state", VIS_OP_VISIBILITY, { { .q = 1 }, U(5), U(4), U(3), U(0) } },
		{ "exposure-flags", VIS_OP_EXPOSURE, { { .q = 1 }, U(5), U(2), U(0), A(NULL, 0) } },
		{ "stack-change", VIS_OP_STACK, { { .q = 1 }, U(VIS_STACK_LOOK + 1), U(5) } },
		{ "stack-external", VIS_OP_STACK,
		  { { .q = 1 }, U(VIS_STACK_CREATE), U(5), U(0), U(0), U(0), U(1), U(1), U(0), U(0),
		    U(0), U(0), { .q = 7 } } },
	};
	for (size_t i = 0; i < sizeof(broken) / sizeof(broken[0]); i++) {
		vis_buf_init(&b);
		put(&b, broken[i].op, broken[i].a);
		seed("client", broken[i].name, 0, b.data, b.len);
		vis_buf_finish(&b);
	}
	/* Past the first answers, a states and a tree record of no state, a region for another
	 * window, a chunk with more = 2. */
	static const struct {
		const char *name;
		uint32_t op;
		union vis_arg a[4];
	} late[] = {
		{ "states-state", VIS_OP_STATES, { U(FUZZ_SEQ_GET_STATES), U(0), A(bad_state, 1) } },
		{ "tree-state", VIS_OP_TREE, { U(FUZZ_SEQ_GET_TREE), U(0), A(bad_node, 1) } },
		{ "tree-external", VIS_OP_TREE, { U(FUZZ_SEQ_GET_TREE), U(0), A(bad_external, 1) } },
		{ "region-window", VIS_OP_REGION, { U(FUZZ_SEQ_GET_REGION), U(6), U(0), A(NULL, 0) } },
		{ "more-2", VIS_OP_REPAINT, { U(FUZZ_SEQ_GET_REPAINT), U(2), A(NULL, 0) } },
	};
	for (size_t i = 0; i < sizeof(late) / sizeof(late[0]); i++) {
		vis_buf_init(&b);
		put(&b, VIS_OP_CREATED, (union vis_arg[]){ U(FUZZ_SEQ_CREATE), U(5) });
		put(&b, VIS_OP_STATE, (union vis_arg[]){ U(FUZZ_SEQ_GET_STATE), U(5), U(3) });
		if (late[i].op != VIS_OP_STATES)
			put(&b, VIS_OP_STATES, (union vis_arg[]){ U(FUZZ_SEQ_GET_STATES), U(0), A(NULL, 0) });
		if (late[i].op == VIS_OP_REGION || late[i].op == VIS_OP_REPAINT)
			put(&b, VIS_OP_TREE, (union vis_arg[]){ U(FUZZ_SEQ_GET_TREE), U(0), A(NULL, 0) });
		if (late[i].op == VIS_OP_REPAINT)
			put(&b, VIS_OP_REGION, (union vis_arg[]){ U(FUZZ_SEQ_GET_REGION), U(5), U(0),
								  A(NULL, 0) });
		put(&b, late[i].op, late[i].a);
		seed("client", late[i].name, 2, b.data, b.len);
		vis_buf_finish(&b);
	}
	/* Bytes the codec refuses, and a message cut short by the hang-up. */
	uint8_t raw[16];
	vis_wire_put_u32(raw, 0x7ffffff0u);
	vis_wire_put_u32(raw + 4, VIS_OP_SYNCED);
	seed("client", "oversized", 0, raw, 8);
	vis_wire_put_u32(raw, 32);
	seed("client", "truncated", 0, raw, 12);
	vis_wire_put_u32(raw, 12);
	vis_wire_put_u32(raw + 4, VIS_OP_MAP);
	seed("client", "request-opcode", 0, raw, 12);
	seed("client", "nothing", 0, raw, 0);
}

int main(int argc, char **argv)
{
	if (argc != 2) {
		fprintf(stderr, "usage: gen-corpus DIR (with DIR/codec, DIR/scene, DIR/client)\n");
		return 2;
	}
	out_dir = argv[1];
	codec_seeds();
	scene_seeds();
	client_seeds();
	printf("gen-corpus: %d seeds written\n", written);
	return 0;
}
