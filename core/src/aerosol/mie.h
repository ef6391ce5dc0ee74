/* Lorenz-Mie scattering by one homogeneous sphere.
 *
 * Size parameter x = 2 pi r / lambda (in the surrounding medium), complex refractive index m
 * relative to that medium.  Sign convention: m = n - i k with k >= 0 for an absorbing sphere, as
 * in Wiscombe's MIEV0 and the OPAC tables (time dependence exp(+i omega t)).  An index written
 * n + i k (Bohren & Huffman) gives the same efficiencies; only the phases of S1, S2 flip sign.
 * As in MIEV0, a purely imaginary m (real part exactly 0) stands for a perfect conductor, the limit
 * |m| -> infinity.
 *
 * Method (Bohren & Huffman 1983, ch. 4; Wiscombe 1980, NCAR/TN-140+STR):
 *  - the logarithmic derivative D_n(mx) by downward recurrence from n = max(N, |mx|) + 16, which
 *    is stable for every m (also strongly absorbing or conductor-like spheres);
 *  - the Riccati-Bessel functions psi_n(x), xi_n(x) of the real argument by upward recurrence,
 *    which is accurate up to Wiscombe's term count N = x + 4.05 x^(1/3) + 2;
 *  - the angular functions pi_n, tau_n by their upward recurrence.
 * Nothing overflows for x up to 1e5: chi_n(x) stays moderate for n <= N.
 *
 * Usage:
 *     mie_result r;
 *     double complex s1[2], s2[2];
 *     double mu[2] = {1.0, -1.0};
 *     mie_sphere(10.0, 1.5 - 0.1 * I, 2, mu, s1, s2, &r);   // r.q_ext = 2.459791 */
#ifndef FM_AEROSOL_MIE_H
#define FM_AEROSOL_MIE_H

#include <complex.h>

typedef struct mie_result {
    double q_ext;  /* extinction efficiency C_ext / (pi r^2) */
    double q_sca;  /* scattering efficiency */
    double q_back; /* backscattering efficiency 4 |S1(180 deg)|^2 / x^2 */
    double g;      /* asymmetry parameter <cos theta> */
} mie_result;

/* Wiscombe's number of terms for size parameter x (> 0). */
int mie_term_count(double x);

/* The scattering coefficients a_n, b_n (n = 1..count, stored at index n - 1) for x > 0 and m != 0;
 * a and b hold at least mie_term_count(x) values.  Returns the number of terms. */
int mie_coefficients(double x, double complex m, double complex *a, double complex *b);

/* Efficiencies from the coefficients of mie_coefficients. */
mie_result mie_efficiencies(double x, int count, const double complex *a, const double complex *b);

/* Amplitudes S1(mu), S2(mu) at the cosines mu[0..n_mu-1] from the coefficients. */
void mie_amplitudes(int count, const double complex *a, const double complex *b, int n_mu, const double *mu,
                    double complex *s1, double complex *s2);

/* Everything for one sphere: efficiencies into *out and, when n_mu > 0, S1 and S2 at mu[].
 * Returns 0, or -1 when x or m is out of range (x <= 0, x > 1e5, Im m > 0) or memory ran out. */
int mie_sphere(double x, double complex m, int n_mu, const double *mu, double complex *s1, double complex *s2,
               mie_result *out);

/* Unpolarised phase function (sr^-1, integrates to 1 over the sphere) from S1, S2 at one angle. */
double mie_phase_function(double x, double q_sca, double complex s1, double complex s2);

#endif
