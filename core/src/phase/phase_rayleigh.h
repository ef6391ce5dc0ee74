/* Rayleigh phase function with depolarisation (Chandrasekhar; Bucholtz 1995, eq. 11), normalised
 * over the sphere (integral of p dOmega = 1):
 *     p(cos_theta) = 3 / (16 pi) * ((1 + 3 gamma) + (1 - gamma) cos^2 theta) / (1 + 2 gamma),
 * cos_theta = cosine between the propagation directions before and after scattering (1 = forward).
 * Sampling inverts the cumulative distribution of cos_theta exactly (a cubic, solved in closed form),
 * so the pdf of a sampled direction equals phase_rayleigh_eval. */
#ifndef FM_PHASE_PHASE_RAYLEIGH_H
#define FM_PHASE_PHASE_RAYLEIGH_H

#include "base/units.h"

#include <math.h>

static inline double phase_rayleigh_eval(double cos_theta, double gamma)
{
    return 3.0 / (16.0 * FM_PI) * ((1.0 + 3.0 * gamma) + (1.0 - gamma) * cos_theta * cos_theta) / (1.0 + 2.0 * gamma);
}

/* cos_theta with density proportional to phase_rayleigh_eval, from u uniform in [0, 1). */
double phase_rayleigh_sample(double u, double gamma);

#endif
