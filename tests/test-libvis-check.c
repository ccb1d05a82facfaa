/* test-libvis's checks after an update: states, visible regions, changes, exposures, repaints. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "test-libvis.h"

static int by_value(const void *a, const void *b)
{
	uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
	return x < y ? -1 : x > y;
}

/* Grows a pixel set by one. */
static void push(uint64_t **v, size_t *n, size_t *cap, uint64_t x)
{
	if (*n == *cap) {
		*cap = *cap ? 2 * *cap : 64;
		if (!(*v = realloc(*v, *cap * sizeof **v)))
			tl_fail("out of memory", 0, 0);
	}
	(*v)[(*n)++] = x;
}

/* Window i's visible pixels inside the screen box x0 ≤ x < x1, y0 ≤ y < y1, in its window
 * coordinates, packed and sorted: a new array, *n long. */
static uint64_t *painted(const struct pm_tree *t, const struct pm_paint *p, int i, int64_t x0,
			 int64_t y0, int64_t x1, int64_t y1, size_t *n)
{
	uint64_t *v = NULL;
	size_t cap = 0;
	int64_t ix, iy;
	pm_inside(t, i, &ix, &iy);
	*n = 0;
	for (int64_t y = y0 < 0 ? 0 : y0; y < y1 && y < t->sh; y++)
		for (int64_t x = x0 < 0 ? 0 : x0; x < x1 && x < t->sw; x++)
			if (pm_visible(t, p, i, x, y))
				push(&v, n, &cap, pm_pack(x - ix, y - iy));
	if (*n)
		qsort(v, *n, sizeof *v, by_value);
	return v;
}

/* Rectangles of window i (window coordinates) as a sorted pixel set; they must lie on the screen
 * and not overlap. A new array, *n long. */
static uint64_t *listed(const struct pm_tree *t, int i, const struct vis_rect32 *r, size_t k,
			size_t *n)
{
	uint64_t *v = NULL;
	size_t cap = 0;
	int64_t ix, iy;
	pm_inside(t, i, &ix, &iy);
	*n = 0;
	for (size_t j = 0; j < k; j++) {
		tl_check(r[j].width >= 1 && r[j].height >= 1 &&
				 (uint64_t)r[j].width * r[j].height <= (uint64_t)t->sw * t->sh,
			 "a rectangle is empty or larger than the screen");
		for (int64_t y = r[j].y; y < (int64_t)r[j].y + r[j].height; y++)
			for (int64_t x = r[j].x; x < (int64_t)r[j].x + r[j].width; x++) {
				tl_check(ix + x >= 0 && iy + y >= 0 && ix + x < t->sw &&
						 iy + y < t->sh,
					 "a rectangle leaves the screen");
				push(&v, n, &cap, pm_pack(x, y));
			}
	}
	if (*n)
		qsort(v, *n, sizeof *v, by_value);
	for (size_t j = 1; j < *n; j++)
		tl_check(v[j] != v[j - 1], "rectangles overlap");
	return v;
}

static bool same(const uint64_t *a, size_t na, const uint64_t *b, size_t nb)
{
	return na == nb && (na == 0 || !memcmp(a, b, na * sizeof *a));
}

/* a less b, both sorted, into a (its count returned). */
static size_t less(uint64_t *a, size_t na, const uint64_t *b, size_t nb)
{
	size_t k = 0, j = 0;
	for (size_t i = 0; i < na; i++) {
		while (j < nb && b[j] < a[i])
			j++;
		if (j == nb || b[j] != a[i])
			a[k++] = a[i];
	}
	return k;
}

void tl_baseline(struct tl *c, int i)
{
	struct pm_paint p;
	if (!pm_paint(&c->t, &p))
		tl_fail("out of memory", 0, 0);
	struct pm_win *m = &c->t.w[i];
	free(m->base);
	m->base = painted(&c->t, &p, i, INT64_MIN, INT64_MIN, INT64_MAX, INT64_MAX, &m->n_base);
	pm_paint_finish(&p);
}

/* The repaint set of a random damaged box against the painter. */
static void check_repaint(struct tl *c, const struct pm_paint *p)
{
	const struct pm_tree *t = &c->t;
	struct vis_rect32 d = { (int32_t)tl_range(-6, t->sw + 2), (int32_t)tl_range(-6, t->sh + 2),
				(uint32_t)tl_range(1, t->sw + 8), (uint32_t)tl_range(1, t->sh + 8) };
	if (tl_range(0, 9) == 0)
		d = (struct vis_rect32){ INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX };
	else if (tl_range(0, 1) == 0)
		tl_kept_damage(c->vt, &d); /* inside the last change's box, often: a frame's damage */
	const struct vis_repaint *out;
	size_t n;
	if (vis_tree_repaint(c->vt, &d, &out, &n) < 0)
		tl_fail("vis_tree_repaint failed", errno, 0);
	int64_t x1 = (int64_t)d.x + d.width, y1 = (int64_t)d.y + d.height;
	size_t at = 0;
	int last = -1;
	for (int k = 0; k < p->n; k++) {
		int i = p->order[k];
		size_t ne, nl = 0;
		uint64_t *e = painted(t, p, i, d.x, d.y, x1, y1, &ne), *l = NULL;
		if (ne) {
			tl_check(at < n && out[at].win == t->w[i].win, "the repaint set's windows");
			tl_check(out[at].data == vis_win_get_data(t->w[i].win), "a repaint's data");
			int64_t ix, iy;
			pm_inside(t, i, &ix, &iy);
			tl_check(out[at].x == ix && out[at].y == iy, "a repaint's origin");
			l = listed(t, i, out[at].rects, out[at].n_rects, &nl);
			tl_check(same(e, ne, l, nl), "a repaint's part to draw");
			tl_check(k > last, "the repaint set's order");
			last = k;
			at++;
		}
		free(e);
		free(l);
	}
	tl_check(at == n, "the repaint set lists a window that shows nothing in the damage");
}

/* A change's order: the windows not viewable first (0), then by place in pre-order. */
static int rank(const struct pm_tree *t, const struct pm_paint *p, int i)
{
	return pm_viewable(t, i) ? 1 + p->pos[i] : 0;
}

void tl_update_and_check(struct tl *c)
{
	struct pm_tree *t = &c->t;
	const struct vis_change *ch;
	size_t n;
	if (vis_tree_update(c->vt, &ch, &n) < 0)
		tl_fail("vis_tree_update failed", errno, 0);
	t->dirty = false;
	struct pm_paint p;
	if (!pm_paint(t, &p))
		tl_fail("out of memory", 0, 0);
	int now[PM_MAX + 1];
	uint64_t *exposed[PM_MAX + 1] = { 0 };
	size_t n_exposed[PM_MAX + 1] = { 0 }, expected = 0;
	bool due[PM_MAX + 1] = { 0 }, seen[PM_MAX + 1] = { 0 };
	for (int i = 1; i <= PM_MAX; i++) {
		struct pm_win *m = &t->w[i];
		if (!m->alive)
			continue;
		now[i] = pm_state(t, &p, i);
		tl_check(vis_win_state(m->win) == now[i], "a state");
		size_t nv, nl, nr;
		const struct vis_rect32 *r;
		uint64_t *v = painted(t, &p, i, INT64_MIN, INT64_MIN, INT64_MAX, INT64_MAX, &nv);
		if (vis_win_visible_region(m->win, &r, &nr) < 0)
			tl_fail("vis_win_visible_region failed", i, errno);
		uint64_t *l = listed(t, i, r, nr, &nl);
		tl_check(same(v, nv, l, nl), "a visible region");
		uint64_t tally;
		tl_check(!tl_tally(m->win, &tally) || tally == pm_seen(t, &p, i),
			 "a tally of seen pixels");
		free(l);
		if (m->tracked) {
			/* Newly visible: what it shows less what it showed, in window coordinates. */
			exposed[i] = malloc((nv ? nv : 1) * sizeof *v);
			if (nv)
				memcpy(exposed[i], v, nv * sizeof *v);
			n_exposed[i] = less(exposed[i], nv, m->base, m->n_base);
			free(m->base);
			m->base = v;
			m->n_base = nv;
		} else {
			n_exposed[i] = 0;
			free(v);
		}
		due[i] = now[i] != m->state || n_exposed[i];
		expected += due[i];
	}
	int last = -1;
	for (size_t k = 0; k < n; k++) {
		int i = (int)(intptr_t)ch[k].data;
		tl_check(i >= 1 && i <= PM_MAX && t->w[i].alive && ch[k].win == t->w[i].win,
			 "a change's window");
		tl_check(due[i] && !seen[i], "a change listed that did not happen, or twice");
		seen[i] = true;
		tl_check(ch[k].previous == (uint32_t)t->w[i].state && ch[k].state == (uint32_t)now[i],
			 "a change's states");
		size_t nl;
		uint64_t *l = listed(t, i, ch[k].exposed, ch[k].n_exposed, &nl);
		tl_check(same(exposed[i], n_exposed[i], l, nl), "a change's exposure");
		free(l);
		tl_check(rank(t, &p, i) >= last, "the changes' order");
		last = rank(t, &p, i);
	}
	for (int i = 1; i <= PM_MAX; i++)
		if (due[i] && !seen[i])
			tl_fail(t->w[i].state != now[i] ? "a state change missing (slot, state)"
							: "an exposure missing (slot, pixels)",
				i, t->w[i].state != now[i] ? now[i] : (long)n_exposed[i]);
	tl_check(n == expected, "a change missing");
	for (int i = 1; i <= PM_MAX; i++) {
		free(exposed[i]);
		if (t->w[i].alive)
			t->w[i].state = now[i];
	}
	for (int k = 0; k < 3; k++)
		check_repaint(c, &p);
	pm_paint_finish(&p);
}
