/* The raw-bytes test harness: a private visd, connections, decoded messages, clean shutdown. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "harness.h"
#include "progress.h"
#include "vis/protocol.h"
#include "wire.h"

static struct harness_daemon *running[8];
static pid_t owner; /* the process that started them: forked children must leave them alone */
static char context[200] = "start";
static uint64_t seed;
static int errors_checked;

/* The last bytes of a daemon's log, on stderr. */
static void print_log_tail(const struct harness_daemon *d)
{
	FILE *f = fopen(d->log, "r");
	if (!f)
		return;
	fseek(f, 0, SEEK_END);
	long size = ftell(f);
	fseek(f, size > 4096 ? size - 4096 : 0, SEEK_SET);
	fprintf(stderr, "--- the end of %s:\n", d->log);
	char buf[4096];
	size_t n;
	while ((n = fread(buf, 1, sizeof buf, f)) > 0)
		fwrite(buf, 1, n, stderr);
	fprintf(stderr, "---\n");
	fclose(f);
}

void harness_fail(const char *file, int line, const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	fprintf(stderr, "%s:%d: %s: ", file, line, context);
	vfprintf(stderr, fmt, ap);
	fputc('\n', stderr);
	va_end(ap);
	if (seed)
		fprintf(stderr, "seed %llu\n", (unsigned long long)seed);
	if (getpid() != owner)
		_exit(1);
	for (size_t i = 0; i < sizeof running / sizeof *running; i++) {
		if (!running[i])
			continue;
		kill(running[i]->pid, SIGKILL);
		waitpid(running[i]->pid, NULL, 0);
		print_log_tail(running[i]);
	}
	exit(1);
}

void harness_context(const char *fmt, ...)
{
	va_list ap;
	va_start(ap, fmt);
	vsnprintf(context, sizeof context, fmt, ap);
	va_end(ap);
}

void harness_seed(uint64_t s)
{
	seed = s;
}

static void sleep_ms(int ms)
{
	struct timespec t = { ms / 1000, (long)(ms % 1000) * 1000000 };
	nanosleep(&t, NULL);
}

struct progress harness_working(const struct harness_daemon *d)
{
	pid_t pids[PROGRESS_MAX_PIDS];
	size_t n = 0;
	for (size_t i = 0; i < sizeof running / sizeof *running && n < PROGRESS_MAX_PIDS; i++)
		if (running[i] && (!d || running[i] == d))
			pids[n++] = running[i]->pid;
	if (d && !n)
		pids[n++] = d->pid;
	struct progress p;
	progress_begin(&p, pids, n);
	return p;
}

/* Fails, saying what was waited for, when the daemons of the wait died or stopped working. */
static void check_working(struct progress *p, const char *what)
{
	for (size_t i = 0; i < sizeof running / sizeof *running; i++)
		for (size_t k = 0; k < p->n; k++)
			if (running[i] && running[i]->pid == p->pid[k])
				harness_check_alive(running[i]);
	if (progress_stopped(p))
		harness_fail(__FILE__, __LINE__, "%s: %s", what, p->why);
}

void harness_still_working(struct progress *p, const char *what)
{
	check_working(p, what);
	sleep_ms(10);
}

void harness_start(struct harness_daemon *d, const char *visd, const char *const *extra)
{
	snprintf(d->dir, sizeof d->dir, "/tmp/visd-harness-XXXXXX");
	CHECK(mkdtemp(d->dir), "mkdtemp: %s", strerror(errno));
	snprintf(d->sock, sizeof d->sock, "%s/sock", d->dir);
	snprintf(d->rsock, sizeof d->rsock, "%s/restricted", d->dir);
	snprintf(d->log, sizeof d->log, "%s/stderr", d->dir);
	/* Recomputes go live even on the tests' small trees, as on large desktops. */
	const char *argv[32] = { visd, "--socket", d->sock, "--restricted-socket", d->rsock,
				 "--live-from", "0" };
	size_t argc = 7;
	for (size_t i = 0; extra && extra[i]; i++) {
		CHECK(argc + 1 < sizeof argv / sizeof *argv, "too many options");
		argv[argc++] = extra[i];
	}
	argv[argc] = NULL;
	int log = open(d->log, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
	CHECK(log >= 0, "%s: %s", d->log, strerror(errno));
	fflush(NULL);
	owner = getpid();
	d->pid = fork();
	CHECK(d->pid >= 0, "fork: %s", strerror(errno));
	if (d->pid == 0) {
		/* Nothing on our stdout, and no daemon left behind if the test dies. */
		if (dup2(log, 1) < 0 || dup2(log, 2) < 0 || prctl(PR_SET_PDEATHSIG, SIGKILL) < 0)
			_exit(127);
		closefrom(3); /* connections the test holds must not outlive it in the daemon */
		struct rlimit rl = { (rlim_t)d->nofile, (rlim_t)d->nofile };
		if (d->nofile && setrlimit(RLIMIT_NOFILE, &rl) < 0)
			_exit(127);
		execv(visd, (char *const *)argv);
		perror(visd);
		_exit(127);
	}
	close(log);
	for (size_t i = 0;; i++) {
		CHECK(i < sizeof running / sizeof *running, "too many daemons");
		if (!running[i]) {
			running[i] = d;
			break;
		}
	}
	for (struct progress p = harness_working(d);
	     access(d->sock, F_OK) < 0 || access(d->rsock, F_OK) < 0;)
		harness_still_working(&p, "visd did not create its sockets");
}

/* Fails when the log holds a sanitizer's report. */
static void check_log(const struct harness_daemon *d)
{
	static const char *const reports[] = { "ERROR: AddressSanitizer", "ERROR: LeakSanitizer",
					       "runtime error:" };
	FILE *f = fopen(d->log, "r");
	CHECK(f, "cannot read %s: %s", d->log, strerror(errno));
	char line[4096];
	while (fgets(line, sizeof line, f))
		for (size_t i = 0; i < sizeof reports / sizeof *reports; i++)
			if (strstr(line, reports[i])) {
				fclose(f);
				harness_fail(__FILE__, __LINE__,
					     "visd's stderr has a sanitizer report: %s", line);
			}
	fclose(f);
}

void harness_check_alive(struct harness_daemon *d)
{
	int status;
	pid_t r = waitpid(d->pid, &status, WNOHANG);
	if (r == d->pid) {
		for (size_t i = 0; i < sizeof running / sizeof *running; i++)
			if (running[i] == d)
				running[i] = NULL;
		print_log_tail(d);
		harness_fail(__FILE__, __LINE__, "visd is gone (status %#x)", status);
	}
	check_log(d);
}

void harness_stop(struct harness_daemon *d)
{
	harness_check_alive(d);
	kill(d->pid, SIGTERM);
	int status = 0;
	pid_t r = 0;
	/* The exit may take a while: the leak check of a sanitizer build runs then. */
	struct progress p = harness_working(d);
	while ((r = waitpid(d->pid, &status, WNOHANG)) == 0) {
		/* Gone since waitpid looked is what was awaited, not a failure. */
		if (progress_stopped(&p) && (r = waitpid(d->pid, &status, WNOHANG)) == 0)
			harness_fail(__FILE__, __LINE__, "visd did not exit after SIGTERM: %s",
				     p.why);
		if (r)
			break;
		sleep_ms(10);
	}
	CHECK(r == d->pid, "waitpid: %s", strerror(errno));
	for (size_t i = 0; i < sizeof running / sizeof *running; i++)
		if (running[i] == d)
			running[i] = NULL;
	if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
		print_log_tail(d);
		harness_fail(__FILE__, __LINE__, "visd exited with status %#x", status);
	}
	check_log(d);
	char lock[128];
	snprintf(lock, sizeof lock, "%s.lock", d->sock);
	CHECK(access(d->sock, F_OK) < 0 && access(d->rsock, F_OK) < 0 && access(lock, F_OK) < 0,
	      "visd left its sockets or lock behind");
	unlink(d->log);
	CHECK(rmdir(d->dir) == 0, "rmdir %s: %s", d->dir, strerror(errno));
}

int harness_count_fds(const struct harness_daemon *d)
{
	char path[64];
	snprintf(path, sizeof path, "/proc/%d/fd", (int)d->pid);
	DIR *dir = opendir(path);
	if (!dir)
		return -1;
	int n = 0;
	for (struct dirent *e; (e = readdir(dir));)
		n += e->d_name[0] != '.';
	closedir(dir);
	return n;
}

void harness_wait_fds(const struct harness_daemon *d, int want)
{
	struct progress p = harness_working(d);
	for (int n; (n = harness_count_fds(d)) != want;) {
		if (progress_stopped(&p))
			harness_fail(__FILE__, __LINE__, "visd holds %d descriptors, wanted %d: %s",
				     n, want, p.why);
		sleep_ms(10);
	}
}

int harness_connect(const char *path)
{
	struct sockaddr_un addr = { .sun_family = AF_UNIX };
	if (strlen(path) >= sizeof addr.sun_path) {
		errno = ENAMETOOLONG;
		return -1;
	}
	strcpy(addr.sun_path, path);
	int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
	if (fd < 0)
		return -1;
	if (connect(fd, (struct sockaddr *)&addr, sizeof addr) < 0) {
		int e = errno;
		close(fd);
		errno = e;
		return -1;
	}
	return fd;
}

void harness_open(struct harness_conn *c, const char *path)
{
	memset(c, 0, sizeof *c);
	c->fd = harness_connect(path);
	CHECK(c->fd >= 0, "connect to %s: %s", path, strerror(errno));
	vis_buf_init(&c->in);
}

void harness_open_as(struct harness_conn *c, const char *path, int role)
{
	harness_open(c, path);
	if (role >= 0)
		harness_hello(c, (uint32_t)role);
}

void harness_close(struct harness_conn *c)
{
	if (c->fd >= 0)
		close(c->fd);
	c->fd = -1;
	vis_buf_finish(&c->in);
}

int harness_send(struct harness_conn *c, const void *p, size_t n)
{
	const uint8_t *b = p;
	while (n) {
		ssize_t w = send(c->fd, b, n, MSG_NOSIGNAL);
		if (w < 0 && errno == EINTR)
			continue;
		if (w < 0)
			return -1;
		b += w;
		n -= (size_t)w;
	}
	return 0;
}

size_t harness_build(uint8_t *out, uint32_t opcode, const uint32_t *words, size_t n)
{
	size_t size = VIS_MSG_HEADER + 4 * n;
	vis_wire_put_u32(out, (uint32_t)size);
	vis_wire_put_u16(out + 4, (uint16_t)opcode);
	vis_wire_put_u16(out + 6, 0);
	for (size_t i = 0; i < n; i++)
		vis_wire_put_u32(out + VIS_MSG_HEADER + 4 * i, words[i]);
	return size;
}

uint32_t harness_request_raw(struct harness_conn *c, const void *p, size_t n)
{
	CHECK(harness_send(c, p, n) == 0, "send: %s", strerror(errno));
	return ++c->seq;
}

uint32_t harness_request(struct harness_conn *c, uint32_t opcode, const uint32_t *words, size_t n)
{
	uint8_t b[VIS_MSG_HEADER + 4 * VIS_MSG_MAX_ARGS];
	CHECK(n <= VIS_MSG_MAX_ARGS, "a request of %zu words", n);
	return harness_request_raw(c, b, harness_build(b, opcode, words, n));
}

/* Milliseconds on the monotonic clock. */
static long long now_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (long long)t.tv_sec * 1000 + t.tv_nsec / 1000000;
}

double harness_clock_ms(void)
{
	struct timespec t;
	clock_gettime(CLOCK_MONOTONIC, &t);
	return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

void harness_send_copies(struct harness_conn *c, const void *req, size_t size, uint32_t n)
{
	enum { PER = 4096 };
	uint8_t *b = malloc(PER * size);
	CHECK(b, "out of memory");
	for (size_t i = 0; i < PER; i++)
		memcpy(b + i * size, req, size);
	for (uint32_t sent = 0; sent < n;) {
		uint32_t k = n - sent < PER ? n - sent : PER;
		CHECK(harness_send(c, b, k * size) == 0, "send: %s", strerror(errno));
		sent += k;
		c->seq += k;
	}
	free(b);
}

void harness_create_many(struct harness_conn *c, uint32_t n, int32_t x, int32_t y)
{
	uint8_t create[VIS_MSG_HEADER + 40];
	harness_put(create, VIS_OP_CREATE, 0, (uint32_t)x, (uint32_t)y, 5, 5, 0, 0, 0, 0, 0);
	harness_send_copies(c, create, sizeof create, n);
	for (uint32_t i = 0; i < n; i++) {
		struct vis_msg m;
		harness_next_reply(c, &m, NULL);
		CHECK(m.type->opcode == VIS_OP_CREATED, "create %u of %u: %s", i + 1, n,
		      m.type->name);
	}
}

int harness_recv(struct harness_conn *c, int timeout_ms, struct vis_msg *m)
{
	vis_buf_consume(&c->in, c->taken);
	c->taken = 0;
	/* HARNESS_WORKING: slices of a second, after the first of which the daemons must be
	 * working (read from /proc only then: most messages come at once). */
	struct progress work;
	bool working = timeout_ms < 0, begun = false;
	long long deadline = now_ms() + (working ? 1000 : timeout_ms);
	for (;;) {
		char why[200];
		enum vis_decode r = vis_msg_decode(c->in.data, c->in.len, VIS_PROTOCOL_MAX_MESSAGE,
						   0, m, why, sizeof why);
		CHECK(r != VIS_DECODE_MALFORMED, "the daemon sent a malformed message: %s", why);
		if (r == VIS_DECODE_OK) {
			c->taken = m->size;
			return 1;
		}
		long long left = deadline - now_ms();
		struct pollfd p = { c->fd, POLLIN, 0 };
		int k = poll(&p, 1, left > 0 ? (int)left : 0);
		if (k < 0 && errno == EINTR)
			continue;
		CHECK(k >= 0, "poll: %s", strerror(errno));
		if (k == 0 && working) {
			if (!begun)
				work = harness_working(NULL);
			begun = true;
			check_working(&work, "no message from visd");
			deadline = now_ms() + 1000;
			continue;
		}
		if (k == 0)
			return -1;
		size_t at = c->in.len;
		CHECK(vis_buf_append(&c->in, NULL, 65536) == 0, "out of memory");
		ssize_t got = read(c->fd, c->in.data + at, 65536);
		c->in.len = at + (got > 0 ? (size_t)got : 0);
		if (got < 0 && errno == EINTR)
			continue;
		/* A daemon that closes with our bytes unread resets the connection after its data.
		 */
		if (got == 0 || (got < 0 && errno == ECONNRESET)) {
			CHECK(!c->in.len, "the connection ended inside a message (%zu bytes)",
			      c->in.len);
			return 0;
		}
		CHECK(got > 0, "read: %s", strerror(errno));
	}
}

void harness_next_reply(struct harness_conn *c, struct vis_msg *m, size_t *notices)
{
	for (;;) {
		int r = harness_recv(c, HARNESS_WORKING, m);
		CHECK(r > 0, "the daemon closed the connection (request %u was the last)", c->seq);
		if (m->type->dir != VIS_DIR_NOTICE)
			return;
		if (notices)
			++*notices;
		if (c->on_notice)
			c->on_notice(c->notice_data, m);
	}
}

/* Fails unless m is an error with these fields. */
static void check_error(const struct vis_msg *m, uint32_t seq, uint32_t opcode, uint32_t code,
			const char *reason)
{
	if (m->type->opcode != VIS_OP_ERROR)
		harness_fail(__FILE__, __LINE__,
			     "request %u: wanted error %u, got %s for request %u", seq, code,
			     m->type->name, m->args[0].u);
	const union vis_arg *a = m->args;
	char msg[300];
	errors_checked++;
	snprintf(msg, sizeof msg, "%.*s", (int)a[3].s.len, a[3].s.p);
	CHECK(a[0].u == seq && a[1].u == opcode && a[2].u == code && msg[0] &&
		      (!reason || strstr(msg, reason)),
	      "wanted error %u for request %u (opcode %u) saying '%s'; got error %u for request %u "
	      "(opcode %u): '%s'",
	      code, seq, opcode, reason ? reason : "", a[2].u, a[0].u, a[1].u, msg);
}

size_t harness_fields(const struct vis_msg_type *t, struct harness_field *f)
{
	size_t n = 0;
	for (const char *p = t->signature; *p && n < VIS_MSG_MAX_ARGS;) {
		p += strspn(p, " ");
		const char *colon = strchr(p, ':');
		if (!colon)
			break;
		size_t len = strcspn(colon + 1, " ");
		f[n].type = p[0] == 'a' ? p[1] : p[0];
		snprintf(f[n].name, sizeof f[n].name, "%.*s", (int)len, colon + 1);
		n++;
		p = colon + 1 + len;
	}
	return n;
}

void harness_expect(struct harness_conn *c, uint32_t seq, uint32_t opcode, struct vis_msg *m)
{
	harness_next_reply(c, m, NULL);
	if (m->type->opcode == VIS_OP_ERROR)
		harness_fail(__FILE__, __LINE__, "request %u: wanted %s, got error %u: %.*s", seq,
			     vis_msg_type_find(opcode)->name, m->args[2].u, (int)m->args[3].s.len,
			     m->args[3].s.p);
	CHECK(m->type->opcode == opcode && m->args[0].u == seq,
	      "request %u: wanted %s, got %s for request %u", seq, vis_msg_type_find(opcode)->name,
	      m->type->name, m->args[0].u);
}

void harness_expect_error(struct harness_conn *c, uint32_t seq, uint32_t opcode, uint32_t code,
			  const char *reason, bool fatal)
{
	struct vis_msg m;
	if (!fatal) {
		harness_next_reply(c, &m, NULL);
		check_error(&m, seq, opcode, code, reason);
		return;
	}
	/* Before the error: notices and replies to earlier requests; after it: the end. */
	bool seen = false;
	for (;;) {
		int r = harness_recv(c, HARNESS_WORKING, &m);
		if (r == 0)
			break;
		CHECK(!seen, "request %u: a %s after the fatal error", seq, m.type->name);
		if (m.type->dir == VIS_DIR_NOTICE)
			continue;
		if (m.type->opcode != VIS_OP_ERROR && m.args[0].u < seq)
			continue;
		check_error(&m, seq, opcode, code, reason);
		seen = true;
	}
	CHECK(seen, "request %u: the connection ended without an error", seq);
}

void harness_expect_fatal(const char *path, const void *bytes, size_t n, int role, uint32_t opcode,
			  uint32_t code, const char *reason)
{
	struct harness_conn c;
	harness_open_as(&c, path, role);
	uint32_t seq = harness_request_raw(&c, bytes, n);
	harness_expect_error(&c, seq, opcode, code, reason, true);
	harness_close(&c);
}

int harness_errors_checked(void)
{
	return errors_checked;
}

void harness_sync(struct harness_conn *c, size_t *notices)
{
	struct vis_msg m;
	uint32_t seq = harness_req(c, VIS_OP_SYNC);
	harness_next_reply(c, &m, notices);
	CHECK(m.type->opcode == VIS_OP_SYNCED && m.args[0].u == seq,
	      "sync %u: got %s for request %u", seq, m.type->name, m.args[0].u);
}

void harness_hello(struct harness_conn *c, uint32_t role)
{
	struct vis_msg m;
	uint32_t seq = harness_req(c, VIS_OP_HELLO, VIS_PROTOCOL_MAGIC, VIS_PROTOCOL_VERSION, role);
	harness_expect(c, seq, VIS_OP_HELLO_REPLY, &m);
	CHECK(m.args[1].u == VIS_PROTOCOL_VERSION && m.args[3].u == role,
	      "hello-reply: version %u, role %u", m.args[1].u, m.args[3].u);
	c->id = m.args[2].u;
	c->max_request = m.args[6].u;
}

uint32_t harness_look(struct harness_conn *c, uint32_t op, uint32_t window, uint32_t mode,
		      const uint32_t *rects, uint32_t n)
{
	size_t words_n = 3 + 4 * (size_t)n;
	uint32_t *words = malloc(words_n * sizeof *words);
	uint8_t *b = malloc(VIS_MSG_HEADER + 4 * words_n);
	CHECK(words && b, "out of memory");
	words[0] = window;
	words[1] = mode;
	words[2] = n;
	if (n)
		memcpy(words + 3, rects, 16 * (size_t)n);
	uint32_t seq = harness_request_raw(c, b, harness_build(b, op, words, words_n));
	free(words);
	free(b);
	return seq;
}

uint32_t harness_create(struct harness_conn *c, uint32_t parent, int32_t x, int32_t y, uint32_t w,
			uint32_t h, uint32_t flags)
{
	struct vis_msg m;
	uint32_t seq = harness_req(c, VIS_OP_CREATE, parent, (uint32_t)x, (uint32_t)y, w, h, flags, 0, 0, 0, 0);
	harness_expect(c, seq, VIS_OP_CREATED, &m);
	return m.args[1].u;
}

/*
 * Sends a query without arguments and gathers the records of its list reply, whose array is the
 * third field (the second is more): host-order words, malloc'd; *n records.
 */
static uint32_t *gather(struct harness_conn *c, uint32_t request, uint32_t reply, char record,
			size_t *n)
{
	uint32_t seq = harness_request(c, request, NULL, 0);
	uint32_t words = vis_msg_record_words(record), *v = NULL;
	size_t count = 0;
	for (bool more = true; more;) {
		struct vis_msg m;
		harness_expect(c, seq, reply, &m);
		const union vis_arg *a = &m.args[2];
		uint32_t *grown = realloc(v, (count + a->a.n + 1) * words * sizeof *v);
		CHECK(grown, "out of memory");
		v = grown;
		for (uint32_t i = 0; i < a->a.n; i++, count++)
			for (uint32_t k = 0; k < words; k++)
				v[count * words + k] = vis_arg_word(a, record, i, k);
		more = m.args[1].u;
	}
	*n = count;
	return v;
}

struct harness_node *harness_get_tree(struct harness_conn *c, size_t *n)
{
	uint32_t *w = gather(c, VIS_OP_GET_TREE, VIS_OP_TREE, 'T', n);
	struct harness_node *v = malloc((*n + 1) * sizeof *v);
	CHECK(v, "out of memory");
	for (size_t i = 0; i < *n; i++) {
		const uint32_t *r = w + 12 * i;
		v[i] = (struct harness_node){ r[0], r[1], (int32_t)r[2], (int32_t)r[3], r[4],
					      r[5], r[6], r[7], r[8] };
	}
	free(w);
	return v;
}

struct harness_state *harness_get_states(struct harness_conn *c, size_t *n)
{
	uint32_t *w = gather(c, VIS_OP_GET_STATES, VIS_OP_STATES, 'S', n);
	struct harness_state *v = malloc((*n + 1) * sizeof *v);
	CHECK(v, "out of memory");
	for (size_t i = 0; i < *n; i++)
		v[i] = (struct harness_state){ w[2 * i], w[2 * i + 1] };
	free(w);
	return v;
}
