/* Random numbers: PCG32 (M. E. O'Neill, "PCG: a family of simple fast space-efficient
 * statistically good algorithms for random number generation", 2014), seeded per work item so that
 * results depend only on (seed, item, sample), never on threads or scheduling.  A stream made by
 * rng_for_qmc draws its first FM_SOBOL_DIMS numbers from point `sample` of a scrambled Sobol
 * sequence (base/sobol.h) shared by the item's samples, the rest from PCG32. */
#ifndef FM_BASE_RNG_H
#define FM_BASE_RNG_H

#include "base/hash.h"
#include "base/sobol.h"

#include <stddef.h>
#include <stdint.h>

typedef struct rng {
    uint64_t state, inc;
    uint64_t qmc_seed;           /* the item's scramble */
    uint32_t qmc_index;          /* the sample's point */
    int qmc_dim, qmc_dims;       /* next coordinate; how many come from the point (0: none) */
    int qmc_levels;              /* scrambled digits (sobol_owen) */
    const sobol_scramble *qmc_table; /* the scramble tabulated, or NULL (rng_use_scramble) */
} rng;

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
    r.qmc_seed = 0;
    r.qmc_index = 0;
    r.qmc_dim = r.qmc_dims = r.qmc_levels = 0;
    r.qmc_table = NULL;
    return r;
}

/* The scramble seed of an item's points (rng_for_qmc), for sobol_scramble_init. */
static inline uint64_t rng_qmc_seed(uint64_t seed, uint64_t item)
{
    return mix64(seed ^ mix64(item ^ 0x2545F4914F6CDD1Dull));
}

/* As rng_for, but the first draws are a quasi-Monte Carlo point: the samples 0 to samples - 1 of
 * one item together stratify each of those dimensions.  Samples take the points in a shuffled order
 * (sobol_shuffle): the caller's own use of the sample number (the hero wavelength cycles with it)
 * would otherwise meet the points' structure (docs/decisions/2026-12-06-random-numbers-and-lookups.md).
 * (Past 2^31 samples, plain random numbers.) */
static inline rng rng_for_qmc(uint64_t seed, uint64_t item, uint64_t sample, uint64_t samples)
{
    rng r = rng_for(seed, item, sample);
    if (samples <= (1ull << 31) && sample < samples) {
        r.qmc_seed = rng_qmc_seed(seed, item);
        r.qmc_levels = sobol_levels(samples);
        r.qmc_index = sobol_shuffle((uint32_t)sample, r.qmc_levels, r.qmc_seed);
        r.qmc_dims = FM_SOBOL_DIMS;
    }
    return r;
}

/* Lets a stream of rng_for_qmc(seed, item, ...) draw its points from the item's tabulated scramble
 * (sobol_scramble_init(table, rng_qmc_seed(seed, item), its levels)): the same numbers, fewer
 * hashes.  A table of other levels, or none (levels 0), is not used. */
static inline void rng_use_scramble(rng *r, const sobol_scramble *table)
{
    if (r->qmc_dims && table->levels == r->qmc_levels)
        r->qmc_table = table;
}

/* Uniform double in [0, 1) with 53 random bits. */
static inline double rng_uniform(rng *r)
{
    if (r->qmc_dim < r->qmc_dims)
        return r->qmc_table ? sobol_owen_tabulated(r->qmc_table, r->qmc_index, r->qmc_dim++)
                            : sobol_owen(r->qmc_index, r->qmc_dim++, r->qmc_seed, r->qmc_levels);
    uint64_t hi = rng_next_u32(r), lo = rng_next_u32(r);
    return (double)(((hi << 32) | lo) >> 11) * 0x1.0p-53;
}

#endif
