/* Periodic terms of NREL's Solar Position Algorithm (Reda & Andreas 2004, tables A4.2 and A4.3);
 * the values and their units are described in data/spa_terms.c. */
#ifndef FM_DATA_SPA_TERMS_H
#define FM_DATA_SPA_TERMS_H

#define SPA_L_COUNT 6 /* L0..L5 */
#define SPA_B_COUNT 2 /* B0, B1 */
#define SPA_R_COUNT 5 /* R0..R4 */
#define SPA_NUTATION_COUNT 63

/* One series: count rows of A, B, C for the term A cos(B + C JME). */
typedef struct spa_series {
    int count;
    const double (*terms)[3];
} spa_series;

typedef struct spa_nutation_term {
    int y[5];          /* multipliers of the fundamental arguments X0..X4 */
    double a, b, c, d; /* delta psi = (a + b JCE) sin(...), delta epsilon = (c + d JCE) cos(...), 1e-4 arcsec */
} spa_nutation_term;

extern const spa_series spa_l_series[SPA_L_COUNT];
extern const spa_series spa_b_series[SPA_B_COUNT];
extern const spa_series spa_r_series[SPA_R_COUNT];
extern const spa_nutation_term spa_nutation_terms[SPA_NUTATION_COUNT];

#endif
