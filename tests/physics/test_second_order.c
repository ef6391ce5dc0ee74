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
    double gamma = a->species[0].phase_param[0];
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

static double second_order_quadrature(const fm_sky *sky, vec3 d, int steps)
{
    const atmosphere *a = &sky->atm;
    path_context one = sky_path_context(sky, 1, 1);
    vec3 o = sky->observer;
    double t_end = ray_distance_to_boundary(a, v3_length(o), d.z, NULL);
    double sum = 0.0, tau = 0.0, t_prev = 0.0;
    vec3 x_prev = o;
    for (int i = 0; i <= steps; i++) {
        double u = (double)i / steps, t = t_end * u * u, dt_du = 2.0 * t_end * u;
        vec3 x = v3_madd(o, d, t);
        if (i > 0) {
            double col[FM_MAX_SPECIES];
            column_exact(a, v3_length(x_prev), v3_dot(x_prev, d) / v3_length(x_prev), t - t_prev, col);
            tau += atmosphere_optical_depth(a, col, 0);
        }
        double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        if (dt_du > 0.0) {
            double n = profile_density(&a->species[0].profile, v3_length(x) - a->bottom_radius_m);
            sum += w * dt_du * exp(-tau) * a->species[0].sigma_s[0] * n * in_scattered(sky, &one, x, d);
        }
        t_prev = t;
        x_prev = x;
    }
    return sum / (3.0 * steps);
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
        const int N = 4000000;
        double sum = 0.0, sum2 = 0.0;
        for (int j = 0; j < N; j++) {
            rng r = rng_for(99, (uint64_t)i, (uint64_t)j);
            double L[1] = {0};
            path_trace(&two, sky->observer, d, 0, &r, L);
            sum += L[0];
            sum2 += L[0] * L[0];
        }
        double mean = sum / N, se = sqrt((sum2 / N - mean * mean) / N);
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
