/*
 * The hostile suite's hidden windows: a window a client may not see does not exist for it
 * anywhere. Seeded random operations of three clients and a manager (windows at the top level,
 * under a client's own windows, the manager's under a client's and a client's reparented under
 * the manager's, restacks, maps, moves, destroys of subtrees) while one client, b, subscribed to
 * everything, also queries the whole screen and names the others' windows: every window ID of
 * every message b receives — replies, errors, notices, the resync after an overflow — must be 0
 * or one of b's, and its stack notices must say what PROTOCOL.md says: the parent if it is b's,
 * else 0; the window just below among the window's siblings if it is b's, else 0. The truth is the
 * manager's tree, read after every operation.
 */
#include <ctype.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hostile.h"
#include "rng.h"
#include "vis/protocol.h"

enum { MANAGER, B, OTHER1, OTHER2, N_PEERS };
#define MAX_IDS 8192	/* window IDs one run may hand out; a power of two */
#define MOST_WINDOWS 48 /* past this many, operations destroy */
#define NO_OWNER 0xff
#define HIDDEN_STEPS 500 /* operations a run */

/* A stack notice b got. */
struct notice {
	uint32_t change, window, parent, sibling, flags;
	int32_t x, y;
	uint32_t width, height;
};

/* A window ID that b received, and where, checked once the round trip is over. */
struct named {
	uint32_t id;
	const char *where;
};

static struct vis_rng rng;
static struct harness_conn peer[N_PEERS];
/* The peer that created each window, hashed by ID (IDs are not small numbers): ids[k] 0 is a
 * free slot. */
static uint32_t ids[2 * MAX_IDS];
static uint8_t owner[2 * MAX_IDS];
static uint32_t last_created[N_PEERS];
/* What b sent that may come back in an error: the window it named, by request number. */
static uint32_t b_named[256];
static struct notice *got;
static size_t n_got, cap_got;
static struct named *names;
static size_t n_names, cap_names;
static struct harness_node *b_tree; /* b's last get-tree reply */
static size_t n_b_tree, cap_b_tree;
static uint32_t overflows;
/* What a run covered, for its summary line. */
static struct {
	size_t stack, under_hidden, sibling_skipped, in_subtree, errors, flood, resync;
} covered;

/* The slot of window id (not 0), taken for it if new. */
static size_t slot(uint32_t id)
{
	size_t k = (size_t)((id * 0x9e3779b97f4a7c15ull) >> 32) & (2 * MAX_IDS - 1), probes = 0;
	for (; ids[k] && ids[k] != id; k = (k + 1) & (2 * MAX_IDS - 1))
		CHECK(++probes < MAX_IDS, "more than %d window IDs", MAX_IDS);
	ids[k] = id;
	return k;
}

static uint32_t owner_of(uint32_t id)
{
	return owner[slot(id)];
}

/* Grows *v (of *cap elements of size) to hold one more than n. */
static void *grow(void *v, size_t n, size_t *cap, size_t size)
{
	if (n < *cap)
		return v;
	*cap = *cap ? 2 * *cap : 64;
	v = realloc(v, *cap * size);
	CHECK(v, "out of memory");
	return v;
}

static void name(uint32_t id, const char *where)
{
	names = grow(names, n_names, &cap_names, sizeof *names);
	names[n_names++] = (struct named){ id, where };
}

/*
 * Notes every window ID of a message to b, from its signature: window, parent and sibling fields
 * and the records that hold windows. A new record type fails here, so that nothing goes unchecked.
 */
static void name_all(const struct vis_msg *m)
{
	struct harness_field f[VIS_MSG_MAX_ARGS];
	size_t n = harness_fields(m->type, f);
	for (size_t k = 0; k < n; k++) {
		const union vis_arg *a = &m->args[k];
		switch (f[k].type) {
		case 'u':
			if (hostile_is_window_field(f[k].name))
				name(a->u, m->type->name);
			break;
		case 'i':
		case 'q':
		case 's': /* an error's message: see check_error() */
		case 'R':
			break;
		case 'W':
		case 'S':
			for (uint32_t i = 0; i < a->a.n; i++)
				name(vis_arg_word(a, f[k].type, i, 0), m->type->name);
			break;
		case 'T':
			for (uint32_t i = 0; i < a->a.n; i++) {
				name(vis_arg_word(a, 'T', i, 0), "tree window");
				name(vis_arg_word(a, 'T', i, 1), "tree parent");
			}
			break;
		default:
			CHECK(0, "%s: field %s of unknown type %c", m->type->name, f[k].name,
			      f[k].type);
		}
	}
}

/*
 * An error to b: only the window b named in that request may appear in the message, and b only
 * names others' windows to get window errors.
 */
static void check_error(const struct vis_msg *m)
{
	const union vis_arg *a = m->args;
	char msg[300];
	snprintf(msg, sizeof msg, "%.*s", (int)a[3].s.len, a[3].s.p);
	covered.errors++;
	CHECK(a[2].u == VIS_ERROR_WINDOW, "request %u (opcode %u): error %u: %s", a[0].u, a[1].u,
	      a[2].u, msg);
	for (const char *p = msg; *p;) {
		if (!isdigit((unsigned char)*p)) {
			p++;
			continue;
		}
		char *end;
		unsigned long id = strtoul(p, &end, 10);
		CHECK(id == b_named[a[0].u % 256], "request %u: the error names %lu: %s", a[0].u,
		      id, msg);
		p = end;
	}
}

/* Takes in one message to peer p: created IDs, and for b everything it names. */
static void take(int p, const struct vis_msg *m)
{
	const union vis_arg *a = m->args;
	uint32_t op = m->type->opcode;
	if (op == VIS_OP_CREATED) {
		CHECK(owner_of(a[1].u) == NO_OWNER, "window %u created twice", a[1].u);
		owner[slot(a[1].u)] = (uint8_t)p;
		last_created[p] = a[1].u;
	}
	if (p != B) {
		CHECK(op != VIS_OP_ERROR, "peer %d: request %u (opcode %u): error %u: %.*s", p,
		      a[0].u, a[1].u, a[2].u, (int)a[3].s.len, a[3].s.p);
		return;
	}
	name_all(m);
	if (op == VIS_OP_ERROR)
		check_error(m);
	if (op == VIS_OP_OVERFLOW)
		overflows++;
	if (op == VIS_OP_STACK) {
		got = grow(got, n_got, &cap_got, sizeof *got);
		got[n_got++] = (struct notice){ a[1].u, a[2].u, a[3].u, a[8].u, a[9].u,
						a[4].i, a[5].i, a[6].u, a[7].u };
	}
	if (op == VIS_OP_TREE) {
		for (uint32_t i = 0; i < a[2].a.n; i++) {
			uint32_t r[9];
			for (uint32_t k = 0; k < 9; k++)
				r[k] = vis_arg_word(&a[2], 'T', i, k);
			b_tree = grow(b_tree, n_b_tree, &cap_b_tree, sizeof *b_tree);
			b_tree[n_b_tree++] = (struct harness_node){ r[0], r[1], (int32_t)r[2],
								    (int32_t)r[3], r[4], r[5],
								    r[6], r[7], r[8] };
		}
	}
}

/* A sync on peer p, taking in everything up to its answer; then b's names are checked. */
static void roundtrip(int p)
{
	uint32_t seq = harness_req(&peer[p], VIS_OP_SYNC);
	struct vis_msg m;
	do {
		CHECK(harness_recv(&peer[p], HARNESS_WORKING, &m) > 0, "peer %d: no answer to sync",
		      p);
		take(p, &m);
	} while (m.type->opcode != VIS_OP_SYNCED || m.args[0].u != seq);
	for (size_t i = 0; i < n_names; i++)
		CHECK(names[i].id == 0 || owner_of(names[i].id) == B,
		      "b got window %u (of peer %u) in a %s message", names[i].id,
		      owner_of(names[i].id), names[i].where);
	n_names = 0;
}

/* The truth: every window, in stacking order, as the manager sees it. */
struct truth {
	struct harness_node *t;
	size_t n;
};

static const struct harness_node *find(const struct truth *tr, uint32_t id, size_t *at)
{
	for (size_t i = 0; i < tr->n; i++)
		if (tr->t[i].window == id) {
			if (at)
				*at = i;
			return &tr->t[i];
		}
	return NULL;
}

/* The parent as b may know it. */
static uint32_t seen(uint32_t id)
{
	return id && owner_of(id) == B ? id : 0;
}

/* A window's flags as b gets them: the truth's, and whether its parent is hidden from b. */
static uint32_t b_flags(const struct harness_node *t)
{
	return t->flags | (t->parent && !seen(t->parent) ? VIS_WINDOW_PARENT_HIDDEN : 0);
}

/* The window just below the one at i among its siblings if it is b's, else 0. */
static uint32_t b_sibling(const struct truth *tr, size_t i)
{
	uint32_t below = 0;
	for (size_t k = 0; k < i; k++)
		if (tr->t[k].parent == tr->t[i].parent)
			below = tr->t[k].window;
	return seen(below);
}

/* Counts what the notice about the window at i covers: a hidden parent, hidden siblings passed. */
static void count_cover(const struct truth *tr, size_t i, uint32_t sibling)
{
	uint32_t below = 0;
	for (size_t k = 0; k < i; k++)
		if (tr->t[k].parent == tr->t[i].parent)
			below = tr->t[k].window;
	covered.stack++;
	covered.under_hidden += tr->t[i].parent && !seen(tr->t[i].parent);
	covered.sibling_skipped += below != sibling;
}

/* Whether a is b or an ancestor of b. */
static bool ancestor(const struct truth *tr, uint32_t a, uint32_t b)
{
	for (const struct harness_node *n; b; b = n ? n->parent : 0) {
		if (a == b)
			return true;
		n = find(tr, b, NULL);
	}
	return false;
}

/* How deep a window is (top level: 1; the screen: 0). */
static uint32_t depth(const struct truth *tr, uint32_t id)
{
	uint32_t d = 0;
	for (const struct harness_node *n; id; id = n->parent, d++)
		n = find(tr, id, NULL);
	return d;
}

/* A random window of peer p's (any window for the manager when mine is false), or 0. */
static uint32_t pick(const struct truth *tr, int p, bool mine)
{
	uint32_t cand[MOST_WINDOWS * 2 + 64];
	size_t n = 0;
	for (size_t i = 0; i < tr->n && n < sizeof cand / sizeof *cand; i++)
		if (owner_of(tr->t[i].window) == (uint32_t)p || (p == MANAGER && !mine))
			cand[n++] = tr->t[i].window;
	return n ? cand[vis_rng_below(&rng, n)] : 0;
}

/* A random window of peer p's (any for the manager) that is a sibling of w, or 0. */
static uint32_t pick_sibling(const struct truth *tr, int p, uint32_t w)
{
	const struct harness_node *n = find(tr, w, NULL);
	uint32_t cand[MOST_WINDOWS * 2 + 64];
	size_t k = 0;
	for (size_t i = 0; i < tr->n && k < sizeof cand / sizeof *cand; i++)
		if (tr->t[i].parent == n->parent && tr->t[i].window != w &&
		    (p == MANAGER || owner_of(tr->t[i].window) == (uint32_t)p))
			cand[k++] = tr->t[i].window;
	return k ? cand[vis_rng_below(&rng, k)] : 0;
}

static struct truth read_truth(void)
{
	struct truth tr;
	tr.t = harness_get_tree(&peer[MANAGER], &tr.n);
	for (size_t i = 0; i < tr.n; i++)
		CHECK(owner_of(tr.t[i].window) != NO_OWNER, "window %u of no known peer",
		      tr.t[i].window);
	return tr;
}

/* b's stack notices of one operation, against what its change of the truth says they must be. */
struct expect {
	uint32_t change[2], window[2]; /* one or two notices about one window, or */
	size_t n;
	uint32_t destroyed; /* a destroy: one notice per window of b's in its subtree */
};

static void check_notices(const struct expect *e, const struct truth *before,
			  const struct truth *after)
{
	size_t want = e->n;
	uint32_t order[MOST_WINDOWS * 2 + 64]; /* b's destroyed windows, as the daemon goes */
	if (e->destroyed) {
		/* Children before their parent, the top one first: reverse pre-order. */
		size_t at;
		want = 0;
		CHECK(find(before, e->destroyed, &at), "window %u to destroy is gone",
		      e->destroyed);
		for (size_t i = before->n; i-- > at;)
			if (ancestor(before, e->destroyed, before->t[i].window) &&
			    owner_of(before->t[i].window) == B)
				order[want++] = before->t[i].window;
	}
	CHECK(n_got == want, "b got %zu stack notices, wanted %zu", n_got, want);
	for (size_t i = 0; i < n_got; i++) {
		const struct notice *g = &got[i];
		size_t at = 0;
		const struct harness_node *t;
		uint32_t sibling;
		if (e->destroyed) {
			CHECK(g->change == VIS_STACK_DESTROY && g->window == order[i],
			      "notice %zu: change %u of %u, wanted the destruction of %u", i,
			      g->change, g->window, order[i]);
			t = find(before, g->window, &at);
			CHECK(t, "the destruction of %u, unknown before", g->window);
			/* The subtree's top is unlinked first: nothing is below it any more. */
			sibling = g->window == e->destroyed ? 0 : b_sibling(before, at);
		} else {
			CHECK(g->change == e->change[i] && g->window == e->window[i],
			      "notice %zu: change %u of %u, wanted %u of %u", i, g->change,
			      g->window, e->change[i], e->window[i]);
			t = find(after, g->window, &at);
			CHECK(t, "a notice about %u, which is gone", g->window);
			sibling = b_sibling(after, at);
		}
		if (g->window != e->destroyed)
			count_cover(g->change == VIS_STACK_DESTROY ? before : after, at, sibling);
		covered.in_subtree += e->destroyed && g->window != e->destroyed;
		const uint32_t hid = VIS_WINDOW_PARENT_HIDDEN;
		CHECK(g->parent == seen(t->parent) && g->sibling == sibling && g->x == t->x &&
			      g->y == t->y && g->width == t->width && g->height == t->height &&
			      (g->flags & hid) == (b_flags(t) & hid),
		      "stack notice %u of %u: parent %u, sibling %u at %d,%d %ux%u; wanted parent "
		      "%u (really %u), sibling %u at %d,%d %ux%u",
		      g->change, g->window, g->parent, g->sibling, g->x, g->y, g->width, g->height,
		      seen(t->parent), t->parent, sibling, t->x, t->y, t->width, t->height);
	}
	n_got = 0;
}

/* b's get-tree: the truth's windows of b's, in its order, parents as b may know them. */
static void check_b_tree(const struct truth *tr)
{
	size_t k = 0;
	for (size_t i = 0; i < tr->n; i++) {
		const struct harness_node *t = &tr->t[i];
		if (owner_of(t->window) != B)
			continue;
		CHECK(k < n_b_tree, "b's tree lacks window %u", t->window);
		const struct harness_node *g = &b_tree[k++];
		CHECK(g->window == t->window && g->parent == seen(t->parent) && g->x == t->x &&
			      g->y == t->y && g->width == t->width && g->height == t->height &&
			      g->flags == b_flags(t) && g->state == t->state,
		      "b's tree has %u (parent %u) where the truth has %u (parent %u, for b %u)",
		      g->window, g->parent, t->window, t->parent, seen(t->parent));
	}
	CHECK(k == n_b_tree, "b's tree has %zu windows, the truth %zu of b's", n_b_tree, k);
}

/* A request of b's naming a window of another's: each answers a window error naming it alone. */
static void b_names_hidden(const struct truth *tr)
{
	uint32_t h = 0, own = pick(tr, B, true);
	for (int tries = 0; tries < 8 && (!h || owner_of(h) == B); tries++)
		h = pick(tr, MANAGER, false);
	if (!h || owner_of(h) == B)
		return;
	struct harness_conn *b = &peer[B];
	uint32_t seq;
	switch (vis_rng_below(&rng, own ? 6 : 4)) {
	case 0:
		seq = harness_req(b, VIS_OP_GET_STATE, h);
		break;
	case 1:
		seq = harness_req(b, VIS_OP_GET_REGION, h);
		break;
	case 2:
		seq = harness_req(b, VIS_OP_CREATE, h, 0, 0, 5, 5, 0, 0, 0, 0, 0);
		break;
	case 3:
		seq = harness_req(b, VIS_OP_SUBSCRIBE, h, VIS_NOTICE_ALL, 0);
		break;
	case 4:
		seq = harness_req(b, VIS_OP_RESTACK, own, VIS_RESTACK_ABOVE, h);
		break;
	default:
		seq = harness_req(b, VIS_OP_REPARENT, own, h, 0, 0);
		break;
	}
	b_named[seq % 256] = h;
	roundtrip(B); /* before anyone destroys own */
	CHECK(n_got == 0, "b got %zu stack notices with nothing changed", n_got);
}

/* b's queries over everything: the tree (checked against the truth), states, repaint, regions. */
static void b_queries(const struct truth *tr)
{
	struct harness_conn *b = &peer[B];
	n_b_tree = 0;
	harness_req(b, VIS_OP_GET_TREE);
	harness_req(b, VIS_OP_GET_STATES);
	harness_req(b, VIS_OP_GET_REPAINT, (uint32_t)-50, (uint32_t)-50, 500, 400);
	uint32_t own = pick(tr, B, true);
	if (own) {
		harness_req(b, VIS_OP_GET_STATE, own);
		harness_req(b, VIS_OP_GET_REGION, own);
	}
	roundtrip(B);
	CHECK(n_got == 0, "b got %zu stack notices with nothing changed", n_got);
	check_b_tree(tr);
}

/*
 * One random operation by a random peer; fills e with the stack notices b must get. Returns the
 * peer that made it.
 */
static int operate(const struct truth *tr, struct expect *e)
{
	/* Mostly b and the manager, the manager often on b's windows: b hears of those. */
	uint64_t r = vis_rng_below(&rng, 20);
	int p = r < 7 ? B : r < 14 ? MANAGER : r < 17 ? OTHER1 : OTHER2;
	struct harness_conn *c = &peer[p];
	*e = (struct expect){ 0 };
	uint32_t w = p == MANAGER && vis_rng_below(&rng, 2) ? pick(tr, B, true) : 0;
	if (!w)
		w = pick(tr, p, false);
	size_t b_windows = 0;
	for (size_t i = 0; i < tr->n; i++)
		b_windows += owner_of(tr->t[i].window) == B;
	uint32_t kind = tr->n >= MOST_WINDOWS		? 9
			: p == B && b_windows < 4	? (uint32_t)vis_rng_below(&rng, 2)
							: (uint32_t)vis_rng_below(&rng, 13);
	if (kind >= 11) /* more reparents: by the manager, b's windows under its own */
		kind = p == MANAGER ? 2 : 1;
	if (!w && kind >= 2)
		kind = 0;
	const struct harness_node *n = w ? find(tr, w, NULL) : NULL;
	bool mine = w && owner_of(w) == B;
	int32_t x = (int32_t)vis_rng_range(&rng, -20, 380);
	int32_t y = (int32_t)vis_rng_range(&rng, -20, 280);
	uint32_t wd = (uint32_t)vis_rng_range(&rng, 5, 150);
	uint32_t ht = (uint32_t)vis_rng_range(&rng, 5, 120);
	switch (kind) {
	case 0:
	case 1: {
		/* At the top level, or under a window it may change (for the manager: anyone's). */
		uint32_t parent = kind == 0 || !w || depth(tr, w) >= 16 ? 0 : w;
		uint32_t flags = vis_rng_below(&rng, 3) ? VIS_CREATE_MAP : 0;
		harness_req(c, VIS_OP_CREATE, parent, (uint32_t)x, (uint32_t)y, wd, ht, flags, 0, 0, 0, 0);
		if (p == B) {
			/* Its ID is known once the reply is in: filled in after the round trip. */
			e->change[0] = VIS_STACK_CREATE;
			e->change[1] = VIS_STACK_MAP;
			e->n = flags ? 2 : 1;
		}
		break;
	}
	case 2: {
		/* Under another window it may change (the manager: often b's under its own). */
		uint32_t parent = p == MANAGER && vis_rng_below(&rng, 3) ? pick(tr, MANAGER, true)
									 : pick(tr, p, false);
		if (vis_rng_below(&rng, 4) == 0 || ancestor(tr, w, parent) ||
		    depth(tr, parent) >= 16)
			parent = 0;
		harness_req(c, VIS_OP_REPARENT, w, parent, (uint32_t)(x / 4), (uint32_t)(y / 4));
		*e = (struct expect){ { VIS_STACK_REPARENT }, { w }, mine, 0 };
		break;
	}
	case 3: {
		uint32_t s = pick_sibling(tr, p, w);
		if (s)
			harness_req(c, VIS_OP_RESTACK, w, (uint32_t)vis_rng_below(&rng, 2), s);
		else
			harness_req(c, VIS_OP_RAISE, w);
		*e = (struct expect){ { VIS_STACK_RESTACK }, { w }, mine, 0 };
		break;
	}
	case 4:
	case 5:
		harness_req(c, kind == 4 ? VIS_OP_RAISE : VIS_OP_LOWER, w);
		*e = (struct expect){ { VIS_STACK_RESTACK }, { w }, mine, 0 };
		break;
	case 6: {
		bool mapped = n->flags & VIS_WINDOW_MAPPED, to = vis_rng_below(&rng, 3) != 0;
		harness_req(c, to ? VIS_OP_MAP : VIS_OP_UNMAP, w);
		*e = (struct expect){ { to ? VIS_STACK_MAP : VIS_STACK_UNMAP },
				      { w },
				      mine && mapped != to,
				      0 };
		break;
	}
	case 7:
		harness_req(c, VIS_OP_MOVE, w, (uint32_t)x, (uint32_t)y);
		*e = (struct expect){ { VIS_STACK_CONFIGURE }, { w }, mine, 0 };
		break;
	case 8:
		harness_req(c, VIS_OP_RESIZE, w, wd, ht);
		*e = (struct expect){ { VIS_STACK_CONFIGURE }, { w }, mine, 0 };
		break;
	default:
		/* Destroys: a window with children if a few tries find one. */
		for (int tries = 0; tries < 4; tries++) {
			size_t at = 0;
			find(tr, w, &at);
			if (at + 1 < tr->n && tr->t[at + 1].parent == w)
				break;
			w = pick(tr, p, false);
		}
		harness_req(c, VIS_OP_DESTROY, w);
		e->destroyed = w;
		break;
	}
	return p;
}

/* b's windows in stacking order into mine; returns how many. */
static size_t b_windows(uint32_t *mine)
{
	struct truth tr = read_truth();
	size_t n = 0;
	for (size_t i = 0; i < tr.n; i++)
		if (owner_of(tr.t[i].window) == B)
			mine[n++] = tr.t[i].window;
	free(tr.t);
	return n;
}

/*
 * b stops reading while the manager moves and resizes b's windows, until b's output overflows;
 * then b reads its notices and the resync. Moves change no parent or sibling: every stack notice
 * must match the truth after them but for geometry, the resync's in geometry too.
 */
static void overflow_b(void)
{
	uint32_t mine[MOST_WINDOWS * 2 + 64];
	struct harness_conn *m = &peer[MANAGER];
	size_t n = b_windows(mine);
	if (!n) {
		/* b has no window: two to move, their notices not checked here. */
		harness_req(&peer[B], VIS_OP_CREATE, 0, 10, 10, 50, 50, VIS_CREATE_MAP, 0, 0, 0, 0);
		harness_req(&peer[B], VIS_OP_CREATE, 0, 30, 30, 50, 50, VIS_CREATE_MAP, 0, 0, 0, 0);
		roundtrip(B);
		n_got = 0;
		n = b_windows(mine);
	}
	/*
	 * So that the resync has a parent to hide and a sibling to pass over: the manager's frame
	 * with b's first and last windows in it, one of its own between them.
	 */
	harness_req(m, VIS_OP_CREATE, 0, 0, 0, 300, 200, VIS_CREATE_MAP, 0, 0, 0, 0);
	roundtrip(MANAGER);
	uint32_t frame = last_created[MANAGER];
	harness_req(m, VIS_OP_REPARENT, mine[0], frame, 5, 5);
	harness_req(m, VIS_OP_CREATE, frame, 0, 0, 10, 10, VIS_CREATE_MAP, 0, 0, 0, 0);
	if (n > 1)
		harness_req(m, VIS_OP_REPARENT, mine[n - 1], frame, 20, 20);
	roundtrip(MANAGER);
	n = b_windows(mine);
	uint32_t before = overflows;
	/* More each time, in case this machine's socket buffers hold more than a flood. */
	for (int round = 0, ops = 5000; round < 5 && overflows == before; round++, ops *= 2) {
		for (int i = 0; i < ops; i++) {
			uint32_t w = mine[vis_rng_below(&rng, n)];
			uint32_t x = (uint32_t)vis_rng_range(&rng, -20, 380);
			uint32_t y = (uint32_t)vis_rng_range(&rng, -20, 280);
			if (i % 2)
				harness_req(m, VIS_OP_MOVE, w, x, y);
			else
				harness_req(m, VIS_OP_RESIZE, w, x / 3 + 10, y / 3 + 10);
		}
		roundtrip(MANAGER);
		n_got = 0;
		roundtrip(B);
		struct truth tr = read_truth();
		size_t resync = 0;
		for (size_t i = 0; i < n_got; i++) {
			const struct notice *g = &got[i];
			size_t at;
			const struct harness_node *t = find(&tr, g->window, &at);
			CHECK(t, "a notice about %u, which is gone", g->window);
			bool exact = g->change == VIS_STACK_RESYNC;
			covered.flood++;
			covered.resync += exact;
			CHECK(g->parent == seen(t->parent) && g->sibling == b_sibling(&tr, at) &&
				      (!exact || (g->x == t->x && g->y == t->y &&
						  g->width == t->width && g->height == t->height &&
						  g->flags == b_flags(t))),
			      "stack notice %u of %u: parent %u, sibling %u at %d,%d; wanted "
			      "parent %u (really %u), sibling %u at %d,%d",
			      g->change, g->window, g->parent, g->sibling, g->x, g->y,
			      seen(t->parent), t->parent, b_sibling(&tr, at), t->x, t->y);
			if (exact) {
				/* In stacking order, each of b's windows once. */
				CHECK(resync < n && g->window == mine[resync],
				      "resync notice %zu is about %u, wanted %u", resync, g->window,
				      resync < n ? mine[resync] : 0);
				resync++;
			}
		}
		CHECK(overflows == before || resync == n,
		      "the resync restated %zu of b's %zu windows", resync, n);
		n_got = 0;
		free(tr.t);
	}
	CHECK(overflows > before, "b's output never overflowed");
}

/* One seeded run on its own daemon: steps operations, an overflow of b's halfway. */
static void run(const char *visd, uint64_t seed, int steps)
{
	harness_context("hidden windows, seed %llu", (unsigned long long)seed);
	harness_seed(seed);
	rng.state = seed;
	memset(owner, NO_OWNER, sizeof owner);
	memset(ids, 0, sizeof ids);
	memset(b_named, 0, sizeof b_named);
	n_got = n_names = 0;
	overflows = 0;
	memset(&covered, 0, sizeof covered);
	struct harness_daemon d = { 0 };
	const char *const options[] = { "--screen", "400x300", "--max-pending", "65536", NULL };
	harness_start(&d, visd, options);
	for (int p = 0; p < N_PEERS; p++)
		harness_open_as(&peer[p], p == OTHER2 ? d.rsock : d.sock,
				p == MANAGER ? VIS_ROLE_MANAGER : VIS_ROLE_CLIENT);
	harness_req(&peer[B], VIS_OP_SUBSCRIBE, VIS_WINDOW_ALL, VIS_NOTICE_ALL, 0);
	roundtrip(B);
	struct truth before = read_truth();
	for (int step = 0; step < steps; step++) {
		harness_context("hidden windows, seed %llu, step %d", (unsigned long long)seed,
				step);
		if (step == steps / 2) {
			overflow_b(); /* moved b's windows: the truth is new */
			free(before.t);
			before = read_truth();
		}
		if (vis_rng_below(&rng, 8) == 0)
			b_names_hidden(&before);
		struct expect e;
		int p = operate(&before, &e);
		if (p != B)
			roundtrip(p);
		roundtrip(B); /* after p's answer: every notice of the operation is in */
		if (e.n && !e.window[0]) /* b's create */
			e.window[0] = e.window[1] = last_created[B];
		struct truth after = read_truth();
		check_notices(&e, &before, &after);
		if (vis_rng_below(&rng, 4) == 0)
			b_queries(&after);
		free(before.t);
		before = after;
	}
	free(before.t);
	harness_check_alive(&d);
	for (int p = 0; p < N_PEERS; p++)
		harness_close(&peer[p]);
	harness_stop(&d);
	printf("hidden windows, seed %llu: %zu stack notices to the client checked (%zu under "
	       "another's window, %zu past another's sibling, %zu destroyed with an ancestor), %zu "
	       "in a flood (%zu resync after %u overflows), %zu errors naming another's window\n",
	       (unsigned long long)seed, covered.stack, covered.under_hidden,
	       covered.sibling_skipped, covered.in_subtree, covered.flood, covered.resync,
	       overflows, covered.errors);
}

void hostile_hidden_windows(const char *visd, uint64_t seed)
{
	if (seed) {
		run(visd, seed, HIDDEN_STEPS);
	} else {
		for (seed = 1; seed <= 4; seed++)
			run(visd, seed, HIDDEN_STEPS);
	}
	harness_seed(0);
	free(got);
	free(names);
	free(b_tree);
	got = NULL;
	names = NULL;
	b_tree = NULL;
	cap_got = cap_names = cap_b_tree = 0;
}
