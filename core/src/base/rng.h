/* Random numbers: PCG32 (M. E. O'Neill, "PCG: a family of simple fast space-efficient
 * statistically good algorithms for random number generation", 2014), seeded per work item so that
 * results depend only on (seed, item, sample), never on threads or scheduling. */
#ifndef FM_BASE_RNG_H
#define FM_BASE_RNG_H

#include <stdint.h>

typedef struct rng {
    uint64_t state, inc;
} rng;

/* SplitMix64 finaliser: a bijective 64-bit mix, used to derive seeds from tuples. */
static inline uint64_t mix64(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static inline uint32_t rng_next_u32(rng *r)
{
    uint64_t old = r->state;
    r->state = old * 6364136223846793005ull + r->inc;
    uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = (uint32_t)(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
}

/* Independent stream for (seed, item, sample); streams differ in both state and increment. */
static inline rng rng_for(uint64_t seed, uint64_t item, uint64_t sample)
{
    uint64_t h = mix64(seed ^ mix64(item ^ mix64(sample + 0x632BE59BD9B4E019ull)));
    rng r;
    r.inc = (mix64(h ^ 0xDA3E39CB94B95BDBull) << 1u) | 1u;
    r.state = 0;
    rng_next_u32(&r);
    r.state += h;
    rng_next_u32(&r);
    return r;
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double rng_uniform(rng *r)
{
    uint64_t hi = rng_next_u32(r), lo = rng_next_u32(r);
    return (double)(((hi << 32) | lo) >> 11) * 0x1.0p-53;
}

#endif
