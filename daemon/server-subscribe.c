/* Subscriptions: who hears about which windows, and the exposure baselines they start from. */
#include <stdlib.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"

/* Counts (or, with delta −1, uncounts) a subscription in the window data and server totals. */
static void count(struct client *c, const struct sub *s, int delta)
{
	struct server *server = c->server;
	bool exposure = s->mask & VIS_NOTICE_EXPOSURE;
	/* Windows may no longer be wanted: the next recompute stops tracking them. */
	if (exposure && delta < 0)
		server->untrack_due = true;
	if (s->window) {
		struct vis_window *w = vis_wtree_find(&server->vis->core, s->window);
		struct window_data *d = w ? server_data_of(w) : NULL;
		if (d) {
			d->subs += (uint32_t)delta;
			if (exposure)
				d->exposure_subs += (uint32_t)delta;
		}
	} else if (exposure) {
		if (c->role != VIS_ROLE_CLIENT)
			server->role_all_exposure += (uint32_t)delta;
		else
			c->all_exposure = delta > 0;
	}
}

/*
 * Starts exposure baselines for the windows a new subscription covers, from what they show now:
 * those not viewable too, which show nothing yet, so that libvis lists what they show once they
 * are.
 */
static void track_covered(struct client *c, const struct sub *s)
{
	struct server *server = c->server;
	if (!(s->mask & VIS_NOTICE_EXPOSURE))
		return;
	if (s->window) {
		server_track(vis_wtree_find(&server->vis->core, s->window), server);
		return;
	}
	server->work += server->vis->core.count;
	for (struct vis_window *w = server->vis->core.root.bottom; w; w = vis_wtree_next(w))
		if (server_may_see(c, w))
			server_track(w, server);
}

/*
 * A new subscription's first notices: the state of every viewable window it covers, in stacking
 * order, so that a client that subscribes after creating a window learns its state at once.
 */
static void send_initial(struct client *c, const struct sub *s)
{
	struct server *server = c->server;
	if (!(s->mask & VIS_NOTICE_VISIBILITY))
		return;
	if (s->window) {
		struct vis_window *w = vis_wtree_find(&server->vis->core, s->window);
		if (w && w->state != VIS_WTREE_STATE_NONE)
			server_notice_initial(c, w);
		return;
	}
	server->work += server->vis->core.count;
	for (struct vis_window *w = vis_wtree_next_viewable(&server->vis->core, NULL); w && !c->closing;
	     w = vis_wtree_next_viewable(&server->vis->core, w))
		if (w->state != VIS_WTREE_STATE_NONE && server_may_see(c, w))
			server_notice_initial(c, w);
}

void server_subscription(struct client *c, uint32_t seq, uint32_t op, const union vis_arg *a)
{
	struct server *server = c->server;
	uint32_t window = a[0].u;
	struct sub *found = NULL;
	for (size_t i = 0; i < c->n_subs; i++)
		if (c->subs[i].window == window)
			found = &c->subs[i];
	if (op == VIS_OP_UNSUBSCRIBE) {
		if (!found) {
			server_client_error(c, seq, op, VIS_ERROR_VALUE, "no subscription to %s%.0u",
					    window ? "window " : "every window", window);
			return;
		}
		count(c, found, -1);
		*found = c->subs[--c->n_subs];
		return;
	}
	uint32_t mask = a[1].u, limit = a[2].u ? a[2].u : VIS_EXPOSURE_RECT_LIMIT;
	if (!mask || (mask & ~(uint32_t)VIS_NOTICE_ALL)) {
		server_client_error(c, seq, op, VIS_ERROR_VALUE, "notice mask %#x: use bits 1, 2, 4",
				    mask);
		return;
	}
	struct vis_window *w = NULL;
	if (window) {
		w = vis_wtree_find(&server->vis->core, window);
		if (!w || !server_may_see(c, w)) {
			server_client_error(c, seq, op, VIS_ERROR_WINDOW, "no such window %u", window);
			return;
		}
		if (!server_window_data(w)) {
			server_client_error(c, seq, op, VIS_ERROR_LIMIT, "out of memory");
			return;
		}
	}
	if (!found && c->n_subs >= server->opt.max_subs) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "this connection has %zu subscriptions, the limit "
				    "(visd --max-subscriptions)",
				    c->n_subs);
		return;
	}
	/* States and baselines are the current ones: what earlier changes did is computed first,
	 * and its notices are not this subscription's. */
	server_flush(server);
	if (!found) {
		if (c->n_subs == c->cap_subs) {
			size_t cap = c->cap_subs ? 2 * c->cap_subs : 4;
			struct sub *more = realloc(c->subs, cap * sizeof *more);
			if (!more) {
				server_client_error(c, seq, op, VIS_ERROR_LIMIT, "out of memory");
				return;
			}
			c->subs = more;
			c->cap_subs = cap;
		}
		found = &c->subs[c->n_subs++];
	} else {
		count(c, found, -1);
	}
	*found = (struct sub){ window, mask, limit };
	count(c, found, +1);
	track_covered(c, found);
	send_initial(c, found);
}

void server_unsubscribe_all(struct client *c)
{
	for (size_t i = 0; i < c->n_subs; i++)
		count(c, &c->subs[i], -1);
	c->n_subs = 0;
}
