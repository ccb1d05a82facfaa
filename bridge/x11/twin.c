/*
 * visd's twin of the mirror: checked against visd's own tree (SIGUSR1), and made again when they
 * differ. Every mirror function sends visd the change it makes, so the two can only differ after
 * a request visd refused or a bug; the check says so rather than trust it.
 */
#include <stdio.h>
#include <stdlib.h>

#include "bridge.h"

/* The mirror's next window in visd's get-tree order: pre-order, children bottom to top. */
static struct xwin *next_pre(struct xwin *w)
{
	if (w->bottom)
		return w->bottom;
	for (; w->parent; w = w->parent)
		if (w->above)
			return w->above;
	return NULL;
}

/* Whether record t says what the mirror says of w; else why not, into why. */
static bool same(const struct bridge *b, const struct xwin *w, const struct vis_window_info *t,
		 char *why, size_t size)
{
	uint32_t parent = w->parent == b->root ? 0 : w->parent->vid;
	if (w->id != t->external)
		snprintf(why, size, "visd has 0x%llx where the mirror has 0x%x",
			 (unsigned long long)t->external, w->id);
	else if (w->vid != t->window || parent != t->parent)
		snprintf(why, size, "0x%x is window %u under %u in visd, %u under %u in the mirror",
			 w->id, t->window, t->parent, w->vid, parent);
	else if (w->x != t->x || w->y != t->y || w->width != t->width || w->height != t->height ||
		 (w->input_only ? 0 : w->border) != t->border)
		snprintf(why, size, "0x%x is %ux%u%+d%+d border %u in visd, %ux%u%+d%+d border %u "
				    "in the mirror",
			 w->id, t->width, t->height, t->x, t->y, t->border, w->width, w->height, w->x,
			 w->y, w->border);
	else if (w->mapped != ((t->flags & VIS_WINDOW_MAPPED) != 0))
		snprintf(why, size, "0x%x is %s in visd, not in the mirror", w->id,
			 w->mapped ? "unmapped" : "mapped");
	else
		return true;
	return false;
}

int twin_check(struct bridge *b, char *why, size_t size)
{
	struct vis_window_info *t;
	size_t n;
	if (vis_client_get_tree(b->vc, &t, &n) < 0) {
		b->visd_failed = true;
		return -1;
	}
	struct xwin *w = b->root->bottom;
	bool equal = true;
	for (size_t i = 0; i < n && equal; i++) {
		if (t[i].ext_namespace != VIS_EXTERNAL_X11)
			continue; /* another manager's before: not the bridge's to check */
		if (!w) {
			snprintf(why, size, "visd has 0x%llx, which the mirror has not",
				 (unsigned long long)t[i].external);
			equal = false;
		} else {
			equal = same(b, w, &t[i], why, size);
			w = next_pre(w);
		}
	}
	if (equal && w) {
		snprintf(why, size, "visd lacks 0x%x", w->id);
		equal = false;
	}
	free(t);
	return equal ? 0 : 1;
}

/* Forgets w's twin, and its subtree's. */
static void forget(struct bridge *b, struct xwin *w)
{
	for (struct xwin *c = w->bottom; c; c = c->above)
		forget(b, c);
	w->vid = 0;
	w->pending = false;
	w->look_due = false;
	w->vstate = VIS_VISIBILITY_NONE;
}

int twin_rebuild(struct bridge *b)
{
	/* Destroying the top-level windows takes their subtrees. */
	for (struct xwin *w = b->root->bottom; w; w = w->above)
		if (w->vid) {
			visd_begin(b);
			vis_client_destroy_window(b->vc, w->vid);
		}
	if (visd_end_turn(b) < 0)
		return -1;
	vis_idmap_finish(&b->by_vid);
	vis_idmap_init(&b->by_vid);
	vis_idmap_finish(&b->early_states);
	vis_idmap_init(&b->early_states);
	b->look_due.n = 0;
	forget(b, b->root);
	/* Level by level: a level's creations wait for their parents' IDs once. */
	size_t cap = b->n_windows + 1, head = 0, tail = 0;
	struct xwin **queue = malloc(cap * sizeof(*queue));
	if (!queue)
		return -1;
	for (struct xwin *w = b->root->bottom; w && tail < cap; w = w->above)
		queue[tail++] = w;
	while (head < tail) {
		struct xwin *w = queue[head++];
		mirror_create_in_visd(b, w);
		for (struct xwin *c = w->bottom; c && tail < cap; c = c->above)
			queue[tail++] = c;
	}
	free(queue);
	return visd_end_turn(b);
}
