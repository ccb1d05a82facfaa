/* test-libvis's pieces (test-libvis.c says what it tests): the random source, the model beside
 * the tree, the checks after an update and the bad inputs. */
#ifndef VIS_TESTS_TEST_LIBVIS_H
#define VIS_TESTS_TEST_LIBVIS_H

#include <stdbool.h>
#include <stdint.h>

#include "libvis-painter.h"

/* A tree under test: libvis's and the model of it. */
struct tl {
	struct vis_tree *vt;
	struct pm_tree t;
	bool looks; /* whether its windows get shapes and opaque regions */
	/* A desktop: top-level windows only, dragged half the time (a window moving alone, whose
	 * walk below counts what the windows there gain and lose, libvis-tally.c). */
	bool flat;
};

/* The seeded random source; a number in lo … hi. */
uint64_t tl_rand(void);
int64_t tl_range(int64_t lo, int64_t hi);

/* Fails the test, printing the seed, what went wrong and two numbers about it. */
void tl_fail(const char *what, long a, long b);
/* Counts a check; fails unless ok. */
void tl_check(bool ok, const char *what);

/* Takes what window i shows as its known exposure baseline (the tree as the last update left it). */
void tl_baseline(struct tl *c, int i);

/* vis_tree_update(), then every state, visible region, change, exposure and a few repaint sets
 * against the painter (test-libvis-check.c). */
void tl_update_and_check(struct tl *c);

/* Every bad input fails with its errno and changes nothing (test-libvis-bad.c); on a tree just
 * updated. */
void tl_bad_inputs(struct tl *c);

/* The engine a tree's updates take (libvis-live.c): tallies (libvis's default for small trees),
 * the live engine from the first window, through the core below 64 windows, or tallies up to a
 * few windows only, past which the core takes over and back. */
enum tl_engine { TL_TALLY, TL_LIVE, TL_THROUGH, TL_SWITCH };
void tl_engine(struct vis_tree *tree, enum tl_engine engine);

/* A box at random inside the one whose repaint set the tree keeps from its last change, into *d
 * (libvis-live.c; with none kept, *d stays). */
void tl_kept_damage(struct vis_tree *tree, struct vis_rect32 *d);

/* While the window's tree keeps tallies (libvis-live.c), the pixels its tally says it sees, into
 * *seen, and true; else false. The states show a tally only where it reaches 0 or the window's
 * total: the test compares every tally with the painter's count. */
bool tl_tally(const struct vis_win *win, uint64_t *seen);

#endif
