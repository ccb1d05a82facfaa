/*
 * test-libvis's one hook past <vis/vis.h>: which engine a tree's updates take. The test's trees
 * are small, so libvis keeps tallies for them (libvis-tally.c); so that they also exercise the
 * core, an update can go through it instead, with the live engine from the first window, or
 * with tallies kept only up to a few windows, so that trees go in and out of them.
 */
#include "libvis-private.h"
#include "test-libvis.h"

void tl_engine(struct vis_tree *tree, enum tl_engine engine)
{
	if (engine == TL_LIVE && vis_wtree_live_from(&tree->core, 0) < 0)
		tl_fail("vis_wtree_live_from", 0, 0);
	if (engine == TL_LIVE || engine == TL_THROUGH)
		libvis_tally_below(tree, 0);
	if (engine == TL_SWITCH)
		libvis_tally_below(tree, (size_t)tl_range(1, 12));
}
