/*
 * What each uid may hold, so that no other uid can take what the daemon's owner needs (the model
 * of dbus-broker's per-user accounting, with fixed bounds): connections, counted per uid and on
 * the restricted socket, with the last slots of --max-clients kept for the daemon's uid; and
 * retained windows, which outlive the connection that made them and so are counted against its
 * uid for as long as they exist.
 */
#include <stdlib.h>

#include "log.h"
#include "server.h"
#include "vis/protocol.h"

/*
 * One uid's holdings. Invariant: a uid is in server->quotas exactly while it has a connection or
 * a retained window, and clients and retained count exactly those.
 */
struct quota {
	uint32_t clients;  /* connections, on either socket */
	uint32_t retained; /* retained windows its connections created that still exist */
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
	const struct window_data *d = w->data;
	struct quota *q = d ? quota_of(server, d->retained_by) : NULL;
	if (!q || !q->retained) {
		log_error("window %u: a retained window counted off that was never counted", w->id);
		return;
	}
	q->retained--;
	server->n_retained--;
	forget_if_empty(server, d->retained_by, q);
}

void server_quota_finish(struct server *server)
{
	for (size_t i = 0; i < server->quotas.cap; i++)
		if (server->quotas.keys[i])
			free(server->quotas.values[i]);
	vis_idmap_finish(&server->quotas);
}
