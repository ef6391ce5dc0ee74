/* Quasi-Monte Carlo points: the Sobol sequence (I. M. Sobol 1967) with the direction numbers of
 * S. Joe and F. Y. Kuo, "Constructing Sobol sequences with better two-dimensional projections",
 * SIAM J. Sci. Comput. 30 (2008) 2635-2654 (file new-joe-kuo-6.21201), randomised by a nested
 * uniform (Owen 1995) scramble.  Each scrambled point is uniform on the unit cube, so estimates stay
 * unbiased, while any one coordinate of the first 2^m points is stratified into 2^m equal cells. */
#ifndef FM_BASE_SOBOL_H
#define FM_BASE_SOBOL_H

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

/* A bijection of [0, 2^levels), levels 1 to 31, drawn from seed (a nested uniform scramble of the index's digits),
 * so that samples 0 .. N-1 still use points 0 .. N-1 of the sequence (N a power of 2) but in an
 * order unrelated to the sample number. */
uint32_t sobol_shuffle(uint32_t index, int levels, uint64_t seed);

#endif
