/*
 * visctl stress's operations: one thread, one poll loop over a manager connection, which makes the
 * changes, and the subscribers' connections, which count notices.
 *
 * When is an operation done? The daemon queues the notices a change causes to every subscriber
 * before it answers a later sync of the manager, and a subscriber's sync is answered after
 * everything queued to it before. So: after each burst of operations the manager sends a sync;
 * once its reply is in, a round of syncs, one on every subscriber, confirms that every notice the
 * burst caused has arrived. An operation's latency runs from its start to the later of the
 * manager's reply and the last notice that arrived before the confirmation. One operation at a
 * time (--pipeline 1), that is exactly the arrival of its last notice; with several in flight it
 * is an upper bound, as a later operation's notices may be the last. Its start is when it was
 * sent; with a rate, an operation that fell due while the pipeline was full starts when it was
 * due (wrk2's correction for coordinated omission: a stall of the daemon holds back the operations
 * behind it, and their latency must say so), but one due while there was room starts when sent,
 * so that the lateness of visctl's own timer (tens of µs on a VM) is not counted.
 */
#include <errno.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <time.h>

#include "stress.h"

#define NS UINT64_C(1000000000)
/* Without a message from visd for this long, the run gives up rather than hang. */
#define STALL_NS (30 * NS)
#define PROGRESS_NS (NS / 4)

uint64_t stress_loop_now(void)
{
	struct timespec ts;
	clock_gettime(CLOCK_MONOTONIC, &ts);
	return (uint64_t)ts.tv_sec * NS + (uint64_t)ts.tv_nsec;
}

/* Counts a subscriber's notice, checks its serial and keeps the state it reports. */
void stress_loop_notice(void *data, const struct vis_notice *n)
{
	struct stress_sub *u = data;
	struct stress *s = u->s;
	if (n->serial != u->serial + 1 && !u->gap) {
		u->gap = true;
		u->gap_after = u->serial;
	}
	u->serial = n->serial;
	u->notices++;
	s->last_notice = s->now;
	if (n->kind == VIS_NOTICE_KIND_VISIBILITY) {
		uint32_t slot = stress_model_slot(&s->m, n->window);
		if (slot != STRESS_NONE)
			u->view[slot] = (uint8_t)n->visibility.state;
	}
}

void stress_loop_error(void *data, const struct vis_error *e)
{
	struct stress *s = data;
	if (!s->mgr_errors++)
		s->first_error = *e;
}

/* The operations in [confirmed, round_covers) are done: their latencies are known. */
static void confirm(struct stress *s)
{
	uint32_t k = s->o->pipeline;
	if (s->sent - s->confirmed == k && s->round_covers > s->confirmed)
		s->room_at = s->now;
	for (; s->confirmed < s->round_covers; s->confirmed++) {
		const struct stress_op *op = &s->ring[s->confirmed % k];
		uint64_t end = op->applied > s->last_notice ? op->applied : s->last_notice;
		uint64_t ns = end > op->start ? end - op->start : 0;
		histogram_record(&s->r->latency, ns);
		histogram_record(&s->r->kind_latency[op->kind], ns);
	}
	s->round = false;
}

/* A subscriber's sync came back; the round is over when every subscriber's has. */
static void on_sub_synced(void *data, const struct vis_error *err)
{
	(void)err;
	struct stress *s = ((struct stress_sub *)data)->s;
	if (--s->round_pending == 0)
		confirm(s);
}

/* The manager's sync after a burst came back: the burst is applied, its notices queued. */
static void on_applied(void *data, const struct vis_error *err)
{
	(void)err;
	struct stress *s = data;
	uint64_t upto = s->upto[s->syncs_done++ % s->o->pipeline];
	for (; s->applied < upto; s->applied++)
		s->ring[s->applied % s->o->pipeline].applied = s->now;
}

/* Starts a round of subscriber syncs for the operations applied and not yet confirmed. */
static void start_round(struct stress *s)
{
	if (s->round || s->applied == s->confirmed)
		return;
	s->round = true;
	s->round_covers = s->applied;
	s->round_pending = s->o->clients;
	for (uint32_t i = 0; i < s->o->clients; i++)
		vis_client_sync_async(s->subs[i].c, on_sub_synced, &s->subs[i]);
	if (!s->o->clients)
		confirm(s);
}

/* Sends one change on the manager's connection (and into the record). */
static void send_change(struct stress *s, const struct stress_change *c)
{
	uint32_t id = s->m.w[c->slot].id;
	switch (c->kind) {
	case STRESS_MOVE:
		vis_client_move(s->mgr, id, c->a, c->b);
		break;
	case STRESS_RESIZE:
		vis_client_resize(s->mgr, id, (uint32_t)c->a, (uint32_t)c->b);
		break;
	case STRESS_RAISE:
		vis_client_raise(s->mgr, id);
		break;
	case STRESS_LOWER:
		vis_client_lower(s->mgr, id);
		break;
	case STRESS_RESTACK:
		vis_client_restack(s->mgr, id, c->flag ? VIS_RESTACK_ABOVE : VIS_RESTACK_BELOW,
				   s->m.w[c->sibling].id);
		break;
	case STRESS_MAP:
	case STRESS_BATCH:
		c->flag ? vis_client_map(s->mgr, id) : vis_client_unmap(s->mgr, id);
		break;
	case STRESS_BORDER: {
		const struct vis_rect *r = &s->m.w[c->slot].r;
		vis_client_configure(s->mgr, id, r->x, r->y, (uint32_t)r->w, (uint32_t)r->h,
				     (uint32_t)c->a);
		break;
	}
	case STRESS_SHAPE:
	case STRESS_OPAQUE: {
		struct vis_rect32 v[STRESS_LOOK_RECTS];
		for (uint32_t i = 0; i < c->n_rects; i++)
			v[i] = (struct vis_rect32){ c->rects[i].x, c->rects[i].y,
						    (uint32_t)c->rects[i].w, (uint32_t)c->rects[i].h };
		if (c->kind == STRESS_SHAPE)
			vis_client_set_shape(s->mgr, id, c->mode, v, c->n_rects);
		else
			vis_client_set_opaque(s->mgr, id, c->mode, v, c->n_rects);
		break;
	}
	}
	s->r->changes++;
	if (s->o->record)
		stress_model_record(s->o->record, c);
}

/* Draws and sends one operation: a change, or a batch of them. */
static void send_op(struct stress *s, uint64_t start)
{
	struct stress_change c;
	enum stress_kind kind = stress_model_kind(&s->m, s->o->mix, false);
	if (kind == STRESS_BATCH) {
		vis_client_batch_begin(s->mgr);
		if (s->o->record)
			fputs("batch-begin\n", s->o->record);
		for (uint32_t i = 0; i < s->o->batch_size; i++) {
			stress_model_change(&s->m, stress_model_kind(&s->m, s->o->mix, true), &c);
			send_change(s, &c);
		}
		vis_client_batch_commit(s->mgr);
		if (s->o->record)
			fputs("batch-commit\n", s->o->record);
	} else {
		stress_model_change(&s->m, kind, &c);
		send_change(s, &c);
	}
	s->ring[s->sent % s->o->pipeline] = (struct stress_op){ .start = start, .kind = kind };
	s->sent++;
	s->r->ops++;
	s->r->kind_ops[kind]++;
}

/* Sends what is due and fits in the pipeline, then the burst's sync. Returns when the next
 * operation is due (0: none is waiting for its time). */
static uint64_t issue(struct stress *s)
{
	const struct stress_options *o = s->o;
	uint64_t before = s->sent, due = 0;
	while (!s->stopping && s->sent - s->confirmed < o->pipeline) {
		uint64_t start = s->now;
		if (o->rate > 0)
			start = s->t0 + (uint64_t)((double)s->sent * 1e9 / o->rate);
		/* The duration bounds the time, even when a fixed rate has fallen behind. */
		uint64_t last = start > s->now ? start : s->now;
		if ((o->count && s->sent == o->count) ||
		    (o->duration > 0 && (double)(last - s->t0) >= o->duration * 1e9)) {
			s->stopping = true;
			break;
		}
		if (start > s->now) {
			due = start;
			break;
		}
		send_op(s, start < s->room_at ? start : s->now);
	}
	if (s->sent > before) {
		s->upto[s->syncs_sent++ % o->pipeline] = s->sent;
		vis_client_sync_async(s->mgr, on_applied, s);
		s->last_heard = s->now; /* the wait for an answer starts now */
	}
	return due;
}

/*
 * Says how far the run is: on a terminal, overwriting the line a few times a second; otherwise
 * (a log, a pipe) a plain line a second, so that scripts see the run go on without noise.
 */
static void progress(struct stress *s, bool last)
{
	bool tty = s->o->progress_tty;
	uint64_t every = tty ? PROGRESS_NS : NS;
	if (!s->o->progress || (last && !tty) || (!last && s->now - s->last_progress < every))
		return;
	s->last_progress = s->now;
	double t = (double)(s->now - s->t0) / 1e9;
	uint64_t notices = 0;
	for (uint32_t i = 0; i < s->o->clients; i++)
		notices += s->subs[i].notices;
	fprintf(stderr, "%svisctl stress: %llu ops in %.1f s, %.0f ops/s, p99 %.0f us, %llu notices%s",
		tty ? "\r" : "", (unsigned long long)s->confirmed, t,
		t > 0 ? (double)s->confirmed / t : 0,
		(double)histogram_percentile(&s->r->latency, 99) / 1e3, (unsigned long long)notices,
		tty ? "\033[K" : "\n");
	if (last)
		fputs("\r\033[K", stderr);
}

int stress_loop_run(struct stress *s)
{
	uint32_t nfd = s->o->clients + 1;
	struct pollfd *pfd = calloc(nfd, sizeof(*pfd));
	struct vis_client **conn = calloc(nfd, sizeof(*conn));
	int ret = -1;
	if (!pfd || !conn) {
		fprintf(stderr, "visctl stress: %s\n", strerror(ENOMEM));
		goto out;
	}
	/* ppoll's default timer slack (50 µs) would start operations of a fixed rate late. */
	prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
	conn[0] = s->mgr;
	for (uint32_t i = 0; i < s->o->clients; i++)
		conn[i + 1] = s->subs[i].c;
	s->last_heard = s->now = s->last_progress = s->room_at = s->t0;
	for (;;) {
		s->now = stress_loop_now();
		uint64_t due = issue(s);
		start_round(s);
		if (s->stopping && s->confirmed == s->sent)
			break;
		for (uint32_t i = 0; i < nfd; i++) {
			int f = vis_client_flush(conn[i]);
			if (f < 0) {
				stress_run_lost(conn[i], i ? "a subscriber" : "the manager");
				goto out;
			}
			pfd[i] = (struct pollfd){ .fd = vis_client_fd(conn[i]),
						  .events = (short)(POLLIN | (f ? POLLOUT : 0)) };
		}
		progress(s, false);
		if (s->confirmed < s->sent && s->now - s->last_heard > STALL_NS) {
			fprintf(stderr, "visctl stress: visd has answered nothing for %llu s\n",
				(unsigned long long)(STALL_NS / NS));
			goto out;
		}
		uint64_t wake = s->now + PROGRESS_NS;
		if (due && due < wake)
			wake = due;
		struct timespec ts = { (time_t)((wake - s->now) / NS), (long)((wake - s->now) % NS) };
		if (ppoll(pfd, nfd, &ts, NULL) < 0 && errno != EINTR) {
			fprintf(stderr, "visctl stress: poll: %s\n", strerror(errno));
			goto out;
		}
		/* What was readable when ppoll returned arrived by now: one time for every connection,
		 * so that reading the first ones does not make the last ones' notices look late. */
		s->now = stress_loop_now();
		for (uint32_t i = 0; i < nfd; i++) {
			if (!(pfd[i].revents & (POLLIN | POLLHUP | POLLERR)))
				continue;
			s->last_heard = s->now;
			if (vis_client_dispatch(conn[i]) < 0) {
				stress_run_lost(conn[i], i ? "a subscriber" : "the manager");
				goto out;
			}
		}
	}
	progress(s, true);
	ret = 0;
out:
	free(pfd);
	free(conn);
	return ret;
}
