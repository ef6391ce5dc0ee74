/* Quasi-Monte Carlo points: the Sobol sequence (I. M. Sobol 1967) with the direction numbers of
 * S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional projections",
 * SIAM J. Sci. Comput. 30 (2008) 2635-2654 (file new-joe-kuo-6.21201), randomised by a nested
 * uniform (Owen 1995) scramble.  Each scrambled point is uniform on the unit cube, so estimates stay
 * unbiased, while any one coordinate of the first 2^m points is stratified into 2^m equal cells. */
#ifndef FM_BASE_SOBOL_H
#define FM_BASE_SOBOL_H

#include <stddef.h>
#include <stdint.h>

#define FM_SOBOL_DIMS 16

/* Coordinate `dim` (< FM_SOBOL_DIMS) of point `index`, unscrambled: a 32-bit fraction. */
uint32_t sobol_u32(uint32_t index, int dim);

/* Coordinate `dim` of point `index` under the nested uniform scramble drawn from `seed` (one
 * independent scramble per seed and dimension), as a double in [0, 1) with 53 bits.  `levels`
 * (1 to 32) binary digits are scrambled digit by digit; with every index below 2^levels each point
 * has its own prefix of that length, and the digits below become independent random digits, which
 * is what the scramble amounts to there (sobol_levels gives the count for a number of points). */
double sobol_owen(uint32_t index, int dim, uint64_t seed, int levels);
int sobol_levels(uint64_t points);

/* The scramble of one seed tabulated: sobol_owen hashes every digit of every coordinate (a tenth of
 * a multiple-scattering path's instructions), while a table holds every coordinate of the 2^levels
 * points already scrambled, built in one pass over the binary tree's nodes (each hashed once) and the
 * points in Gray-code order (one XOR each), for 16 x 2^levels x 8 bytes (64 kB at 512 points, 1 MB
 * at 8192; docs/decisions/2026-12-06-random-numbers-and-lookups.md). */
#define FM_SOBOL_TABLE_LEVELS 13
typedef struct sobol_scramble {
    int levels;    /* 0: no table (more levels than FM_SOBOL_TABLE_LEVELS, or no memory for it) */
    double *value; /* [index][dim]: sobol_owen(index, dim, seed, levels) */
} sobol_scramble;

/* The table of sobol_owen's scramble for `seed` and `levels`; levels 0 if it needs more than
 * FM_SOBOL_TABLE_LEVELS or its memory cannot be had (the caller then hashes: the same numbers).
 * sobol_scramble_free releases it. */
void sobol_scramble_init(sobol_scramble *s, uint64_t seed, int levels);
void sobol_scramble_free(sobol_scramble *s);

/* sobol_owen(index, dim, seed, levels) of the table's seed and levels, bit for bit; index below
 * 2^levels. */
static inline double sobol_owen_tabulated(const sobol_scramble *s, uint32_t index, int dim)
{
    return s->value[(size_t)index * FM_SOBOL_DIMS + (size_t)dim];
}

/* A bijection of [0, 2^levels), levels 1 to 31, drawn from seed (a nested uniform scramble of the index's digits),
 * so that samples 0 .. N-1 still use points 0 .. N-1 of the sequence (N a power of 2) but in an
 * order unrelated to the sample number. */
uint32_t sobol_shuffle(uint32_t index, int levels, uint64_t seed);

#endif
