#include "phase/phase_hg.h"

double phase_hg_sample(double u, double g)
{
    /* With s = 2u - 1 the textbook inverse mu = (1 + g^2 - ((1 - g^2) / (1 + g s))^2) / (2 g) loses
     * every digit as g -> 0.  Expanding the square and dividing by 2 g by hand gives the same
     * function without the 1/g:
     *     mu = (s + g (3 - g^2 + (1 + g^2) s^2 + 2 g s) / 2) / (1 + g s)^2,
     * exact at s = -1 (mu = -1) and s = 1 (mu = 1) for every g, and mu = s at g = 0. */
    double s = 2.0 * u - 1.0;
    double t = 1.0 + g * s;
    double mu = (s + 0.5 * g * (3.0 - g * g + (1.0 + g * g) * s * s + 2.0 * g * s)) / (t * t);
    return mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu);
}
