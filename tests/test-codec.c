/* Unit tests of the protocol codec: every message round-trips; truncated, extended, oversized
 * and lying messages are refused with a reason and never read out of bounds. */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "vis/protocol.h"
#include "wire.h"

/* Two records of the longest kind (T, 12 words). */
static const uint32_t words[24] = { 1,	2,  3,	4,  5,	6,  7,	8,  9,	10, 11, 12,
				    13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24 };

/* How many fields a signature has. */
static int field_count(const char *sig)
{
	int n = 0;
	for (const char *p = sig; *p;) {
		while (*p == ' ')
			p++;
		if (!*p)
			break;
		n++;
		while (*p && *p != ' ')
			p++;
	}
	return n;
}

/* Fills args for a type with distinct values; arrays get two records. */
static void fill(const struct vis_msg_type *t, union vis_arg *args)
{
	const char *sig = t->signature;
	int k = 0;
	memset(args, 0, sizeof(union vis_arg) * VIS_MSG_MAX_ARGS);
	for (const char *p = sig; *p; k++) {
		while (*p == ' ')
			p++;
		char c = p[0] == 'a' ? p[1] : p[0];
		if (c == 'q')
			args[k].q = 0x0123456789abcdefull + (uint64_t)k;
		else if (c == 's') {
			args[k].s.p = "bad window";
			args[k].s.len = 10;
		} else if (c == 'u' || c == 'i')
			args[k].u = 0x80000000u + (uint32_t)k;
		else {
			args[k].a.words = words;
			args[k].a.n = 2;
		}
		while (*p && *p != ' ')
			p++;
	}
}

/* Decodes buf[0, len) expecting result r. */
static enum vis_decode decode(const uint8_t *buf, size_t len, int requests, struct vis_msg *m)
{
	char why[200] = "";
	/* A copy of exactly len bytes, so that ASan catches any read past what was given. */
	uint8_t *copy = malloc(len ? len : 1);
	memcpy(copy, buf, len);
	enum vis_decode r = vis_msg_decode(copy, len, VIS_PROTOCOL_MAX_MESSAGE, requests, m, why,
					   sizeof why);
	if (r == VIS_DECODE_MALFORMED)
		assert(why[0]);
	free(copy);
	return r;
}

int main(void)
{
	size_t count;
	const struct vis_msg_type *types = vis_msg_types(&count);
	int checked = 0;
	for (size_t i = 0; i < count; i++) {
		const struct vis_msg_type *t = &types[i];
		assert(vis_msg_type_find(t->opcode) == t);
		assert(field_count(t->signature) <= VIS_MSG_MAX_ARGS);
		int req = t->dir == VIS_DIR_REQUEST;
		union vis_arg args[VIS_MSG_MAX_ARGS];
		fill(t, args);
		struct vis_buf b;
		vis_buf_init(&b);
		assert(vis_msg_encode(&b, t->opcode, args) == 0);
		assert(vis_wire_get_u32(b.data) == b.len);

		/* Round trip; the message must not decode in the other direction. */
		struct vis_msg m;
		uint8_t *copy = malloc(b.len);
		memcpy(copy, b.data, b.len);
		char why[200];
		assert(vis_msg_decode(copy, b.len, VIS_PROTOCOL_MAX_MESSAGE, req, &m, why,
				      sizeof why) == VIS_DECODE_OK);
		assert(m.type == t && m.size == b.len);
		struct vis_buf again;
		vis_buf_init(&again);
		union vis_arg back[VIS_MSG_MAX_ARGS];
		memcpy(back, m.args, sizeof back);
		for (int k = 0; k < VIS_MSG_MAX_ARGS; k++)
			if (args[k].a.words == words && back[k].a.raw) {
				/* Re-encode decoded arrays from their words. */
				static uint32_t tmp[VIS_MSG_MAX_ARGS][24];
				char rec = 0;
				const char *p = t->signature;
				for (int f = 0; f <= k; f++) {
					while (*p == ' ')
						p++;
					rec = p[0] == 'a' ? p[1] : p[0];
					while (*p && *p != ' ')
						p++;
				}
				for (uint32_t r = 0; r < back[k].a.n; r++)
					for (uint32_t w = 0; w < vis_msg_record_words(rec); w++)
						tmp[k][r * vis_msg_record_words(rec) + w] =
							vis_arg_word(&back[k], rec, r, w);
				back[k].a.words = tmp[k];
			}
		assert(vis_msg_encode(&again, t->opcode, back) == 0);
		assert(again.len == b.len && memcmp(again.data, b.data, b.len) == 0);
		vis_buf_finish(&again);
		free(copy);
		assert(decode(b.data, b.len, !req, &m) == VIS_DECODE_MALFORMED);

		/* Every prefix needs more; a shorter declared size is malformed. */
		for (size_t len = 0; len < b.len; len++)
			assert(decode(b.data, len, req, &m) == VIS_DECODE_MORE);
		for (uint32_t size = 0; size < b.len; size++) {
			uint8_t *t2 = malloc(b.len);
			memcpy(t2, b.data, b.len);
			vis_wire_put_u32(t2, size);
			assert(decode(t2, b.len, req, &m) == VIS_DECODE_MALFORMED);
			free(t2);
		}
		/* An extended payload (4 more zero bytes) is malformed. */
		uint8_t *ext = calloc(1, b.len + 4);
		memcpy(ext, b.data, b.len);
		vis_wire_put_u32(ext, (uint32_t)b.len + 4);
		assert(decode(ext, b.len + 4, req, &m) == VIS_DECODE_MALFORMED);
		free(ext);
		vis_buf_finish(&b);
		checked++;
	}

	/*
	 * Protocol 3's fields where the table puts them: create's namespace and 64-bit external ID
	 * after its border, little-endian; lookup; the tree record's 12 words; the stack notice's
	 * external ID at its end.
	 */
	struct vis_buf e;
	vis_buf_init(&e);
	union vis_arg c[VIS_MSG_MAX_ARGS] = { { .u = 0 }, { .i = -1 }, { .i = 2 }, { .u = 3 },
					      { .u = 4 }, { .u = 1 }, { .u = 5 },
					      { .u = VIS_EXTERNAL_X11 }, { .q = 0x1122334455667788ull } };
	assert(vis_msg_encode(&e, VIS_OP_CREATE, c) == 0 && e.len == VIS_MSG_HEADER + 40);
	assert(vis_wire_get_u32(e.data + VIS_MSG_HEADER + 28) == VIS_EXTERNAL_X11);
	assert(vis_wire_get_u32(e.data + VIS_MSG_HEADER + 32) == 0x55667788u &&
	       vis_wire_get_u32(e.data + VIS_MSG_HEADER + 36) == 0x11223344u);
	struct vis_msg dm;
	assert(decode(e.data, e.len, 1, &dm) == VIS_DECODE_OK && dm.args[7].u == VIS_EXTERNAL_X11 &&
	       dm.args[8].q == 0x1122334455667788ull);
	e.len = 0;
	union vis_arg l[VIS_MSG_MAX_ARGS] = { { .u = VIS_EXTERNAL_X11 }, { .q = 0x1e00003 } };
	assert(vis_msg_encode(&e, VIS_OP_LOOKUP, l) == 0 && e.len == VIS_MSG_HEADER + 12);
	assert(decode(e.data, e.len, 1, &dm) == VIS_DECODE_OK && dm.type->opcode == 26 &&
	       dm.args[0].u == 1 && dm.args[1].q == 0x1e00003);
	e.len = 0;
	union vis_arg f[VIS_MSG_MAX_ARGS] = { { .u = 9 }, { .u = 42 } };
	assert(vis_msg_encode(&e, VIS_OP_FOUND, f) == 0 && e.len == VIS_MSG_HEADER + 8);
	assert(decode(e.data, e.len, 0, &dm) == VIS_DECODE_OK && dm.type->opcode == 73 &&
	       dm.args[1].u == 42);
	assert(vis_msg_record_words('T') == 12);
	e.len = 0;
	union vis_arg tr[VIS_MSG_MAX_ARGS] = { { .u = 1 }, { .u = 0 } };
	tr[2].a.words = words;
	tr[2].a.n = 2;
	assert(vis_msg_encode(&e, VIS_OP_TREE, tr) == 0 && e.len == VIS_MSG_HEADER + 12 + 2 * 48);
	char why[200];
	/* Not through decode(), whose copy is gone with the array's words. */
	assert(vis_msg_decode(e.data, e.len, VIS_PROTOCOL_MAX_MESSAGE, 0, &dm, why, sizeof why) ==
		       VIS_DECODE_OK &&
	       dm.args[2].a.n == 2 && vis_arg_word(&dm.args[2], 'T', 1, 11) == 24);
	e.len = 0;
	union vis_arg st[VIS_MSG_MAX_ARGS] = { { .q = 7 } };
	st[11].u = VIS_EXTERNAL_WAYLAND;
	st[12].q = UINT64_MAX - 1;
	assert(vis_msg_encode(&e, VIS_OP_STACK, st) == 0 && e.len == VIS_MSG_HEADER + 8 + 44 + 8);
	assert(decode(e.data, e.len, 0, &dm) == VIS_DECODE_OK && dm.args[11].u == 2 &&
	       dm.args[12].q == UINT64_MAX - 1);
	vis_buf_finish(&e);

	/* Sizes: 0, 1, header - 1, not a multiple of 4, the maximum + 1, UINT32_MAX. */
	uint8_t h[VIS_MSG_HEADER] = { 0 };
	struct vis_msg m;
	uint32_t bad_sizes[] = { 0, 1, VIS_MSG_HEADER - 1, 13, VIS_PROTOCOL_MAX_MESSAGE + 1,
				 UINT32_MAX };
	for (size_t i = 0; i < sizeof bad_sizes / sizeof bad_sizes[0]; i++) {
		vis_wire_put_u32(h, bad_sizes[i]);
		vis_wire_put_u16(h + 4, VIS_OP_SYNC);
		assert(decode(h, sizeof h, 1, &m) == VIS_DECODE_MALFORMED);
	}
	/* The maximum itself is accepted by the header check (then needs the bytes). */
	vis_wire_put_u32(h, VIS_PROTOCOL_MAX_MESSAGE);
	assert(decode(h, sizeof h, 1, &m) == VIS_DECODE_MORE);
	/* Unknown opcodes, and nonzero padding. */
	vis_wire_put_u32(h, VIS_MSG_HEADER);
	vis_wire_put_u16(h + 4, 999);
	assert(decode(h, sizeof h, 1, &m) == VIS_DECODE_MALFORMED);
	vis_wire_put_u16(h + 4, VIS_OP_SYNC);
	h[6] = 1;
	assert(decode(h, sizeof h, 1, &m) == VIS_DECODE_MALFORMED);
	h[6] = 0;
	assert(decode(h, sizeof h, 1, &m) == VIS_DECODE_OK);

	/* Counts larger than the payload, and a count whose byte size would wrap 32 bits. */
	uint8_t arr[VIS_MSG_HEADER + 12] = { 0 };
	vis_wire_put_u32(arr, sizeof arr);
	vis_wire_put_u16(arr + 4, VIS_OP_REPAINT);
	vis_wire_put_u32(arr + 16, 1); /* 1 record of 4 bytes: exactly fits? no: 0 bytes left */
	assert(decode(arr, sizeof arr, 0, &m) == VIS_DECODE_MALFORMED);
	vis_wire_put_u32(arr + 16, 0x40000000u);
	assert(decode(arr, sizeof arr, 0, &m) == VIS_DECODE_MALFORMED);
	vis_wire_put_u32(arr + 16, 0);
	assert(decode(arr, sizeof arr, 0, &m) == VIS_DECODE_OK);
	/* A string length near UINT32_MAX. */
	uint8_t err[VIS_MSG_HEADER + 16] = { 0 };
	vis_wire_put_u32(err, sizeof err);
	vis_wire_put_u16(err + 4, VIS_OP_ERROR);
	vis_wire_put_u32(err + 20, UINT32_MAX);
	assert(decode(err, sizeof err, 0, &m) == VIS_DECODE_MALFORMED);
	vis_wire_put_u32(err + 20, 0);
	assert(decode(err, sizeof err, 0, &m) == VIS_DECODE_OK);

	/* Encoding refuses strings with NUL and oversized arrays. */
	struct vis_buf b;
	vis_buf_init(&b);
	union vis_arg a[VIS_MSG_MAX_ARGS] = { 0 };
	a[3].s.p = "a\0b";
	a[3].s.len = 3;
	assert(vis_msg_encode(&b, VIS_OP_ERROR, a) == -1 && b.len == 0);
	a[1].u = 0;
	a[2].a.n = VIS_PROTOCOL_MAX_MESSAGE / 4;
	a[2].a.words = words;
	assert(vis_msg_encode(&b, VIS_OP_REPAINT, a) == -1 && b.len == 0);
	assert(vis_msg_encode(&b, 12345, a) == -1);
	vis_buf_finish(&b);

	printf("codec: %d message types round-trip, every truncation refused\n", checked);
	return 0;
}
