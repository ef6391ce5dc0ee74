/* Phase functions of the atmosphere's constituents, behind one interface so the estimators never
 * depend on which kinds exist: a new kind (Henyey-Greenstein, tabulated Mie) is a new case here.
 * Convention: cos_theta is the cosine between the propagation directions before and after
 * scattering (1 = forward); every phase function integrates to 1 over the sphere, and sampling
 * draws cos_theta with exactly the density phase_evaluate gives (azimuth uniform). */
#ifndef FM_PHASE_PHASE_H
#define FM_PHASE_PHASE_H

#include "spectrum/spectral_grid.h"

typedef enum phase_kind {
    PHASE_NONE = 0, /* pure absorber: never scatters */
    PHASE_RAYLEIGH  /* param: gamma = rho / (2 - rho), phase/phase_rayleigh.h */
} phase_kind;

typedef struct phase_function {
    phase_kind kind;
    double param[FM_MAX_WAVELENGTHS]; /* per grid wavelength */
} phase_function;

/* Value (sr^-1) at grid wavelength k. */
double phase_evaluate(const phase_function *p, int k, double cos_theta);

/* cos_theta drawn from the phase function at grid wavelength k, from u uniform in [0, 1). */
double phase_sample(const phase_function *p, int k, double u);

#endif
