/* Symmetries of the radiance field, checked on estimators that do not assume them.
 *  - Mirror symmetry about the sun's vertical plane: the reference mode traces every pixel on its
 *    own, so pixels mirrored about the solar plane must agree within their standard errors.
 *  - Reciprocity (Helmholtz; Chandrasekhar's transmission function T(mu, mu0) is symmetric): with the
 *    sun at zenith angle a and the view at zenith angle b, mu_b L(view b; sun a) = mu_a L(view a; sun b)
 *    at the same relative azimuth, for all orders of scattering through a free atmosphere (ground
 *    albedo 0; with a reflecting ground the sky seen from below also carries the ground's
 *    irradiance, mu_a T(a), and the symmetry is lost).  It holds exactly in a plane-parallel
 *    atmosphere; the curvature of a spherical one changes it by well under 0.5% for zenith angles up
 *    to 70 degrees. */
#include "check.h"

#include "base/rng.h"
#include "base/units.h"
#include "transport/path.h"
#include "transport/sky_path.h"

#include <math.h>

static void mirror_symmetry_of_the_reference_render(void **state)
{
    fm_sky_params p = test_params(20.0, 0.0);
    p.sun_azimuth_deg = 180.0; /* u = 0.75: the boundary between columns 3W/4 - 1 and 3W/4 */
    fm_sky *sky = test_sky(&p);
    const int W = 32, H = 16;
    fm_image *img = test_render(sky, W, FM_QUALITY_REFERENCE, 0, 7, 1024, 1.0, 0);
    double chi2 = 0.0, worst = 0.0;
    int n = 0;
    for (int y = 0; y < H / 2 + 2; y++) { /* the sky and the horizon rows */
        for (int k = 0; k < W / 2; k++) {
            int a = (3 * W / 4 - 1 - k + W) % W, b = (3 * W / 4 + k) % W;
            for (int c = 0; c < 3; c++) {
                size_t ia = ((size_t)y * W + a) * 3 + c, ib = ((size_t)y * W + b) * 3 + c;
                double s = hypot(img->std_error[ia], img->std_error[ib]);
                double z = (img->pixels[ia] - img->pixels[ib]) / s;
                chi2 += z * z;
                worst = fmax(worst, fabs(z));
                n++;
            }
        }
    }
    print_message("mirror pairs: mean z^2 = %.3f over %d values, worst |z| = %.2f\n", chi2 / n, n, worst);
    assert_true(chi2 / n > 0.6 && chi2 / n < 1.4); /* chi-square of n values: mean 1 +- sqrt(2/n) */
    assert_true(worst < 5.0);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

/* All-orders radiance at the observer toward (elevation, relative azimuth), mean and standard error. */
static void radiance(double sun_elevation, double view_elevation, double rel_azimuth, int N, uint64_t seed,
                     double *mean, double *se)
{
    fm_sky_params p = test_params(sun_elevation, 450.0);
    p.sun_azimuth_deg = 0.0;
    p.ground_albedo = 0.0;
    fm_sky *sky = test_sky(&p);
    path_context all = sky_path_context(sky, 1, 0);
    vec3 d = direction_from_elevation_azimuth(view_elevation * FM_DEG, rel_azimuth * FM_DEG);
    *mean = test_path_radiance(&all, sky->observer, d, N, seed, 0, se);
    fm_sky_destroy(sky);
}

static void reciprocity(void **state)
{
    const double pairs[3][3] = {{30, 60, 90}, {20, 70, 0}, {45, 10, 150}}; /* zenith a, zenith b, azimuth */
    for (int i = 0; i < 3; i++) {
        double za = pairs[i][0], zb = pairs[i][1], phi = pairs[i][2];
        double la, sa, lb, sb;
        radiance(90.0 - za, 90.0 - zb, phi, 400000, 10 + i, &la, &sa); /* sun at a, view b */
        radiance(90.0 - zb, 90.0 - za, phi, 400000, 20 + i, &lb, &sb); /* sun at b, view a */
        double left = cos(zb * FM_DEG) * la, right = cos(za * FM_DEG) * lb;
        double se = hypot(cos(zb * FM_DEG) * sa, cos(za * FM_DEG) * sb) / right;
        print_message("zenith %g / %g, azimuth %g: ratio %.5f (standard error %.1e)\n", za, zb, phi, left / right, se);
        check_rel(left, right, 5e-3 + 3.0 * se, "reciprocity mu_b L(b; a) = mu_a L(a; b)");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mirror_symmetry_of_the_reference_render),
        cmocka_unit_test(reciprocity),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
