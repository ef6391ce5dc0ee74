/* The table's grids and the integrals a consumer of its phase functions sees; kept apart from
 * the table lookup so that the generator links without a table. */
#include "aerosol/aerosol_optics.h"

#include "base/units.h"

#include <math.h>

double aerosol_optics_angle_rad(int j)
{
    double t = (double)j / (AEROSOL_ANGLE_COUNT - 1);
    return FM_PI * t * t;
}

double aerosol_optics_wavelength_nm(int i)
{
    return AEROSOL_FIRST_NM + AEROSOL_STEP_NM * i;
}

double aerosol_phase_integral(const float *phase, double *mean_cos)
{
    double total = 0.0, first = 0.0;
    double mu_a = cos(aerosol_optics_angle_rad(0));
    for (int j = 0; j + 1 < AEROSOL_ANGLE_COUNT; j++) {
        double mu_b = cos(aerosol_optics_angle_rad(j + 1)), pa = phase[j], pb = phase[j + 1];
        double h = mu_a - mu_b; /* > 0 */
        total += h * 0.5 * (pa + pb);
        /* exact integral of mu p(mu) for p linear between the nodes */
        first += h * (2.0 * mu_a * pa + mu_a * pb + mu_b * pa + 2.0 * mu_b * pb) / 6.0;
        mu_a = mu_b;
    }
    if (mean_cos)
        *mean_cos = 2.0 * FM_PI * first;
    return 2.0 * FM_PI * total;
}
