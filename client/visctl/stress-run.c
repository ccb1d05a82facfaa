/*
 * visctl stress's run: the manager's connection and the desktop it creates, the subscribers and
 * their first view, then (after stress-loop.c's operations) the measures of the daemon from /proc,
 * the final check against the model, and the windows destroyed again.
 */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "gen.h"
#include "proc-cpu.h"
#include "stress.h"
#include "visctl.h"

#define NS UINT64_C(1000000000)
/* Windows created per batch while setting up, so that no batch nears the daemon's 16 MiB. */
#define SETUP_CHUNK 65536
/* Mismatches printed before only counting them. */
#define REPORT_LIMIT 10
/* How long the manager role is waited for. */
#define MANAGER_WAIT_NS (2 * NS)

int stress_run_lost(struct vis_client *c, const char *who)
{
	fprintf(stderr, "visctl stress: %s: %s\n", who, vis_client_error_message(c));
	return -1;
}

/* visd's resident memory now and at its peak, in KiB, from /proc/PID/status (-1: unreadable). */
static void daemon_memory(pid_t pid, long *rss, long *hwm)
{
	char path[64], line[256];
	*rss = *hwm = -1;
	snprintf(path, sizeof(path), "/proc/%d/status", (int)pid);
	FILE *f = pid > 0 ? fopen(path, "r") : NULL;
	if (!f)
		return;
	while (fgets(line, sizeof(line), f)) {
		if (strncmp(line, "VmRSS:", 6) == 0)
			*rss = strtol(line + 6, NULL, 10);
		else if (strncmp(line, "VmHWM:", 6) == 0)
			*hwm = strtol(line + 6, NULL, 10);
	}
	fclose(f);
}

/* This process's CPU time in seconds. */
static double self_cpu(void)
{
	struct rusage ru;
	getrusage(RUSAGE_SELF, &ru);
	return (double)ru.ru_utime.tv_sec + (double)ru.ru_utime.tv_usec / 1e6 +
	       (double)ru.ru_stime.tv_sec + (double)ru.ru_stime.tv_usec / 1e6;
}

/* A process's name (/proc/PID/comm) into name; false when there is no such process. */
static bool process_name(pid_t pid, char *name, size_t len)
{
	char path[64];
	snprintf(path, sizeof(path), "/proc/%d/comm", (int)pid);
	FILE *f = pid > 0 ? fopen(path, "r") : NULL;
	if (!f)
		return false;
	bool ok = fgets(name, (int)len, f) != NULL;
	fclose(f);
	if (ok)
		name[strcspn(name, "\n")] = '\0';
	return ok;
}

/*
 * Checks --pid: a running visd, and not another visd than the one serving the socket (the
 * socket's peer, unless a service manager listens for visd). 0, or -1 after saying why.
 */
static int check_pid(pid_t pid, pid_t peer)
{
	char name[64], peer_name[64];
	if (!process_name(pid, name, sizeof(name))) {
		fprintf(stderr, "visctl stress: --pid %d: no such process\n", (int)pid);
		return -1;
	}
	if (strcmp(name, "visd") != 0) {
		fprintf(stderr, "visctl stress: --pid %d is '%s', not visd\n", (int)pid, name);
		return -1;
	}
	if (peer > 0 && peer != pid && process_name(peer, peer_name, sizeof(peer_name)) &&
	    strcmp(peer_name, "visd") == 0) {
		fprintf(stderr, "visctl stress: --pid %d is not the visd serving the socket (%d is)\n",
			(int)pid, (int)peer);
		return -1;
	}
	return 0;
}

/*
 * Connects with a role; NULL after saying why (and what the run needs) on stderr. The manager
 * role is waited for a while: the daemon may not yet have seen a previous run's manager go.
 */
static struct vis_client *open_connection(const struct stress_options *o, uint32_t role)
{
	struct vis_client *c;
	int err;
	for (uint64_t t0 = stress_loop_now();;) {
		if (!(c = vis_client_connect(o->socket, role))) {
			fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
			return NULL;
		}
		if (!(err = vis_client_error(c)))
			return c;
		if (err != EBUSY || stress_loop_now() - t0 > MANAGER_WAIT_NS)
			break;
		vis_client_destroy(c);
		nanosleep(&(struct timespec){ 0, 20000000 }, NULL);
	}
	fprintf(stderr, "visctl stress: %s\n", vis_client_error_message(c));
	if (err == EBUSY)
		fprintf(stderr, "visctl stress: the run needs the manager role, which another "
				"connection holds\n");
	else if (err == EACCES)
		fprintf(stderr, "visctl stress: the run needs the manager and observer roles, which "
				"visd gives only to its own user\n");
	vis_client_destroy(c);
	return NULL;
}

/* Creates the scene's windows, mapped, in batches; the model learns their IDs. 0, or -1. */
static int create_windows(struct stress *s, const struct vis_scene *scene)
{
	uint32_t *ids = malloc((scene->n ? scene->n : 1) * sizeof(*ids));
	int ret = -1;
	if (!ids) {
		fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
		return -1;
	}
	for (size_t i = 0; i < scene->n; i += SETUP_CHUNK) {
		struct vis_scene part = *scene;
		part.n = part.cap = scene->n - i < SETUP_CHUNK ? scene->n - i : SETUP_CHUNK;
		part.ids = scene->ids + i;
		part.rects = scene->rects + i;
		struct load ld = { .windows = ids + i };
		if (cmd_load_batch(s->mgr, &part, VIS_CREATE_MAP, &ld) == 0)
			continue;
		if (ld.failed && !vis_client_error(s->mgr))
			fprintf(stderr, "visctl stress: creating window %zu: %s: %s\n",
				i + ld.failed_at + 1, vis_error_code_name(ld.error.code),
				ld.error.message);
		else
			stress_run_lost(s->mgr, "creating the windows");
		goto out;
	}
	for (uint32_t k = 0; k < s->m.n; k++) {
		if (stress_model_set_id(&s->m, k, ids[k]) < 0) {
			fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
			goto out;
		}
		if (s->o->record)
			fprintf(s->o->record, "create %d %d %d %d --map\n", s->m.w[k].r.x,
				s->m.w[k].r.y, s->m.w[k].r.w, s->m.w[k].r.h);
	}
	ret = 0;
out:
	free(ids);
	return ret;
}

/*
 * Destroys the run's windows and waits until they are gone, so that the daemon is left as the
 * run found it when visctl exits (it would destroy them itself, but later: a next run could come
 * first). 0, or -1 after saying why.
 */
static int destroy_windows(struct stress *s)
{
	if (vis_client_error(s->mgr))
		return -1; /* said already; the daemon destroys them when it sees the connection go */
	for (uint32_t k = 0; k < s->m.n; k++) {
		if (k % SETUP_CHUNK == 0)
			vis_client_batch_begin(s->mgr);
		if (s->m.w[k].id)
			vis_client_destroy_window(s->mgr, s->m.w[k].id);
		if (k % SETUP_CHUNK == SETUP_CHUNK - 1 || k == s->m.n - 1)
			vis_client_batch_commit(s->mgr);
	}
	if (vis_client_roundtrip(s->mgr) < 0)
		return stress_run_lost(s->mgr, "destroying the windows");
	return 0;
}

/* A subscriber's first view: the states when it subscribed. */
static void on_first_states(void *data, const struct vis_error *err,
			    const struct vis_window_state *states, size_t n)
{
	struct stress_sub *u = data;
	if (err)
		fprintf(stderr, "visctl stress: a subscriber's get-states: %s: %s\n",
			vis_error_code_name(err->code), err->message);
	u->unread = err != NULL;
	for (size_t i = 0; i < n; i++) {
		uint32_t slot = stress_model_slot(&u->s->m, states[i].window);
		if (slot != STRESS_NONE)
			u->view[slot] = (uint8_t)states[i].state;
	}
}

/* Connects the subscribers, subscribes each to every window and reads its first view. */
static int connect_subscribers(struct stress *s)
{
	const struct stress_options *o = s->o;
	uint32_t mask = VIS_NOTICE_VISIBILITY | (o->exposure ? VIS_NOTICE_EXPOSURE : 0);
	/* A descriptor a subscriber: raise the soft limit (often 1,024) as far as needed and allowed. */
	struct rlimit fds;
	rlim_t want = (rlim_t)o->clients + 64;
	if (getrlimit(RLIMIT_NOFILE, &fds) == 0 && fds.rlim_cur < want) {
		fds.rlim_cur = fds.rlim_max < want ? fds.rlim_max : want;
		setrlimit(RLIMIT_NOFILE, &fds);
	}
	for (uint32_t i = 0; i < o->clients; i++) {
		struct stress_sub *u = &s->subs[i];
		u->s = s;
		if (!(u->view = malloc(s->m.n ? s->m.n : 1))) {
			fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
			return -1;
		}
		memset(u->view, VIS_VISIBILITY_NONE, s->m.n);
		if (!(u->c = open_connection(o, VIS_ROLE_OBSERVER)))
			return -1;
		vis_client_set_notice_handler(u->c, stress_loop_notice, u);
		vis_client_subscribe(u->c, VIS_WINDOW_ALL, mask, 0);
		vis_client_get_states_async(u->c, on_first_states, u);
		if (vis_client_flush(u->c) < 0)
			return stress_run_lost(u->c, "a subscriber");
	}
	for (uint32_t i = 0; i < o->clients; i++) {
		struct stress_sub *u = &s->subs[i];
		if (vis_client_roundtrip(u->c) < 0)
			return stress_run_lost(u->c, "subscribing");
		struct vis_error e;
		if (u->unread || vis_client_last_error(u->c, &e)) {
			if (!u->unread)
				fprintf(stderr, "visctl stress: a subscriber's %s: %s: %s\n",
					vis_request_name(e.opcode), vis_error_code_name(e.code),
					e.message);
			return -1;
		}
	}
	return 0;
}

/* Compares the daemon's tree and states, and every subscriber's view, with the model's.
 * Returns the number of differences, after saying what they are on stderr. */
static uint64_t check(struct stress *s, const uint8_t *want)
{
	uint64_t bad = 0, said = 0;
	if (s->mgr_errors) {
		fprintf(stderr, "visctl stress: %llu changes failed; the first, %s: %s: %s\n",
			(unsigned long long)s->mgr_errors, vis_request_name(s->first_error.opcode),
			vis_error_code_name(s->first_error.code), s->first_error.message);
		bad += s->mgr_errors;
	}
	struct vis_window_info *tree = NULL;
	struct vis_window_state *states = NULL;
	size_t nt, ns;
	uint8_t *got = malloc(s->m.n ? s->m.n : 1);
	if (!got || vis_client_get_tree(s->mgr, &tree, &nt) < 0 ||
	    vis_client_get_states(s->mgr, &states, &ns) < 0) {
		stress_run_lost(s->mgr, "reading the final states");
		bad++;
		goto out;
	}
	bad += stress_model_compare_tree(&s->m, tree, nt, REPORT_LIMIT);
	memset(got, VIS_VISIBILITY_NONE, s->m.n);
	for (size_t i = 0; i < ns; i++) {
		uint32_t slot = stress_model_slot(&s->m, states[i].window);
		if (slot != STRESS_NONE)
			got[slot] = (uint8_t)states[i].state;
	}
	for (uint32_t k = 0; k < s->m.n; k++) {
		if (got[k] != want[k] && bad++ < REPORT_LIMIT)
			fprintf(stderr, "visctl stress: window %u: visd says %s, visctl compute on the "
					"model %s\n", s->m.w[k].id, vis_visibility_name(got[k]),
				vis_visibility_name(want[k]));
		for (uint32_t i = 0; i < s->o->clients; i++) {
			const struct stress_sub *u = &s->subs[i];
			if (want[k] == VIS_VISIBILITY_NONE || u->view[k] == want[k])
				continue;
			if (bad++ < REPORT_LIMIT)
				fprintf(stderr, "visctl stress: subscriber %u: the last notice of window "
						"%u says %s, its state is %s\n", i + 1, s->m.w[k].id,
					vis_visibility_name(u->view[k]), vis_visibility_name(want[k]));
		}
	}
	for (uint32_t i = 0; i < s->o->clients; i++) {
		const struct stress_sub *u = &s->subs[i];
		if (u->gap && bad++ < REPORT_LIMIT)
			fprintf(stderr, "visctl stress: subscriber %u: notices missing after serial "
					"%llu\n", i + 1, (unsigned long long)u->gap_after);
	}
	said = bad < REPORT_LIMIT ? bad : REPORT_LIMIT;
	if (bad > said)
		fprintf(stderr, "visctl stress: … and %llu more differences\n",
			(unsigned long long)(bad - said));
out:
	free(got);
	free(tree);
	free(states);
	return bad;
}

/* Ends the record with the model's final states, which a replay must reproduce. */
static void record_states(const struct stress *s, const uint8_t *want)
{
	FILE *f = s->o->record;
	fprintf(f, "# The model's final states (visctl compute on it), @N STATE for each mapped "
		   "window:\n");
	for (uint32_t k = 0; k < s->m.n; k++)
		if (want[k] != VIS_VISIBILITY_NONE)
			fprintf(f, "# @%u %s\n", k + 1, vis_visibility_name(want[k]));
}

int stress_run(const struct stress_options *o, struct stress_result *r)
{
	struct stress s = { .o = o, .r = r };
	struct vis_scene scene;
	uint8_t *want = NULL;
	int ret = -1;
	memset(r, 0, sizeof(*r));
	r->daemon_cpu = -1;
	r->daemon_rss_kb = r->daemon_hwm_kb = -1;
	vis_scene_init(&scene);

	if (!(s.mgr = open_connection(o, VIS_ROLE_MANAGER)))
		goto out;
	vis_client_set_error_handler(s.mgr, stress_loop_error, &s);
	struct vis_window_info *tree;
	size_t nt;
	if (vis_client_get_tree(s.mgr, &tree, &nt) < 0) {
		stress_run_lost(s.mgr, "get-tree");
		goto out;
	}
	free(tree);
	if (nt) {
		fprintf(stderr, "visctl stress: visd has %zu windows already; the run's model must be "
				"the whole stack, so it needs a daemon of its own\n", nt);
		goto out;
	}
	uint32_t sw, sh;
	vis_client_screen(s.mgr, &sw, &sh);
	r->screen_w = (int32_t)sw;
	r->screen_h = (int32_t)sh;
	struct ucred cred;
	socklen_t len = sizeof(cred);
	pid_t peer = getsockopt(vis_client_fd(s.mgr), SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0
			     ? cred.pid
			     : 0;
	if (o->pid && check_pid(o->pid, peer) < 0)
		goto out;
	r->daemon_pid = o->pid ? o->pid : peer;

	if (vis_gen(&scene, o->scene, o->windows, o->seed, (int32_t)sw, (int32_t)sh) < 0 ||
	    stress_model_init(&s.m, scene.rects, (uint32_t)scene.n, (int32_t)sw, (int32_t)sh,
			      o->seed) < 0 ||
	    !(s.subs = calloc(o->clients ? o->clients : 1, sizeof(*s.subs))) ||
	    !(s.ring = calloc(o->pipeline, sizeof(*s.ring))) ||
	    !(s.upto = calloc(o->pipeline, sizeof(*s.upto))) || !(want = malloc(o->windows))) {
		fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
		goto out;
	}
	if (o->record)
		fprintf(o->record, "# visctl stress: %u windows on a %ux%u screen, seed %llu, scene "
				   "%s; replay with `visctl script FILE`\n", o->windows, sw, sh,
			(unsigned long long)o->seed, vis_gen_kind_name(o->scene));
	if (create_windows(&s, &scene) < 0 || connect_subscribers(&s) < 0)
		goto out;

	double cpu0 = proc_cpu_seconds(r->daemon_pid), self0 = self_cpu();
	s.t0 = stress_loop_now();
	if (stress_loop_run(&s) < 0)
		goto out;
	r->seconds = (double)(s.now - s.t0) / 1e9;
	double cpu1 = proc_cpu_seconds(r->daemon_pid);
	if (cpu0 >= 0 && cpu1 >= 0)
		r->daemon_cpu = cpu1 - cpu0;
	daemon_memory(r->daemon_pid, &r->daemon_rss_kb, &r->daemon_hwm_kb);
	r->self_cpu = self_cpu() - self0;
	for (uint32_t i = 0; i < o->clients; i++)
		r->notices += s.subs[i].notices;

	if (o->corrupt_model)
		stress_model_corrupt(&s.m);
	if (stress_model_states(&s.m, want) < 0) {
		fprintf(stderr, "visctl stress: computing the model's states: %s\n", strerror(errno));
		goto out;
	}
	r->mismatches = check(&s, want);
	if (o->record)
		record_states(&s, want);
	ret = 0;
out:
	for (uint32_t i = 0; s.subs && i < o->clients; i++) {
		vis_client_destroy(s.subs[i].c);
		free(s.subs[i].view);
	}
	if (s.mgr && destroy_windows(&s) < 0)
		ret = -1;
	vis_client_destroy(s.mgr);
	free(s.subs);
	free(s.ring);
	free(s.upto);
	free(want);
	stress_model_finish(&s.m);
	vis_scene_finish(&scene);
	return ret;
}

