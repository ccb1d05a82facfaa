/* Unit tests of the large-block allocator: alignment, zeroing, and the reuse of kept blocks. */
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "bigalloc.h"
#include "check.h"

#define MIB ((size_t)1 << 20)

static int all_zero(const unsigned char *p, size_t bytes)
{
	for (size_t i = 0; i < bytes; i++)
		if (p[i])
			return 0;
	return 1;
}

static void test_small(void)
{
	unsigned char *p = vis_bigalloc(1000, true);
	CHECK(p && (uintptr_t)p % VIS_BIGALLOC_ALIGN == 0 && all_zero(p, 1000));
	vis_bigfree(p);
	vis_bigfree(NULL);
}

static void test_kept(void)
{
	size_t bytes = 20 * MIB;
	unsigned char *a = vis_bigalloc(bytes, false);
	CHECK(a && (uintptr_t)a % VIS_BIGALLOC_ALIGN == 0);
	if (!a)
		return;
	memset(a, 0xab, bytes);
	vis_bigfree(a);

	/* The kept block comes back, zeroed when asked. */
	unsigned char *b = vis_bigalloc(bytes, true);
	CHECK(b == a);
	CHECK(b && all_zero(b, bytes));
	/* Not while it is out, and not for a request under half its size. */
	unsigned char *c = vis_bigalloc(bytes, false);
	CHECK(c && c != b);
	vis_bigfree(c);
	unsigned char *d = vis_bigalloc(bytes / 4, false);
	CHECK(d && d != c);
	vis_bigfree(d);
	vis_bigfree(b);

	/* Released, the blocks are gone: a new request may land anywhere, but must work. */
	vis_bigalloc_release();
	unsigned char *e = vis_bigalloc(bytes, true);
	CHECK(e && all_zero(e, bytes));
	vis_bigfree(e);
}

/* More blocks than are kept, and one larger than all that is kept: every one freed, none lost. */
static void test_limits(void)
{
	enum { N = 40 };
	unsigned char *p[N];
	for (size_t i = 0; i < N; i++) {
		p[i] = vis_bigalloc(8 * MIB + i * MIB, false);
		CHECK(p[i] != NULL);
		if (p[i])
			p[i][0] = 1;
	}
	for (size_t i = 0; i < N; i++)
		vis_bigfree(p[i]);
	unsigned char *huge = vis_bigalloc(VIS_BIGALLOC_KEEP_BYTES + 2 * MIB, false);
	if (huge) {
		huge[0] = 1;
		vis_bigfree(huge);
	}
	vis_bigalloc_release();
}

int main(void)
{
	test_small();
	test_kept();
	test_limits();
	vis_bigalloc_release();
	printf("bigalloc: %s\n", failures ? "FAILED" : "ok");
	printf("%d passed, %d failed\n", failures ? 0 : 3, failures ? 1 : 0);
	return failures != 0;
}
