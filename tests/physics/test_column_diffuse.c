/* The column solver lit by a diffuse field at its top (transport/plane_column.h,
 * plane_column_diffuse_level; the fog column in twilight, docs/decisions/2026-12-07-twilight-fog.md):
 *  - against the tests' own adding-doubling (adding_doubling.c, written apart): a field I(mu, phi)
 *    with three azimuthal modes on the Gauss nodes is a sum of beams, one per node (F0 = I dOmega,
 *    dOmega = 2 pi c_j dmu over the azimuth's modes), so the diffuse light at the bottom and at the
 *    top of a Henyey-Greenstein layer cut in two over a Lambertian ground must be those beams' sum,
 *    mode by mode, to 1e-4 of the mean (the two start doubling at optical depths 1e-6 and 1e-9),
 *    and so must the column's map of the field (plane_column_diffuse_response) applied to it;
 *  - energy: a layer that absorbs nothing over a ground of albedo 1 under an isotropic field sends
 *    all of it back up (the top's upward flux pi I) and, at the bottom, the downward flux less the
 *    upward is nil, to 2e-4 (the doubling from 1e-6).
 * Faults it fails on: the field's azimuthal modes above 0 dropped (its mode 1 and 2 off by their
 * whole size), the ground's reflection left out (every check), the map carrying only its first
 * node's field through the layers (the map's modes 0-2 off). Well under a second of CPU. */
#include "check.h"

#include "adding_doubling.h"
#include "base/quadrature.h"
#include "transport/plane_column.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define STREAMS 12
#define MODES (2 * STREAMS)
#define N_MU 5
static const double view_mu[N_MU] = {0.05, 0.2, 0.5, 0.8, 1.0};

/* the field's modes at node mu: a limb-brightened sky, brighter toward phi = 0 */
static void field_modes(double mu, double *modes)
{
    for (int m = 0; m < MODES; m++)
        modes[m] = 0.0;
    modes[0] = 1.0 + 2.0 * (1.0 - mu);
    modes[1] = 0.3 * modes[0];
    modes[2] = 0.1 * modes[0] * mu;
}

static void field_as_beams(void **state)
{
    (void)state;
    const double g = 0.5, tau = 2.0, ssa = 0.95, albedo = 0.3;
    double node[STREAMS], incident[STREAMS * MODES];
    plane_column_nodes(STREAMS, node);
    for (int j = 0; j < STREAMS; j++)
        field_modes(node[j], incident + j * MODES);
    /* the beams' sum: the Gauss weights on [0, 1] */
    gauss_rule q;
    gauss_legendre(STREAMS, &q);
    double want_bottom[N_MU * MODES] = {0}, want_top[N_MU * MODES] = {0}, moments[MODES] = {0};
    for (int j = 0; j < STREAMS; j++) {
        ad_problem p = {.tau = tau, .ssa = ssa, .ground_albedo = albedo, .mu0 = node[j], .phase = ad_phase_hg,
                        .phase_ctx = &g, .streams = STREAMS, .delta_m = 0, .n_mu = N_MU, .mu = view_mu};
        ad_solution s;
        assert_int_equal(ad_solve(&p, &s), 0);
        const double dOmega = 2.0 * FM_PI * 0.5 * q.w[j];
        for (int i = 0; i < N_MU * MODES; i++) {
            want_bottom[i] += dOmega * incident[j * MODES + i % MODES] * s.bottom[i];
            want_top[i] += dOmega * incident[j * MODES + i % MODES] * s.top[i];
        }
        for (int l = 0; l < MODES; l++)
            moments[l] = s.moments[l];
        ad_free(&s);
    }
    plane_layer layer[2] = {{.tau = 0.4 * tau, .ssa = ssa, .chi = moments}, {.tau = 0.6 * tau, .ssa = ssa, .chi = moments}};
    plane_column c = {.streams = STREAMS, .layer_count = 2, .layer = layer, .ground_albedo = albedo, .mu0 = 1.0,
                      .n_mu = N_MU, .mu = view_mu};
    double bottom[N_MU * MODES], top[N_MU * MODES];
    assert_int_equal(plane_column_diffuse_level(&c, 2, incident, bottom, NULL, NULL), FM_OK);
    assert_int_equal(plane_column_diffuse_level(&c, 0, incident, NULL, top, NULL), FM_OK);
    char what[96];
    for (int k = 0; k < N_MU; k++)
        for (int m = 0; m < MODES; m++) {
            const int i = k * MODES + m;
            snprintf(what, sizeof what, "bottom, mu %g mode %d", view_mu[k], m);
            check_abs(bottom[i], want_bottom[i], 1e-4 * fabs(want_bottom[k * MODES]), what);
            snprintf(what, sizeof what, "top, mu %g mode %d", view_mu[k], m);
            check_abs(top[i], want_top[i], 1e-4 * fabs(want_top[k * MODES]), what);
        }
    assert_int_equal(plane_column_diffuse_level(&c, 2, NULL, bottom, NULL, NULL), FM_ERR_INVALID_ARGUMENT);
    /* the same light from the column's map of the field (plane_column_diffuse_response) */
    double response[MODES * N_MU * STREAMS];
    assert_int_equal(plane_column_diffuse_response(&c, 2, response), FM_OK);
    for (int k = 0; k < N_MU; k++)
        for (int m = 0; m < MODES; m++) {
            double L = 0.0;
            for (int j = 0; j < STREAMS; j++)
                L += response[(m * N_MU + k) * STREAMS + j] * incident[j * MODES + m];
            snprintf(what, sizeof what, "bottom from the response, mu %g mode %d", view_mu[k], m);
            check_abs(L, want_bottom[k * MODES + m], 1e-4 * fabs(want_bottom[k * MODES]), what);
        }
}

static void no_energy_lost(void **state)
{
    (void)state;
    const double g = 0.85;
    ad_problem p = {.tau = 8.0, .ssa = 1.0, .ground_albedo = 1.0, .mu0 = 0.5, .phase = ad_phase_hg, .phase_ctx = &g,
                    .streams = STREAMS, .delta_m = 1, .n_mu = 1, .mu = view_mu + N_MU - 1};
    ad_solution s;
    assert_int_equal(ad_solve(&p, &s), 0);
    double node[STREAMS], incident[STREAMS * MODES] = {0};
    plane_column_nodes(STREAMS, node);
    for (int j = 0; j < STREAMS; j++)
        incident[j * MODES] = 1.0;
    plane_layer layer[3] = {{.tau = 0.2 * s.tau_scaled, .ssa = 1.0, .chi = s.moments},
                            {.tau = 0.5 * s.tau_scaled, .ssa = 1.0, .chi = s.moments},
                            {.tau = 0.3 * s.tau_scaled, .ssa = 1.0, .chi = s.moments}};
    plane_column c = {.streams = STREAMS, .layer_count = 3, .layer = layer, .ground_albedo = 1.0, .mu0 = 1.0,
                      .n_mu = STREAMS, .mu = node};
    gauss_rule q;
    gauss_legendre(STREAMS, &q);
    double up[STREAMS * MODES], flux_down;
    assert_int_equal(plane_column_diffuse_level(&c, 0, incident, NULL, up, NULL), FM_OK);
    double flux_up = 0.0;
    for (int j = 0; j < STREAMS; j++)
        flux_up += 2.0 * FM_PI * 0.5 * q.w[j] * node[j] * up[j * MODES];
    check_rel(flux_up, FM_PI, 2e-4, "the top's upward flux, albedo 1");
    assert_int_equal(plane_column_diffuse_level(&c, 3, incident, NULL, up, &flux_down), FM_OK);
    flux_up = 0.0;
    for (int j = 0; j < STREAMS; j++)
        flux_up += 2.0 * FM_PI * 0.5 * q.w[j] * node[j] * up[j * MODES];
    check_rel(flux_up, flux_down, 2e-4, "the ground's upward flux, albedo 1");
    ad_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(field_as_beams),
        cmocka_unit_test(no_energy_lost),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
