/* The sun: angular size, limb darkening (Neckel & Labs 1994), the chord quadrature over the disk and
 * the disk drawn into the map carrying exactly the direct irradiance. */
#include "check.h"

#include "base/units.h"
#include "camera/equirect.h"
#include "data/tables.h"
#include "sun/sun_disk.h"

#include <math.h>

static void visible_sun_at_1_au(spectral_grid *g, sun_disk *sun)
{
    spectral_grid_visible(g);
    sun_disk_init(sun, g, 1.0);
}

static void angular_radius(void **state)
{
    spectral_grid g;
    sun_disk sun;
    visible_sun_at_1_au(&g, &sun);
    check_rel(sun.angular_radius / FM_DEG, 0.26645, 1e-4, "mean angular radius (deg)");
    sun_disk_init(&sun, &g, 1.0167); /* aphelion: the disk shrinks as 1/d */
    check_rel(sun.angular_radius / FM_DEG, 0.26645 / 1.0167, 1e-4, "aphelion angular radius (deg)");
}

/* Table 1 of Neckel & Labs lists, beside each polynomial, the disk-averaged intensity over the
 * central one: an independent check of the transcription and of our disk mean. */
static void limb_darkening_disk_mean(void **state)
{
    for (int i = 0; i < FM_LIMB_DARKENING_COUNT; i++) {
        spectral_grid g;
        spectral_grid_single(&g, fm_limb_darkening_neckel_labs[i][0]);
        sun_disk sun;
        sun_disk_init(&sun, &g, 1.0);
        check_abs(sun.ld_mean[0], fm_limb_darkening_neckel_labs[i][7], 1.5e-3, "disk mean / centre");
        check_abs(sun_limb_darkening(&sun, 0, 1.0), 1.0, 1e-12, "centre intensity");
        /* darker toward the limb; the limb itself (mu = 0) is A0: 0.08 in the UV, 0.51 at 1.1 um */
        assert_true(sun_limb_darkening(&sun, 0, 0.05) < sun_limb_darkening(&sun, 0, 0.5));
        assert_true(sun_limb_darkening(&sun, 0, 0.5) < 1.0);
        check_abs(sun_limb_darkening(&sun, 0, 0.0), fm_limb_darkening_neckel_labs[i][1], 2e-3, "limb intensity A0");
    }
}

/* The coarse whole-disk rule (3 chords) against the 12-chord rule: the same moments 1 and delta^2
 * at every wavelength, and the same disk average of a transmittance that falls by a factor e^2
 * across the disk (the optical depth of a 4-degree sun through heavy haze changes about that
 * much) within 2e-4 (1.6e-4 at the ends of the visible range, where the limb darkening differs
 * most from the middle wavelength that placed the nodes). */
static void coarse_rule_matches_the_full_rule(void **state)
{
    spectral_grid g;
    sun_disk sun;
    visible_sun_at_1_au(&g, &sun);
    sun_chord_rule fine;
    sun_chord_rule_above(&sun, g.count, -1.0, &fine);
    const sun_chord_rule *c = &sun.coarse;
    assert_int_equal(c->n, FM_SUN_COARSE_CHORD_POINTS);
    double rho = sun.angular_radius;
    for (int k = 0; k < g.count; k++) {
        double m[2][3] = {{0}};
        for (int r = 0; r < 2; r++) {
            const sun_chord_rule *rule = r ? c : &fine;
            for (int j = 0; j < rule->n; j++) {
                double d = rule->delta[j] / rho;
                m[r][0] += rule->weight[j][k];
                m[r][1] += rule->weight[j][k] * d * d;
                m[r][2] += rule->weight[j][k] * exp(-d);
            }
        }
        check_abs(m[1][0], 1.0, 1e-12, "coarse weights");
        check_rel(m[1][1], m[0][1], 1e-9, "second moment");
        check_rel(m[1][2], m[0][2], 2e-4, "disk average of exp(-delta / radius)");
    }
}

static void chord_rule_integrates_the_disk(void **state)
{
    spectral_grid g;
    sun_disk sun;
    visible_sun_at_1_au(&g, &sun);
    sun_chord_rule rule;
    sun_chord_rule_above(&sun, g.count, -1.0, &rule);
    for (int k = 0; k < g.count; k++) {
        double s = 0.0;
        for (int j = 0; j < rule.n; j++)
            s += rule.weight[j][k];
        check_abs(s, 1.0, 1e-8, "weights over the whole disk");
    }
    /* the upper half holds half the light (the limb darkening is symmetric) */
    sun_chord_rule_above(&sun, g.count, 0.0, &rule);
    double s = 0.0;
    for (int j = 0; j < rule.n; j++)
        s += rule.weight[j][20];
    check_abs(s, 0.5, 1e-9, "upper half");
    /* brute force: the fraction above delta = 0.5 radius by a fine 2D midpoint sum */
    sun_chord_rule_above(&sun, g.count, 0.5 * sun.angular_radius, &rule);
    double frac = 0.0, total = 0.0;
    const int n = 2000;
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i + 0.5) / n * 2 - 1, y = (j + 0.5) / n * 2 - 1, rr = x * x + y * y;
            if (rr >= 1.0)
                continue;
            double ld = sun_limb_darkening(&sun, 20, sqrt(1.0 - rr));
            total += ld;
            if (y > 0.5)
                frac += ld;
        }
    s = 0.0;
    for (int j = 0; j < rule.n; j++)
        s += rule.weight[j][20];
    check_abs(s, frac / total, 2e-5, "cap above half a radius");
}

/* Drawn into the map, the disk carries exactly the direct normal irradiance (any resolution). */
static void disk_in_the_map_carries_the_direct_irradiance(void **state)
{
    const double elevations[] = {30.0, 0.1};
    const int widths[] = {64, 4096};
    for (int e = 0; e < 2; e++) {
        fm_sky_params p = test_params(elevations[e], 0.0);
        fm_sky *sky = test_sky(&p);
        fm_sun_light sun;
        fm_sky_sun_light(sky, &sun);
        for (int w = 0; w < 2; w++) {
            fm_image *img = test_render(sky, widths[w], FM_QUALITY_PREVIEW, 0, 1, 0, 0.05, 1);
            double y = 0.0;
            for (int py = 0; py < img->height; py++) {
                double omega = equirect_pixel_solid_angle(img->width, img->height, py);
                for (int px = 0; px < img->width; px++)
                    y += img->sun_disk[((size_t)py * img->width + px) * 3 + 1] * omega;
            }
            check_rel(y, sun.normal_irradiance[1], 1e-3, "disk energy in the map vs sidecar");
            fm_image_destroy(img);
        }
        fm_sky_destroy(sky);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(angular_radius),
        cmocka_unit_test(limb_darkening_disk_mean),
        cmocka_unit_test(chord_rule_integrates_the_disk),
        cmocka_unit_test(coarse_rule_matches_the_full_rule),
        cmocka_unit_test(disk_in_the_map_carries_the_direct_irradiance),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
