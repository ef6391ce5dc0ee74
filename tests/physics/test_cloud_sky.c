/* Clouds in the sky (api.c, aerosol/cloud_file.h): what a thin layer does to the sun and its
 * surroundings, none of which depends on the estimators' convergence inside thick layers.
 *  - The sun's direct light is attenuated by exp(-tau / mu) through a cloud layer (the chord through
 *    the spherical shell), and the sidecar's cloud transmittance says the same;
 *  - under a thick deck (stratus, tau 30) the disk is hidden: its irradiance below 1e-12 of clear;
 *  - thin cirrostratus (sun 60 degrees up) keeps a visible sun with a bright aureole: the radiance
 *    3 degrees from the sun is the single-scattering aureole of the crystals' phase function
 *    within the share of light scattered twice, and at tau 0.5 the disk stays thousands of times
 *    brighter than it.
 * The unscattered beam is what "direct" means here: light diffracted by the crystals into the disk's
 * own 0.27 degrees is sky light in the map (0.01 % of the scattered light for the ice phase
 * function), not part of the sun's irradiance. */
#include "check.h"

#include "aerosol/cloud_layer.h"
#include "base/units.h"
#include "firmament/firmament.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static fm_sky *make_sky(const char *clouds, double tau, double wavelength_nm)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = 60.0;
    p.biome = "none";
    p.wavelength_nm = wavelength_nm;
    p.clouds = clouds;
    p.cloud_tau550 = clouds ? tau : 0.0;
    fm_sky *sky;
    fm_error err;
    fm_status s = fm_sky_create(&p, &sky, &err);
    if (s)
        fail_msg("%s", err.message);
    return sky;
}

static void direct_transmittance(void **state)
{
    (void)state;
    fm_sky *clear = make_sky(NULL, 0.0, 0.0), *cs = make_sky("cirrostratus", 0.5, 0.0);
    fm_sun_light a, b;
    fm_sky_sun_light(clear, &a);
    fm_sky_sun_light(cs, &b);
    /* the layer 8-9.5 km up, seen from the ground: the chord of the shell for the sun 60 degrees up */
    double r = FM_EARTH_RADIUS_M, mu = sin(60.0 * FM_DEG);
    double chord = cloud_shell_chord_m(r, mu, r + 8000.0, r + 9500.0);
    double expected = exp(-0.5 * chord / 1500.0);
    print_message("cirrostratus tau 0.5: chord / thickness %.6f (1 / mu = %.6f), T = %.6f; sun_light says %.6f, "
                  "illuminance ratio %.6f\n",
                  chord / 1500.0, 1.0 / mu, expected, b.cloud_transmittance, b.normal_irradiance[1] / a.normal_irradiance[1]);
    check_rel(chord / 1500.0, 1.0 / mu, 2e-3, "chord through a high shell ~ thickness / mu");
    check_rel(b.cloud_transmittance, expected, 1e-9, "reported cloud transmittance");
    /* the crystals' extinction does not depend on wavelength: the illuminance falls by the same factor;
     * the profile's 50 m sampling of the layer's edges holds the column exactly */
    check_rel(b.normal_irradiance[1] / a.normal_irradiance[1], expected, 1e-4, "direct illuminance ratio");
    check_rel(a.cloud_transmittance, 1.0, 0.0, "no clouds: transmittance 1");
    fm_sky_destroy(cs);

    fm_sky *st = make_sky("stratus", 30.0, 0.0);
    fm_sky_sun_light(st, &b);
    print_message("stratus tau 30: T = %.3g, direct normal %.3g lux (clear %.0f lux)\n", b.cloud_transmittance,
                  683 * b.normal_irradiance[1], 683 * a.normal_irradiance[1]);
    assert_true(b.cloud_transmittance < 1e-12);
    assert_true(b.normal_irradiance[1] < 1e-12 * a.normal_irradiance[1]);
    fm_sky_destroy(st);
    fm_sky_destroy(clear);
}

/* Radiance (550 nm) of the map pixel d degrees below the sun, and of the sun's own pixel. */
static void radiance_below_sun(const fm_sky *sky, int width, double d_deg, float out[2])
{
    fm_render_params rp = fm_render_params_default();
    rp.width = width;
    rp.reference_samples = 512;
    rp.seed = 7;
    rp.threads = 2;
    double per_deg = width / 360.0;
    int x[2] = {(int)(0.75 * width), (int)(0.75 * width)};
    int y[2] = {(int)((30.0 + d_deg) * per_deg), (int)(30.0 * per_deg)};
    fm_error err;
    if (fm_render_pixels(sky, &rp, 2, x, y, out, NULL, &err))
        fail_msg("%s", err.message);
}

/* The aureole of a thin ice layer: its excess over the clear sky 3 degrees below the sun against
 * single scattering in a plane layer seen from below, E tau p(theta) / mu_view (E the direct
 * irradiance under the layer; the layer's own attenuation of the scattered light is the sun's within
 * exp(tau (1/mu_sun - 1/mu_view)), 0.3 % here); light scattered twice adds 4 % at tau 0.1. */
static double aureole_excess(double tau, double d_deg, double *disk_over_aureole, double *over_clear, double *excess)
{
    fm_sky *clear = make_sky(NULL, 0.0, 550.0), *cs = make_sky("cirrostratus", tau, 550.0);
    fm_sun_light sun;
    fm_sky_sun_light(cs, &sun);
    float lc[2], lo[2];
    radiance_below_sun(clear, 720, d_deg, lo);
    radiance_below_sun(cs, 720, d_deg, lc);
    double mu_view = sin((60.0 - d_deg) * FM_DEG);
    double single = sun.normal_irradiance[0] * tau / mu_view * cloud_ice_phase(cos(d_deg * FM_DEG));
    double disk = sun.normal_irradiance[0] / (FM_PI * pow(sun.angular_radius_deg * FM_DEG, 2.0));
    print_message("tau %.2f, %.0f deg below the sun: %.4g W m^-2 sr^-1 nm^-1 (clear %.4g), single scattering %.4g: "
                  "excess / single %.4f; disk radiance %.4g\n",
                  tau, d_deg, lc[0], lo[0], single, (lc[0] - lo[0]) / single, disk);
    *disk_over_aureole = disk / lc[0];
    *over_clear = lc[0] / lo[0];
    *excess = lc[0] - lo[0];
    fm_sky_destroy(cs);
    fm_sky_destroy(clear);
    return (lc[0] - lo[0]) / single;
}

static void thin_cirrostratus_aureole(void **state)
{
    (void)state;
    double disk_ratio, clear_ratio, unused;
    /* tau 0.1: single scattering within its second order (+4 % expected) */
    double excess = aureole_excess(0.1, 3.0, &disk_ratio, &clear_ratio, &unused);
    assert_true(excess > 0.99 && excess < 1.08);
    /* tau 0.5: a bright aureole (tens of times the clear sky there) and a disk still thousands of
     * times brighter than it */
    excess = aureole_excess(0.5, 3.0, &disk_ratio, &clear_ratio, &unused);
    print_message("tau 0.5: aureole %.0f x the clear sky, disk %.0f x the aureole\n", clear_ratio, disk_ratio);
    assert_true(excess > 1.0 && excess < 1.3);
    assert_true(clear_ratio > 20.0);
    assert_true(disk_ratio > 1000.0);
}

/* The 22-degree halo in the sky: below the sun, just outside the crystals' minimum deviation (21.96
 * degrees, aerosol/ice_halo.h) the thin veil's sky is brighter than just inside it, though the forward
 * lobe falls with angle, and both follow single scattering within its second order. */
static void cirrostratus_halo(void **state)
{
    (void)state;
    double disk_ratio, clear_ratio, e_inside, e_ring;
    double inside = aureole_excess(0.1, 20.5, &disk_ratio, &clear_ratio, &e_inside);
    double ring = aureole_excess(0.1, 22.5, &disk_ratio, &clear_ratio, &e_ring);
    print_message("halo: the veil's light at 22.5 degrees from the sun %.3f times that at 20.5\n", e_ring / e_inside);
    assert_true(inside > 0.97 && inside < 1.1);
    assert_true(ring > 0.95 && ring < 1.1);
    assert_true(e_ring > 1.1 * e_inside); /* the lobes alone: 0.8 times */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(direct_transmittance),
        cmocka_unit_test(thin_cirrostratus_aureole),
        cmocka_unit_test(cirrostratus_halo),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
