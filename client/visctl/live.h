/*
 * What visctl's live subcommands (the ones that talk to visd) share: one connection, opened by
 * the first command that needs it and kept for a whole script, and the way errors are reported.
 */
#ifndef VISCTL_LIVE_H
#define VISCTL_LIVE_H

#include <stdbool.h>
#include <stdint.h>

#include "vis/visclient.h"

struct live {
	const char *socket; /* -s SOCKET, or NULL for the default */
	uint32_t role;      /* enum vis_role, from --role */
	bool role_given;    /* --role was given: commands keep to it rather than pick their own */
	struct vis_client *client; /* NULL until a command connects */
	const char *where; /* what messages start with: "visctl", or "FILE:LINE" in a script */
	bool in_script;
	bool in_batch;    /* a script's batch-begin is sent and its batch-commit not yet */
	uint32_t created; /* the window the last create made, for a script's @N */
};

/* A live subcommand: argv[0] is its name; returns a VISCTL_EXIT_* status. */
typedef int (*live_fn)(struct live *l, int argc, char **argv);

/* The connection, opened on first use; NULL after saying why on stderr. */
struct vis_client *live_connect(struct live *l);

/* Says "WHERE: message" on stderr; returns VISCTL_EXIT_FAILURE. */
int live_error(struct live *l, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Says "WHERE: NAME: message" and the command's usage line on stderr; returns VISCTL_EXIT_USAGE. */
int live_usage(struct live *l, const char *name, const char *fmt, ...)
	__attribute__((format(printf, 3, 4)));

/*
 * Reports the failure of what the command asked (e.g. "map 42"): the connection's error if it
 * failed, else the daemon's last error (code name and message). Returns VISCTL_EXIT_FAILURE.
 */
int live_failed(struct live *l, const char *what);

/* The command line, "NAME ARG …", for messages naming the request. */
const char *live_describe(int argc, char **argv, char *buf, size_t len);

/* Whether an argument is an option rather than a (possibly negative) number or '-'. */
int live_is_option(const char *a);

/* Prints a command's usage line and help text on stdout, for --help; returns the exit status. */
int live_help(const char *name);

/*
 * Checks that argv holds exactly n arguments and no option but --help (which prints the help)
 * and, when json is not NULL, --json (which sets *json and is taken out of argv), naming the
 * arguments (names, e.g. "ID X Y") when the count is wrong. Returns 0 (*argc then counts what
 * is left), or -1 with *ret the status to exit with.
 */
int live_expect_args(struct live *l, int *argc, char **argv, int n, const char *names, bool *json,
		     int *ret);

/* Parse an argument of a command called name: a window ID (any 32-bit number), a coordinate
 * (32-bit signed), a size (1 … 2^31 − 1, as the daemon takes them) named what. Return 0, or -1
 * with *ret the usage status after saying why. */
int live_window_arg(struct live *l, const char *name, const char *s, uint32_t *id, int *ret);
int live_coord_arg(struct live *l, const char *name, const char *what, const char *s,
		   int32_t *v, int *ret);
int live_size_arg(struct live *l, const char *name, const char *what, const char *s,
		  uint32_t *v, int *ret);

/*
 * External IDs on the command line: an X window ID (XID: 1 … 0xffffffff, hexadecimal with 0x or
 * decimal), or the general NS:TAG (NS a namespace from 1 to 4294967295 in decimal, TAG a 64-bit
 * number as an XID is written). Return 0, or -1 with *ret the usage status after saying why.
 */
int live_xid_arg(struct live *l, const char *name, const char *s, uint64_t *xid, int *ret);
int live_external_arg(struct live *l, const char *name, const char *s, uint32_t *ns,
		      uint64_t *tag, int *ret);

/* An external ID as visctl prints it: "x11:0xXID", "NS:0xTAG", or "-" for none. */
const char *live_external_name(uint32_t ns, uint64_t tag, char *buf, size_t len);

/*
 * With --x11 and no --role, the role a command takes: observer, which sees every X window (they
 * are the bridge's, the manager's: a plain client sees none of them).
 */
void live_x11_role(struct live *l);

/* Parses an unsigned 64-bit number: decimal, or hexadecimal after 0x. Returns 0, or -1. */
int live_parse_u64(const char *s, uint64_t *out);

/* Parses plain decimal numbers ('-' allowed for signed ones). Return 0, or -1. */
int live_parse_u32(const char *s, uint32_t *out);
int live_parse_i32(const char *s, int32_t *out);

/*
 * Whether the connection is a plain client (no role) that owns no window: it sees nothing, as a
 * new visctl connection does. Asks the daemon (a tree round trip) only for plain clients.
 */
bool live_sees_nothing(struct live *l);

/* Says on stderr that a plain client's connection sees nothing, and how to see every window. */
void live_warn_sees_nothing(struct live *l, const char *name);

/* Writes all queued requests, reading what comes meanwhile. Returns 0, or -1 (connection error). */
int live_drain(struct vis_client *c);

#endif
