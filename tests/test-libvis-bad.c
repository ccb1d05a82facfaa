/* test-libvis's bad inputs: each call fails with its errno, and the tree stays as it was. */
#include <errno.h>
#include <stdlib.h>

#include "test-libvis.h"

/* Expects rc -1 with errno e. */
static void refused(int rc, int e, const char *what)
{
	if (rc != -1 || errno != e)
		tl_fail(what, rc, errno);
	tl_check(true, what);
}

/* As refused(), for the calls that return a pointer. */
static void refused_ptr(const void *p, int e, const char *what)
{
	refused(p ? 0 : -1, e, what);
}

/* A live window of the model other than not (0: none). */
static int some(const struct tl *c, bool (*ok)(const struct pm_win *))
{
	for (int i = 1; i <= PM_MAX; i++)
		if (c->t.w[i].alive && (!ok || ok(&c->t.w[i])))
			return i;
	return 0;
}

static bool input_only(const struct pm_win *m)
{
	return m->input_only;
}

static bool has_pixels(const struct pm_win *m)
{
	return !m->input_only;
}

void tl_bad_inputs(struct tl *c)
{
	struct vis_tree *vt = c->vt, *other = vis_tree_create(3, 3);
	const int32_t big = INT32_MAX;
	if (!other)
		tl_fail("vis_tree_create", 3, 3);
	struct vis_win *stranger = vis_win_create(other, NULL, 0, 0, 1, 1, 0, 0);
	refused_ptr(vis_tree_create(0, 1), EINVAL, "a screen 0 wide");
	refused_ptr(vis_tree_create(1, -1), EINVAL, "a screen -1 high");
	int32_t w, h;
	refused(vis_tree_screen(NULL, &w, &h), EINVAL, "screen of no tree");
	refused_ptr(vis_win_create(NULL, NULL, 0, 0, 1, 1, 0, 0), EINVAL, "create in no tree");
	refused_ptr(vis_win_create(vt, stranger, 0, 0, 1, 1, 0, 0), EINVAL, "a parent of another tree");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 0, 1, 0, 0), EINVAL, "width 0");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 1, INT32_MIN, 0, 0), EINVAL, "negative height");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 1, 1, -1, 0), EINVAL, "negative border");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, big, 1, 1, 0), EOVERFLOW, "a border box too wide");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 1, big - 1, 1, 0), EOVERFLOW, "one too high");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 1, 1, 0, 2), EINVAL, "unknown flags");
	refused_ptr(vis_win_create(vt, NULL, 0, 0, 1, 1, 1, VIS_WIN_INPUT_ONLY), EINVAL,
		    "an input-only window with a border");
	refused(vis_win_map(NULL), EINVAL, "map no window");
	refused(vis_win_unmap(NULL), EINVAL, "unmap no window");
	refused(vis_win_raise(NULL), EINVAL, "raise no window");
	refused(vis_win_lower(NULL), EINVAL, "lower no window");
	refused(vis_win_move(NULL, 0, 0), EINVAL, "move no window");
	refused(vis_win_configure(NULL, 0, 0, 1, 1, 0), EINVAL, "configure no window");
	refused(vis_win_set_data(NULL, NULL), EINVAL, "data of no window");
	tl_check(vis_win_get_data(NULL) == NULL, "data of no window");
	refused(vis_win_track_exposure(NULL, 1), EINVAL, "track no window");
	refused(vis_win_state(NULL), EINVAL, "state of no window");
	refused(vis_win_set_shape(NULL, 0, NULL, 0), EINVAL, "shape no window");
	refused(vis_win_set_opaque(NULL, 0, NULL, 0), EINVAL, "opaque no window");
	refused(vis_win_set_external(NULL, 1, 1), EINVAL, "tag no window");
	refused(vis_win_restack(NULL, stranger, 1), EINVAL, "restack no window");
	refused(vis_win_reparent(NULL, NULL, 0, 0), EINVAL, "reparent no window");
	const struct vis_change *ch;
	const struct vis_repaint *rp;
	const struct vis_rect32 *r;
	size_t n;
	refused(vis_tree_update(NULL, &ch, &n), EINVAL, "update no tree");
	refused(vis_tree_update(vt, NULL, &n), EINVAL, "update without changes");
	struct vis_rect32 box = { 0, 0, 1, 1 }, zero = { 0, 0, 0, 1 }, huge = { 0, 0, 1, 1u << 31 };
	refused(vis_tree_repaint(NULL, &box, &rp, &n), EINVAL, "repaint no tree");
	refused(vis_tree_repaint(vt, NULL, &rp, &n), EINVAL, "repaint no damage");
	refused(vis_tree_repaint(vt, &zero, &rp, &n), EINVAL, "repaint an empty box");
	refused(vis_tree_repaint(vt, &huge, &rp, &n), EINVAL, "repaint a box past INT32_MAX");
	refused(vis_win_visible_region(NULL, &r, &n), EINVAL, "region of no window");
	tl_check(vis_tree_find_external(NULL, 1, 1) == NULL, "find in no tree");
	tl_check(vis_tree_find_external(vt, 0, 0) == NULL, "find namespace 0");
	int i = some(c, NULL);
	if (i) {
		struct pm_win *m = &c->t.w[i];
		refused(vis_win_configure(m->win, 0, 0, 0, 1, 0), EINVAL, "configure width 0");
		refused(vis_win_configure(m->win, 0, 0, 1, 1, -2), EINVAL, "configure a negative border");
		refused(vis_win_restack(m->win, m->win, 0), EINVAL, "restack by itself");
		refused(vis_win_restack(m->win, stranger, 0), EINVAL, "restack by another tree's");
		refused(vis_win_restack(m->win, NULL, 0), EINVAL, "restack by no window");
		refused(vis_win_reparent(m->win, m->win, 0, 0), EINVAL, "reparent under itself");
		refused(vis_win_reparent(m->win, stranger, 0, 0), EINVAL, "reparent to another tree");
		for (int k = 0; k < m->n_kids; k++)
			refused(vis_win_reparent(m->win, c->t.w[m->kids[k]].win, 0, 0), EINVAL,
				"reparent under a child");
		int p = m->parent;
		for (int k = 0; k < c->t.w[p].n_kids; k++)
			if (c->t.w[p].kids[k] != i && c->t.w[c->t.w[p].kids[k]].n_kids)
				refused(vis_win_restack(m->win,
							c->t.w[c->t.w[c->t.w[p].kids[k]].kids[0]].win, 1),
					EINVAL, "restack by a nephew");
		refused(vis_win_set_external(m->win, 0, 5), EINVAL, "tag namespace 0");
		uint64_t tag = tl_rand();
		tl_check(vis_win_set_external(m->win, 7, tag) == 0, "tag a window");
		tl_check(vis_tree_find_external(vt, 7, tag) == m->win, "find a tagged window");
		refused(vis_win_set_external(m->win, 8, tag), EINVAL, "tag a window twice");
		int j = i;
		while (++j <= PM_MAX && !c->t.w[j].alive)
			;
		if (j <= PM_MAX)
			refused(vis_win_set_external(c->t.w[j].win, 7, tag), EEXIST, "a tag taken");
	}
	if ((i = some(c, input_only))) {
		struct vis_win *win = c->t.w[i].win;
		refused(vis_win_configure(win, 0, 0, 1, 1, 1), EINVAL, "a border on an input-only window");
		refused(vis_win_set_shape(win, 0, NULL, 0), EINVAL, "shape an input-only window");
		refused(vis_win_set_opaque(win, 0, NULL, 0), EINVAL, "opaque an input-only window");
	}
	if ((i = some(c, has_pixels))) {
		struct vis_win *win = c->t.w[i].win;
		struct vis_rect32 bad[2] = { { 0, 0, 1, 1 }, { 0, 0, 0, 1 } };
		struct vis_rect32 wide[1] = { { 0, 0, 1u << 31, 1 } };
		refused(vis_win_configure(win, 0, 0, big - 2, 1, 2), EOVERFLOW,
			"configure a border box too wide");
		refused(vis_win_set_shape(win, 1, NULL, 1), EINVAL, "shape rects NULL");
		refused(vis_win_set_shape(win, 1, bad, 2), EINVAL, "shape a rectangle 0 wide");
		refused(vis_win_set_shape(win, 1, wide, 1), EINVAL, "shape a rectangle too wide");
		refused(vis_win_set_shape(win, 0, bad, 1), EINVAL, "unshape with rectangles");
		refused(vis_win_set_shape(win, 1, bad, VIS_LOOK_MAX_RECTS + 1), E2BIG, "shape too many");
		refused(vis_win_set_opaque(win, 3, NULL, 0), EINVAL, "opaque mode 3");
		refused(vis_win_set_opaque(win, VIS_OPAQUE_MODE_ALL, bad, 1), EINVAL,
			"opaque all with rectangles");
		refused(vis_win_set_opaque(win, VIS_OPAQUE_MODE_RECTS, bad, 2), EINVAL,
			"opaque a rectangle 0 wide");
		refused(vis_win_set_opaque(win, VIS_OPAQUE_MODE_RECTS, bad, VIS_LOOK_MAX_RECTS + 1),
			E2BIG, "opaque too many");
	}
	vis_tree_destroy(other);
	vis_win_destroy(NULL);
	vis_tree_destroy(NULL);
	/* Nothing changed: no change to list, and the queries answer. */
	tl_check(vis_tree_update(vt, &ch, &n) == 0 && n == 0, "a refused call changed the tree");
	tl_check(vis_tree_repaint(vt, &box, &rp, &n) == 0, "a refused call left the tree dirty");
	/* A change makes the queries wait for the next update. */
	if ((i = some(c, NULL))) {
		tl_check(vis_win_raise(c->t.w[i].win) == 0, "raise");
		int p = c->t.w[i].parent, k = 0;
		while (c->t.w[p].kids[k] != i)
			k++;
		for (; k + 1 < c->t.w[p].n_kids; k++)
			c->t.w[p].kids[k] = c->t.w[p].kids[k + 1];
		c->t.w[p].kids[k] = i;
		c->t.dirty = true;
		refused(vis_win_visible_region(c->t.w[i].win, &r, &n), EAGAIN, "a region of a dirty tree");
		refused(vis_tree_repaint(vt, &box, &rp, &n), EAGAIN, "a repaint of a dirty tree");
		tl_update_and_check(c);
	}
}
