/* The measure of a map's noise from two seeds (bench/seed_noise.h), which test_twilight and
 * bench/bench.sh --twilight use to say that a map is noise-free:
 *  - CIEDE2000 against the 34 pairs of Sharma, Wu & Dalal (2005), "The CIEDE2000 color-difference
 *    formula: implementation notes, supplementary test data, and mathematical observations", Color
 *    Research and Application 30(1), 21-30, Table 1 (published to 4 decimals);
 *  - on maps made for it: two maps a uniform 2% apart have one map's noise log(1.02) / sqrt 2, no
 *    grain and no colour change; a map whose pixels alternate 2% up and down has it all as grain;
 *    the display difference of two greys 2% apart is the CIEDE2000 of their CIELAB. */
#include "check.h"
#include "seed_noise.h"

#include <math.h>

static const double SHARMA_2005[34][7] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};

static void ciede2000_matches_sharma_2005(void **state)
{
    double worst = 0.0;
    for (int i = 0; i < 34; i++) {
        const double *c = SHARMA_2005[i];
        double de = seed_noise_ciede2000(c, c + 3), back = seed_noise_ciede2000(c + 3, c);
        worst = fmax(worst, fabs(de - c[6]));
        check_abs(back, de, 1e-12, "CIEDE2000: symmetric");
    }
    print_message("CIEDE2000 against Sharma et al. 2005: worst difference %.2e over 34 pairs\n", worst);
    /* half a unit of the published 4th decimal (pair 23 is 1.0000495 to full precision), and float slack */
    check_abs(worst, 0.0, 5.1e-5, "CIEDE2000: Sharma et al. 2005, Table 1");
}

/* A grey equirect map (XYZ of D65 white times v) of 64 x 32 pixels, pixel (x, y) scaled by f(x). */
static fm_image *grey_map(double v, double up, double down)
{
    fm_image *m = image_create(64, 32, 3, FM_IMAGE_XYZ, 0, 0);
    assert_non_null(m);
    const double white[3] = {0.95047, 1.0, 1.08883};
    for (int y = 0; y < m->height; y++)
        for (int x = 0; x < m->width; x++)
            for (int c = 0; c < 3; c++)
                m->pixels[3 * ((size_t)y * m->width + x) + c] = (float)(v * white[c] * (x % 2 ? down : up));
    return m;
}

static double lab_f(double t) { return t > 216.0 / 24389.0 ? cbrt(t) : (24389.0 / 27.0 * t + 16.0) / 116.0; }

static void measures_maps_made_for_it(void **state)
{
    fm_image *a = grey_map(0.18, 1.0, 1.0), *b = grey_map(0.18, 1.02, 1.02), *c = grey_map(0.18, 1.02, 1.0 / 1.02);
    seed_noise n;
    assert_int_equal(seed_noise_measure(a, b, 0.0, &n), 0);
    check_rel(n.luminance, log(1.02) / sqrt(2.0), 1e-4, "uniform 2%: one map's noise");
    check_abs(n.grain, 0.0, 1e-6, "uniform 2%: no grain");
    check_abs(n.red_green, 0.0, 1e-5, "uniform 2%: no R / G change");
    check_abs(n.blue_green, 0.0, 1e-5, "uniform 2%: no B / G change");
    /* two greys, Y = 0.18 and 0.1836: CIELAB differs in L* alone */
    double la[3] = {116.0 * lab_f(0.18) - 16.0, 0.0, 0.0}, lb[3] = {116.0 * lab_f(0.18 * 1.02) - 16.0, 0.0, 0.0};
    check_rel(n.de_mean, seed_noise_ciede2000(la, lb), 2e-3, "uniform 2%: CIEDE2000 as displayed");
    check_rel(n.de_p99, n.de_mean, 1e-6, "uniform 2%: the same everywhere");
    assert_int_equal(seed_noise_measure(a, c, 0.0, &n), 0);
    check_rel(n.grain, log(1.02), 1e-3, "alternating 2%: all grain");
    check_rel(n.luminance, log(1.02) / sqrt(2.0), 1e-3, "alternating 2%: one map's noise");
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_image_destroy(c);
}

static void refuses_maps_of_two_sizes(void **state)
{
    fm_image *a = grey_map(0.18, 1.0, 1.0), *b = image_create(32, 16, 3, FM_IMAGE_XYZ, 0, 0);
    seed_noise n;
    assert_int_equal(seed_noise_measure(a, b, 0.0, &n), 1);
    fm_image_destroy(a);
    fm_image_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ciede2000_matches_sharma_2005),
        cmocka_unit_test(measures_maps_made_for_it),
        cmocka_unit_test(refuses_maps_of_two_sizes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
