/*
 * What the looks of a connection's windows cost: the pieces they cut into (vis_wtree_cut()),
 * counted against the window's owner and its uid (server_quota_look()) and bounded by
 * --max-look-pieces, as every recompute that meets a window places its pieces.
 */
#include <errno.h>
#include <string.h>

#include "server.h"
#include "vis/protocol.h"

/*
 * What cutting a look costs, a rectangle at a time, in the units of a turn's and a batch's work
 * (windows walked): cutting 120,000 rectangles took 30 ms where walking 131,072 windows takes
 * about 1 ms, so about 32 windows a rectangle. A batch of resizes of a window whose look has
 * 262,144 rectangles would otherwise cut it again for each, in one turn.
 */
#define LOOK_RECT_WORK 32u

uint64_t server_look_charged(const struct vis_window *w)
{
	return w->cut ? w->cut->n : 0;
}

uint64_t server_look_rects(const struct vis_window *w)
{
	return (uint64_t)w->look.n_shape + w->look.n_opaque;
}

bool server_look_pieces_ok(struct client *c, uint32_t seq, uint32_t op, const struct vis_window *w,
			   const struct vis_look *look, int32_t width, int32_t height,
			   struct vis_look_cut *cut)
{
	*cut = (struct vis_look_cut){ 0 };
	if (!vis_look_cuts_inside(look))
		return true;
	struct server *server = c->server;
	uint64_t work = LOOK_RECT_WORK * ((uint64_t)look->n_shape + look->n_opaque + 1);
	if (work > server->walk_left) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT,
				    "the batch's changes cut looks of too many rectangles (the work "
				    "of walking %u windows); send the rest in another batch",
				    SERVER_BATCH_WORK);
		return false;
	}
	server->walk_left -= work;
	server->work += work; /* the turn ends sooner */
	if (vis_look_cut_fill(cut, look, width, height) < 0) {
		server_client_error(c, seq, op, VIS_ERROR_LIMIT, "cannot cut window %u's look: %s",
				    w->id, strerror(errno));
		return false;
	}
	uint64_t old = server_look_charged(w);
	if (cut->n > old && !server_quota_look_room(c, seq, op, w, 0, cut->n - old)) {
		vis_look_cut_finish(cut);
		return false;
	}
	return true;
}

void server_look_keep(struct server *server, struct vis_window *w, uint64_t old,
		      struct vis_look_cut *cut)
{
	server_quota_look(server, w, 0, (int64_t)cut->n - (int64_t)old);
	vis_wtree_keep_cut(w, cut);
}
