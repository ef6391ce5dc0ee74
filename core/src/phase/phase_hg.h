/* Henyey-Greenstein phase function (Henyey & Greenstein 1941), normalised over the sphere:
 *     p(cos_theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^(3/2)),
 * g = mean cos_theta in (-1, 1) (g > 0 forward scattering), cos_theta = cosine between the
 * propagation directions before and after scattering (1 = forward).  Sampling inverts the
 * cumulative distribution exactly, in a form that stays accurate as g -> 0 (and at g = 0). */
#ifndef FM_PHASE_PHASE_HG_H
#define FM_PHASE_PHASE_HG_H

#include "base/units.h"

#include <math.h>

static inline double phase_hg_eval(double cos_theta, double g)
{
    /* 1 + g^2 - 2 g mu written as (1 - g)^2 + 2 g (1 - mu): no cancellation in the forward peak */
    double d = (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - cos_theta);
    return (1.0 - g * g) / (4.0 * FM_PI * d * sqrt(d));
}

/* cos_theta with density phase_hg_eval, from u uniform in [0, 1) (u = 0 gives -1). */
double phase_hg_sample(double u, double g);

#endif
