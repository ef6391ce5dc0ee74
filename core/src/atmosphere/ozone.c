#include "atmosphere/ozone.h"

#include "atmosphere/standard_atmosphere.h"
#include "base/units.h"
#include "data/tables.h"
#include "spectrum/spectrum_table.h"

#include <math.h>
#include <pthread.h>

double ozone_cross_section_m2(double lambda_nm, double temperature_k)
{
    double dt = temperature_k - 273.15, c[3];
    if (!table_interpolate_uniform(&fm_ozone_bogumil_1nm[0][0], FM_OZONE_COUNT, 3, FM_OZONE_FIRST_NM, lambda_nm, c))
        return 0.0;
    double sigma_cm2 = (c[0] + c[1] * dt + c[2] * dt * dt) * 1e-20;
    return sigma_cm2 > 0.0 ? sigma_cm2 * FM_CM2 : 0.0;
}

/* Profile shape: log-linear interpolation of the AFGL levels (ozone varies exponentially between
 * them), normalised to a 1 DU column. */
static double afgl_density(double altitude_m)
{
    double z_km = altitude_m / FM_KM;
    const int n = FM_OZONE_PROFILE_COUNT;
    if (z_km <= fm_ozone_profile_afgl_us[0][0])
        return fm_ozone_profile_afgl_us[0][1];
    if (z_km >= fm_ozone_profile_afgl_us[n - 1][0])
        return fm_ozone_profile_afgl_us[n - 1][1];
    int i = 0;
    while (i < n - 2 && fm_ozone_profile_afgl_us[i + 1][0] <= z_km)
        i++;
    double z0 = fm_ozone_profile_afgl_us[i][0], z1 = fm_ozone_profile_afgl_us[i + 1][0];
    double n0 = fm_ozone_profile_afgl_us[i][1], n1 = fm_ozone_profile_afgl_us[i + 1][1];
    double t = (z_km - z0) / (z1 - z0);
    return n0 * pow(n1 / n0, t);
}

/* Column of the AFGL profile from 0 to 100 km in molecules m^-2, exact for the log-linear form. */
static double afgl_column(void)
{
    double total = 0.0;
    for (int i = 0; i + 1 < FM_OZONE_PROFILE_COUNT; i++) {
        double z0 = fm_ozone_profile_afgl_us[i][0], z1 = fm_ozone_profile_afgl_us[i + 1][0];
        if (z0 >= FM_ATMOSPHERE_HEIGHT_M / FM_KM)
            break;
        double n0 = fm_ozone_profile_afgl_us[i][1], n1 = fm_ozone_profile_afgl_us[i + 1][1];
        double dz = (z1 - z0) * FM_KM;
        total += (n0 == n1) ? n0 * dz : (n1 - n0) / log(n1 / n0) * dz;
    }
    return total;
}

static double per_du_scale;
static pthread_once_t scale_once = PTHREAD_ONCE_INIT;

static void init_scale(void)
{
    per_du_scale = FM_DU_MOLECULES_PER_M2 / afgl_column();
}

double ozone_number_density_per_du(double altitude_m)
{
    pthread_once(&scale_once, init_scale);
    return afgl_density(altitude_m) * per_du_scale;
}

double ozone_effective_temperature_k(void)
{
    /* trapezoid over 100 m steps of n(z) T(z) / n(z) */
    double num = 0.0, den = 0.0;
    const double dz = 100.0;
    for (double z = 0.0; z <= FM_ATMOSPHERE_HEIGHT_M; z += dz) {
        double w = (z == 0.0 || z + dz > FM_ATMOSPHERE_HEIGHT_M) ? 0.5 : 1.0;
        double n = afgl_density(z);
        num += w * n * us76_temperature_k(z);
        den += w * n;
    }
    return num / den;
}
