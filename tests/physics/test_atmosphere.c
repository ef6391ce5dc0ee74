/* The molecular atmosphere and ozone against published numbers. */
#include "check.h"

#include "atmosphere/ozone.h"
#include "atmosphere/rayleigh.h"
#include "atmosphere/standard_atmosphere.h"
#include "base/units.h"

#include <math.h>

/* U.S. Standard Atmosphere 1976 air number densities (m^-3) at 0, 11, 20 and 50 km, as tabulated in
 * AFGL-TR-86-0110 (Anderson et al. 1986, U.S. Standard profile, file afglus.dat). */
static void us76_number_density_matches_the_standard(void **state)
{
    const double z_km[] = {0, 11, 20, 50};
    const double n_ref[] = {2.545818e25, 7.583652e24, 1.847990e24, 2.134605e22};
    for (int i = 0; i < 4; i++)
        check_rel(us76_number_density(z_km[i] * FM_KM), n_ref[i], 5e-3, "US76 number density");
    /* defining values: sea level and the 11 km and 20 km geopotential layer bases
     * (geometric 11019 m and 20063 m): 288.15 K / 101325 Pa, 216.65 K / 22632 Pa, 216.65 K / 5474.9 Pa */
    check_abs(us76_temperature_k(0.0), 288.15, 1e-9, "T(0)");
    check_abs(us76_pressure_pa(0.0), 101325.0, 1e-6, "p(0)");
    check_rel(us76_temperature_k(11019.1), 216.65, 1e-5, "T at 11 km geopotential");
    check_rel(us76_pressure_pa(11019.1), 22632.06, 1e-4, "p at 11 km geopotential");
    check_rel(us76_pressure_pa(20063.1), 5474.889, 1e-4, "p at 20 km geopotential");
    check_rel(us76_temperature_k(50000.0), 270.65, 1e-4, "T(50 km)");
}

/* Rayleigh optical depth of the whole standard atmosphere: 0.360 / 0.0970 / 0.0364 at 400 / 550 /
 * 700 nm (PHYSICS.md section 2.4: Bucholtz cross section x the U.S. Standard air column). */
static void rayleigh_optical_depth(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    p.ozone_column_du = 0.0;
    fm_sky *sky = test_sky(&p);
    double col[FM_MAX_SPECIES];
    column_exact(&sky->atm, sky->atm.bottom_radius_m, 1.0, FM_ATMOSPHERE_HEIGHT_M, col);
    check_rel(col[0], 2.1525e29, 5e-3, "vertical air column (m^-2, AFGL 2.1525e25 cm^-2)");
    const double lambda[] = {400, 550, 700}, tau[] = {0.360, 0.0970, 0.0364};
    for (int i = 0; i < 3; i++)
        check_rel(rayleigh_cross_section_m2(lambda[i]) * col[0], tau[i], 0.01, "Rayleigh optical depth");
    /* Bucholtz fit value and the depolarisation of air (rho about 0.028-0.03 in the visible) */
    check_rel(rayleigh_cross_section_m2(550.0), 4.507e-31, 2e-3, "sigma_R(550 nm) m^2");
    double rho = rayleigh_depolarization_ratio(550.0);
    assert_true(rho > 0.027 && rho < 0.031);
    check_rel(rayleigh_gamma(550.0), 0.01442, 0.01, "gamma(550 nm) vs Bucholtz 1995 Table 1 (0.01442)");
    fm_sky_destroy(sky);
}

static void ozone_column_and_cross_section(void **state)
{
    /* Bogumil et al. (2003): sigma(600 nm, 273 K) = 5.24e-21 cm^2 (PHYSICS.md section 4.1) */
    check_rel(ozone_cross_section_m2(600.0, 273.15), 5.24e-25, 5e-3, "sigma_O3(600 nm, 273 K)");
    double t_eff = ozone_effective_temperature_k();
    assert_true(t_eff > 215.0 && t_eff < 235.0);
    fm_sky_params p = test_params(30.0, 600.0);
    p.ozone_column_du = 300.0;
    fm_sky *sky = test_sky(&p);
    assert_int_equal(sky->atm.species_count, 2);
    double col[FM_MAX_SPECIES];
    column_exact(&sky->atm, sky->atm.bottom_radius_m, 1.0, FM_ATMOSPHERE_HEIGHT_M, col);
    check_rel(col[1], 300.0 * FM_DU_MOLECULES_PER_M2, 2e-3, "ozone column = 300 DU");
    /* 300 DU x 5.0e-21 cm^2 ~ 0.040 (PHYSICS.md section 6); published cross sections at 600 nm span
     * 4.9-5.25e-21 cm^2, so 0.038-0.044 */
    double tau = sky->atm.species[1].sigma_a[0] * col[1];
    assert_true(tau > 0.038 && tau < 0.044);
    print_message("ozone optical depth at 600 nm, 300 DU: %.4f\n", tau);
    /* the profile peaks in the 20-30 km layer */
    double best = 0.0, z_best = 0.0;
    for (double z = 0.0; z < 60000.0; z += 100.0) {
        double n = ozone_number_density_per_du(z);
        if (n > best)
            best = n, z_best = z;
    }
    assert_true(z_best >= 20000.0 && z_best <= 30000.0);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(us76_number_density_matches_the_standard),
        cmocka_unit_test(rayleigh_optical_depth),
        cmocka_unit_test(ozone_column_and_cross_section),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
