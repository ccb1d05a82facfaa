#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "engine.h"
#include "look.h"

static const char *const engine_names[VIS_ENGINE_COUNT] = {
	[VIS_ENGINE_AUTO] = "auto",
	[VIS_ENGINE_GMV] = "gmv",
	[VIS_ENGINE_GMV_HEAP] = "gmv-heap",
	[VIS_ENGINE_REGION] = "region",
	[VIS_ENGINE_BRUTE] = "brute",
};

const char *vis_engine_name(enum vis_engine engine)
{
	return (unsigned)engine < VIS_ENGINE_COUNT ? engine_names[engine] : "invalid";
}

int vis_engine_from_name(const char *name, enum vis_engine *engine)
{
	for (int i = 0; i < VIS_ENGINE_COUNT; i++) {
		if (strcmp(name, engine_names[i]) == 0) {
			*engine = (enum vis_engine)i;
			return 0;
		}
	}
	return -1;
}

/* Runs one engine on a stack of rectangles. */
static int compute_rects(enum vis_engine engine, const struct vis_stack *stack, uint8_t *states)
{
	switch (engine) {
	case VIS_ENGINE_AUTO:
		return vis_auto_compute(stack, states);
	case VIS_ENGINE_GMV:
		return vis_gmv_compute(stack, states);
	case VIS_ENGINE_GMV_HEAP:
		return vis_gmv_heap_compute(stack, states);
	case VIS_ENGINE_REGION:
		return vis_region_compute(stack, states);
	case VIS_ENGINE_BRUTE:
		return vis_brute_compute(stack, states);
	}
	errno = EINVAL;
	return -1;
}

int vis_compute(enum vis_engine engine, const struct vis_stack *stack, uint8_t *states)
{
	if (stack->looks == NULL)
		return compute_rects(engine, stack, states);

	/* Windows with a look are cut into rectangles, whose states make the windows'. */
	struct vis_pieces pieces;
	if (vis_pieces_init(&pieces, stack) < 0)
		return -1;
	uint8_t *piece_states = malloc(pieces.stack.n + 1);
	int rc = -1;
	if (piece_states == NULL)
		errno = ENOMEM;
	else
		rc = compute_rects(engine, &pieces.stack, piece_states);
	if (rc == 0)
		vis_pieces_join(&pieces, stack, piece_states, states);
	free(piece_states);
	vis_pieces_finish(&pieces);
	return rc;
}
