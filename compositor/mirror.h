/*
 * The mirror (--visd SOCKET): viscomp's model, copied into a visd as its manager, so that visd's
 * clients (visctl, libvisclient applications, other tools) see the Wayland desktop's windows and
 * states as viscomp has them.
 *
 * Every model surface placed once is a top-level visd window carrying the external ID
 * (VIS_EXTERNAL_WAYLAND, pid << 32 | the wl_surface's protocol object ID): a client finds its
 * own surface's window from its pid and wl_proxy_get_id(). The outside (model.h) is a shaped
 * window without an external ID. Positions, sizes, opaque regions, mapping and stacking follow
 * the model once a frame (model_update()), in one batch; visd's states then equal libvis'
 * (given a visd screen at least as large as the output layout).
 *
 * When visd goes away or breaks the connection, viscomp logs it, carries on without a mirror (the
 * model, and so the throttling, does not depend on it) and connects again on its own: first
 * after 100 ms, then each time waiting twice as long, up to 5 s between attempts. Once connected,
 * it mirrors its whole model anew, as at the start. The handshake is synchronous (libvisclient
 * has no other): a visd that accepts the connection but never answers would hold viscomp.
 */
#ifndef VISCOMP_MIRROR_H
#define VISCOMP_MIRROR_H

#include <stdint.h>

struct mirror;
struct mirror_win;
struct model_surface;
struct server;

/* Connects to visd at path as its manager and creates the outside. NULL on failure (logged):
 * at the start, visd must be there. */
struct mirror *mirror_create(struct server *server, const char *path);

/* Disconnects: visd drops the windows (they are not retained). NULL: no-op. */
void mirror_destroy(struct mirror *mirror);

/* Sends what changed in the model since the last call, in one batch. NULL: no-op. */
void mirror_sync(struct mirror *mirror);

/* A surface is going: its window too. */
void mirror_surface_gone(struct mirror *mirror, struct model_surface *ms);

/* The outside's pixels changed (model_set_shown()). */
void mirror_outside_changed(struct mirror *mirror);

#endif
