/* The equirectangular layout is Blender's Environment Texture (BLENDER.md section 1.6): u = 0.5 looks
 * along +X (east), u = 0.25 along +Y (north), u = 0 and 1 along -X, u = 0.75 along -Y; top row zenith. */
#include "check.h"

#include "base/units.h"
#include "camera/equirect.h"
#include "transport/sky_grid.h"

#include <math.h>

static void blender_orientation(void **state)
{
    const int W = 360, H = 180;
    struct {
        double u;
        vec3 d;
    } cases[] = {{0.5, {1, 0, 0}}, {0.25, {0, 1, 0}}, {0.0, {-1, 0, 0}}, {0.75, {0, -1, 0}}};
    for (int i = 0; i < 4; i++) {
        vec3 d = equirect_direction(W, H, cases[i].u * W, 0.5 * H);
        check_abs(d.x, cases[i].d.x, 1e-12, "x");
        check_abs(d.y, cases[i].d.y, 1e-12, "y");
        check_abs(d.z, 0.0, 1e-12, "z at the middle row");
    }
    vec3 top = equirect_direction(W, H, 10, 0), bottom = equirect_direction(W, H, 10, H);
    check_abs(top.z, 1.0, 1e-12, "top row is the zenith");
    check_abs(bottom.z, -1.0, 1e-12, "bottom row is the nadir");
    /* Blender's lookup: u = 0.5 - atan2(y, x) / 2pi, v(from top) = 0.5 - elevation / pi
     * (on a grid whose pixel edges do not fall on the test angles) */
    const int W2 = 358, H2 = 179;
    for (double a = -170.0; a < 180.0; a += 37.0) {
        for (double e = -80.0; e <= 80.0; e += 40.0) {
            vec3 d = direction_from_elevation_azimuth(e * FM_DEG, a * FM_DEG);
            double u = 0.5 - atan2(d.y, d.x) / (2.0 * FM_PI);
            u -= floor(u);
            int px, py;
            assert_true(equirect_pixel(W2, H2, d, &px, &py));
            assert_int_equal(px, (int)(u * W2) % W2);
            assert_int_equal(py, (int)((0.5 - e / 180.0) * H2));
        }
    }
}

static void pixel_solid_angles_cover_the_sphere(void **state)
{
    const int W = 64, H = 32;
    double total = 0.0;
    for (int y = 0; y < H; y++)
        total += W * equirect_pixel_solid_angle(W, H, y);
    check_rel(total, 4.0 * FM_PI, 1e-12, "sum of pixel solid angles");
}

static void round_trip_pixel_centres(void **state)
{
    const int W = 200, H = 100;
    for (int y = 0; y < H; y += 7)
        for (int x = 0; x < W; x += 11) {
            int px, py;
            assert_true(equirect_pixel(W, H, equirect_direction(W, H, x + 0.5, y + 0.5), &px, &py));
            assert_int_equal(px, x);
            assert_int_equal(py, y);
        }
}

/* The radiance table's zenith and nadir rows look one way in every column: pooling replaces them by
 * the columns' mean and leaves every other row alone. */
static void sky_grid_pools_the_poles(void **state)
{
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -0.01, 5, 4, 6, 2, 0), FM_OK);
    for (int i = 0; i < sky_grid_nodes(&g); i++)
        for (int c = 0; c < 2; c++)
            sky_grid_set(&g, i, c, (float)(i * 2 + c));
    double e, phi;
    sky_grid_node_angles(&g, 4 * 6, &e, &phi);
    assert_float_equal(e, 0.5 * FM_PI, 1e-12); /* row 4 is the zenith */
    sky_grid_node_angles(&g, 9 * 6 - 1, &e, &phi);
    assert_float_equal(e, -0.5 * FM_PI, 1e-12); /* the last row is the nadir */
    sky_grid_average_poles(&g);
    for (int j = 0; j < 6; j++)
        for (int c = 0; c < 2; c++) {
            assert_float_equal(g.values[(4 * 6 + j) * 2 + c], (4 * 6 + 2.5) * 2 + c, 1e-4);
            assert_float_equal(g.values[(8 * 6 + j) * 2 + c], (8 * 6 + 2.5) * 2 + c, 1e-4);
            assert_float_equal(g.values[(3 * 6 + j) * 2 + c], (3 * 6 + j) * 2 + c, 0.0);
        }
    sky_grid_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blender_orientation),
        cmocka_unit_test(pixel_solid_angles_cover_the_sphere),
        cmocka_unit_test(round_trip_pixel_centres),
        cmocka_unit_test(sky_grid_pools_the_poles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
