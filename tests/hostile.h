/*
 * The hostile suite's shared state (test-hostile.c, hostile-access.c): one visd, and an innocent
 * client whose windows have known states that no hostile client may change.
 */
#ifndef VIS_TESTS_HOSTILE_H
#define VIS_TESTS_HOSTILE_H

#include "harness.h"

#define HOSTILE_WINDOWS 5

extern struct harness_daemon hostile_visd;
extern struct harness_conn hostile_innocent;
extern uint32_t hostile_win[HOSTILE_WINDOWS]; /* the innocent's windows */

/*
 * Fails unless the daemon is alive and clean, the hostile connections are freed and their windows
 * gone, the innocent's windows and states are as they were, and a new connection is served.
 */
void hostile_check_unaffected(void);

/*
 * A well-formed request's words with harmless values: the window fields name own (sibling:
 * sibling), parents the screen, positions right of the innocent's windows, no external ID.
 * Requests have 32-bit fields and, after them, 64-bit ones (two words each); a new field type or
 * name fails here so that the cases stay complete. Returns the number of words.
 */
size_t hostile_request_words(const struct vis_msg_type *t, uint32_t own, uint32_t sibling,
			     uint32_t *words);
/* Whether a field names a window: window, parent, sibling. */
bool hostile_is_window_field(const char *name);

/* Destroys, as the manager, every window that is not the innocent's (retained leftovers). */
void hostile_destroy_leftovers(void);

/* Expects hello asking for the observer and then the manager role on path to be refused. */
void hostile_expect_no_role(const char *path, const char *reason);

/* The access cases (hostile-access.c). */
void hostile_access_window_ids(void);
void hostile_access_isolation(void);
void hostile_access_stack_notices(void);
void hostile_access_other_uid(void);
/* Batches that are too large, or hold work meant to stall the daemon (hostile-batch.c). */
void hostile_batch(void);
/* Clients that hang up with requests in flight (hostile-hangup.c). */
void hostile_hangup(void);

/*
 * Hidden windows (hostile-hidden.c): seeded random runs on daemons of their own, checking that a
 * client never receives the ID of a window it may not see. seed 0: the suite's fixed seeds.
 */
void hostile_hidden_windows(const char *visd, uint64_t seed);

#endif
