/* Reproducibility: the same seed gives the same bits whatever the thread count; different seeds,
 * and different wavelengths, draw independent random numbers.  (Rendering every wavelength with
 * the same random numbers correlates their noise, so it never averages out in colour.) */
#include "check.h"

#include <math.h>
#include <string.h>

static int same_pixels(const fm_image *a, const fm_image *b)
{
    size_t n = (size_t)a->width * a->height * a->channels;
    return a->width == b->width && memcmp(a->pixels, b->pixels, n * sizeof(float)) == 0;
}

static void same_bits_for_any_thread_count(double sun_elevation)
{
    fm_sky_params p = test_params(sun_elevation, 0.0);
    fm_sky *sky = test_sky(&p);
    for (int q = 0; q < 2; q++) {
        fm_quality quality = q ? FM_QUALITY_REFERENCE : FM_QUALITY_PREVIEW;
        int width = q ? 16 : 64;
        fm_image *one = test_render(sky, width, quality, 1, 5, 64, 0.25, 1);
        fm_image *two = test_render(sky, width, quality, 2, 5, 64, 0.25, 1);
        fm_image *three = test_render(sky, width, quality, 3, 5, 64, 0.25, 1);
        assert_true(same_pixels(one, two));
        assert_true(same_pixels(one, three));
        fm_image *other = test_render(sky, width, quality, 2, 6, 64, 0.25, 1);
        assert_false(same_pixels(one, other)); /* another seed, other numbers */
        fm_image_destroy(one);
        fm_image_destroy(two);
        fm_image_destroy(three);
        fm_image_destroy(other);
    }
    fm_sky_destroy(sky);
}

static void thread_count_does_not_change_the_bits(void **state) { same_bits_for_any_thread_count(25.0); }
/* twilight: the sky guide is built on the render's threads, the paths use it (transport/twilight.h) */
static void thread_count_does_not_change_the_bits_at_twilight(void **state) { same_bits_for_any_thread_count(-3.0); }
/* deep twilight: the guided flights' table too (transport/shadow_flight.h) */
static void thread_count_does_not_change_the_bits_in_deep_twilight(void **state) { same_bits_for_any_thread_count(-12.0); }

/* Noise of a monochromatic reference render: the difference of two seeds. */
static void noise(double lambda, fm_image **a, fm_image **b)
{
    fm_sky_params p = test_params(30.0, lambda);
    fm_sky *sky = test_sky(&p);
    *a = test_render(sky, 32, FM_QUALITY_REFERENCE, 0, 1, 64, 1.0, 0);
    *b = test_render(sky, 32, FM_QUALITY_REFERENCE, 0, 2, 64, 1.0, 0);
    fm_sky_destroy(sky);
}

static void wavelengths_draw_independent_numbers(void **state)
{
    fm_image *a1, *a2, *b1, *b2;
    noise(550.0, &a1, &a2);
    noise(551.0, &b1, &b2); /* nearly the same physics: shared random numbers would show at once */
    double sab = 0.0, saa = 0.0, sbb = 0.0;
    for (int y = 0; y < 8; y++) /* sky rows: the ground of an observer at 0 m is noise-free */
        for (int x = 0; x < 32; x++) {
            double na = test_pixel_y(a1, x, y) - test_pixel_y(a2, x, y);
            double nb = test_pixel_y(b1, x, y) - test_pixel_y(b2, x, y);
            sab += na * nb;
            saa += na * na;
            sbb += nb * nb;
        }
    double corr = sab / sqrt(saa * sbb);
    print_message("correlation of the noise at 550 and 551 nm: %.3f (256 pixels)\n", corr);
    assert_true(fabs(corr) < 0.25); /* independent: 0 +- 0.06 */
    fm_image_destroy(a1);
    fm_image_destroy(a2);
    fm_image_destroy(b1);
    fm_image_destroy(b2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(thread_count_does_not_change_the_bits),
        cmocka_unit_test(thread_count_does_not_change_the_bits_at_twilight),
        cmocka_unit_test(thread_count_does_not_change_the_bits_in_deep_twilight),
        cmocka_unit_test(wavelengths_draw_independent_numbers),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
