/* A small deterministic random generator (splitmix64), so scenes are the same on every machine. */
#ifndef VIS_RNG_H
#define VIS_RNG_H

#include <stdint.h>

struct vis_rng {
	uint64_t state;
};

static inline uint64_t vis_rng_next(struct vis_rng *rng)
{
	uint64_t z = (rng->state += 0x9e3779b97f4a7c15ull);
	z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
	z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
	return z ^ (z >> 31);
}

/* A number in [0, bound), bound ≥ 1 (the tiny modulo bias does not matter for scenes). */
static inline uint64_t vis_rng_below(struct vis_rng *rng, uint64_t bound)
{
	return vis_rng_next(rng) % bound;
}

/* A number in [lo, hi], lo ≤ hi. */
static inline int64_t vis_rng_range(struct vis_rng *rng, int64_t lo, int64_t hi)
{
	return lo + (int64_t)vis_rng_below(rng, (uint64_t)(hi - lo) + 1);
}

#endif
