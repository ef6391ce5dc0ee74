/* Cameras (camera/camera.h): round trips between positions and directions, orientation against the
 * stated conventions, the solid angle per pixel area against the mapping's own derivatives, pixel
 * solid angles against brute-force integrals and their sums against the closed forms (4 pi, 2 pi, the
 * pinhole frustum), the footprint average across a horizon against a brute-force average, and the
 * validation of camera parameters. */
#include "check.h"

#include "base/units.h"
#include "camera/camera.h"
#include "camera/footprint.h"

#include <math.h>
#include <string.h>

static camera make(fm_camera_type type, int width, double fov, double azimuth, double elevation, double aspect,
                   fm_fisheye_projection projection)
{
    fm_camera p = {.type = type,
                   .fisheye_projection = projection,
                   .fov_deg = fov,
                   .look_azimuth_deg = azimuth,
                   .look_elevation_deg = elevation,
                   .aspect = aspect};
    camera c;
    fm_error err;
    if (camera_init(&c, &p, width, &err) != FM_OK)
        fail_msg("camera_init: %s", err.message);
    return c;
}

/* The cameras under test: odd sizes where allowed, so that no symmetry hides a mistake. */
#define CAMERAS 7
static camera test_camera(int i)
{
    switch (i) {
    case 0:
        return make(FM_CAMERA_EQUIRECT, 64, 0, 0, 0, 0, 0);
    case 1:
        return make(FM_CAMERA_FISHEYE, 64, 0, 0, 0, 0, FM_FISHEYE_EQUIDISTANT);
    case 2:
        return make(FM_CAMERA_FISHEYE, 38, 0, 0, 0, 0, FM_FISHEYE_EQUISOLID);
    case 3:
        return make(FM_CAMERA_PINHOLE, 48, 70.0, 123.0, 20.0, 4.0 / 3.0, 0);
    case 4:
        return make(FM_CAMERA_PINHOLE, 40, 170.0, -30.0, 90.0, 0.5, 0); /* wide, portrait, at the zenith */
    case 5:
        return make(FM_CAMERA_PINHOLE, 64, 0.5, 200.0, -45.0, 2.0, 0); /* narrow, looking down */
    default:
        return make(FM_CAMERA_PINHOLE, 30, 100.0, 10.0, -90.0, 1.0, 0); /* at the nadir */
    }
}

static void round_trips(void **state)
{
    for (int i = 0; i < CAMERAS; i++) {
        camera c = test_camera(i);
        double worst = 0.0;
        for (int y = 0; y < c.height; y++)
            for (int x = 0; x < c.width; x++) {
                /* pixel centre -> direction -> the same pixel */
                vec3 d;
                if (!camera_direction(&c, x + 0.5, y + 0.5, &d))
                    continue; /* outside the fisheye's circle */
                assert_true(fabs(v3_length(d) - 1.0) < 1e-12);
                int px, py;
                assert_true(camera_pixel(&c, d, &px, &py));
                assert_int_equal(px, x);
                assert_int_equal(py, y);
                /* an arbitrary position -> direction -> the same position */
                double fx = x + 0.13 + 0.7 * ((x * 7 + y * 3) % 10) / 10.0, fy = y + 0.21 + 0.6 * ((x + y * 5) % 10) / 10.0;
                double bx, by;
                if (!camera_direction(&c, fx, fy, &d))
                    continue;
                assert_true(camera_project(&c, d, &bx, &by));
                worst = fmax(worst, fmax(fabs(bx - fx), fabs(by - fy)));
            }
        print_message("%s %d x %d: worst round-trip error %.2e pixels\n", camera_type_name(c.type), c.width,
                      c.height, worst);
        assert_true(worst < 1e-9);
    }
}

static double azimuth_deg(vec3 d)
{
    double a = atan2(d.x, d.y) / FM_DEG;
    return a < 0.0 ? a + 360.0 : a;
}

static void orientation(void **state)
{
    /* fisheye: zenith at the centre, north up, east LEFT, south down, west right, horizontal on the
     * circle; equidistant radius 45 degrees from the zenith at half the radius */
    for (int proj = 0; proj < 2; proj++) {
        camera c = make(FM_CAMERA_FISHEYE, 100, 0, 0, 0, 0, proj ? FM_FISHEYE_EQUISOLID : FM_FISHEYE_EQUIDISTANT);
        vec3 d;
        assert_true(camera_direction(&c, 50.0, 50.0, &d));
        check_abs(d.z, 1.0, 1e-12, "centre = zenith");
        struct {
            double x, y, azimuth;
        } compass[] = {{50, 10, 0}, {10, 50, 90}, {50, 90, 180}, {90, 50, 270}}; /* N up, E left, S down, W right */
        for (int k = 0; k < 4; k++) {
            assert_true(camera_direction(&c, compass[k].x, compass[k].y, &d));
            check_abs(azimuth_deg(d), compass[k].azimuth, 1e-9, "fisheye compass");
        }
        assert_true(camera_direction(&c, 100.0, 50.0, &d));
        check_abs(d.z, 0.0, 1e-12, "the circle is the horizontal");
        assert_false(camera_direction(&c, 1.0, 1.0, &d)); /* a corner: outside the circle */
        double theta_half = acos(camera_direction(&c, 50.0, 25.0, &d) ? d.z : 2.0) / FM_DEG;
        check_abs(theta_half, proj ? 2.0 * asin(0.5 / sqrt(2.0)) / FM_DEG : 45.0, 1e-9, "zenith angle at r = R/2");
        int px, py;
        assert_false(camera_pixel(&c, v3(0.0, 1.0, -0.1), &px, &py)); /* below the horizontal: not in the image */
    }
    /* pinhole: the centre looks along the look direction; right of centre is clockwise seen from above
     * (larger azimuth); up is toward the zenith; the horizontal projects onto one image row */
    camera c = make(FM_CAMERA_PINHOLE, 64, 60.0, 30.0, 25.0, 2.0, 0);
    vec3 d;
    camera_direction(&c, 32.0, 16.0, &d);
    check_abs(azimuth_deg(d), 30.0, 1e-9, "look azimuth");
    check_abs(asin(d.z) / FM_DEG, 25.0, 1e-9, "look elevation");
    /* the middle of the right edge: normalise(f + tan 30 r), r horizontal and clockwise from f */
    camera_direction(&c, 64.0, 16.0, &d);
    check_abs(asin(d.z) / FM_DEG, asin(sin(25.0 * FM_DEG) * cos(30.0 * FM_DEG)) / FM_DEG, 1e-9, "right edge elevation");
    check_abs(azimuth_deg(d), 30.0 + atan(tan(30.0 * FM_DEG) / cos(25.0 * FM_DEG)) / FM_DEG, 1e-9,
              "right edge azimuth: to the right is clockwise seen from above");
    vec3 up;
    camera_direction(&c, 32.0, 0.0, &up);
    assert_true(up.z > d.z);
    double row = 16.0 + tan(25.0 * FM_DEG) / c.pin.scale; /* where the horizontal plane cuts the image */
    for (double x = 0.0; x <= 64.0; x += 8.0) {
        camera_direction(&c, x, row, &d);
        check_abs(d.z, 0.0, 1e-12, "level horizon");
    }
    check_abs(pinhole_vertical_fov(&c.pin), 2.0 * atan(tan(30.0 * FM_DEG) / 2.0), 1e-12, "vertical field of view");
}

/* The solid angle per square pixel equals |dd/dx x dd/dy| from the mapping itself (central
 * differences). */
static void jacobian_matches_the_mapping(void **state)
{
    const double h = 1e-3;
    for (int i = 0; i < CAMERAS; i++) {
        camera c = test_camera(i);
        double worst = 0.0;
        for (double y = 0.37; y < c.height; y += c.height / 7.3)
            for (double x = 0.61; x < c.width; x += c.width / 6.9) {
                vec3 d, a, b, e, f;
                if (!camera_direction(&c, x, y, &d))
                    continue;
                camera_direction(&c, x + h, y, &a);
                camera_direction(&c, x - h, y, &b);
                camera_direction(&c, x, y + h, &e);
                camera_direction(&c, x, y - h, &f);
                vec3 dx = v3_scale(v3_sub(a, b), 0.5 / h), dy = v3_scale(v3_sub(e, f), 0.5 / h);
                double expected = v3_length(v3_cross(dx, dy));
                worst = fmax(worst, fabs(camera_jacobian(&c, x, y) / expected - 1.0));
            }
        print_message("%s: worst relative error of the Jacobian %.2e\n", camera_type_name(c.type), worst);
        assert_true(worst < 1e-6);
    }
}

/* Brute force: midpoint sum of the Jacobian over an n x n grid of the pixel. */
static double brute_solid_angle(const camera *c, int px, int py, int n)
{
    double sum = 0.0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++)
            sum += camera_jacobian(c, px + (i + 0.5) / n, py + (j + 0.5) / n);
    return sum / ((double)n * n);
}

static int wholly_inside(const camera *c, int x, int y)
{
    vec3 d;
    return camera_direction(c, x, y, &d) && camera_direction(c, x + 1, y, &d) && camera_direction(c, x, y + 1, &d) &&
           camera_direction(c, x + 1, y + 1, &d);
}

static void pixel_solid_angles(void **state)
{
    for (int i = 0; i < CAMERAS; i++) {
        camera c = test_camera(i);
        /* every pixel against a brute-force integral, where the rim is crossed too */
        double worst = 0.0, total = 0.0;
        for (int y = 0; y < c.height; y++)
            for (int x = 0; x < c.width; x++) {
                double omega = camera_pixel_solid_angle(&c, x, y);
                assert_true(omega >= 0.0);
                total += omega;
                if ((x * 13 + y * 7) % 23 == 0 && wholly_inside(&c, x, y)) { /* a scattered subset */
                    double brute = brute_solid_angle(&c, x, y, 100);
                    worst = fmax(worst, fabs(omega - brute) / brute);
                }
            }
        double expected;
        if (c.type == FM_CAMERA_EQUIRECT)
            expected = 4.0 * FM_PI;
        else if (c.type == FM_CAMERA_FISHEYE)
            expected = 2.0 * FM_PI;
        else { /* the frustum of half-angles a, b: 4 atan(tan a tan b / sqrt(1 + tan^2 a + tan^2 b)) */
            double ta = 0.5 * c.width * c.pin.scale, tb = 0.5 * c.height * c.pin.scale;
            expected = 4.0 * atan(ta * tb / sqrt(1.0 + ta * ta + tb * tb));
        }
        print_message("%s %d x %d: pixel solid angles vs 100 x 100 midpoint sums: worst %.2e\n",
                      camera_type_name(c.type), c.width, c.height, worst);
        assert_true(worst < 1e-5); /* the midpoint rule's own error, ~1e-7 */
        check_rel(total, expected, 1e-10, "sum of the pixel solid angles");
        check_rel(camera_solid_angle(&c), expected, 1e-12, "the image's solid angle");
    }
    /* the fisheye's rim pixels (cut by the circle) at a fine brute force: Green's theorem is exact, the
     * midpoint sum errs by about 1e-5 of a whole pixel where the circle crosses its grid */
    for (int proj = 0; proj < 2; proj++) {
        camera c = make(FM_CAMERA_FISHEYE, 16, 0, 0, 0, 0, proj ? FM_FISHEYE_EQUISOLID : FM_FISHEYE_EQUIDISTANT);
        int rim[][2] = {{0, 7}, {1, 3}, {2, 2}, {4, 1}, {15, 8}, {13, 13}};
        for (int k = 0; k < 6; k++) {
            int x = rim[k][0], y = rim[k][1];
            double omega = camera_pixel_solid_angle(&c, x, y), brute = brute_solid_angle(&c, x, y, 1500);
            double whole = camera_jacobian(&c, c.width / 2.0, c.width / 2.0);
            print_message("rim pixel (%d, %d): %.9f sr, brute force %.9f sr\n", x, y, omega, brute);
            assert_false(wholly_inside(&c, x, y));
            check_abs(omega / whole, brute / whole, 1e-4, "rim pixel vs 1500 x 1500 midpoint sum (in pixels)");
        }
    }
    /* the cosine-weighted integral over the fisheye is pi (the diffuse horizontal of radiance 1) */
    for (int proj = 0; proj < 2; proj++) {
        camera f = make(FM_CAMERA_FISHEYE, 30, 0, 0, 0, 0, proj ? FM_FISHEYE_EQUISOLID : FM_FISHEYE_EQUIDISTANT);
        double sum = 0.0;
        for (int y = 0; y < 30; y++)
            for (int x = 0; x < 30; x++)
                sum += fisheye_pixel_integral(&f.fish, x, y, 1);
        check_rel(sum, FM_PI, 1e-6, "integral of cos(theta) dOmega over the fisheye");
    }
}

/* A sky-like radiance with a jump at the horizon and, with climb > 0, a steep rise just above it. */
typedef struct step_sky {
    double horizon;
    double climb;
} step_sky;

static void step_radiance(void *ctx, vec3 d, double elevation, float *out)
{
    const step_sky *s = ctx;
    double e = elevation - s->horizon;
    out[0] = (float)(e < 0.0 ? 0.3 : 1.0 + s->climb * exp(-e / (1.0 * FM_DEG)) + 0.2 * d.x);
}

static double brute_average(const camera *c, int px, int py, const step_sky *s, int n)
{
    double sum = 0.0, wsum = 0.0;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            /* rows shifted per column by a golden-ratio sequence: a horizontal edge then cuts every
             * column at another phase, and the step's error averages out instead of adding up */
            double shift = fmod(0.5 + i * 0.6180339887498949, 1.0);
            double x = px + (i + 0.5) / n, y = py + (j + shift) / n;
            vec3 d;
            if (!camera_direction(c, x, y, &d))
                continue;
            double w = camera_jacobian(c, x, y);
            float v;
            step_radiance((void *)s, d, asin(d.z), &v);
            sum += w * v;
            wsum += w;
        }
    return wsum > 0.0 ? sum / wsum : NAN; /* no sample inside the image (0 / 0 as before, not a UB report) */
}

/* Pixels that straddle the horizon, or the fisheye's rim where radiance climbs steeply: against a
 * 1000 x 1000 brute-force average, a pure step is right to the brute force's own accuracy (the split
 * is exact; 1e-4 allowed), and with radiance quadrupling over the last degree above the horizon, to
 * well under 1% (0.05% allowed; measured 0.02%: the midpoint rule's error at 0.1 degree steps over a 1 degree scale).
 * Sampling the same pixels on a plain 3 x 3 lattice misses by several per cent. */
static void footprint_across_the_horizon(void **state)
{
    struct {
        camera c;
        double horizon_deg;
        int pixels[4][2];
    } cases[] = {
        /* eye level, 1.9 degree pixels, the horizon a slightly curved line (a cone below the horizontal) */
        {make(FM_CAMERA_PINHOLE, 32, 60.0, 75.0, 0.0, 4.0 / 3.0, 0), -0.3, {{3, 12}, {16, 12}, {30, 12}, {9, 11}}},
        /* looking up at 40 degrees, 120 degrees wide: the horizon across row 17.8 */
        {make(FM_CAMERA_PINHOLE, 24, 120.0, 200.0, 40.0, 1.0, 0), 0.0, {{0, 17}, {5, 17}, {12, 17}, {20, 17}}},
        /* the fisheye's rim: the horizon on the circle */
        {make(FM_CAMERA_FISHEYE, 32, 0, 0, 0, 0, FM_FISHEYE_EQUIDISTANT), 0.0, {{0, 15}, {2, 7}, {5, 3}, {27, 28}}},
        {make(FM_CAMERA_FISHEYE, 32, 0, 0, 0, 0, FM_FISHEYE_EQUISOLID), -0.2, {{0, 16}, {3, 5}, {9, 1}, {31, 14}}},
    };
    for (int test = 0; test < 8; test++) {
        int k = test / 2;
        step_sky s = {cases[k].horizon_deg * FM_DEG, test % 2 ? 3.0 : 0.0};
        footprint_settings fs = footprint_default_settings(3, s.horizon);
        footprint_settings plain = fs;
        plain.band_above = plain.band_below = -1.0; /* never near: 3 x 3 points, no split */
        double worst = 0.0, worst_plain = 0.0;
        for (int p = 0; p < 4; p++) {
            int px = cases[k].pixels[p][0], py = cases[k].pixels[p][1];
            double v, vp, brute = brute_average(&cases[k].c, px, py, &s, 1000);
            footprint_average(&cases[k].c, px, py, &fs, step_radiance, &s, 1, &v);
            footprint_average(&cases[k].c, px, py, &plain, step_radiance, &s, 1, &vp);
            worst = fmax(worst, fabs(v / brute - 1.0));
            worst_plain = fmax(worst_plain, fabs(vp / brute - 1.0));
        }
        print_message("%s, horizon %g deg, %s: worst footprint error %.2e (a plain 3 x 3 lattice: %.2e)\n",
                      camera_type_name(cases[k].c.type), cases[k].horizon_deg, s.climb > 0.0 ? "steep climb" : "step",
                      worst, worst_plain);
        assert_true(worst < (s.climb > 0.0 ? 5e-4 : 1e-4));
        if (s.climb > 0.0 || cases[k].c.type == FM_CAMERA_PINHOLE) /* (inside the fisheye a step is no jump) */
            assert_true(worst_plain > 5e-3);                        /* the test can tell */
    }
    /* outside the circle: 0 */
    camera f = make(FM_CAMERA_FISHEYE, 32, 0, 0, 0, 0, FM_FISHEYE_EQUIDISTANT);
    step_sky s = {0.0, 3.0};
    footprint_settings fs = footprint_default_settings(3, 0.0);
    double v = 1.0;
    footprint_average(&f, 0, 0, &fs, step_radiance, &s, 1, &v);
    assert_true(v == 0.0);
}

static void expect_refused(fm_camera p, int width, const char *field, const char *what)
{
    camera c;
    fm_error err;
    memset(&err, 0, sizeof err);
    fm_status s = camera_init(&c, &p, width, &err);
    print_message("%-32s %s\n", what, err.message);
    assert_int_equal(s, FM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.parameter, field);
}

static void parameters_are_validated(void **state)
{
    fm_camera pin = {.type = FM_CAMERA_PINHOLE, .fov_deg = 90, .look_azimuth_deg = 180, .aspect = 1.5};
    fm_camera p = pin;
    p.fov_deg = 0.0;
    expect_refused(p, 64, "camera.fov_deg", "fov 0");
    p.fov_deg = 170.5;
    expect_refused(p, 64, "camera.fov_deg", "fov 170.5");
    p.fov_deg = NAN;
    expect_refused(p, 64, "camera.fov_deg", "fov nan");
    p = pin;
    p.look_elevation_deg = 90.5;
    expect_refused(p, 64, "camera.look_elevation_deg", "look elevation 90.5");
    p = pin;
    p.look_azimuth_deg = -400.0;
    expect_refused(p, 64, "camera.look_azimuth_deg", "look azimuth -400");
    p = pin;
    p.aspect = 0.0;
    expect_refused(p, 64, "camera.aspect", "aspect 0");
    p.aspect = 10.0; /* 64 / 10 = 6.4: a height of 6 */
    expect_refused(p, 64, "camera.aspect", "aspect too wide");
    p.aspect = 0.001;
    expect_refused(p, 64, "camera.aspect", "aspect too tall");
    p = (fm_camera){.type = 7};
    expect_refused(p, 64, "camera.type", "unknown camera");
    p = (fm_camera){.type = FM_CAMERA_FISHEYE, .fisheye_projection = 5};
    expect_refused(p, 64, "camera.fisheye_projection", "unknown projection");
    /* another camera's fields do not matter; heights */
    fm_camera eq = {.type = FM_CAMERA_EQUIRECT, .fov_deg = -5};
    camera c;
    assert_int_equal(camera_init(&c, &eq, 64, NULL), FM_OK);
    assert_int_equal(fm_camera_height(&eq, 64), 32);
    fm_camera fish = {.type = FM_CAMERA_FISHEYE};
    assert_int_equal(fm_camera_height(&fish, 64), 64);
    p = pin;
    p.aspect = 16.0 / 9.0;
    assert_int_equal(fm_camera_height(&p, 2048), 1152);
    assert_int_equal(fm_camera_height(&p, 100), 56); /* 56.25, rounded to even */
    p.aspect = 9.0; /* 7.1, rounded to 8 */
    assert_int_equal(fm_camera_height(&p, 64), 8);
    p.aspect = 10.0;
    assert_int_equal(fm_camera_height(&p, 64), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(round_trips),
        cmocka_unit_test(orientation),
        cmocka_unit_test(jacobian_matches_the_mapping),
        cmocka_unit_test(pixel_solid_angles),
        cmocka_unit_test(footprint_across_the_horizon),
        cmocka_unit_test(parameters_are_validated),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
