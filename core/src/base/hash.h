/* Hashes for deriving seeds from tuples (rng.h, sobol.c). */
#ifndef FM_BASE_HASH_H
#define FM_BASE_HASH_H

#include <stddef.h>
#include <stdint.h>

/* SplitMix64 finaliser: a bijective 64-bit mix, used to derive seeds from tuples. */
static inline uint64_t mix64(uint64_t z)
{
    z += 0x9E3779B97F4A7C15ull;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

/* A 64-bit hash of n bytes (8 at a time through mix64, the tail and the length last); different
 * seeds give independent hashes, two of them a 128-bit one.  For keys and checksums, not security. */
static inline uint64_t hash_bytes(const void *data, size_t n, uint64_t seed)
{
    const unsigned char *p = data;
    uint64_t h = mix64(seed);
    size_t i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w = 0;
        for (int b = 0; b < 8; b++)
            w |= (uint64_t)p[i + b] << (8 * b);
        h = mix64(h ^ w);
    }
    uint64_t tail = 0;
    for (int b = 0; i + b < n; b++)
        tail |= (uint64_t)p[i + b] << (8 * b);
    return mix64(mix64(h ^ tail) ^ (uint64_t)n);
}

#endif
