/* Mie optics of a log-normal population of homogeneous spheres, per particle.
 *
 * Size distribution (OPAC; Hess, Koepke & Schult 1998, eq. 1):
 *     dN/dln r = N / (sqrt(2 pi) ln sigma) exp(-(ln r - ln r_mod)^2 / (2 ln^2 sigma)),
 * truncated to [r_min, r_max].  N is the number of particles in the full (untruncated)
 * distribution, as in OPAC: the per-particle cross sections below are for one particle of the
 * full distribution, of which only those inside [r_min, r_max] scatter (tests/physics/test_opac.c
 * tells the two normalisations apart against OPAC's own tables; the truncated one is 3.7 % off
 * for waso, the full one within 0.5 %).
 *
 * Radius quadrature: the trapezoid rule in a variable u with du = dln r sqrt(1/d^2 + (x/h)^2),
 * i.e. steps of d in ln r for small spheres and of h in size parameter x for large ones (defaults
 * d = 0.02, h = 1).  The amplitudes of large spheres oscillate in x (interference of rays,
 * resonance ripple) with periods of a few units; a uniform step in x over a weight as smooth as
 * the log-normal averages them instead of aliasing them into the phase function.  Measured on
 * coarse sea salt at 99 % humidity, 300 nm, against h = 0.25: the phase function agrees within
 * 0.6 % at most angles, 2-4 % at a few side and backward angles (the rainbow and glory ripple);
 * h = 0.5 halves those and doubles the generator's time.
 *
 * Usage:
 *     lognormal_size d = {.r_mod_um = 0.0212, .sigma = 2.24, .r_min_um = 0.005, .r_max_um = 20};
 *     mie_lognormal_result r;
 *     mie_lognormal(&d, 0.55, 1.53 - 0.006 * I, NULL, 0, NULL, NULL, &r);  // r.ext_m2 = 3.9e-15 */
#ifndef FM_AEROSOL_MIE_LOGNORMAL_H
#define FM_AEROSOL_MIE_LOGNORMAL_H

#include <complex.h>

typedef struct lognormal_size {
    double r_mod_um;            /* mode radius of the number distribution (um) */
    double sigma;               /* geometric standard deviation (> 1) */
    double r_min_um, r_max_um;  /* truncation (um) */
} lognormal_size;

typedef struct mie_lognormal_quadrature {
    double step_ln_r; /* largest step in ln r */
    double step_x;    /* largest step in size parameter */
} mie_lognormal_quadrature;

/* The quadrature the tables use (tests may pass coarser or finer ones). */
mie_lognormal_quadrature mie_lognormal_default_quadrature(void);

typedef struct mie_lognormal_result {
    double ext_m2; /* extinction cross section per particle (m^2) */
    double sca_m2; /* scattering cross section per particle (m^2) */
    double g;      /* asymmetry parameter */
    int radii;     /* number of radius nodes used */
} mie_lognormal_result;

/* Optics at wavelength lambda_um (um) for index m = n - ik (k >= 0, see aerosol/mie.h).  When
 * n_mu > 0, phase[j] receives the phase function (sr^-1, normalised over the sphere) at
 * cos(theta) = mu[j].  quad may be NULL for the default.  Returns 0, or -1 on bad input or when
 * memory ran out. */
int mie_lognormal(const lognormal_size *size, double lambda_um, double complex m,
                  const mie_lognormal_quadrature *quad, int n_mu, const double *mu, double *phase,
                  mie_lognormal_result *out);

/* dN/dln r at r_um for one particle in the full distribution (ln-normal density). */
double lognormal_density(const lognormal_size *size, double r_um);

/* Cloud droplets: the modified gamma distribution (Deirmendjian 1969; OPAC's water clouds, Hess,
 * Koepke & Schult 1998)
 *     dN/dr = A r^alpha exp(-B r^gamma), r_min <= r <= r_max (r in um),
 * normalised to one particle inside [r_min, r_max].  gamma = 1 is the gamma distribution of Hansen &
 * Travis (1974, eq. 2.56) with effective radius r_eff = (alpha + 3) / B and effective variance
 * v_eff = 1 / (alpha + 3).  The same quadrature as the log-normal's, up to where r^4 dN/dln r (the
 * forward peak's weight) has fallen below 1e-9 of its peak. */
typedef struct modified_gamma_size {
    double alpha, b, gamma;    /* B in um^-gamma */
    double r_min_um, r_max_um;
} modified_gamma_size;

int mie_modified_gamma(const modified_gamma_size *size, double lambda_um, double complex m,
                       const mie_lognormal_quadrature *quad, int n_mu, const double *mu, double *phase,
                       mie_lognormal_result *out);

/* Effective radius <r^3> / <r^2> (um) and mean particle volume 4/3 pi <r^3> (um^3) of the truncated
 * distribution; 0 for an invalid one. */
double modified_gamma_effective_radius_um(const modified_gamma_size *size);
double modified_gamma_mean_volume_um3(const modified_gamma_size *size);

#endif
