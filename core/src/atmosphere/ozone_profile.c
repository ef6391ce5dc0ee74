#include "atmosphere/ozone_profile.h"

#include "base/quadrature.h"
#include "base/units.h"
#include "data/tables.h"

#include <math.h>
#include <pthread.h>

_Static_assert(OZONE_PROFILE_COUNT == FM_AFGL_PROFILE_COUNT, "one AFGL table per ozone profile");

enum { LEVEL_Z_KM, LEVEL_T_K, LEVEL_O3 };

static int valid(ozone_profile p)
{
    return (int)p >= 0 && p < OZONE_PROFILE_COUNT;
}

ozone_profile ozone_profile_for(double latitude_deg, int day_of_year)
{
    double band = fabs(latitude_deg);
    if (band < 23.0)
        return OZONE_PROFILE_TROPICAL;
    int northern_summer =
        day_of_year >= OZONE_NORTHERN_SUMMER_FIRST_DAY && day_of_year <= OZONE_NORTHERN_SUMMER_LAST_DAY;
    int summer = latitude_deg > 0.0 ? northern_summer : !northern_summer;
    if (band <= 60.0)
        return summer ? OZONE_PROFILE_MIDLATITUDE_SUMMER : OZONE_PROFILE_MIDLATITUDE_WINTER;
    return summer ? OZONE_PROFILE_SUBARCTIC_SUMMER : OZONE_PROFILE_SUBARCTIC_WINTER;
}

const char *ozone_profile_name(ozone_profile p)
{
    static const char *const names[OZONE_PROFILE_COUNT] = {
        "us-standard", "tropical", "midlatitude-summer", "midlatitude-winter", "subarctic-summer", "subarctic-winter",
    };
    return valid(p) ? names[p] : NULL;
}

/* Index i of the layer [z_i, z_i+1] holding z_km (levels ascend; clamped to the first/last layer). */
static int layer_of(const double (*lv)[3], double z_km)
{
    int i = 0;
    while (i < FM_AFGL_LEVEL_COUNT - 2 && lv[i + 1][LEVEL_Z_KM] <= z_km)
        i++;
    return i;
}

/* Tabulated density (m^-3), log-linear between levels: ozone varies roughly exponentially between
 * them. */
static double raw_density(const double (*lv)[3], double z_km)
{
    if (z_km <= lv[0][LEVEL_Z_KM])
        return lv[0][LEVEL_O3];
    if (z_km >= lv[FM_AFGL_LEVEL_COUNT - 1][LEVEL_Z_KM])
        return lv[FM_AFGL_LEVEL_COUNT - 1][LEVEL_O3];
    int i = layer_of(lv, z_km);
    double t = (z_km - lv[i][LEVEL_Z_KM]) / (lv[i + 1][LEVEL_Z_KM] - lv[i][LEVEL_Z_KM]);
    return lv[i][LEVEL_O3] * pow(lv[i + 1][LEVEL_O3] / lv[i][LEVEL_O3], t);
}

static double raw_temperature(const double (*lv)[3], double z_km)
{
    if (z_km <= lv[0][LEVEL_Z_KM])
        return lv[0][LEVEL_T_K];
    if (z_km >= lv[FM_AFGL_LEVEL_COUNT - 1][LEVEL_Z_KM])
        return lv[FM_AFGL_LEVEL_COUNT - 1][LEVEL_T_K];
    int i = layer_of(lv, z_km);
    double t = (z_km - lv[i][LEVEL_Z_KM]) / (lv[i + 1][LEVEL_Z_KM] - lv[i][LEVEL_Z_KM]);
    return lv[i][LEVEL_T_K] + t * (lv[i + 1][LEVEL_T_K] - lv[i][LEVEL_T_K]);
}

/* Per profile, over the ground to the top of the atmosphere: the column (molecules m^-2, exact for
 * the log-linear form) and the ozone-weighted temperature (Gauss-Legendre in each layer). */
static double column_m2[OZONE_PROFILE_COUNT], t_eff_k[OZONE_PROFILE_COUNT];
static pthread_once_t init_once = PTHREAD_ONCE_INIT;

static void init_profiles(void)
{
    const gauss_rule *g = gauss_legendre_cached(8);
    const double top_km = FM_ATMOSPHERE_HEIGHT_M / FM_KM;
    for (int p = 0; p < OZONE_PROFILE_COUNT; p++) {
        const double(*lv)[3] = fm_afgl_profiles[p];
        double col = 0.0, col_t = 0.0;
        for (int i = 0; i + 1 < FM_AFGL_LEVEL_COUNT && lv[i][LEVEL_Z_KM] < top_km; i++) {
            double z0 = lv[i][LEVEL_Z_KM], z1 = fmin(lv[i + 1][LEVEL_Z_KM], top_km);
            double n0 = lv[i][LEVEL_O3], n1 = raw_density(lv, z1), dz = (z1 - z0) * FM_KM;
            col += (n0 == n1) ? n0 * dz : (n1 - n0) / log(n1 / n0) * dz;
            for (int k = 0; k < g->n; k++) {
                double z = z0 + 0.5 * (z1 - z0) * (g->x[k] + 1.0);
                col_t += 0.5 * dz * g->w[k] * raw_density(lv, z) * raw_temperature(lv, z);
            }
        }
        column_m2[p] = col;
        t_eff_k[p] = col_t / col;
    }
}

double ozone_profile_density_per_du(ozone_profile p, double altitude_m)
{
    if (!valid(p))
        return 0.0;
    pthread_once(&init_once, init_profiles);
    return raw_density(fm_afgl_profiles[p], altitude_m / FM_KM) * (FM_DU_MOLECULES_PER_M2 / column_m2[p]);
}

double ozone_profile_effective_temperature_k(ozone_profile p)
{
    if (!valid(p))
        return 0.0;
    pthread_once(&init_once, init_profiles);
    return t_eff_k[p];
}

double ozone_profile_tabulated_column_du(ozone_profile p)
{
    if (!valid(p))
        return 0.0;
    pthread_once(&init_once, init_profiles);
    return column_m2[p] / FM_DU_MOLECULES_PER_M2;
}
