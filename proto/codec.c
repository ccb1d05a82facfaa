/* The generic codec: one encoder and one decoder for every message, driven by messages.h. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "vis/protocol.h"
#include "wire.h"

enum {
#define VIS_MSG_INDEX(e, op, dir, name, sig, doc) MSG_INDEX_##e,
	VIS_MESSAGES(VIS_MSG_INDEX)
#undef VIS_MSG_INDEX
	MSG_COUNT
};

static const struct vis_msg_type msg_types[MSG_COUNT] = {
#define VIS_MSG_TYPE(e, op, d, n, sig, text) { op, VIS_DIR_##d, n, sig, text },
	VIS_MESSAGES(VIS_MSG_TYPE)
#undef VIS_MSG_TYPE
};

const struct vis_msg_type *vis_msg_type_find(uint32_t opcode)
{
	switch (opcode) {
#define VIS_MSG_CASE(e, op, dir, name, sig, doc) \
	case op:                                 \
		return &msg_types[MSG_INDEX_##e];
		VIS_MESSAGES(VIS_MSG_CASE)
#undef VIS_MSG_CASE
	default:
		return NULL;
	}
}

const struct vis_msg_type *vis_msg_types(size_t *count)
{
	*count = MSG_COUNT;
	return msg_types;
}

uint32_t vis_msg_record_words(char record)
{
	switch (record) {
	case 'W':
		return 1;
	case 'S':
		return 2;
	case 'R':
		return 4;
	case 'T':
		return 12;
	default:
		return 0;
	}
}

/*
 * Reads the next field's type from a signature: 'u', 'i', 'q', 's', or an array's record letter.
 * Returns 0 at the end.
 */
static char next_field(const char **sig)
{
	const char *p = *sig;
	while (*p == ' ')
		p++;
	if (!*p)
		return 0;
	char type = p[0] == 'a' ? p[1] : p[0];
	while (*p && *p != ' ')
		p++;
	*sig = p;
	return type;
}

static int is_array(char type)
{
	return vis_msg_record_words(type) != 0;
}

enum vis_decode vis_msg_peek(const uint8_t *p, size_t avail, uint32_t max, uint32_t *size,
			     char *why, size_t why_len)
{
	if (avail < VIS_MSG_HEADER)
		return VIS_DECODE_MORE;
	uint32_t n = vis_wire_get_u32(p);
	if (n < VIS_MSG_HEADER) {
		snprintf(why, why_len, "declared size %u is less than the %u-byte header", n,
			 VIS_MSG_HEADER);
		return VIS_DECODE_MALFORMED;
	}
	if (n > max) {
		snprintf(why, why_len, "declared size %u is over the maximum of %u", n, max);
		return VIS_DECODE_MALFORMED;
	}
	if (n % 4) {
		snprintf(why, why_len, "declared size %u is not a multiple of 4", n);
		return VIS_DECODE_MALFORMED;
	}
	*size = n;
	return VIS_DECODE_OK;
}

enum vis_decode vis_msg_decode(const uint8_t *p, size_t avail, uint32_t max, int want_requests,
			       struct vis_msg *out, char *why, size_t why_len)
{
	uint32_t size;
	out->type = NULL;
	enum vis_decode r = vis_msg_peek(p, avail, max, &size, why, why_len);
	if (r != VIS_DECODE_OK)
		return r;
	/* The opcode is known from the header alone: name it even if the body is incomplete. */
	uint16_t opcode = vis_wire_get_u16(p + 4);
	const struct vis_msg_type *type = vis_msg_type_find(opcode);
	if (!type || (type->dir == VIS_DIR_REQUEST) != (want_requests != 0)) {
		snprintf(why, why_len, "unknown opcode %u", opcode);
		return VIS_DECODE_MALFORMED;
	}
	out->type = type;
	if (vis_wire_get_u16(p + 6) != 0) {
		snprintf(why, why_len, "%s: header padding is not zero", type->name);
		return VIS_DECODE_MALFORMED;
	}
	if (avail < size)
		return VIS_DECODE_MORE;
	out->size = size;

	size_t off = VIS_MSG_HEADER;
	const char *sig = type->signature;
	char t;
	for (int k = 0; (t = next_field(&sig)); k++) {
		size_t left = size - off;
		union vis_arg *a = &out->args[k];
		if (t == 'q') {
			if (left < 8)
				goto truncated;
			a->q = vis_wire_get_u64(p + off);
			off += 8;
			continue;
		}
		if (left < 4)
			goto truncated;
		uint32_t v = vis_wire_get_u32(p + off);
		off += 4;
		left -= 4;
		if (t == 'u') {
			a->u = v;
		} else if (t == 'i') {
			a->i = (int32_t)v;
		} else if (t == 's') {
			/* Compared in 64 bits: v + 3 must not wrap. */
			uint64_t padded = ((uint64_t)v + 3) & ~(uint64_t)3;
			if (padded > left) {
				snprintf(why, why_len,
					 "%s: field %d: string of %u bytes, only %zu left in the message",
					 type->name, k + 1, v, left);
				return VIS_DECODE_MALFORMED;
			}
			if (memchr(p + off, 0, v)) {
				snprintf(why, why_len, "%s: field %d: string holds a NUL byte",
					 type->name, k + 1);
				return VIS_DECODE_MALFORMED;
			}
			for (uint64_t j = v; j < padded; j++)
				if (p[off + j]) {
					snprintf(why, why_len, "%s: field %d: string padding is not zero",
						 type->name, k + 1);
					return VIS_DECODE_MALFORMED;
				}
			a->s.p = (const char *)(p + off);
			a->s.len = v;
			off += padded;
		} else {
			uint64_t bytes = (uint64_t)v * 4 * vis_msg_record_words(t);
			if (bytes > left) {
				snprintf(why, why_len,
					 "%s: field %d: %u records need %llu bytes, only %zu left in the "
					 "message",
					 type->name, k + 1, v, (unsigned long long)bytes, left);
				return VIS_DECODE_MALFORMED;
			}
			a->a.raw = p + off;
			a->a.words = NULL;
			a->a.n = v;
			off += bytes;
		}
	}
	if (off != size) {
		snprintf(why, why_len, "%s: %u bytes declared, the fields take %zu", type->name, size,
			 off);
		return VIS_DECODE_MALFORMED;
	}
	return VIS_DECODE_OK;

truncated:
	snprintf(why, why_len, "%s: %u bytes declared, too few for its fields", type->name, size);
	return VIS_DECODE_MALFORMED;
}

uint32_t vis_arg_word(const union vis_arg *arg, char record, uint32_t i, uint32_t k)
{
	uint32_t w = vis_msg_record_words(record);
	if (arg->a.words)
		return arg->a.words[(size_t)i * w + k];
	return vis_wire_get_u32(arg->a.raw + ((size_t)i * w + k) * 4);
}

/* The encoded size of a message, or 0 when an argument cannot be encoded. */
static uint64_t encoded_size(const struct vis_msg_type *type, const union vis_arg *args)
{
	uint64_t size = VIS_MSG_HEADER;
	const char *sig = type->signature;
	char t;
	for (int k = 0; (t = next_field(&sig)); k++) {
		if (t == 'q')
			size += 8;
		else if (t == 's') {
			if (args[k].s.len && (!args[k].s.p || memchr(args[k].s.p, 0, args[k].s.len)))
				return 0;
			size += 4 + (((uint64_t)args[k].s.len + 3) & ~(uint64_t)3);
		} else if (is_array(t)) {
			if (args[k].a.n && !args[k].a.words)
				return 0;
			size += 4 + (uint64_t)args[k].a.n * 4 * vis_msg_record_words(t);
		} else
			size += 4;
	}
	return size;
}

int vis_msg_encode(struct vis_buf *out, uint32_t opcode, const union vis_arg *args)
{
	const struct vis_msg_type *type = vis_msg_type_find(opcode);
	if (!type) {
		errno = EINVAL;
		return -1;
	}
	uint64_t size = encoded_size(type, args);
	if (!size) {
		errno = EINVAL;
		return -1;
	}
	if (size > VIS_PROTOCOL_MAX_MESSAGE) {
		errno = EMSGSIZE;
		return -1;
	}
	size_t start = out->len;
	if (vis_buf_append(out, NULL, (size_t)size) < 0)
		return -1;
	uint8_t *p = out->data + start;
	memset(p, 0, (size_t)size);
	vis_wire_put_u32(p, (uint32_t)size);
	vis_wire_put_u16(p + 4, (uint16_t)opcode);
	size_t off = VIS_MSG_HEADER;
	const char *sig = type->signature;
	char t;
	for (int k = 0; (t = next_field(&sig)); k++) {
		const union vis_arg *a = &args[k];
		if (t == 'q') {
			vis_wire_put_u64(p + off, a->q);
			off += 8;
		} else if (t == 'u' || t == 'i') {
			vis_wire_put_u32(p + off, a->u);
			off += 4;
		} else if (t == 's') {
			vis_wire_put_u32(p + off, a->s.len);
			if (a->s.len)
				memcpy(p + off + 4, a->s.p, a->s.len);
			off += 4 + ((a->s.len + 3u) & ~3u);
		} else {
			size_t words = (size_t)a->a.n * vis_msg_record_words(t);
			vis_wire_put_u32(p + off, a->a.n);
			off += 4;
			for (size_t j = 0; j < words; j++, off += 4)
				vis_wire_put_u32(p + off, a->a.words[j]);
		}
	}
	return 0;
}

void vis_buf_init(struct vis_buf *buf)
{
	buf->data = NULL;
	buf->len = buf->cap = 0;
}

void vis_buf_finish(struct vis_buf *buf)
{
	free(buf->data);
	vis_buf_init(buf);
}

void vis_buf_consume(struct vis_buf *buf, size_t n)
{
	if (n >= buf->len) {
		buf->len = 0;
		return;
	}
	memmove(buf->data, buf->data + n, buf->len - n);
	buf->len -= n;
}

int vis_buf_reserve(struct vis_buf *buf, size_t n)
{
	if (n > SIZE_MAX - buf->len) {
		errno = ENOMEM;
		return -1;
	}
	if (buf->len + n > buf->cap) {
		size_t cap = buf->cap ? buf->cap : 256;
		while (cap < buf->len + n)
			cap = cap > SIZE_MAX / 2 ? buf->len + n : cap * 2;
		uint8_t *data = realloc(buf->data, cap);
		if (!data)
			return -1;
		buf->data = data;
		buf->cap = cap;
	}
	return 0;
}

int vis_buf_append(struct vis_buf *buf, const void *p, size_t n)
{
	if (vis_buf_reserve(buf, n) < 0)
		return -1;
	if (p)
		memcpy(buf->data + buf->len, p, n);
	buf->len += n;
	return 0;
}
