/* Adding-doubling: a deterministic solution of the plane-parallel radiative transfer equation for
 * one homogeneous layer over a Lambertian ground, lit by a parallel solar beam (Hansen & Travis 1974,
 * Space Sci. Rev. 16, 527, section 2.6; van de Hulst 1980, "Multiple Light Scattering", ch. 4).
 * It is the independent reference the tests compare the path tracer with in optically thick media;
 * nothing of the renderer is used
 * but the Gauss-Legendre rule (base/quadrature.h).
 *
 * Method.  The radiance is split into azimuthal Fourier modes; for each mode the layer's reflection
 * and transmission kernels R(mu, mu'), T(mu, mu') are known on Gauss nodes (N per hemisphere) plus the
 * view cosines and the sun's, which enter with zero weight (so their rows and columns are computed
 * without changing the integrals).  A layer of optical depth tau / 2^k (< 1e-6) is initialised by
 * single scattering and doubled k times.  The phase function is expanded in 2N Legendre moments; with
 * delta_m the forward peak beyond them is truncated (delta-M, Wiscombe 1977, J. Atmos. Sci. 34, 1408)
 * and the single-scattered radiance is replaced by its exact value with the untruncated phase
 * function (the TMS correction of Nakajima & Tanaka 1988, JQSRT 40, 51).  Without delta_m the
 * expansion is simply truncated: use it only where the moments have decayed (HG g^2N << 1e-6).
 *
 * Units: solar irradiance F0 = 1 on a surface normal to the beam; radiances are per unit F0 (so
 * pi L / mu0 is van de Hulst's reflection function R), fluxes per unit incident flux mu0 F0. */
#ifndef FM_TEST_ADDING_DOUBLING_H
#define FM_TEST_ADDING_DOUBLING_H

/* the phase function at the cosine of the scattering angle, any normalisation */
typedef double (*ad_phase_fn)(double cos_theta, const void *ctx);

typedef struct ad_problem {
    double tau;           /* vertical optical depth */
    double ssa;           /* single-scattering albedo, [0, 1] */
    double ground_albedo; /* Lambertian, [0, 1] */
    double mu0;           /* cosine of the solar zenith angle, (0, 1] */
    ad_phase_fn phase;
    const void *phase_ctx;
    int streams;          /* Gauss nodes per hemisphere, N in [2, 64] (2N Legendre moments) */
    int delta_m;          /* 1: delta-M truncation + exact single scattering */
    int n_mu;             /* view cosines, each in (0, 1] */
    const double *mu;
} ad_problem;

typedef struct ad_solution {
    ad_problem p;      /* a copy; p.mu points into the solution */
    int modes;         /* Fourier modes kept, 2N */
    double *bottom;    /* [n_mu][modes]: modes of the diffuse downward radiance at the bottom */
    double *top;       /* [n_mu][modes]: modes of the upward radiance at the top */
    double f;          /* delta-M truncated fraction (0 without delta_m) */
    double tau_scaled, ssa_scaled;
    double *moments;   /* [modes]: truncated, renormalised Legendre moments of the scaled phase */
    double phase_scale;  /* p.phase times this is normalised to 1 over 4 pi steradians */
    double flux_down_direct;  /* at the bottom, per mu0 F0: exp(-tau / mu0) */
    double flux_down_diffuse; /* at the bottom, per mu0 F0, ground reflections included */
    double flux_up_top;       /* at the top, per mu0 F0 (the layer-ground system's albedo) */
    double flux_up_bottom;    /* leaving the ground, per mu0 F0 */
} ad_solution;

/* Solves; returns 0, or -1 on invalid input or no memory.  Free with ad_free. */
int ad_solve(const ad_problem *p, ad_solution *s);
void ad_free(ad_solution *s);

/* Radiance (per unit F0) at the bottom looking up, or at the top looking down, at the k-th view
 * cosine and azimuth phi (radians) from the sun's azimuth (phi = 0: toward the sun's side). */
double ad_radiance_bottom(const ad_solution *s, int k, double phi);
double ad_radiance_top(const ad_solution *s, int k, double phi);

/* Henyey-Greenstein at *(const double *)ctx = g, normalised to 1 over 4 pi steradians. */
double ad_phase_hg(double cos_theta, const void *ctx);

#endif
