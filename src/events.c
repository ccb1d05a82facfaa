#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "events.h"
#include "radix.h"

void vis_events_finish(struct vis_events *ev)
{
	free(ev->idx);
	free(ev->lo);
	free(ev->hi);
	free(ev->x1);
	free(ev->x2);
	memset(ev, 0, sizeof(*ev));
}

/* Ranks the 2n y edges: after it, lo[k] and hi[k] are leaf indices. */
static int rank_y(struct vis_events *ev, const int64_t *y1, const int64_t *y2)
{
	size_t n = ev->n, m = 2 * n;
	uint64_t *key = malloc(m * sizeof(*key) + 1);
	uint32_t *val = malloc(m * sizeof(*val) + 1);
	if (!key || !val) {
		free(key);
		free(val);
		errno = ENOMEM;
		return -1;
	}
	int64_t ymin = INT64_MAX;
	for (size_t k = 0; k < n; k++)
		ymin = y1[k] < ymin ? y1[k] : ymin;
	for (size_t k = 0; k < n; k++) {
		key[2 * k] = (uint64_t)(y1[k] - ymin);
		val[2 * k] = (uint32_t)(2 * k);
		key[2 * k + 1] = (uint64_t)(y2[k] - ymin);
		val[2 * k + 1] = (uint32_t)(2 * k + 1);
	}
	if (vis_radix_sort(key, val, m) < 0) {
		free(key);
		free(val);
		return -1;
	}
	uint32_t rank = 0;
	for (size_t i = 0; i < m; i++) {
		if (i > 0 && key[i] != key[i - 1])
			rank++;
		uint32_t e = val[i];
		if (e & 1)
			ev->hi[e >> 1] = rank;
		else
			ev->lo[e >> 1] = rank;
	}
	ev->nleaves = m ? rank : 0;
	free(key);
	free(val);
	return 0;
}

int vis_events_init(struct vis_events *ev, const struct vis_stack *stack)
{
	memset(ev, 0, sizeof(*ev));
	if (stack->n > (1u << 30)) {
		errno = EOVERFLOW;
		return -1;
	}
	size_t cap = stack->n;
	int64_t *y1 = malloc(cap * sizeof(*y1) + 1);
	int64_t *y2 = malloc(cap * sizeof(*y2) + 1);
	ev->idx = malloc(cap * sizeof(*ev->idx) + 1);
	ev->lo = malloc(cap * sizeof(*ev->lo) + 1);
	ev->hi = malloc(cap * sizeof(*ev->hi) + 1);
	ev->x1 = malloc(cap * sizeof(*ev->x1) + 1);
	ev->x2 = malloc(cap * sizeof(*ev->x2) + 1);
	if (!y1 || !y2 || !ev->idx || !ev->lo || !ev->hi || !ev->x1 || !ev->x2)
		goto nomem;
	size_t n = 0;
	for (size_t i = 0; i < stack->n; i++) {
		struct vis_box b = vis_stack_clip(stack, i);
		if (vis_box_empty(b))
			continue;
		ev->idx[n] = (uint32_t)i;
		ev->x1[n] = b.x1;
		ev->x2[n] = b.x2;
		y1[n] = b.y1;
		y2[n] = b.y2;
		n++;
	}
	ev->n = n;
	if (rank_y(ev, y1, y2) < 0)
		goto fail;
	free(y1);
	free(y2);
	return 0;
nomem:
	errno = ENOMEM;
fail:
	free(y1);
	free(y2);
	vis_events_finish(ev);
	return -1;
}

int vis_events_schedule(const struct vis_events *ev, uint32_t *sched)
{
	size_t n = ev->n, m = 2 * n;
	if (n == 0)
		return 0;
	uint64_t *key = malloc(m * sizeof(*key));
	if (!key) {
		errno = ENOMEM;
		return -1;
	}
	int64_t xmin = INT64_MAX;
	for (size_t k = 0; k < n; k++)
		xmin = ev->x1[k] < xmin ? ev->x1[k] : xmin;
	/* The radix sort is stable: lay the events out in their tie order first. */
	size_t at = 0;
	for (size_t k = n; k-- > 0;) {
		key[at] = (uint64_t)(ev->x1[k] - xmin);
		sched[at++] = (uint32_t)(k << 1);
	}
	for (size_t k = 0; k < n; k++) {
		key[at] = (uint64_t)(ev->x2[k] - xmin);
		sched[at++] = (uint32_t)(k << 1 | 1);
	}
	int rc = vis_radix_sort(key, sched, m);
	free(key);
	return rc;
}
