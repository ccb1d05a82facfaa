/*
 * test-libvis's one hook past <vis/vis.h>: libvis recomputes through the tree below 64
 * windows, where that costs less, and most of the test's trees are smaller; so that they also
 * exercise the live engine's lists of changed windows, it can go live from the first window.
 */
#include "libvis-private.h"
#include "test-libvis.h"

void tl_go_live(struct vis_tree *tree)
{
	if (vis_wtree_live_from(&tree->core, 0) < 0)
		tl_fail("vis_wtree_live_from", 0, 0);
}
