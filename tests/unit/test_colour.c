/* Colour: CIE tables, spectrum -> XYZ -> linear Rec.709, and the spectral grid's quadrature. */
#include "check.h"

#include "colour/colour.h"
#include "spectrum/cie.h"
#include "spectrum/solar.h"
#include "spectrum/spectral_grid.h"

#include <math.h>

/* CIE standard illuminant D65, relative spectral power at 5 nm from 380 to 780 nm (ISO/CIE 11664-2,
 * Table B.1; every 5th value of the 1 nm table).  Its XYZ chromaticity is (0.3127, 0.3290). */
static const double d65_5nm[] = {
    49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204, 91.486,  92.4589, 93.4318, 90.057,  86.6823,
    95.7736, 104.865, 110.936, 117.008, 117.41,  117.812, 116.336, 114.861, 115.392, 115.923, 112.367,
    108.811, 109.082, 109.354, 108.578, 107.802, 106.296, 104.79,  106.239, 107.689, 106.047, 104.405,
    104.225, 104.046, 102.023, 100.0,   98.1671, 96.3342, 96.0611, 95.788,  92.2368, 88.6856, 89.3459,
    90.0062, 89.8026, 89.5991, 88.6489, 87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863,  80.0268,
    80.1207, 80.2146, 81.2462, 82.2778, 80.281,  78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979,
    74.349,  67.9765, 61.604,  65.7448, 69.8856, 72.4863, 75.087,  69.3398, 63.5927, 55.0054, 46.4182,
    56.6118, 66.8054, 65.0941, 63.3828};

static void d65_is_white_in_rec709(void **state)
{
    double lambda[81];
    for (int i = 0; i < 81; i++)
        lambda[i] = 380.0 + 5.0 * i;
    double xyz[3], rgb[3];
    cie_spectrum_to_xyz(lambda, d65_5nm, 81, xyz);
    double sum = xyz[0] + xyz[1] + xyz[2];
    check_abs(xyz[0] / sum, 0.3127, 2e-4, "D65 chromaticity x");
    check_abs(xyz[1] / sum, 0.3290, 2e-4, "D65 chromaticity y");
    colour_xyz_to_rec709(xyz, rgb);
    /* D65 is the white of Rec.709: equal R, G, B (to the precision of the 5 nm table) */
    check_rel(rgb[0], rgb[1], 2e-3, "R vs G for D65");
    check_rel(rgb[2], rgb[1], 2e-3, "B vs G for D65");
    check_rel(rgb[1], xyz[1], 2e-3, "G = Y for white");
}

static void matrices_round_trip_and_preserve_luminance(void **state)
{
    const double samples[4][3] = {{1, 0, 0}, {0.2, 0.5, 0.9}, {3.0, 1.0, 0.01}, {0.3127 / 0.329, 1.0, 0.3583 / 0.329}};
    for (int i = 0; i < 4; i++) {
        double rgb[3], back[3];
        colour_xyz_to_rec709(samples[i], rgb);
        colour_rec709_to_xyz(rgb, back);
        for (int c = 0; c < 3; c++)
            check_abs(back[c], samples[i][c], 1e-12, "XYZ round trip");
        /* Y is the luminance row of the Rec.709 -> XYZ matrix */
        check_abs(0.2126729 * rgb[0] + 0.7151522 * rgb[1] + 0.0721750 * rgb[2], samples[i][1], 1e-12, "Y from RGB");
    }
}

static void cie_table_peaks(void **state)
{
    double xyz[3];
    cie_xyz_at(555.0, xyz);
    check_abs(xyz[1], 1.0, 1e-6, "y(555 nm)");
    cie_xyz_at(600.0, xyz);
    check_abs(xyz[0], 1.0622, 1e-4, "x(600 nm)"); /* CVRL ciexyz31_1: 1.062200 */
    cie_xyz_at(449.0, xyz);
    check_abs(xyz[2], 1.78, 0.03, "z near its 445 nm peak");
}

static void solar_spectrum_values(void **state)
{
    check_abs(solar_irradiance_at(550.0), 1.863, 1e-3, "ASTM G173 ETR at 550 nm (W m-2 nm-1)");
    /* integral over 300-1000 nm: about 1366 * 0.7 W/m2 (the visible and near-IR part) */
    double total = 0.0;
    for (double l = 300.0; l < 1000.0; l += 0.5)
        total += 0.5 * solar_irradiance_at(l + 0.25);
    assert_true(total > 880.0 && total < 1000.0);
}

static void spectral_grid_integrates_like_1nm(void **state)
{
    /* A sky-like spectrum E(l) * l^-4 * exp(-0.1 (l/550)^-4): the 10 nm grid with the solar spectrum in
     * its weights must give the XYZ of a 1 nm integration to 0.1%. */
    spectral_grid g;
    spectral_grid_visible(&g);
    assert_int_equal(g.count, 41);
    double values[FM_MAX_WAVELENGTHS], xyz[3];
    for (int k = 0; k < g.count; k++) {
        double l = g.lambda_nm[k], s = pow(l / 550.0, -4.0);
        values[k] = g.solar_irradiance[k] * s * exp(-0.1 * s);
    }
    spectral_grid_to_xyz(&g, values, xyz);
    double ref[3] = {0, 0, 0};
    for (int l = 380; l <= 780; l++) {
        double c[3], s = pow(l / 550.0, -4.0), w = (l == 380 || l == 780) ? 0.5 : 1.0;
        cie_xyz_at(l, c);
        for (int j = 0; j < 3; j++)
            ref[j] += w * c[j] * solar_irradiance_at(l) * s * exp(-0.1 * s);
    }
    for (int j = 0; j < 3; j++)
        check_rel(xyz[j], ref[j], 1e-3, "XYZ from the 10 nm grid vs 1 nm");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(d65_is_white_in_rec709),
        cmocka_unit_test(matrices_round_trip_and_preserve_luminance),
        cmocka_unit_test(cie_table_peaks),
        cmocka_unit_test(solar_spectrum_values),
        cmocka_unit_test(spectral_grid_integrates_like_1nm),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
