/*
 * What each uid may hold, so that no other uid can take what the daemon's owner needs (the model
 * of dbus-broker's per-user accounting, with fixed bounds): connections, counted per uid and on
 * the restricted socket, with the last slots of --max-clients kept for the daemon's uid; and
 * retained windows, which outlive the connection that made them and so are counted against its
 * uid for as long as they exist.
 */
#include <stdio.h>
#include <stdlib.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"

/*
 * One uid's holdings. Invariant: a uid is in server->quotas exactly while it has a connection or
 * a retained window, and clients and retained count exactly those; rects and pieces count the
 * looks (shape and opaque rectangles, the pieces they cut into) of the windows its connections
 * own and of the retained windows they left behind, left_rects and left_pieces those of the
 * latter alone.
 */
struct quota {
	uint32_t clients;  /* connections, on either socket */
	uint32_t retained; /* retained windows its connections created that still exist */
	uint64_t rects, pieces, left_rects, left_pieces;
};

/* The map's key of a uid: uid + 1, as key 0 marks an empty slot and uid 0 is root. */
static uint32_t key_of(uid_t uid)
{
	return (uint32_t)uid + 1;
}

static struct quota *quota_of(struct server *server, uid_t uid)
{
	return vis_idmap_get(&server->quotas, key_of(uid));
}

/* Forgets a uid that holds nothing any more. */
static void forget_if_empty(struct server *server, uid_t uid, struct quota *q)
{
	if (!q->clients && !q->retained) {
		vis_idmap_remove(&server->quotas, key_of(uid));
		free(q);
	}
}

bool server_quota_admit(struct server *server, int fd, uid_t uid, bool restricted)
{
	const struct server_options *opt = &server->opt;
	if (key_of(uid) == 0) {
		/* (uid_t)-1 means "unchanged" to setuid(): no process runs as it. */
		server_refuse(server, fd, "uid %u is not a process's uid", (unsigned)uid);
		return false;
	}
	struct quota *q = quota_of(server, uid);
	/* A connection that may take a role: only it may have the reserve. */
	bool owner = uid == opt->allowed_uid && !restricted;
	if (restricted && server->n_restricted >= opt->max_restricted_clients) {
		server_refuse(server, fd,
			      "too many clients on the restricted socket: the limit is %u "
			      "(visd --max-restricted-clients)",
			      opt->max_restricted_clients);
		return false;
	}
	if (uid != opt->allowed_uid && q && q->clients >= opt->max_clients_per_uid) {
		server_refuse(server, fd,
			      "too many clients of uid %u: the limit is %u (visd --max-clients-per-uid)",
			      (unsigned)uid, opt->max_clients_per_uid);
		return false;
	}
	if (server->n_clients >= opt->max_clients) {
		server_refuse(server, fd, "too many clients: the limit is %u (visd --max-clients)",
			      opt->max_clients);
		return false;
	}
	if (!owner && server->n_clients >= opt->max_clients - opt->owner_reserve) {
		server_refuse(server, fd,
			      "too many clients: the last %u of %u slots are kept for the daemon's "
			      "uid (visd --owner-reserve)",
			      opt->owner_reserve, opt->max_clients);
		return false;
	}
	if (!q) {
		q = calloc(1, sizeof *q);
		if (!q || vis_idmap_put(&server->quotas, key_of(uid), q) < 0) {
			free(q);
			server_refuse(server, fd, "the daemon is out of memory");
			return false;
		}
	}
	q->clients++;
	server->n_restricted += restricted;
	return true;
}

void server_quota_leave(struct server *server, uid_t uid, bool restricted)
{
	struct quota *q = quota_of(server, uid);
	if (!q || !q->clients) {
		log_error("uid %u: a connection counted off that was never counted", (unsigned)uid);
		return;
	}
	q->clients--;
	server->n_restricted -= restricted;
	forget_if_empty(server, uid, q);
}

bool server_quota_may_retain(struct client *c, uint32_t seq)
{
	struct server *server = c->server;
	const struct quota *q = quota_of(server, c->uid); /* c is connected: never NULL */
	if (q && q->retained >= server->opt.max_retained_per_uid) {
		server_client_error(c, seq, VIS_OP_CREATE, VIS_ERROR_LIMIT,
				    "uid %u has %u retained windows, the limit "
				    "(visd --max-retained-per-uid)",
				    (unsigned)c->uid, q->retained);
		return false;
	}
	if (server->n_retained >= server->opt.max_retained) {
		server_client_error(c, seq, VIS_OP_CREATE, VIS_ERROR_LIMIT,
				    "%u retained windows exist, the limit (visd --max-retained)",
				    server->n_retained);
		return false;
	}
	return true;
}

int server_quota_retain(struct client *c, struct vis_window *w)
{
	struct quota *q = quota_of(c->server, c->uid);
	struct window_data *d = server_window_data(w);
	if (!q || !d)
		return -1;
	d->retained_by = c->uid;
	w->retained = true;
	q->retained++;
	c->server->n_retained++;
	return 0;
}

void server_quota_release(struct server *server, struct vis_window *w)
{
	const struct window_data *d = server_data_of(w);
	struct quota *q = d ? quota_of(server, d->retained_by) : NULL;
	if (!q || !q->retained) {
		log_error("window %u: a retained window counted off that was never counted", w->id);
		return;
	}
	q->retained--;
	server->n_retained--;
	forget_if_empty(server, d->retained_by, q);
}

/* Adds a signed change to a count that the invariants keep from going below zero. */
static void add(uint64_t *count, int64_t d)
{
	*count = (uint64_t)((int64_t)*count + d);
}

void server_quota_look(struct server *server, const struct vis_window *w, int64_t rects,
		       int64_t pieces)
{
	struct client *owner = vis_idmap_get(&server->clients_by_id, w->owner);
	const struct window_data *d = server_data_of(w);
	struct quota *q = owner ? quota_of(server, owner->uid)
			  : w->retained && d ? quota_of(server, d->retained_by) : NULL;
	if (owner) {
		add(&owner->n_look_rects, rects);
		add(&owner->n_look_pieces, pieces);
	} else if (q) {
		add(&q->left_rects, rects);
		add(&q->left_pieces, pieces);
	}
	if (q) {
		add(&q->rects, rects);
		add(&q->pieces, pieces);
	}
}

void server_quota_orphan(struct server *server, struct vis_window *w, struct client *owner)
{
	const struct window_data *d = server_data_of(w);
	struct quota *q = d ? quota_of(server, d->retained_by) : NULL;
	uint64_t rects = server_look_rects(w);
	uint64_t pieces = server_look_charged(w);
	add(&owner->n_look_rects, -(int64_t)rects);
	add(&owner->n_look_pieces, -(int64_t)pieces);
	if (q) {
		/* Its creator's uid held it through the connection: the totals stay. */
		q->left_rects += rects;
		q->left_pieces += pieces;
	}
}

/* Whether count + more passes limit; a limit error naming option and whose they are if so. */
static bool passes(struct client *c, uint32_t seq, uint32_t op, uint64_t count, uint64_t more,
		   uint32_t limit, const char *what, const char *whose, const char *option)
{
	if (count + more <= limit)
		return false;
	server_client_error(c, seq, op, VIS_ERROR_LIMIT,
			    "%s would have %llu %s, past the limit of %u (visd %s)", whose,
			    (unsigned long long)(count + more), what, limit, option);
	return true;
}

bool server_quota_look_room(struct client *c, uint32_t seq, uint32_t op,
			    const struct vis_window *w, uint64_t rects, uint64_t pieces)
{
	struct server *server = c->server;
	const struct server_options *opt = &server->opt;
	struct client *owner = vis_idmap_get(&server->clients_by_id, w->owner);
	/* The manager's windows, and those left behind that only it may change, are the desktop's
	 * own (visd-x11 mirrors every X window's shape): X bounds no window's looks. */
	if (!owner || owner->role == VIS_ROLE_MANAGER || (!rects && !pieces))
		return true;
	const struct quota *q = quota_of(server, owner->uid);
	uint64_t left_rects = q ? q->left_rects : 0, left_pieces = q ? q->left_pieces : 0;
	char whose[96];
	if (owner->uid != opt->allowed_uid && q) {
		/* Its uid's connections are many: they hold one allowance. */
		snprintf(whose, sizeof whose, "the windows of uid %u", (unsigned)owner->uid);
		return !passes(c, seq, op, q->rects, rects, opt->max_look_rects,
			       "shape and opaque rectangles", whose, "--max-look-rects") &&
		       !passes(c, seq, op, q->pieces, pieces, opt->max_look_pieces,
			       "look pieces", whose, "--max-look-pieces");
	}
	/* Retained windows left behind count against the connections of their uid that follow:
	 * else a client could leave looks behind, connect again and leave more. */
	snprintf(whose, sizeof whose, "the windows of client %u%s", owner->id,
		 left_rects || left_pieces ? " (with those its uid left retained)" : "");
	return !passes(c, seq, op, owner->n_look_rects + left_rects, rects, opt->max_look_rects,
		       "shape and opaque rectangles", whose, "--max-look-rects") &&
	       !passes(c, seq, op, owner->n_look_pieces + left_pieces, pieces,
		       opt->max_look_pieces, "look pieces", whose, "--max-look-pieces");
}

void server_quota_finish(struct server *server)
{
	for (size_t i = 0; i < server->quotas.cap; i++)
		if (server->quotas.keys[i])
			free(server->quotas.values[i]);
	vis_idmap_finish(&server->quotas);
}
