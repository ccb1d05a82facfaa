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

static const uint32_t words[18] = { 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18 };

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
				static uint32_t tmp[VIS_MSG_MAX_ARGS][18];
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
