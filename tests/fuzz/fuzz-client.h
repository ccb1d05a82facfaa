/*
 * What fuzz-client.c sets up before the daemon's bytes arrive, shared with gen-corpus.c so that
 * the seeds answer the requests actually waiting.
 *
 * An input is one control byte, then the bytes the daemon sends. The control byte:
 *   bits 0-2  how many bytes are written before each dispatch: fuzz_client_chunks[bits]
 *   bit 3     handlers (notices, errors) call vis_client_dispatch themselves
 *   bit 4     the bytes answer the hello (request 1) too; otherwise the target answers it first
 *             with a hello-reply granting FUZZ_CLIENT_ID the client role
 */
#ifndef VIS_FUZZ_CLIENT_H
#define VIS_FUZZ_CLIENT_H

#include <stddef.h>
#include <stdint.h>

#define FUZZ_CLIENT_ID 7
#define FUZZ_WINDOW 5 /* the window asked about by get-state and get-region */
#define FUZZ_REENTER 8u
#define FUZZ_HANDSHAKE 16u
/* How many sync requests there may be in all: each synced reply sends one more until then. */
#define FUZZ_SYNCS 40

static const size_t fuzz_client_chunks[8] = { SIZE_MAX, 1, 3, 8, 13, 64, 512, 4096 };

/* The requests sent after hello (request 1), in order, before its reply is read. */
enum fuzz_client_seq {
	FUZZ_SEQ_CREATE = 2,
	FUZZ_SEQ_MAP,         /* no reply: only an error can answer it */
	FUZZ_SEQ_GET_STATE,   /* of FUZZ_WINDOW */
	FUZZ_SEQ_GET_STATES,
	FUZZ_SEQ_GET_TREE,
	FUZZ_SEQ_GET_REGION,  /* of FUZZ_WINDOW */
	FUZZ_SEQ_GET_REPAINT,
	FUZZ_SEQ_SYNC,        /* then FUZZ_SEQ_SYNC + 1 … from the synced callbacks */
};

#endif
