/*
 * Committing a batch: its changes apply at once, atomically, and everything else it held waits in
 * the connection's answers for serve() (server-client.c) to run at the connection's fair rate.
 */
#include <event2/buffer.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"
#include "wire.h"

/* Appends an answer record holding data. */
static void add_answer(struct client *c, uint32_t kind, uint32_t seq, const void *data,
		       size_t size)
{
	uint8_t h[SERVER_ANSWER_HEADER];
	vis_wire_put_u32(h, kind);
	vis_wire_put_u32(h + 4, seq);
	vis_wire_put_u32(h + 8, (uint32_t)size);
	if (evbuffer_add(c->answers, h, sizeof h) < 0 || evbuffer_add(c->answers, data, size) < 0) {
		log_error("client %u: out of memory holding a batch's answers", c->id);
		server_client_close(c);
	}
}

bool server_batch_change(uint32_t op)
{
	switch (op) {
	case VIS_OP_CREATE:
	case VIS_OP_DESTROY:
	case VIS_OP_MAP:
	case VIS_OP_UNMAP:
	case VIS_OP_MOVE:
	case VIS_OP_RESIZE:
	case VIS_OP_CONFIGURE:
	case VIS_OP_SET_SHAPE:
	case VIS_OP_SET_OPAQUE:
	case VIS_OP_RAISE:
	case VIS_OP_LOWER:
	case VIS_OP_RESTACK:
	case VIS_OP_REPARENT:
	case VIS_OP_BATCH_BEGIN:
		return true;
	default:
		return false;
	}
}

bool server_batch_no_effect(uint32_t op)
{
	return !server_batch_change(op) && op != VIS_OP_HELLO && op != VIS_OP_BATCH_COMMIT;
}

void server_batch_commit(struct client *c)
{
	struct server *server = c->server;
	size_t bound = (size_t)server->opt.max_pending + server->opt.max_batch;
	/* A buffer of bytes, not an evbuffer: moving an evbuffer's chain into the answers at each
	 * change cost a 1 KiB chain per reply (100 MiB for 10^5 creates). */
	struct vis_buf capture;
	vis_buf_init(&capture);
	c->in_batch = false;
	server->deferring = true;
	server->walk_left = SERVER_BATCH_WORK;
	while (evbuffer_get_length(c->batch) && !c->closing && !c->close_after_answers) {
		uint8_t *p = evbuffer_pullup(c->batch, 4 + VIS_MSG_HEADER);
		uint32_t seq = vis_wire_get_u32(p), size = vis_wire_get_u32(p + 4);
		p = evbuffer_pullup(c->batch, 4 + (ssize_t)size);
		struct vis_msg m;
		char why[200];
		if (vis_msg_decode(p + 4, size, size, 1, &m, why, sizeof why) != VIS_DECODE_OK) {
			log_error("client %u: a held request no longer decodes: %s", c->id, why);
		} else if (!server_batch_change(m.type->opcode)) {
			add_answer(c, SERVER_ANSWER_REQUEST, seq, p + 4, size);
		} else {
			c->capture = &capture;
			if (evbuffer_get_length(c->answers) > bound) {
				/* Replies are never dropped: past this, the connection ends. */
				server_client_error(c, seq, m.type->opcode, VIS_ERROR_LIMIT,
						    "the batch's replies take over %zu bytes; closing the "
						    "connection",
						    bound);
				c->close_after_answers = true;
			} else if (m.type->opcode == VIS_OP_BATCH_BEGIN) {
				server_client_error(c, seq, VIS_OP_BATCH_BEGIN, VIS_ERROR_STATE,
						    "batch-begin inside a batch");
			} else {
				server_client_dispatch(c, seq, &m);
			}
			c->capture = NULL;
			if (capture.len)
				add_answer(c, SERVER_ANSWER_REPLY, seq, capture.data, capture.len);
			capture.len = 0;
		}
		evbuffer_drain(c->batch, 4 + (size_t)size);
	}
	evbuffer_drain(c->batch, evbuffer_get_length(c->batch));
	vis_buf_finish(&capture);
	server->walk_left = UINT64_MAX;
	server->deferring = false;
	server_flush(server);
}
