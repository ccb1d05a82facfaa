#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

#include "bigalloc.h"

#define HUGE_PAGE ((size_t)2 << 20)
/* Below this, a few huge pages would cost more in zeroing and waste than they save. */
#define BIG_ENOUGH (4 * HUGE_PAGE)

void *vis_bigalloc(size_t bytes, bool zero)
{
#ifdef MADV_HUGEPAGE
	if (bytes >= BIG_ENOUGH && bytes <= SIZE_MAX - HUGE_PAGE) {
		size_t size = (bytes + HUGE_PAGE - 1) / HUGE_PAGE * HUGE_PAGE;
		void *p = aligned_alloc(HUGE_PAGE, size);
		if (p) {
			(void)madvise(p, size, MADV_HUGEPAGE);
			if (zero)
				memset(p, 0, size);
			return p;
		}
	}
#endif
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
