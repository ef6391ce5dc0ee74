/* Phase functions of the atmosphere's constituents, behind one interface so the estimators never
 * depend on which kinds exist: a new kind is a new case here.
 * Convention: cos_theta is the cosine between the propagation directions before and after
 * scattering (1 = forward); every phase function integrates to 1 over the sphere, and sampling
 * draws cos_theta with exactly the density phase_evaluate gives (azimuth uniform). */
#ifndef FM_PHASE_PHASE_H
#define FM_PHASE_PHASE_H

#include "firmament/firmament.h"
#include "phase/phase_table.h"
#include "spectrum/spectral_grid.h"

typedef enum phase_kind {
    PHASE_NONE = 0,          /* pure absorber: never scatters */
    PHASE_RAYLEIGH,          /* param: gamma = rho / (2 - rho), phase/phase_rayleigh.h */
    PHASE_HENYEY_GREENSTEIN, /* param: asymmetry parameter g in (-1, 1) */
    PHASE_TABULATED          /* table: per grid wavelength, piecewise linear in cos_theta */
} phase_kind;

typedef struct phase_function {
    phase_kind kind;
    double param[FM_MAX_WAVELENGTHS]; /* per grid wavelength (Rayleigh, Henyey-Greenstein) */
    phase_table *table;               /* PHASE_TABULATED: owned, freed by phase_free */
} phase_function;

/* Builds a tabulated phase function from values[k * angle_count + j] at theta_rad[j] (ascending,
 * theta_rad[0] = 0, theta_rad[n-1] = pi), in any normalisation (each wavelength is renormalised).
 * Fails with FM_ERR_INVALID_ARGUMENT on non-finite or negative values, a zero integral or a bad
 * angle grid, FM_ERR_OUT_OF_MEMORY on allocation failure. */
fm_status phase_init_tabulated(phase_function *p, int wavelength_count, int angle_count, const double *theta_rad,
                               const double *values, fm_error *err);
/* Frees a tabulated phase function's table (any kind accepted; the kind is kept). */
void phase_free(phase_function *p);

/* Value (sr^-1) at grid wavelength k. */
double phase_evaluate(const phase_function *p, int k, double cos_theta);

/* Values (sr^-1) at grid wavelengths 0 .. K-1 (one table lookup for all of them). */
void phase_evaluate_all(const phase_function *p, int K, double cos_theta, double *out);

/* cos_theta drawn from the phase function at grid wavelength k, from u uniform in [0, 1). */
double phase_sample(const phase_function *p, int k, double u);

/* Asymmetry parameter (mean cos_theta) at grid wavelength k. */
double phase_asymmetry(const phase_function *p, int k);

#endif
