/* Allocation of the sweeps' large arrays, backed by huge pages where the system offers them. */
#ifndef VIS_BIGALLOC_H
#define VIS_BIGALLOC_H

#include <stdbool.h>
#include <stddef.h>

/*
 * Allocates bytes (zeroed if zero), to be released with vis_bigfree(); NULL (ENOMEM) on failure.
 * The block is aligned to VIS_BIGALLOC_ALIGN, a cache line, so that records laid out in lines stay
 * in them. The sweeps visit their trees and per-node arrays at random, tens of megabytes of them:
 * with 4 KiB pages nearly every such visit also misses the TLB. An array of several megabytes is
 * therefore aligned to 2 MiB and marked for transparent huge pages (a hint the system may ignore).
 * O(bytes) when zeroed. Thread-safe.
 */
#define VIS_BIGALLOC_ALIGN 64

void *vis_bigalloc(size_t bytes, bool zero);

/*
 * Releases a block of vis_bigalloc() (NULL: nothing). Blocks of several megabytes are kept, up to
 * VIS_BIGALLOC_KEEP_BYTES in all, for the next computation to reuse: faulting fresh pages in
 * costs the kernel's zeroing of them, and on a virtual machine that hands freed memory back to its
 * host, the host's too, which can outweigh the work the sweep then does on them. O(1).
 */
#define VIS_BIGALLOC_KEEP_BYTES ((size_t)1 << 30)

void vis_bigfree(void *p);

/* Releases the blocks kept for reuse. */
void vis_bigalloc_release(void);

#endif
