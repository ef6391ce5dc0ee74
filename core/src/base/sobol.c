#include "base/sobol.h"

#include "base/hash.h"

#include <pthread.h>
#include <stdlib.h>

/* Joe & Kuo (2008), new-joe-kuo-6.21201, dimensions 2 to 16 (the first is the van der Corput
 * sequence): degree s of the primitive polynomial, its inner coefficients a, initial numbers m. */
static const struct {
    int s, a, m[6];
} PRIMITIVE[FM_SOBOL_DIMS - 1] = {
    {1, 0, {1}},
    {2, 1, {1, 3}},
    {3, 1, {1, 3, 1}},
    {3, 2, {1, 1, 1}},
    {4, 1, {1, 1, 3, 3}},
    {4, 4, {1, 3, 5, 13}},
    {5, 2, {1, 1, 5, 5, 17}},
    {5, 4, {1, 1, 5, 5, 5}},
    {5, 7, {1, 1, 7, 11, 19}},
    {5, 11, {1, 1, 5, 1, 1}},
    {5, 13, {1, 1, 1, 3, 11}},
    {5, 14, {1, 3, 5, 5, 31}},
    {6, 1, {1, 3, 3, 9, 7, 49}},
    {6, 13, {1, 1, 1, 15, 21, 21}},
    {6, 16, {1, 3, 1, 13, 27, 49}},
};

static uint32_t V[FM_SOBOL_DIMS][32]; /* direction numbers: V[d][i] for bit i of the index */
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void build_direction_numbers(void)
{
    for (int i = 0; i < 32; i++)
        V[0][i] = 1u << (31 - i);
    for (int d = 1; d < FM_SOBOL_DIMS; d++) {
        const int s = PRIMITIVE[d - 1].s, a = PRIMITIVE[d - 1].a;
        uint32_t *v = V[d];
        for (int i = 0; i < s; i++)
            v[i] = (uint32_t)PRIMITIVE[d - 1].m[i] << (31 - i);
        /* the recurrence of the primitive polynomial x^s + a_1 x^(s-1) + ... + 1 */
        for (int i = s; i < 32; i++) {
            v[i] = v[i - s] ^ (v[i - s] >> s);
            for (int k = 1; k < s; k++)
                if ((a >> (s - 1 - k)) & 1)
                    v[i] ^= v[i - k];
        }
    }
}

uint32_t sobol_u32(uint32_t index, int dim)
{
    pthread_once(&once, build_direction_numbers);
    uint32_t x = 0;
    for (int i = 0; index; i++, index >>= 1)
        x ^= V[dim][i] & (0u - (index & 1u)); /* no branch on the index's bits: they are random */
    return x;
}

int sobol_levels(uint64_t points)
{
    int levels = 1;
    while (levels < 32 && (1ull << levels) < points)
        levels++;
    return levels;
}

/* Whether the nested scramble of `key` flips the digit at `level` below the digits `prefix`. */
static uint32_t node_flip(uint64_t key, int level, uint32_t prefix)
{
    return (uint32_t)(mix64(key ^ ((uint64_t)level << 32 | prefix)) >> 63);
}

/* The nested uniform scramble of the top `levels` binary digits of x (the rest cleared): each digit
 * is flipped or not by a hash of the key, its level and the digits above it (its node in the binary
 * tree). */
static uint32_t nested_scramble(uint32_t x, int levels, uint64_t key)
{
    uint32_t y = 0;
    for (int level = 0; level < levels; level++) {
        uint32_t prefix = level ? x >> (32 - level) : 0u;
        uint32_t flip = node_flip(key, level, prefix);
        y |= (((x >> (31 - level)) & 1u) ^ flip) << (31 - level);
    }
    return y;
}

uint32_t sobol_shuffle(uint32_t index, int levels, uint64_t seed)
{
    /* the scrambled digits, from the most significant down, are the index's lowest `levels` */
    uint32_t low = nested_scramble(index << (32 - levels), levels, mix64(seed ^ 0x8EBC6AF09C88C6E3ull));
    return index >> levels << levels | low >> (32 - levels);
}

static uint64_t dimension_key(uint64_t seed, int dim)
{
    return mix64(seed ^ mix64((uint64_t)dim + 0x5851F42D4C957F2Dull));
}

/* The scrambled digits y (the top `levels` bits) completed below by random digits drawn from the
 * point's own prefix, as a double in [0, 1). */
static double with_low_digits(uint32_t y, int levels, uint64_t key)
{
    uint64_t prefix = levels < 32 ? y >> (32 - levels) : y;
    uint64_t low = mix64(key ^ 0xA0761D6478BD642Full ^ ((uint64_t)levels << 40) ^ prefix) >> (11 + levels);
    return (double)(prefix << (53 - levels) | low) * 0x1.0p-53;
}

double sobol_owen(uint32_t index, int dim, uint64_t seed, int levels)
{
    uint64_t key = dimension_key(seed, dim);
    return with_low_digits(nested_scramble(sobol_u32(index, dim), levels, key), levels, key);
}

void sobol_scramble_init(sobol_scramble *s, uint64_t seed, int levels)
{
    *s = (sobol_scramble){0};
    if (levels < 1 || levels > FM_SOBOL_TABLE_LEVELS)
        return;
    const uint32_t points = 1u << levels;
    /* scrambled[1 << l | p]: the scrambled digits of the prefix p of l digits (node of the tree) */
    uint32_t *scrambled = malloc(sizeof(uint32_t) * 2 * points);
    s->value = malloc(sizeof(double) * points * FM_SOBOL_DIMS);
    if (!scrambled || !s->value) {
        free(scrambled);
        free(s->value);
        s->value = NULL;
        return;
    }
    pthread_once(&once, build_direction_numbers);
    for (int d = 0; d < FM_SOBOL_DIMS; d++) {
        uint64_t key = dimension_key(seed, d);
        scrambled[1] = 0;
        for (int level = 0; level < levels; level++)
            for (uint32_t prefix = 0; prefix < 1u << level; prefix++) {
                uint32_t node = 1u << level | prefix, flip = node_flip(key, level, prefix);
                for (uint32_t digit = 0; digit < 2; digit++)
                    scrambled[2 * node + digit] = scrambled[node] << 1 | (digit ^ flip);
            }
        /* the points in Gray-code order g = i ^ (i >> 1): each coordinate one XOR from the last */
        uint32_t x = 0;
        for (uint32_t i = 0; i < points; i++) {
            if (i)
                x ^= V[d][__builtin_ctz(i)];
            uint32_t g = i ^ (i >> 1), y = scrambled[points | x >> (32 - levels)] << (32 - levels);
            s->value[(size_t)g * FM_SOBOL_DIMS + (size_t)d] = with_low_digits(y, levels, key);
        }
    }
    free(scrambled);
    s->levels = levels;
}

void sobol_scramble_free(sobol_scramble *s)
{
    free(s->value);
    *s = (sobol_scramble){0};
}
