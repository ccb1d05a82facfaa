/*
 * The protocol versions the daemon speaks, and everything that differs between them, in one
 * place. A connection speaks the version its hello asked for (client.version), from
 * VIS_PROTOCOL_OLDEST_VERSION to VIS_PROTOCOL_VERSION, and the daemon reads and writes for it
 * exactly what that version's daemon did. Today's model is the current version's; what an older
 * version reads differently is converted here, on the way out, and nowhere else.
 *
 * What differs (PROTOCOL.md, History):
 * - 4 from 3: the rectangles of region replies and exposure notices are in window coordinates,
 *   from the inside's corner; version 3 had them from the border box's corner, so a version-3
 *   connection reads them shifted by the window's border width on both axes. Requests are the
 *   same bytes in both (shapes and opaque rectangles were always from the inside's corner), and
 *   no message changed its fields.
 */
#include "server.h"
#include "vis/protocol.h"

bool server_compat_speaks(uint32_t version)
{
	return version >= VIS_PROTOCOL_OLDEST_VERSION && version <= VIS_PROTOCOL_VERSION;
}

/* How far c's rectangles about w lie from today's window coordinates, on both axes. */
static int32_t origin(const struct client *c, const struct vis_window *w)
{
	return c->version < 4 ? w->look.border : 0;
}

bool server_compat_rects_differ(const struct client *c, const struct vis_window *w)
{
	return origin(c, w) != 0;
}

void server_compat_rects(const struct client *c, const struct vis_window *w, uint32_t *words,
			 uint32_t n)
{
	int64_t d = origin(c, w);
	if (!d)
		return;
	/* Inside the border box, as every visible or exposed rectangle is, the shifted ones stay
	 * within 0 … 2^31 − 1: the border box's sides are at most that. */
	for (uint32_t i = 0; i < n; i++) {
		words[4 * i] = (uint32_t)(int32_t)((int32_t)words[4 * i] + d);
		words[4 * i + 1] = (uint32_t)(int32_t)((int32_t)words[4 * i + 1] + d);
	}
}
