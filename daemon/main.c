/*
 * visd: the window-visibility daemon. This file: options, the socket path and its lock, the
 * sockets a service manager passes (activation.c takes them), signals.
 */
#include <ctype.h>
#include <errno.h>
#include <event2/event.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stddef.h>
#include <sys/file.h>
#include <sys/random.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "activation.h"
#include "log.h"
#include "server.h"
#include "vis/protocol.h"
#include "vis/version.h"

static const char usage_text[] =
	"usage: visd [--socket PATH] [--screen WxH] [--restricted-socket PATH] [LIMITS] [-v]\n"
	"       visd --version\n"
	"  --socket PATH             listen here (default: $VISD_SOCKET, else\n"
	"                            $XDG_RUNTIME_DIR/visd-0)\n"
	"  --screen WxH              the screen size (default 3840x2160)\n"
	"  --restricted-socket PATH  a second socket whose clients never get a role\n"
	"  -v                        log debug messages too\n"
	"limits (past most, a request gets a 'limit' error naming the option):\n"
	"  --max-request BYTES       the largest request accepted (default 65536)\n"
	"  --max-clients N           connections at once (default 1024, fewer when\n"
	"                            descriptors are short: see `ulimit -n`)\n"
	"  --owner-reserve N         of those, slots only the daemon's uid may take, on\n"
	"                            the main socket (below --max-clients; default 32,\n"
	"                            or half of --max-clients if less)\n"
	"  --max-clients-per-uid N   connections of one uid other than the daemon's\n"
	"                            (default 256)\n"
	"  --max-restricted-clients N\n"
	"                            connections on the restricted socket (default 256)\n"
	"  --hello-timeout SECONDS   how long a connection may take to complete hello\n"
	"                            before it is closed (default 10)\n"
	"  --max-windows N           windows one connection may own (default 262144)\n"
	"  --max-look-rects N        shape and opaque rectangles of the windows one connection\n"
	"                            owns, and the retained ones its uid left (default 1048576)\n"
	"  --max-look-pieces N       pieces those looks cut into, what recomputes cost\n"
	"                            (default 16384); another uid's connections share both;\n"
	"                            the manager's windows count for neither\n"
	"  --max-retained-per-uid N  retained windows that exist, made by connections of\n"
	"                            one uid, alive or gone (default 262144)\n"
	"  --max-retained N          retained windows that exist (default 1048576)\n"
	"  --max-depth N             depth of the window tree (default 64)\n"
	"  --max-subscriptions N     subscriptions per connection (default 1024)\n"
	"  --max-pending BYTES       output waiting for one connection before its notices\n"
	"                            are dropped for a resync (default 4194304)\n"
	"tuning:\n"
	"  --live-from N             windows from which recomputes go live, costing the\n"
	"                            windows a change can affect; below, through the\n"
	"                            tree (default 0: always live)\n"
	"testing:\n"
	"  --id-key KEY              the window IDs' permutation key (decimal or 0x hex;\n"
	"                            default: random; 0: IDs 1, 2, 3 ... in order), so\n"
	"                            that a recorded session replays with the same IDs\n"
	"socket activation: given a listening socket by its service manager (LISTEN_PID,\n"
	"LISTEN_FDS, LISTEN_FDNAMES, as sd_listen_fds(3) says), visd serves it rather than\n"
	"bind one; a second socket, named 'restricted' in LISTEN_FDNAMES, is the restricted\n"
	"socket. --socket, if given, must name the same socket. PATH.lock is still taken\n"
	"beside the socket's file, which is left in place at exit: the manager owns it.\n";

/* The numeric options: the name, the range accepted, where the value goes. */
struct number_option {
	const char *name;
	unsigned long min, max;
	size_t offset; /* of a uint32_t in struct server_options */
};

static const struct number_option number_options[] = {
	{ "--max-request", VIS_PROTOCOL_MIN_MAX_REQUEST, VIS_PROTOCOL_MAX_MESSAGE,
	  offsetof(struct server_options, max_request) },
	{ "--max-clients", 1, 1000000, offsetof(struct server_options, max_clients) },
	{ "--owner-reserve", 0, 999999, offsetof(struct server_options, owner_reserve) },
	{ "--max-clients-per-uid", 1, 1000000, offsetof(struct server_options, max_clients_per_uid) },
	{ "--max-restricted-clients", 1, 1000000,
	  offsetof(struct server_options, max_restricted_clients) },
	{ "--hello-timeout", 1, 86400, offsetof(struct server_options, hello_timeout) },
	{ "--max-windows", 1, INT32_MAX, offsetof(struct server_options, max_windows) },
	{ "--max-look-rects", 0, INT32_MAX, offsetof(struct server_options, max_look_rects) },
	{ "--max-look-pieces", 0, INT32_MAX, offsetof(struct server_options, max_look_pieces) },
	{ "--max-retained-per-uid", 0, INT32_MAX,
	  offsetof(struct server_options, max_retained_per_uid) },
	{ "--max-retained", 0, INT32_MAX, offsetof(struct server_options, max_retained) },
	{ "--max-depth", 1, 4096, offsetof(struct server_options, max_depth) },
	{ "--max-subscriptions", 1, 1000000, offsetof(struct server_options, max_subs) },
	{ "--max-pending", 65536, 1u << 30, offsetof(struct server_options, max_pending) },
	{ "--live-from", 0, INT32_MAX, offsetof(struct server_options, live_from) },
};

static const struct number_option *find_number_option(const char *name)
{
	for (size_t i = 0; i < sizeof number_options / sizeof number_options[0]; i++)
		if (strcmp(name, number_options[i].name) == 0)
			return &number_options[i];
	return NULL;
}

/*
 * After an option error's one line: the usage line and where the rest is, not the whole --help
 * (forty lines of limits would bury the one that says what was wrong).
 */
static void short_usage(void)
{
	fprintf(stderr, "%.*s(visd --help lists every option)\n",
		(int)(strchr(usage_text, '\n') - usage_text + 1), usage_text);
}

static int usage_error(const char *fmt, const char *arg)
{
	fprintf(stderr, "visd: ");
	fprintf(stderr, fmt, arg);
	fputc('\n', stderr);
	short_usage();
	return 2;
}

/* Parses "WxH" with both in 1 … INT32_MAX. Returns 0, -1 (not WxH) or -2 (a side out of range). */
static int parse_size(const char *s, int32_t *w, int32_t *h)
{
	char *end;
	errno = 0;
	long a = strtol(s, &end, 10);
	if (errno == ERANGE && end != s && *end == 'x' && isdigit((unsigned char)*s))
		a = -1; /* too large: range, not syntax */
	else if (errno || end == s || *end != 'x' || !isdigit((unsigned char)*s))
		return -1;
	const char *t = end + 1;
	errno = 0;
	long b = strtol(t, &end, 10);
	if (end == t || *end || !isdigit((unsigned char)*t) || (errno && errno != ERANGE))
		return -1;
	if (errno == ERANGE || a < 1 || a > INT32_MAX || b < 1 || b > INT32_MAX)
		return -2;
	*w = (int32_t)a;
	*h = (int32_t)b;
	return 0;
}

/*
 * Takes PATH.lock with flock before anything touches PATH, so a stale socket is removed only when
 * no other daemon holds it. Returns the lock's fd, or -1 after logging why.
 */
static int take_lock(const char *path, char *lock_path, size_t len)
{
	if ((size_t)snprintf(lock_path, len, "%s.lock", path) >= len) {
		log_error("socket path '%s' is too long", path);
		return -1;
	}
	int fd = open(lock_path, O_RDWR | O_CREAT | O_CLOEXEC, 0600);
	if (fd < 0) {
		log_error("cannot open lock file '%s': %s", lock_path, strerror(errno));
		return -1;
	}
	if (flock(fd, LOCK_EX | LOCK_NB) < 0) {
		log_error(errno == EWOULDBLOCK ? "another visd is serving '%s' (its lock is held)"
					       : "cannot lock '%s'",
			  path);
		close(fd);
		return -1;
	}
	return fd;
}

/*
 * Refuses a socket directory where another user could replace the socket: one that others may
 * write to without the sticky bit, or owned by someone else than us or root.
 */
static int check_socket_dir(const char *path)
{
	char dir[PATH_MAX];
	const char *slash = strrchr(path, '/');
	if (!slash)
		strcpy(dir, ".");
	else if (slash == path)
		strcpy(dir, "/");
	else if ((size_t)(slash - path) < sizeof dir)
		snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
	else
		return 0; /* too long: binding will say so */
	struct stat st;
	if (stat(dir, &st) < 0) {
		log_error("socket directory '%s': %s", dir, strerror(errno));
		return -1;
	}
	if (!S_ISDIR(st.st_mode)) {
		log_error("socket directory '%s' is not a directory", dir);
		return -1;
	}
	if (st.st_uid != getuid() && st.st_uid != 0) {
		log_error("socket directory '%s' belongs to uid %u, not to us (uid %u)", dir,
			  (unsigned)st.st_uid, (unsigned)getuid());
		return -1;
	}
	if ((st.st_mode & (S_IWGRP | S_IWOTH)) && !(st.st_mode & S_ISVTX)) {
		log_error("socket directory '%s' (mode %04o) lets other users replace the socket; "
			  "use a private directory such as $XDG_RUNTIME_DIR",
			  dir, (unsigned)(st.st_mode & 07777));
		return -1;
	}
	return 0;
}

/* A socket's lock, PATH.lock, held while visd serves PATH; fd -1 when there is none to hold. */
struct socket_lock {
	int fd;
	char path[PATH_MAX + 8];
};

/*
 * Checks the directory of a socket's file and takes its lock. A NULL file (no socket, or a passed
 * one that has no file: abstract or unnamed) needs no lock. Returns 0, or -1 after logging why.
 */
static int lock_socket(const char *file, struct socket_lock *lock)
{
	lock->fd = -1;
	lock->path[0] = '\0';
	if (!file)
		return 0;
	if (check_socket_dir(file) < 0)
		return -1;
	lock->fd = take_lock(file, lock->path, sizeof lock->path);
	return lock->fd < 0 ? -1 : 0;
}

/* Releases a lock lock_socket() took, removing its file. */
static void unlock_socket(struct socket_lock *lock)
{
	if (lock->fd >= 0) {
		unlink(lock->path);
		close(lock->fd);
	}
}

/*
 * Whether the path an option gave (NULL: none) names the socket s that was passed. A passed
 * socket is where the service manager put it, so an option that says otherwise is a mistake in
 * the set-up, refused rather than guessed about. Logs why not.
 */
static bool same_socket(const char *path, const struct activation_socket *s, const char *option)
{
	struct stat a, b;
	if (!path || strcmp(path, s->path) == 0)
		return true;
	if (s->path[0] && stat(path, &a) == 0 && stat(s->path, &b) == 0 && a.st_dev == b.st_dev &&
	    a.st_ino == b.st_ino)
		return true;
	log_error("%s %s, but the socket passed (fd %d) is %s: under socket activation, leave the "
		  "option out or name the same socket", option, path, s->fd, s->name);
	return false;
}

/*
 * Serves the sockets passed instead of binding: the main one, and the restricted one if it came
 * too (else --restricted-socket, if given, is bound as usual). Returns 0, or -1 after logging why.
 */
static int adopt_passed(struct server_options *opt, const struct activation *act)
{
	if (!same_socket(opt->socket_path, &act->main, "--socket") ||
	    (act->restricted.fd >= 0 &&
	     !same_socket(opt->restricted_path, &act->restricted, "--restricted-socket")))
		return -1;
	opt->socket_fd = act->main.fd;
	opt->socket_path = act->main.name;
	if (act->restricted.fd >= 0) {
		opt->restricted_fd = act->restricted.fd;
		opt->restricted_path = act->restricted.name;
	}
	return 0;
}

/*
 * Raises the descriptor limit as far as the clients need and the hard limit allows, and lowers
 * max_clients to what the descriptors left can serve. The owner's reserve then shrinks to half of
 * that at most, so that other uids keep some slots and the owner some of its own; the per-uid and
 * restricted bounds stay, as the slots left to others bound them anyway.
 */
static void fit_descriptors(struct server_options *opt)
{
	const rlim_t spare = 32; /* listeners, the lock, the event loop, the reserve, logs */
	struct rlimit rl;
	if (getrlimit(RLIMIT_NOFILE, &rl) < 0)
		return;
	rlim_t want = (rlim_t)opt->max_clients + spare;
	if (rl.rlim_cur < want) {
		rl.rlim_cur = rl.rlim_max == RLIM_INFINITY || rl.rlim_max > want ? want : rl.rlim_max;
		setrlimit(RLIMIT_NOFILE, &rl);
		getrlimit(RLIMIT_NOFILE, &rl);
	}
	if (rl.rlim_cur < want) {
		uint32_t fit = rl.rlim_cur > spare + 1 ? (uint32_t)(rl.rlim_cur - spare) : 1;
		log_warn("only %llu file descriptors (ulimit -n): serving at most %u clients, not %u",
			 (unsigned long long)rl.rlim_cur, fit, opt->max_clients);
		opt->max_clients = fit;
		if (opt->owner_reserve > fit / 2) {
			log_warn("keeping %u of them for the daemon's uid, not %u (--owner-reserve)",
				 fit / 2, opt->owner_reserve);
			opt->owner_reserve = fit / 2;
		}
	}
}

/*
 * The event loop. With epoll's change list, an event disabled and enabled again within one turn
 * (reading stopped and resumed, write interest armed and dropped) costs no epoll_ctl calls.
 */
static struct event_base *new_event_base(void)
{
	struct event_config *cfg = event_config_new();
	if (!cfg)
		return NULL;
	event_config_set_flag(cfg, EVENT_BASE_FLAG_EPOLL_USE_CHANGELIST);
	struct event_base *base = event_base_new_with_config(cfg);
	event_config_free(cfg);
	return base;
}

/*
 * A random key for the window IDs' permutation, so that a client's IDs say nothing of the windows
 * others created. Without the kernel's randomness (no getrandom), the clock and the pid: the IDs
 * are then still unique, only easier to guess.
 */
static uint64_t id_key(void)
{
	uint64_t key = 0;
	ssize_t got;
	while ((got = getrandom(&key, sizeof key, 0)) < 0 && errno == EINTR)
		;
	if (got != (ssize_t)sizeof key) {
		struct timespec t;
		clock_gettime(CLOCK_REALTIME, &t);
		log_warn("getrandom: %s: window IDs keyed by the clock",
			 got < 0 ? strerror(errno) : "short read");
		key = ((uint64_t)t.tv_sec << 32 ^ (uint64_t)t.tv_nsec ^ (uint64_t)getpid() << 16);
	}
	return key ? key : 1; /* 0 would keep IDs sequential */
}

static void on_signal(evutil_socket_t sig, short what, void *data)
{
	(void)what;
	log_info("%s: shutting down", strsignal((int)sig));
	event_base_loopexit(data, NULL);
}

int main(int argc, char **argv)
{
	struct server_options opt = {
		.screen_width = 3840,
		.screen_height = 2160,
		.max_request = 65536,
		.max_batch = 16u << 20,
		.max_clients = 1024,
		.owner_reserve = UINT32_MAX, /* unless given: 32, at most half of max_clients */
		.max_clients_per_uid = 256,
		.max_restricted_clients = 256,
		.hello_timeout = 10,
		.max_windows = 262144,
		.max_look_rects = 1048576,
		.max_look_pieces = 16384,
		.max_retained_per_uid = 262144,
		.max_retained = 1048576,
		.max_depth = 64,
		.max_subs = 1024,
		.max_pending = 4u << 20,
		.live_from = 0,
		.allowed_uid = getuid(),
		.socket_fd = -1,
		.restricted_fd = -1,
	};
	char default_path[PATH_MAX];
	bool id_key_given = false;
	for (int i = 1; i < argc; i++) {
		const char *a = argv[i];
		const char *val = i + 1 < argc ? argv[i + 1] : NULL;
		if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
			fputs(usage_text, stdout);
			return 0;
		} else if (strcmp(a, "--version") == 0) {
			printf("visd %s (protocol %u)\n", VIS_VERSION, VIS_PROTOCOL_VERSION);
			return 0;
		} else if (strcmp(a, "-v") == 0) {
			log_set_level(LOG_DEBUG);
			continue;
		}
		const struct number_option *num = find_number_option(a);
		if (!num && strcmp(a, "--socket") && strcmp(a, "--screen") &&
		    strcmp(a, "--restricted-socket") && strcmp(a, "--id-key"))
			return usage_error("unknown option '%s'", a);
		if (!val || !*val)
			return usage_error("%s needs a value", a);
		i++;
		if (num) {
			char *end;
			errno = 0;
			unsigned long n = strtoul(val, &end, 10);
			if (errno || *end || !isdigit((unsigned char)*val) || n < num->min ||
			    n > num->max) {
				fprintf(stderr, "visd: %s '%s': want a number from %lu to %lu\n", a,
					val, num->min, num->max);
				short_usage();
				return 2;
			}
			*(uint32_t *)((char *)&opt + num->offset) = (uint32_t)n;
		} else if (strcmp(a, "--socket") == 0) {
			opt.socket_path = val;
		} else if (strcmp(a, "--restricted-socket") == 0) {
			opt.restricted_path = val;
		} else if (strcmp(a, "--id-key") == 0) {
			char *end;
			errno = 0;
			opt.id_key = strtoull(val, &end, 0);
			if (errno || *end || !isdigit((unsigned char)*val))
				return usage_error("--id-key '%s': want a number below 2^64", val);
			id_key_given = true;
		} else {
			int r = parse_size(val, &opt.screen_width, &opt.screen_height);
			if (r == -2)
				return usage_error("--screen '%s': width and height must each be 1 to "
						   "2147483647 (WxH, e.g. 1920x1080)",
						   val);
			if (r < 0)
				return usage_error("--screen '%s': want WxH, e.g. 1920x1080", val);
		}
	}
	/* Before anything opens a descriptor: those passed start at fd 3. */
	struct activation act;
	int activated = activation_take(&act);
	if (activated < 0 || (activated && adopt_passed(&opt, &act) < 0))
		return 1;
	if (!opt.socket_path) {
		const char *env = getenv("VISD_SOCKET"), *dir = getenv("XDG_RUNTIME_DIR");
		if (env && *env)
			opt.socket_path = env;
		else if (dir && *dir) {
			snprintf(default_path, sizeof default_path, "%s/visd-0", dir);
			opt.socket_path = default_path;
		} else {
			fprintf(stderr, "visd: no socket path: pass --socket PATH, or set VISD_SOCKET "
					"or XDG_RUNTIME_DIR\n");
			return 2;
		}
	}

	if (opt.owner_reserve == UINT32_MAX)
		opt.owner_reserve = opt.max_clients / 2 < 32 ? opt.max_clients / 2 : 32;
	else if (opt.owner_reserve >= opt.max_clients) {
		fprintf(stderr, "visd: --owner-reserve %u leaves no slot for others: it must be below "
				"--max-clients (%u)\n",
			opt.owner_reserve, opt.max_clients);
		short_usage();
		return 2;
	}
	fit_descriptors(&opt);
	signal(SIGPIPE, SIG_IGN);
	umask(077); /* the socket and its lock: the owner's only */
	/*
	 * The files to lock: the sockets visd binds, and those passed that are in the file system, so
	 * that a second daemon on the same path refuses to start, activated or not.
	 */
	const char *main_file = opt.socket_fd < 0 ? opt.socket_path
				: act.main.path[0] ? act.main.path : NULL;
	const char *restricted_file = opt.restricted_fd < 0 ? opt.restricted_path
				      : act.restricted.path[0] ? act.restricted.path : NULL;
	struct socket_lock lock, rlock;
	if (lock_socket(main_file, &lock) < 0)
		return 1;
	if (lock_socket(restricted_file, &rlock) < 0) {
		unlock_socket(&lock);
		return 1;
	}
	struct event_base *base = new_event_base();
	struct server server;
	int status = 1;
	if (!base) {
		log_error("cannot create the event loop");
		goto out;
	}
	struct event *sigint = evsignal_new(base, SIGINT, on_signal, base);
	struct event *sigterm = evsignal_new(base, SIGTERM, on_signal, base);
	if (!sigint || !sigterm || evsignal_add(sigint, NULL) < 0 || evsignal_add(sigterm, NULL) < 0) {
		log_error("cannot handle signals");
		goto out_base;
	}
	if (!id_key_given)
		opt.id_key = id_key();
	if (server_init(&server, base, &opt) == 0) {
		const char *passed = " (socket activation)";
		log_info("listening on %s%s (screen %dx%d)%s%s%s", opt.socket_path,
			 opt.socket_fd >= 0 ? passed : "", opt.screen_width, opt.screen_height,
			 opt.restricted_path ? ", restricted " : "",
			 opt.restricted_path ? opt.restricted_path : "",
			 opt.restricted_fd >= 0 ? passed : "");
		status = event_base_dispatch(base) < 0 ? 1 : 0;
	}
	server_finish(&server);
	/* A passed socket's file is the service manager's: it stays, to start visd again. */
	if (opt.socket_fd < 0)
		unlink(opt.socket_path);
	if (opt.restricted_path && opt.restricted_fd < 0)
		unlink(opt.restricted_path);
out_base:
	if (sigint)
		event_free(sigint);
	if (sigterm)
		event_free(sigterm);
	event_base_free(base);
out:
	unlock_socket(&lock);
	unlock_socket(&rlock);
	return status;
}
