/*
 * What each uid may hold, so that no other uid can take what the daemon's owner needs (the model
 * of dbus-broker's per-user accounting, with fixed bounds): connections, counted per uid and on
 * the restricted socket, with the last slots of --max-clients kept for the daemon's uid.
 */
#include <stdlib.h>

#include "log.h"
#include "server.h"

/*
 * One uid's holdings. Invariant: a uid is in server->quotas exactly while it has a connection,
 * and clients counts them.
 */
struct quota {
	uint32_t clients; /* connections, on either socket */
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
	if (!q->clients) {
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

void server_quota_finish(struct server *server)
{
	for (size_t i = 0; i < server->quotas.cap; i++)
		if (server->quotas.keys[i])
			free(server->quotas.values[i]);
	vis_idmap_finish(&server->quotas);
}
