/* The multiple-scattering table's smoothing (transport/sky_grid_fit.h) on synthetic tables whose
 * truth is known: Gaussian noise of a known variance on a smooth field must come out closer to the
 * field, without bias; exact or unrepresentable data must stay as they are. */
#include "check.h"

#include "base/rng.h"
#include "base/units.h"
#include "transport/sky_grid_fit.h"

#include <math.h>
#include <stdlib.h>

#define ROWS_SKY 20
#define ROWS_GROUND 12
#define COLS 16
#define NODES ((ROWS_SKY + ROWS_GROUND) * COLS)
#define CHANNELS 3
#define SUN (60.0 * FM_DEG) /* the sun's elevation, away from the test's features */

/* A smooth field like the urban sunset's multiple scattering: brighter toward the sun (phi = 0) and
 * toward the horizon, three significant cosines; the ground's half dimmer and flatter.  Columns
 * of a pole row see one direction, so the azimuthal part vanishes there. */
static double field(const sky_grid *g, int i)
{
    double e, phi;
    sky_grid_node_angles(g, i, &e, &phi);
    double s = fabs(sin(e)), c = cos(e);
    if (i < ROWS_SKY * COLS)
        return (1.0 + 0.6 * s - 0.4 * s * s) * (1.0 + c * (0.25 * cos(phi) + 0.08 * cos(2.0 * phi)));
    return 0.3 * (1.0 + 0.2 * s) * (1.0 + 0.1 * c * cos(phi));
}

static double gauss(rng *r)
{
    double u1 = rng_uniform(r), u2 = rng_uniform(r);
    return sqrt(-2.0 * log(1.0 - u1)) * cos(2.0 * FM_PI * u2);
}

/* A copy of the first `count` values of g, and the check that they are still the same bit for bit. */
static void copy_values(const sky_grid *g, float *copy, int count)
{
    for (int i = 0; i < count; i++)
        copy[i] = g->values[i];
}

static void check_unchanged(const sky_grid *g, const float *copy, int count)
{
    for (int i = 0; i < count; i++)
        assert_true(g->values[i] == copy[i]);
}

/* Fills g with field + noise (relative sigma rel_sigma, channel c scaled by 1 + c / 2 with the same
 * noise draw, as the XYZ channels of one path estimate move together) and y, var with channel Y. */
static void noisy_table(sky_grid *g, double rel_sigma, uint64_t seed, double *y, double *var)
{
    for (int i = 0; i < NODES; i++) {
        rng r = rng_for(seed, (uint64_t)i, 0);
        double f = field(g, i), sigma = rel_sigma * f, v = f + sigma * gauss(&r);
        for (int c = 0; c < CHANNELS; c++)
            g->values[i * CHANNELS + c] = (float)(v * (1.0 + 0.5 * c));
        y[i] = v * 1.5; /* channel 1 */
        var[i] = sigma * sigma * 2.25;
    }
}

/* Fills the one-channel g and y, var with truth + Gaussian noise of relative sigma rel_sigma;
 * returns the sky nodes' summed squared relative error. */
static double noisy_truth(sky_grid *g, const double *truth, double rel_sigma, uint64_t seed, double *y, double *var)
{
    double raw2 = 0.0;
    for (int i = 0; i < NODES; i++) {
        rng r = rng_for(seed, (uint64_t)i, 0);
        double sigma = rel_sigma * truth[i];
        y[i] = truth[i] + sigma * gauss(&r);
        var[i] = sigma * sigma;
        g->values[i] = (float)y[i];
        if (i < ROWS_SKY * COLS)
            raw2 += (y[i] / truth[i] - 1.0) * (y[i] / truth[i] - 1.0);
    }
    return raw2;
}

/* 8% noise per node (the sunset's at final quality): over 100 tables the fit's RMS relative error
 * is below a third of the raw nodes' (the field has about 3 x 5 significant coefficients per
 * domain, against 320 sky nodes), every channel takes the same fit, and its mean over the tables,
 * the bias the fit trades for less noise, is below 0.5% RMS and 1.25% at every node (a sixth of
 * the raw noise). */
static void noise_averaged_without_bias(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, CHANNELS, 0), FM_OK);
    static double y[NODES], var[NODES], mean_error[NODES];
    double raw2 = 0.0, fit2 = 0.0;
    const int tables = 100;
    for (int t = 0; t < tables; t++) {
        noisy_table(&g, 0.08, 100 + t, y, var);
        for (int i = 0; i < NODES; i++) {
            double e = y[i] / 1.5 / field(&g, i) - 1.0;
            raw2 += e * e;
        }
        sky_grid_fit_choice choice[2];
        assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, choice), FM_OK);
        assert_true(choice[0].azimuth_modes >= 1);
        assert_true(choice[0].risk_fit < 0.5 * choice[0].risk_raw);
        assert_true(choice[1].azimuth_modes >= 0);
        for (int i = 0; i < NODES; i++) {
            double f = field(&g, i), e = g.values[i * CHANNELS] / f - 1.0;
            for (int c = 1; c < CHANNELS; c++)
                assert_float_equal(g.values[i * CHANNELS + c], g.values[i * CHANNELS] * (1.0 + 0.5 * c),
                                   1e-5 * g.values[i * CHANNELS + c]); /* channels share the fit */
            fit2 += e * e;
            mean_error[i] += e / tables;
        }
    }
    double raw = sqrt(raw2 / (tables * NODES)), fit = sqrt(fit2 / (tables * NODES));
    print_message("8%% noise: RMS relative error %.2f%% raw, %.2f%% fitted\n", 100 * raw, 100 * fit);
    assert_true(fit < raw / 3.0);
    double worst = 0.0, bias2 = 0.0;
    for (int i = 0; i < NODES; i++) {
        worst = fmax(worst, fabs(mean_error[i]));
        bias2 += mean_error[i] * mean_error[i] / NODES;
    }
    print_message("mean error over %d tables (noise of that mean about %.2f%%): RMS %.2f%%, largest %.2f%%\n",
                  tables, 100 * fit / sqrt(tables), 100 * sqrt(bias2), 100 * worst);
    assert_true(sqrt(bias2) < 0.005);
    assert_true(worst < 0.0125);
    sky_grid_free(&g);
}

/* Without noise there is nothing to average: the nodes stay bit for bit, and so does a domain of
 * zeros (the ground seen from the ground, which no path reaches). */
static void exact_nodes_kept(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, CHANNELS, 0), FM_OK);
    static double y[NODES], var[NODES];
    static float before[NODES * CHANNELS];
    noisy_table(&g, 0.0, 1, y, var);
    for (int i = ROWS_SKY * COLS; i < NODES; i++) {
        y[i] = 0.0;
        for (int c = 0; c < CHANNELS; c++)
            g.values[i * CHANNELS + c] = 0.0f;
    }
    copy_values(&g, before, NODES * CHANNELS);
    sky_grid_fit_choice choice[2];
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, choice), FM_OK);
    assert_int_equal(choice[0].azimuth_modes, -1);
    assert_int_equal(choice[1].azimuth_modes, -1);
    check_unchanged(&g, before, NODES * CHANNELS);
    sky_grid_free(&g);
}

/* A narrow peak no smooth basis holds (one node at 5 times its neighbours, like an aureole between
 * two columns), with 1% noise: smoothing it away would cost far more than the noise, so it stays
 * (within 3% of its true value: its own noise is 1%) and the sky's nodes come out no farther from
 * the truth than they went in; a fit of the ground (smooth, noisy) is made too. */
static void unrepresentable_peak_kept(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, CHANNELS, 0), FM_OK);
    static double y[NODES], var[NODES], truth[NODES];
    noisy_table(&g, 0.01, 7, y, var);
    const int peak = 11 * COLS;
    for (int i = 0; i < NODES; i++)
        truth[i] = field(&g, i) * (i == peak ? 5.0 : 1.0);
    y[peak] *= 5.0;
    for (int c = 0; c < CHANNELS; c++)
        g.values[peak * CHANNELS + c] *= 5.0f;
    double raw2 = 0.0, fit2 = 0.0;
    for (int i = 0; i < ROWS_SKY * COLS; i++)
        raw2 += (g.values[i * CHANNELS] / truth[i] - 1.0) * (g.values[i * CHANNELS] / truth[i] - 1.0);
    sky_grid_fit_choice choice[2];
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, choice), FM_OK);
    for (int i = 0; i < ROWS_SKY * COLS; i++)
        fit2 += (g.values[i * CHANNELS] / truth[i] - 1.0) * (g.values[i * CHANNELS] / truth[i] - 1.0);
    print_message("peak: RMS relative error of the sky %.3f%% raw, %.3f%% after the fit\n",
                  100 * sqrt(raw2 / (ROWS_SKY * COLS)), 100 * sqrt(fit2 / (ROWS_SKY * COLS)));
    check_rel(g.values[peak * CHANNELS], truth[peak], 0.03, "the peak");
    assert_true(fit2 <= raw2);
    assert_true(choice[1].azimuth_modes >= 0);
    sky_grid_free(&g);
}

/* Desert dust's multiple-scattering aureole: 4 times the smooth sky at the sun (30 degrees up),
 * falling as exp(-gamma / 6 degrees), 3% noise.  No cosine-polynomial basis holds it; with the
 * aureole terms (whose widths differ from the field's) the fit brings the RMS error over 20
 * tables below half the raw nodes', and its mean error below 1% RMS. */
static void aureole_fitted(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    static double y[NODES], var[NODES], truth[NODES], mean_error[NODES];
    const double sun = 30.0 * FM_DEG;
    for (int i = 0; i < NODES; i++) {
        double e, phi;
        sky_grid_node_angles(&g, i, &e, &phi);
        double gamma = acos(fmin(1.0, sin(e) * sin(sun) + cos(e) * cos(sun) * cos(phi)));
        truth[i] = field(&g, i) * (1.0 + 3.0 * exp(-gamma / (6.0 * FM_DEG)));
    }
    double raw2 = 0.0, fit2 = 0.0;
    const int tables = 20, sky_nodes = ROWS_SKY * COLS;
    for (int t = 0; t < tables; t++) {
        raw2 += noisy_truth(&g, truth, 0.03, 900 + t, y, var);
        sky_grid_fit_choice choice[2];
        assert_int_equal(sky_grid_fit(&g, sun, y, var, NULL, choice), FM_OK);
        assert_int_equal(choice[0].aureole_terms, 3);
        for (int i = 0; i < sky_nodes; i++) {
            double e = g.values[i] / truth[i] - 1.0;
            fit2 += e * e;
            mean_error[i] += e / tables;
        }
    }
    double raw = sqrt(raw2 / (tables * sky_nodes)), fit = sqrt(fit2 / (tables * sky_nodes)), bias2 = 0.0;
    for (int i = 0; i < sky_nodes; i++)
        bias2 += mean_error[i] * mean_error[i] / sky_nodes;
    print_message("aureole, 3%% noise: RMS relative error %.2f%% raw, %.2f%% fitted, mean error %.2f%% RMS\n",
                  100 * raw, 100 * fit, 100 * sqrt(bias2));
    assert_true(fit < raw / 2.0);
    assert_true(sqrt(bias2) < 0.01);
    sky_grid_free(&g);
}

/* Deep twilight's rows: toward the sun's side of the horizon up to 1000 times brighter than away
 * from it, 30% noise per node.  A fit weighted by each row's mean would give the dim nodes the row's
 * absolute error, so the rows of wide range (here every row up to 72 degrees) keep their raw nodes;
 * the narrower rows near the zenith may be fitted. */
static void rows_of_wide_range_kept(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    static double y[NODES], var[NODES];
    static float before[NODES];
    int wide_rows = 0;
    for (int i = 0; i < NODES; i++) {
        double e, phi;
        sky_grid_node_angles(&g, i, &e, &phi);
        rng r = rng_for(5, (uint64_t)i, 0);
        double f = 1.0 + 1000.0 * exp(-phi * phi / 0.3) * cos(e), sigma = 0.3 * f;
        y[i] = f + sigma * gauss(&r);
        var[i] = sigma * sigma;
        g.values[i] = (float)y[i];
        if (i < ROWS_SKY * COLS && i % COLS == 0 && cos(e) > 0.3)
            wide_rows = i / COLS + 1;
    }
    copy_values(&g, before, NODES);
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, NULL), FM_OK);
    assert_true(wide_rows >= ROWS_SKY / 2);
    check_unchanged(&g, before, wide_rows * COLS);
    sky_grid_free(&g);
}

/* Deep twilight's shape (a deterministic estimate with the sky's range, here that of
 * rows_of_wide_range_kept: up to 1000 times brighter toward the sun) times a smooth field, 20% noise
 * per node, and twice that within half a degree of the horizon, where the real shape leaves out the
 * most light.  Divided by the shape, the rows have the field's narrow range and are fitted: over
 * 100 tables the RMS relative error falls below 0.6 of the raw nodes' in the horizon's band (the
 * rows within 1.5 degrees, fitted across the azimuth only) and below half above it, and the mean
 * error (the bias) stays below 1.5% RMS in the band and 1% above it (fitted with the rows above,
 * the band's step biased them: 4.1% RMS in the band), and a shape that is not positive everywhere
 * is left out (the result then equals the fit without one). */
static void wide_rows_fitted_through_their_shape(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    static double y[NODES], var[NODES], shape[NODES], truth[NODES], mean_error[NODES], mean_square[NODES];
    static float plain[NODES];
    const int sky_nodes = ROWS_SKY * COLS, tables = 100;
    int band = 0; /* the rows below 1.5 degrees */
    for (int i = 0; i < NODES; i++) {
        double e, phi;
        sky_grid_node_angles(&g, i, &e, &phi);
        shape[i] = 1.0 + 1000.0 * exp(-phi * phi / 0.3) * cos(e);
        truth[i] = field(&g, i) * (i < sky_nodes ? shape[i] * (e < 0.5 * FM_DEG ? 2.0 : 1.0) : 1.0);
        if (i < sky_nodes && e < 1.5 * FM_DEG)
            band = i / COLS + 1;
    }
    assert_true(band >= 2 && band <= 4);
    double raw2[2] = {0.0, 0.0}, fit2[2] = {0.0, 0.0};
    for (int t = 0; t < tables; t++) {
        noisy_truth(&g, truth, 0.2, 700 + t, y, var);
        sky_grid_fit_choice choice[2];
        assert_int_equal(sky_grid_fit(&g, SUN, y, var, shape, choice), FM_OK);
        assert_true(choice[0].azimuth_modes >= 0);
        for (int i = 0; i < sky_nodes; i++) {
            double e = g.values[i] / truth[i] - 1.0, r = y[i] / truth[i] - 1.0;
            raw2[i >= band * COLS] += r * r;
            fit2[i >= band * COLS] += e * e;
            mean_error[i] += e / tables;
            mean_square[i] += e * e / tables;
        }
    }
    /* the bias: each node's mean error squared less that mean's own variance, in the band and above */
    double bias2[2] = {0.0, 0.0};
    for (int i = 0; i < sky_nodes; i++) {
        double m = mean_error[i], v = (mean_square[i] - m * m) / (tables - 1);
        bias2[i >= band * COLS] += (m * m - v) / (i < band * COLS ? band * COLS : sky_nodes - band * COLS);
    }
    for (int d = 0; d < 2; d++) {
        int n = d ? sky_nodes - band * COLS : band * COLS;
        print_message("shaped rows, 20%% noise, %s: RMS relative error %.2f%% raw, %.2f%% fitted, mean error "
                      "%.2f%% RMS\n",
                      d ? "above the horizon's band" : "the horizon's band", 100 * sqrt(raw2[d] / (tables * n)),
                      100 * sqrt(fit2[d] / (tables * n)), 100 * sqrt(fmax(bias2[d], 0.0)));
    }
    assert_true(fit2[0] < 0.36 * raw2[0] && fit2[1] < raw2[1] / 4.0);
    assert_true(bias2[0] < 0.015 * 0.015 && bias2[1] < 0.01 * 0.01);

    /* one node without a shape: the shape is left out */
    for (int i = 0; i < NODES; i++)
        g.values[i] = (float)y[i];
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, NULL), FM_OK);
    copy_values(&g, plain, NODES);
    for (int i = 0; i < NODES; i++)
        g.values[i] = (float)y[i];
    shape[5 * COLS + 3] = 0.0;
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, shape, NULL), FM_OK);
    check_unchanged(&g, plain, NODES);
    sky_grid_free(&g);
}

/* The chromatic ratios of a twilight-like sky: X / Y smooth, Z / Y bluer overhead and away from
 * the sun, with a step within the horizon's rows (0 and 0.25 degrees up). */
static double ratio_truth(const sky_grid *g, int i, int c)
{
    double e, phi;
    sky_grid_node_angles(g, i, &e, &phi);
    double s = fabs(sin(e)), cc = cos(e);
    if (c == 0)
        return 0.95 + 0.1 * s + 0.05 * cc * cos(phi);
    return (1.1 + 0.4 * s - 0.15 * cc * cos(phi)) * (e < 0.1 * FM_DEG ? 0.7 : 1.0);
}

/* sky_grid_fit_chroma: Y stays bit for bit; X and Z become Y times the fitted ratios.  Ratios of
 * 10% noise per node (Y exact, to see the ratios alone): over 100 tables the fitted ratios' RMS
 * relative error is below half the raw ones', their mean error below 1% RMS (each node's mean
 * error less that mean's own variance) and 2.5% at every node: the horizon's step stays in its
 * rows (fitted with the rows above, its worst node's was 3.9%).  A ratio that is
 * not finite leaves its domain raw, and a table of one channel is left as it is. */
static void colour_fitted_through_ratios(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, CHANNELS, 0), FM_OK);
    static double ratio[2][NODES], var[2][NODES], mean_error[2][NODES], mean_square[2][NODES];
    static float y_before[NODES];
    const double *const ratios[2] = {ratio[0], ratio[1]}, *const variances[2] = {var[0], var[1]};
    const int tables = 100;
    double raw2 = 0.0, fit2 = 0.0;
    for (int t = 0; t < tables; t++) {
        for (int i = 0; i < NODES; i++) {
            double y = field(&g, i);
            g.values[i * CHANNELS + 1] = y_before[i] = (float)y;
            for (int c = 0; c < 2; c++) {
                rng r = rng_for(900 + t, (uint64_t)i, (uint64_t)c);
                double truth = ratio_truth(&g, i, c), sigma = 0.1 * truth;
                ratio[c][i] = truth + sigma * gauss(&r);
                var[c][i] = sigma * sigma;
                g.values[i * CHANNELS + 2 * c] = (float)(ratio[c][i] * y);
                raw2 += (ratio[c][i] / truth - 1.0) * (ratio[c][i] / truth - 1.0);
            }
        }
        assert_int_equal(sky_grid_fit_chroma(&g, SUN, ratios, variances), FM_OK);
        for (int i = 0; i < NODES; i++) {
            assert_true(g.values[i * CHANNELS + 1] == y_before[i]);
            for (int c = 0; c < 2; c++) {
                double e = g.values[i * CHANNELS + 2 * c] / y_before[i] / ratio_truth(&g, i, c) - 1.0;
                fit2 += e * e;
                mean_error[c][i] += e / tables;
                mean_square[c][i] += e * e / tables;
            }
        }
    }
    double raw = sqrt(raw2 / (2.0 * tables * NODES)), fit = sqrt(fit2 / (2.0 * tables * NODES)), bias2 = 0.0;
    double worst = 0.0; /* the largest mean error at a node */
    for (int c = 0; c < 2; c++)
        for (int i = 0; i < NODES; i++) {
            double m = mean_error[c][i], v = (mean_square[c][i] - m * m) / (tables - 1);
            bias2 += (m * m - v) / (2.0 * NODES);
            worst = fmax(worst, fabs(m));
        }
    bias2 = fmax(bias2, 0.0);
    print_message("chromatic ratios, 10%% noise: RMS relative error %.2f%% raw, %.2f%% fitted, mean error %.2f%% RMS, "
                  "%.2f%% at worst\n",
                  100 * raw, 100 * fit, 100 * sqrt(bias2), 100 * worst);
    assert_true(fit < raw / 2.0);
    assert_true(sqrt(bias2) < 0.01);
    assert_true(worst < 0.025); /* fitted with the rows above, the horizon's step: 3.9% */

    /* a ratio that is not finite: its domain (the ground) keeps its nodes */
    ratio[1][ROWS_SKY * COLS + 5] = NAN;
    static float before[NODES * CHANNELS];
    copy_values(&g, before, NODES * CHANNELS);
    assert_int_equal(sky_grid_fit_chroma(&g, SUN, ratios, variances), FM_OK);
    for (int i = ROWS_SKY * COLS * CHANNELS; i < NODES * CHANNELS; i += CHANNELS)
        assert_true(g.values[i + 2] == before[i + 2]);
    sky_grid_free(&g);

    /* one channel: nothing to do */
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, 1, 0), FM_OK);
    for (int i = 0; i < NODES; i++)
        g.values[i] = before[i] = (float)field(&g, i);
    assert_int_equal(sky_grid_fit_chroma(&g, SUN, ratios, variances), FM_OK);
    check_unchanged(&g, before, NODES);
    sky_grid_free(&g);
}

/* The zenith row's columns are one direction: the fit gives them one value, within three standard
 * deviations (2% each: 8% over 16 columns) of the truth. */
static void pole_is_one_value(void **state)
{
    (void)state;
    sky_grid g;
    assert_int_equal(sky_grid_init(&g, -1e-4, ROWS_SKY, ROWS_GROUND, COLS, CHANNELS, 0), FM_OK);
    static double y[NODES], var[NODES];
    noisy_table(&g, 0.08, 3, y, var);
    assert_int_equal(sky_grid_fit(&g, SUN, y, var, NULL, NULL), FM_OK);
    const float *zenith = &g.values[(ROWS_SKY - 1) * COLS * CHANNELS];
    for (int j = 1; j < COLS; j++)
        assert_float_equal(zenith[j * CHANNELS], zenith[0], 1e-6 * zenith[0]);
    check_rel(zenith[0], field(&g, (ROWS_SKY - 1) * COLS), 0.06, "zenith value");
    sky_grid_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(noise_averaged_without_bias),
        cmocka_unit_test(exact_nodes_kept),
        cmocka_unit_test(unrepresentable_peak_kept),
        cmocka_unit_test(aureole_fitted),
        cmocka_unit_test(rows_of_wide_range_kept),
        cmocka_unit_test(wide_rows_fitted_through_their_shape),
        cmocka_unit_test(colour_fitted_through_ratios),
        cmocka_unit_test(pole_is_one_value),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
