#include <errno.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "bigalloc.h"

#define HUGE_PAGE ((size_t)2 << 20)
/* Below this, a few huge pages would cost more in zeroing and waste than they save. */
#define BIG_ENOUGH (4 * HUGE_PAGE)

/* The large blocks handed out (so that vis_bigfree() knows their sizes), and those kept. */
#define LIVE_MAX 64
#define KEPT_MAX 16

struct block {
	void *p;
	size_t size;
};

static struct {
	pthread_mutex_t lock;
	struct block live[LIVE_MAX], kept[KEPT_MAX];
	size_t nlive, nkept, kept_bytes;
} big = { .lock = PTHREAD_MUTEX_INITIALIZER };

/* Takes the smallest kept block of size bytes up to twice that, or returns NULL. */
static void *take_kept(size_t size)
{
	size_t best = SIZE_MAX;
	for (size_t i = 0; i < big.nkept; i++) {
		size_t s = big.kept[i].size;
		if (s >= size && s / 2 <= size && (best == SIZE_MAX || s < big.kept[best].size))
			best = i;
	}
	if (best == SIZE_MAX)
		return NULL;
	struct block b = big.kept[best];
	big.kept[best] = big.kept[--big.nkept];
	big.kept_bytes -= b.size;
	if (big.nlive < LIVE_MAX)
		big.live[big.nlive++] = b;
	return b.p;
}

/* A large block, kept or fresh; NULL on failure. */
static void *big_block(size_t size)
{
	pthread_mutex_lock(&big.lock);
	void *p = take_kept(size);
	pthread_mutex_unlock(&big.lock);
	if (p)
		return p;
	p = aligned_alloc(HUGE_PAGE, size);
	if (!p)
		return NULL;
#ifdef MADV_HUGEPAGE
	(void)madvise(p, size, MADV_HUGEPAGE);
#endif
	pthread_mutex_lock(&big.lock);
	if (big.nlive < LIVE_MAX)
		big.live[big.nlive++] = (struct block){ p, size };
	pthread_mutex_unlock(&big.lock);
	return p;
}

void *vis_bigalloc(size_t bytes, bool zero)
{
	if (bytes >= BIG_ENOUGH && bytes <= SIZE_MAX - HUGE_PAGE) {
		size_t size = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
		void *p = big_block(size);
		if (p) {
			if (zero)
				memset(p, 0, size);
			return p;
		}
	}
	if (bytes > SIZE_MAX - 2 * VIS_BIGALLOC_ALIGN) {
		errno = ENOMEM;
		return NULL;
	}
	size_t size = (bytes + VIS_BIGALLOC_ALIGN) / VIS_BIGALLOC_ALIGN * VIS_BIGALLOC_ALIGN;
	void *p = aligned_alloc(VIS_BIGALLOC_ALIGN, size);
	if (!p)
		errno = ENOMEM;
	else if (zero)
		memset(p, 0, size);
	return p;
}

void vis_bigfree(void *p)
{
	if (!p)
		return;
	pthread_mutex_lock(&big.lock);
	size_t i = 0;
	while (i < big.nlive && big.live[i].p != p)
		i++;
	if (i == big.nlive) {
		/* A small block, or a large one handed out while the table was full. */
		pthread_mutex_unlock(&big.lock);
		free(p);
		return;
	}
	struct block b = big.live[i];
	big.live[i] = big.live[--big.nlive];
	/* Keep it, making room by releasing the largest kept blocks first. */
	void *release[KEPT_MAX + 1];
	size_t nrelease = 0;
	if (b.size > VIS_BIGALLOC_KEEP_BYTES) {
		release[nrelease++] = b.p;
	} else {
		while (big.nkept == KEPT_MAX || big.kept_bytes + b.size > VIS_BIGALLOC_KEEP_BYTES) {
			size_t largest = 0;
			for (size_t j = 1; j < big.nkept; j++)
				if (big.kept[j].size > big.kept[largest].size)
					largest = j;
			release[nrelease++] = big.kept[largest].p;
			big.kept_bytes -= big.kept[largest].size;
			big.kept[largest] = big.kept[--big.nkept];
		}
		big.kept[big.nkept++] = b;
		big.kept_bytes += b.size;
	}
	pthread_mutex_unlock(&big.lock);
	for (size_t j = 0; j < nrelease; j++)
		free(release[j]);
}

void vis_bigalloc_release(void)
{
	pthread_mutex_lock(&big.lock);
	for (size_t i = 0; i < big.nkept; i++)
		free(big.kept[i].p);
	big.nkept = 0;
	big.kept_bytes = 0;
	pthread_mutex_unlock(&big.lock);
}
