/* Second-order scattering: the path tracer restricted to exactly two scattering events against a
 * deterministic quadrature of
 *     L2(x0, d) = integral_0^t_end T(0, t) sigma_s(x_t) integral_4pi p(d' . d) L1(x_t, d') dOmega' dt,
 * ground albedo 0 so that only air scatters.  The inner L1 is the single-scattering quadrature that
 * test_single_scattering checks against an independent reference; the outer integrals are Simpson
 * along the ray and Gauss-Legendre x trapezoid over the sphere, split at the local horizon.
 * A path tracer that sampled directions uniformly without the phase weight, or that weighted any
 * vertex wrongly, misses these values by several percent. */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/quadrature.h"
#include "base/rng.h"
#include "base/units.h"
#include "phase/phase_rayleigh.h"
#include "transport/single_scatter.h"

#include <math.h>

/* Integral over the sphere of p(d' . d) L1(y, d') around the point y. */
static double in_scattered(const fm_sky *sky, const path_context *one, vec3 y, vec3 d)
{
    const atmosphere *a = &sky->atm;
    double gamma = a->species[0].phase.param[0];
    double r = v3_length(y);
    frame f = frame_from_normal(v3_scale(y, 1.0 / r));
    double mh = horizon_mu(a, r);
    const double bounds[4] = {-1.0, mh, fmin(mh + 0.15, 1.0), 1.0};
    const int points[3] = {10, 12, 14};
    const int n_phi = 24;
    double sum = 0.0;
    for (int part = 0; part < 3; part++) {
        const gauss_rule *g = gauss_legendre_cached(points[part]);
        double half = 0.5 * (bounds[part + 1] - bounds[part]), mid = 0.5 * (bounds[part + 1] + bounds[part]);
        for (int i = 0; i < g->n; i++) {
            double mu = mid + half * g->x[i], s = sqrt(fmax(0.0, 1.0 - mu * mu));
            for (int j = 0; j < n_phi; j++) {
                double phi = 2.0 * FM_PI * (j + 0.5) / n_phi;
                vec3 dp = frame_to_world(&f, v3(s * cos(phi), s * sin(phi), mu));
                double L1[1] = {0};
                single_scatter_radiance(one, y, dp, L1);
                sum += half * g->w[i] * (2.0 * FM_PI / n_phi) * phase_rayleigh_eval(v3_dot(dp, d), gamma) * L1[0];
            }
        }
    }
    return sum;
}

typedef struct source_ctx {
    const fm_sky *sky;
    const path_context *one;
    vec3 d;
} source_ctx;

/* Order-2 source along the view ray: sigma_s(x) times the in-scattered order-1 radiance. */
static double second_order_source(void *p, vec3 x)
{
    const source_ctx *c = p;
    return test_molecular_scattering(c->sky, x) * in_scattered(c->sky, c->one, x, c->d);
}

static double second_order_quadrature(const fm_sky *sky, vec3 d, int steps)
{
    path_context one = sky_path_context(sky, 1, 1);
    source_ctx ctx = {sky, &one, d};
    return test_view_ray_integral(sky, d, steps, second_order_source, &ctx, NULL, NULL);
}

static void second_order_matches_quadrature(void **state)
{
    fm_sky_params p = test_params(30.0, 450.0);
    p.sun_azimuth_deg = 180.0;
    p.ground_albedo = 0.0;
    fm_sky *sky = test_sky(&p);
    const double dirs[3][2] = {{90, 0}, {20, 180}, {5, 0}};
    path_context two = sky_path_context(sky, 2, 2);
    for (int i = 0; i < 3; i++) {
        vec3 d = direction_from_elevation_azimuth(dirs[i][0] * FM_DEG, dirs[i][1] * FM_DEG);
        double ref = second_order_quadrature(sky, d, 40);
        double se, mean = test_path_radiance(&two, sky->observer, d, 4000000, 99, (uint64_t)i, &se);
        print_message("direction (%g, %g): quadrature %.6e, path tracer %.6e +- %.1e\n", dirs[i][0], dirs[i][1], ref,
                      mean, se);
        assert_true(se < 2.5e-3 * ref);
        check_rel(mean, ref, 1e-2, "second-order radiance: path tracer vs quadrature");
    }
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(second_order_matches_quadrature),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
