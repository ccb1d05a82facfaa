/*
 * The limits suite's shared helpers (test-limits.c) and its cases on what others may hold
 * (limits-quota.c): connections per uid, on the restricted socket, the owner's reserve, the hello
 * deadline; retained windows per uid and in all.
 */
#ifndef VIS_TESTS_LIMITS_H
#define VIS_TESTS_LIMITS_H

#include "harness.h"

/* The visd under test. */
extern const char *limits_visd;

/*
 * Connects to sock and says hello for role client, tolerating a connection refused (and closed)
 * before the hello is written: true when the daemon accepted, false when it refused with a limit
 * error whose message holds reason (any message when reason is NULL).
 */
bool limits_try_hello(struct harness_conn *c, const char *sock, const char *reason);
/* What the daemon wrote to stderr so far. */
const char *limits_read_log(const struct harness_daemon *d);
/* Expects a limit error naming the option for request seq, on a connection that stays. */
void limits_expect_limit(struct harness_conn *c, uint32_t seq, uint32_t op, const char *option);

/* The cases of limits-quota.c. */
void limits_quota_lockout(void);
void limits_quota_connections(void);
void limits_quota_hello_timeout(void);
void limits_quota_retained(void);
void limits_quota_look_pieces(void);

#endif
