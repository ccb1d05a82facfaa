/*
 * libFuzzer target: the protocol decoder on arbitrary bytes. The first byte picks the direction
 * (bit 0: requests, as the daemon decodes) and the receiver's maximum size (bits 1-3); the rest is
 * a stream of messages, decoded one after the other as a connection would until one is
 * incomplete or malformed. Each message that decodes must lie wholly inside its declared size,
 * its fields must fill that size exactly, and encoding its arguments again must give back the
 * very same bytes. Peek and decode must agree, and a refusal must say why.
 */
/* The checks are the test: keep them in release builds too. */
#undef NDEBUG
#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "codec.h"
#include "vis/protocol.h"
#include "wire.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Receivers' maximum sizes: the protocol's, a few small ones, unaligned ones, under the header. */
static const uint32_t max_sizes[8] = { VIS_PROTOCOL_MAX_MESSAGE, 65536, 4096, 100, 64, 30, 8, 0 };

/* The next field's type in a signature ('u', 'i', 'q', 's' or a record letter), 0 at the end. */
static char field(const char **sig)
{
	while (**sig == ' ')
		(*sig)++;
	if (!**sig)
		return 0;
	char t = (*sig)[0] == 'a' ? (*sig)[1] : (*sig)[0];
	*sig += strcspn(*sig, " ");
	return t;
}

/* Whether [q, q + len) lies inside the message [p, p + size). */
static int inside(const uint8_t *p, uint32_t size, const void *q, uint64_t len)
{
	const uint8_t *b = q;
	return b >= p + VIS_MSG_HEADER && b <= p + size && len <= (uint64_t)(p + size - b);
}

/*
 * Checks a decoded message m of p[0, size) field by field, then encodes its arguments again and
 * compares the bytes.
 */
static void check_message(const uint8_t *p, uint32_t size, const struct vis_msg *m)
{
	union vis_arg args[VIS_MSG_MAX_ARGS];
	uint32_t *words[VIS_MSG_MAX_ARGS] = { NULL };
	uint64_t total = VIS_MSG_HEADER;
	const char *sig = m->type->signature;
	char t;
	int k;

	for (k = 0; (t = field(&sig)); k++) {
		assert(k < VIS_MSG_MAX_ARGS);
		const union vis_arg *a = &m->args[k];
		args[k] = *a;
		if (t == 'q') {
			total += 8;
		} else if (t == 'u' || t == 'i') {
			total += 4;
		} else if (t == 's') {
			assert(inside(p, size, a->s.p, a->s.len));
			assert(!memchr(a->s.p, 0, a->s.len));
			total += 4 + (((uint64_t)a->s.len + 3) & ~(uint64_t)3);
		} else {
			uint32_t w = vis_msg_record_words(t);
			uint64_t bytes = (uint64_t)a->a.n * w * 4;
			assert(w && !a->a.words && inside(p, size, a->a.raw, bytes));
			total += 4 + bytes;
			/* The encoder takes host-order words. */
			words[k] = malloc(bytes ? (size_t)bytes : 1);
			assert(words[k]);
			for (uint32_t i = 0; i < a->a.n; i++)
				for (uint32_t j = 0; j < w; j++)
					words[k][(size_t)i * w + j] = vis_arg_word(a, t, i, j);
			args[k].a.words = words[k];
		}
	}
	assert(total == size);

	struct vis_buf b;
	vis_buf_init(&b);
	assert(vis_msg_encode(&b, m->type->opcode, args) == 0);
	assert(b.len == size && memcmp(b.data, p, size) == 0);
	vis_buf_finish(&b);
	for (int j = 0; j < k; j++)
		free(words[j]);
}

/*
 * Decodes the message at p (avail bytes) and checks what the codec says of it. Returns its size
 * when it decoded, 0 when the stream stops there.
 */
static uint32_t check_one(const uint8_t *p, size_t avail, uint32_t max, int requests)
{
	uint32_t size = 0;
	char why[200] = "", why2[200] = "";
	struct vis_msg m;
	enum vis_decode peek = vis_msg_peek(p, avail, max, &size, why, sizeof(why));
	enum vis_decode r = vis_msg_decode(p, avail, max, requests, &m, why2, sizeof(why2));

	if (peek == VIS_DECODE_MORE) {
		assert(avail < VIS_MSG_HEADER && r == VIS_DECODE_MORE);
		return 0;
	}
	if (peek == VIS_DECODE_MALFORMED) {
		assert(why[0] && r == VIS_DECODE_MALFORMED && why2[0] && !m.type);
		return 0;
	}
	assert(size >= VIS_MSG_HEADER && size <= max && size % 4 == 0);
	/* The type is named whenever the opcode is one of this direction's, even if refused. */
	const struct vis_msg_type *t = vis_msg_type_find(vis_wire_get_u16(p + 4));
	int ours = t && (t->dir == VIS_DIR_REQUEST) == (requests != 0);
	assert(m.type == (ours ? t : NULL));
	if (r == VIS_DECODE_MORE) {
		assert(ours && avail < size);
		return 0;
	}
	if (r == VIS_DECODE_MALFORMED) {
		assert(why2[0]);
		return 0;
	}
	assert(ours && m.size == size && size <= avail);

	/* Again from a copy of exactly size bytes, so that ASan sees any read past the message. */
	uint8_t *copy = malloc(size);
	assert(copy);
	memcpy(copy, p, size);
	struct vis_msg m2;
	assert(vis_msg_decode(copy, size, max, requests, &m2, why2, sizeof(why2)) ==
	       VIS_DECODE_OK);
	assert(m2.type == m.type && m2.size == size);
	check_message(copy, size, &m2);
	/* One byte short is incomplete; in the other direction it is no message at all. */
	assert(vis_msg_decode(copy, size - 1, max, requests, &m2, why2, sizeof(why2)) ==
	       VIS_DECODE_MORE);
	assert(vis_msg_decode(copy, size, max, !requests, &m2, why2, sizeof(why2)) ==
	       VIS_DECODE_MALFORMED);
	assert(!m2.type && why2[0]);
	free(copy);
	return size;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	int requests = data[0] & 1;
	uint32_t max = max_sizes[(data[0] >> 1) & 7];
	size_t off = 1;
	uint32_t n;
	while ((n = check_one(data + off, size - off, max, requests)))
		off += n;
	return 0;
}
