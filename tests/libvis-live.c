/*
 * test-libvis's one hook past <vis/vis.h>: which engine a tree's updates take. The test's trees
 * are small, so libvis keeps tallies for them (libvis-tally.c); so that they also exercise the
 * core, an update can go through it instead, with the live engine from the first window (whose
 * grid then serves the repaint queries after a window or three), or
 * with tallies kept only up to a few windows, so that trees go in and out of them; the box
 * whose repaint set a tree keeps, for damage that it serves; and a window's tally.
 */
#include "libvis-private.h"
#include "test-libvis.h"

void tl_engine(struct vis_tree *tree, enum tl_engine engine)
{
	if (engine == TL_LIVE && vis_wtree_live_from(&tree->core, 0) < 0)
		tl_fail("vis_wtree_live_from", 0, 0);
	if (engine == TL_LIVE || engine == TL_THROUGH)
		libvis_tally_below(tree, 0);
	if (engine == TL_LIVE)
		tree->walk.grid_after = (size_t)tl_range(0, 3); /* repaints by the live grid */
	if (engine == TL_SWITCH)
		libvis_tally_below(tree, (size_t)tl_range(1, 12));
}

void tl_kept_damage(struct vis_tree *tree, struct vis_rect32 *d)
{
	if (!tree->kept_ok)
		return;
	struct vis_box b = tree->kept_box;
	int64_t x1 = tl_range(b.x1, b.x2 - 1), y1 = tl_range(b.y1, b.y2 - 1);
	int64_t x2 = tl_range(0, 1) ? b.x2 : tl_range(x1 + 1, b.x2);
	int64_t y2 = tl_range(0, 1) ? b.y2 : tl_range(y1 + 1, b.y2);
	if (tl_range(0, 1))
		x1 = b.x1, y1 = b.y1;
	*d = (struct vis_rect32){ (int32_t)x1, (int32_t)y1, (uint32_t)(x2 - x1), (uint32_t)(y2 - y1) };
}

bool tl_tally(const struct vis_win *win, uint64_t *seen)
{
	const struct vis_tree *tree = win->tree;
	if (!tree->tally || tree->tally_broken)
		return false;
	*seen = win->seen;
	return true;
}
