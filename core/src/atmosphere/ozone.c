#include "atmosphere/ozone.h"

#include "atmosphere/ozone_profile.h"
#include "base/units.h"
#include "data/tables.h"
#include "spectrum/spectrum_table.h"


double ozone_cross_section_m2(double lambda_nm, double temperature_k)
{
    double dt = temperature_k - 273.15, c[3];
    if (!table_interpolate_uniform(&fm_ozone_bogumil_1nm[0][0], FM_OZONE_COUNT, 3, FM_OZONE_FIRST_NM, lambda_nm, c))
        return 0.0;
    double sigma_cm2 = (c[0] + c[1] * dt + c[2] * dt * dt) * 1e-20;
    return sigma_cm2 > 0.0 ? sigma_cm2 * FM_CM2 : 0.0;
}

double ozone_number_density_per_du(double altitude_m)
{
    return ozone_profile_density_per_du(OZONE_PROFILE_US_STANDARD, altitude_m);
}

double ozone_effective_temperature_k(void)
{
    return ozone_profile_effective_temperature_k(OZONE_PROFILE_US_STANDARD);
}
