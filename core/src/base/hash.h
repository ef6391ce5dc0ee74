/* Hashes for deriving seeds from tuples (rng.h, sobol.c). */
#ifndef FM_BASE_HASH_H
#define FM_BASE_HASH_H

#include <stdint.h>

/* SplitMix64 finaliser: a bijective 64-bit mix, used to derive seeds from tuples. */
static inline uint64_t mix64(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

#endif
