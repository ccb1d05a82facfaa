/*
 * The generic encoder and decoder, driven by the message table (messages.h). No I/O: bytes in,
 * a message, "need more" or "malformed" out; arguments in, bytes out.
 *
 * Wire layout of every message: a header of uint32 size (the whole message, header included),
 * uint16 opcode, uint16 zero; then the fields of the opcode's signature, little-endian, each a
 * multiple of 4 bytes. The size is checked against the receiver's maximum before anything else.
 */
#ifndef VIS_PROTO_CODEC_H
#define VIS_PROTO_CODEC_H

#include <stddef.h>
#include <stdint.h>

#include "messages.h"

#define VIS_MSG_HEADER 8u
#define VIS_MSG_MAX_ARGS 14 /* the stack notice has 13 */

struct vis_msg_type {
	uint16_t opcode;
	enum vis_msg_dir dir;
	const char *name;      /* as in logs and PROTOCOL.md, e.g. "get-states" */
	const char *signature; /* see messages.h */
	const char *doc;
};

/*
 * An argument. Arrays: decoded ones point into the message (raw, little-endian: read them with
 * vis_arg_word()); ones to encode give host-order words. Strings are not NUL-terminated.
 */
union vis_arg {
	uint32_t u;
	int32_t i;
	uint64_t q;
	struct {
		const char *p;
		uint32_t len;
	} s;
	struct {
		const uint8_t *raw;
		const uint32_t *words;
		uint32_t n;
	} a;
};

struct vis_msg {
	const struct vis_msg_type *type;
	uint32_t size;
	union vis_arg args[VIS_MSG_MAX_ARGS];
};

enum vis_decode {
	VIS_DECODE_OK,
	VIS_DECODE_MORE,      /* fewer bytes than the header or the declared size */
	VIS_DECODE_MALFORMED, /* never valid, however many bytes follow */
};

/* A growable byte buffer for encoded messages. */
struct vis_buf {
	uint8_t *data;
	size_t len, cap;
};

/* The type of an opcode, or NULL when no message has it. O(1). */
const struct vis_msg_type *vis_msg_type_find(uint32_t opcode);

/* The table, in opcode order, for the documentation check. O(1). */
const struct vis_msg_type *vis_msg_types(size_t *count);

/* The 32-bit words of one record of an array field: 1 (W), 2 (S), 4 (R) or 12 (T). O(1). */
uint32_t vis_msg_record_words(char record);

/*
 * Reads the header at p: on VIS_DECODE_OK, *size is the declared size, already checked to be in
 * [VIS_MSG_HEADER, max]. VIS_DECODE_MORE when avail < VIS_MSG_HEADER. O(1).
 */
enum vis_decode vis_msg_peek(const uint8_t *p, size_t avail, uint32_t max, uint32_t *size,
			     char *why, size_t why_len);

/*
 * Decodes the message at p, of a type sent in direction dir (requests for the daemon, replies and
 * notices for a client). Every length and count is checked against the declared size, and the
 * fields must fill it exactly. On VIS_DECODE_MALFORMED, why says what is wrong; out->type is the
 * message's type when its opcode is known (for the error reply). O(size).
 */
enum vis_decode vis_msg_decode(const uint8_t *p, size_t avail, uint32_t max, int want_requests,
			       struct vis_msg *out, char *why, size_t why_len);

/* Word k of record i of a decoded array argument. O(1). */
uint32_t vis_arg_word(const union vis_arg *arg, char record, uint32_t i, uint32_t k);

/*
 * Appends the message opcode with args (as many as its signature has) to out. Returns 0, or -1
 * with errno EINVAL (unknown opcode, a string with a NUL), EMSGSIZE (over
 * VIS_PROTOCOL_MAX_MESSAGE) or ENOMEM; out is unchanged on failure. O(size).
 */
int vis_msg_encode(struct vis_buf *out, uint32_t opcode, const union vis_arg *args);

void vis_buf_init(struct vis_buf *buf);
void vis_buf_finish(struct vis_buf *buf);
/* Removes the first n bytes. O(len). */
void vis_buf_consume(struct vis_buf *buf, size_t n);
/* Makes room for n bytes after the len there are (cap >= len + n), appending nothing; 0, or -1
 * with ENOMEM. The capacity doubles, from 256 bytes. */
int vis_buf_reserve(struct vis_buf *buf, size_t n);
/* Appends n bytes (left as they are when p is NULL); 0, or -1 with ENOMEM. Amortized O(n). */
int vis_buf_append(struct vis_buf *buf, const void *p, size_t n);

#endif
