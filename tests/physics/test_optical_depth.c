/* Optical depth along rays: ray geometry, the closed form against an independent fine quadrature,
 * the fast quadrature and the tables against the closed form. */
#include "check.h"

#include "atmosphere/atmosphere_file.h"
#include "atmosphere/optical_depth.h"
#include "atmosphere/sun_irradiance.h"
#include "base/exp_array.h"
#include "base/rng.h"
#include "base/threads.h"
#include "base/units.h"
#include "transport/free_flight.h"
#include "transport/single_scatter.h"
#include "transport/sky_path.h"
#include "transport/view_ray_vertices.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static fm_sky *sky;

static int setup(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    fm_error err;
    return fm_sky_create(&p, &sky, &err) == FM_OK ? 0 : -1;
}

static int teardown(void **state)
{
    fm_sky_destroy(sky);
    return 0;
}

static void ray_geometry(void **state)
{
    const atmosphere *a = &sky->atm;
    double R = a->bottom_radius_m, H = FM_ATMOSPHERE_HEIGHT_M;
    check_rel(ray_distance_to_top(a, R, 1.0), H, 1e-12, "vertical distance to the top");
    check_rel(ray_distance_to_top(a, R, 0.0), sqrt((R + H) * (R + H) - R * R), 1e-12, "horizontal");
    assert_false(ray_hits_ground(a, R, 0.0));
    assert_true(ray_hits_ground(a, R + 1000.0, -0.5));
    /* from 10 km, the horizon is at mu = -sqrt(1 - (R/r)^2) */
    double r = R + 10000.0, mh = horizon_mu(a, r);
    assert_true(ray_hits_ground(a, r, mh - 1e-6));
    assert_false(ray_hits_ground(a, r, mh + 1e-6));
    check_rel(ray_distance_to_ground(a, r, -1.0), 10000.0, 1e-9, "straight down");
    /* from the ground itself every downward ray ends where it starts: exactly 0, not a rounding
     * error's sliver of air (an observer on the ground, the table's downward nodes) */
    for (double mu = -0.9999; mu < 0.0; mu += 0.0137)
        assert_true(ray_distance_to_ground(a, R, mu) == 0.0);
    /* 1 m up, the nearer root in long double: (r^2 - R^2) / (-r mu + sqrt(disc)) is the same root */
    for (double mu = -1.0; mu < -0.01; mu += 0.0731) {
        long double rl = (long double)R + 1.0L, disc = rl * rl * ((long double)mu * mu - 1.0L) + (long double)R * R;
        double expected = (double)(-rl * mu - sqrtl(disc));
        check_rel(ray_distance_to_ground(a, R + 1.0, mu), expected, 1e-6, "1 m up");
    }
}

/* Independent check: Simpson's rule with many points on the density evaluated pointwise. */
static double simpson_column(const atmosphere *a, int c, double r, double mu, double t_max, int n)
{
    double h = t_max / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double t = i * h;
        double rr = sqrt(r * r + t * t + 2.0 * r * mu * t);
        double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * profile_density(&a->species[c].profile, rr - a->bottom_radius_m);
    }
    return sum * h / 3.0;
}

static void closed_form_matches_fine_quadrature(void **state)
{
    const atmosphere *a = &sky->atm;
    const double R = a->bottom_radius_m;
    const double cases[][2] = {{0, 1}, {0, 0.3}, {0, 0.0}, {2000, -0.01}, {15000, -0.05}, {40000, 0.7}};
    for (int i = 0; i < 6; i++) {
        double r = R + cases[i][0], mu = cases[i][1];
        double t = ray_distance_to_boundary(a, r, mu, NULL);
        double exact[FM_MAX_SPECIES], quad[FM_MAX_SPECIES];
        column_exact(a, r, mu, t, exact);
        column_quadrature(a, r, mu, t, quad);
        for (int c = 0; c < a->species_count; c++) {
            double simpson = simpson_column(a, c, r, mu, t, 400000);
            check_rel(exact[c], simpson, 2e-6, "closed form vs Simpson");
            check_rel(quad[c], exact[c], 5e-5, "Gauss-Legendre pieces vs closed form");
        }
    }
}

/* Aerosol layers end in 50 m ramps; a Gauss piece with a ramp's end inside misses the kink.  Rays
 * grazing the stratospheric layer's top (35 km, between the fixed breakpoints at 33 and 36 km)
 * and the boundary layer's (2 km), each species' column against the closed form.  Before the
 * layers' kinks were breakpoints, the first ray's stratospheric column was 0.76% off. */
static void quadrature_breaks_at_layer_edges(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *urban;
    fm_error err;
    assert_int_equal(fm_sky_create(&p, &urban, &err), FM_OK);
    const atmosphere *a = &urban->atm;
    const double cases[][2] = {{37904.0, -0.03259}, {35052.0, -0.0118}, {40000.0, -0.0345}, {2500.0, -0.012},
                               {2040.0, -0.0011}, {36000.0, 0.02}};
    for (int i = 0; i < 6; i++) {
        double r = a->bottom_radius_m + cases[i][0], mu = cases[i][1];
        double t = ray_distance_to_top(a, r, mu), exact[FM_MAX_SPECIES], quad[FM_MAX_SPECIES];
        column_exact(a, r, mu, t, exact);
        column_quadrature(a, r, mu, t, quad);
        for (int c = 0; c < a->species_count; c++)
            if (strcmp(a->species[c].name, "aerosol") == 0 && exact[c] > 0.0)
                check_rel(quad[c], exact[c], 1e-6, "aerosol column across a layer's edge");
    }
    fm_sky_destroy(urban);
}

/* The transmittance tables are used for sunlight; check optical depth where it matters. */
static void column_table_accuracy(void **state)
{
    const atmosphere *a = &sky->atm;
    rng r = rng_for(1, 2, 3);
    double worst = 0.0;
    for (int i = 0; i < 3000; i++) {
        double z = 100000.0 * pow(rng_uniform(&r), 2.0), rr = a->bottom_radius_m + z;
        double mh = horizon_mu(a, rr), mu = mh + (1.0 - mh) * pow(rng_uniform(&r), 2.0);
        double tab[FM_MAX_SPECIES], exact[FM_MAX_SPECIES];
        if (!column_table_lookup(&sky->columns, a, rr, mu, tab))
            continue;
        column_exact(a, rr, mu, ray_distance_to_top(a, rr, mu), exact);
        double tau_exact = atmosphere_optical_depth(a, exact, 0); /* 380 nm: the thickest */
        double tau_tab = atmosphere_optical_depth(a, tab, 0);
        double err = fabs(tau_tab - tau_exact) / fmax(1.0, tau_exact); /* absolute below 1, relative above */
        worst = fmax(worst, err);
    }
    check_abs(worst, 0.0, 2e-3, "column table: worst optical-depth error at 380 nm");
}

/* The one-wavelength depth table (the deep-twilight flights' density) is the column table's depth at
 * its wavelength, node for node and so between nodes: up to float rounding of the stored depths,
 * over directions down to below the horizon (where both refuse the ray). */
static void depth_table_is_the_columns_depth(void **state)
{
    const atmosphere *a = &sky->atm;
    const depth_table *d = &sky->mid_depth;
    assert_int_equal(d->k, a->grid.count / 2);
    rng r = rng_for(4, 5, 6);
    double worst = 0.0;
    int compared = 0;
    for (int i = 0; i < 20000; i++) {
        double rr = a->bottom_radius_m + 100000.0 * pow(rng_uniform(&r), 2.0);
        double mh = horizon_mu(a, rr), mu = mh - 0.05 + (1.05 - mh) * rng_uniform(&r);
        double col[FM_MAX_SPECIES], depth = -1.0;
        int has_col = column_table_lookup(&sky->columns, a, rr, mu, col);
        int has_depth = depth_table_lookup(d, a, rr, mu, &depth);
        assert_int_equal(has_col, has_depth);
        if (!has_col)
            continue;
        double tau = atmosphere_optical_depth(a, col, d->k);
        worst = fmax(worst, fabs(depth - tau) / fmax(tau, 1e-3));
        compared++;
    }
    print_message("depth table against the columns' depth at %.0f nm: %d rays, worst %.2e\n", a->grid.lambda_nm[d->k],
                  compared, worst);
    assert_true(compared > 15000);
    check_abs(worst, 0.0, 1e-6, "depth table: worst relative difference from the columns' depth");
}

static void sun_table_accuracy(void **state)
{
    const atmosphere *a = &sky->atm;
    rng r = rng_for(4, 5, 6);
    double worst = 0.0, worst_day = 0.0;
    double tab[FM_MAX_WAVELENGTHS], direct[FM_MAX_WAVELENGTHS];
    for (int i = 0; i < 3000; i++) {
        double z = 100000.0 * pow(rng_uniform(&r), 2.0), rr = a->bottom_radius_m + z;
        double mu = -0.2 + 1.2 * pow(rng_uniform(&r), 2.0);
        sun_irradiance_lookup(&sky->sun_table, a, &sky->sun, rr, mu, tab);
        sun_transmittance_direct(a, &sky->columns, &sky->sun, rr, mu, direct, NULL);
        for (int k = 0; k < a->grid.count; k++) {
            worst = fmax(worst, fabs(tab[k] - direct[k]));
            if (mu > 0.05) /* the sun more than ~3 degrees above the local horizontal */
                worst_day = fmax(worst_day, fabs(tab[k] / direct[k] - 1.0));
        }
    }
    check_abs(worst, 0.0, 6e-3, "sun table: worst absolute transmittance error (twilight included)");
    check_abs(worst_day, 0.0, 1e-3, "sun table: worst relative error with the sun above 3 degrees");
}

static int ready_blocks(const sun_irradiance *t)
{
    int n = 0;
    for (int i = 0; i < t->rows.count * t->blocks_per_row; i++)
        n += atomic_load(&t->block_state[i]) != 0;
    return n;
}

typedef struct lookup_job {
    const fm_sky *sky;
    const double *r, *mu;
    double *out; /* [point][k] */
} lookup_job;

static void lookup_points(void *ctx, int64_t begin, int64_t end, int thread)
{
    lookup_job *job = ctx;
    for (int64_t i = begin; i < end; i++)
        sun_irradiance_lookup(&job->sky->sun_table, &job->sky->atm, &job->sky->sun, job->r[i], job->mu[i],
                              &job->out[i * FM_MAX_WAVELENGTHS]);
}

/* The sun table computes a block of nodes when a lookup first reads it: a new sky has none, one
 * lookup builds only the blocks around it, with the node's value exactly; lookups from two threads
 * at once (racing for the same blocks) return the same bits as from one. */
static void sun_table_builds_what_it_reads(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    fm_sky *a, *b;
    fm_error err;
    assert_int_equal(fm_sky_create(&p, &a, &err), FM_OK);
    assert_int_equal(fm_sky_create(&p, &b, &err), FM_OK);
    const sun_irradiance *t = &a->sun_table;
    assert_int_equal(ready_blocks(t), 0);
    /* node 100 of row 20: the lookup there reads it and its neighbours (one or two blocks per row) */
    int ir = 20, imu = 100;
    double rr = table_rows_radius(&t->rows, &a->atm, ir), lo = t->mu_lo[ir], x = (double)imu / (t->n_mu - 1);
    double mu = lo + (1.0 - lo) * x * x, tab[FM_MAX_WAVELENGTHS], direct[FM_MAX_WAVELENGTHS];
    sun_irradiance_lookup(t, &a->atm, &a->sun, rr, mu, tab);
    int built = ready_blocks(t);
    print_message("one lookup built %d of %d blocks\n", built, t->rows.count * t->blocks_per_row);
    assert_true(built >= 1 && built <= 4);
    sun_transmittance_direct(&a->atm, &a->columns, &a->sun, rr, mu, direct, NULL);
    for (int k = 0; k < a->atm.grid.count; k++)
        check_rel(tab[k], direct[k], 1e-5, "a node's lookup against its direct value (float depths)");

    enum { N = 20000 };
    static double r[N], m[N], one[N * FM_MAX_WAVELENGTHS], two[N * FM_MAX_WAVELENGTHS];
    rng g = rng_for(7, 8, 9);
    for (int i = 0; i < N; i++) {
        r[i] = a->atm.bottom_radius_m + 100000.0 * pow(rng_uniform(&g), 2.0);
        m[i] = -0.2 + 1.2 * rng_uniform(&g);
    }
    lookup_job ja = {a, r, m, one}, jb = {b, r, m, two};
    assert_int_equal(parallel_for(1, N, 64, lookup_points, &ja, NULL, NULL), FM_OK);
    assert_int_equal(parallel_for(2, N, 1, lookup_points, &jb, NULL, NULL), FM_OK);
    assert_int_equal(memcmp(one, two, sizeof one), 0);
    fm_sky_destroy(a);
    fm_sky_destroy(b);
}

/* The compact copy of the few wavelengths' depths (the segment sunlight's proxy reads it) gives the
 * full table's lookup bit for bit, the shadow included, over altitudes and suns from below the
 * horizon up: the same floats, weighed alike. */
static void few_depths_are_the_tables(void **state)
{
    const atmosphere *a = &sky->atm;
    const sun_irradiance *t = &sky->sun_table;
    int ks[SUN_FEW], n = sun_irradiance_few_wavelengths(a->grid.count, ks);
    assert_int_equal(n, SUN_FEW);
    assert_true(ks[0] > 0 && ks[0] < ks[1] && ks[1] < ks[2] && ks[2] < a->grid.count - 1);
    rng r = rng_for(10, 11, 12);
    int lit = 0;
    for (int i = 0; i < 20000; i++) {
        double rr = a->bottom_radius_m + 100000.0 * pow(rng_uniform(&r), 2.0), mu = -0.3 + 1.3 * rng_uniform(&r);
        double few[SUN_FEW], some[SUN_FEW];
        int has_few = sun_irradiance_lookup_few_depths(t, a, &sky->sun, rr, mu, few);
        int has_some = sun_irradiance_lookup_some_depths(t, a, &sky->sun, rr, mu, n, ks, some);
        assert_int_equal(has_few, has_some);
        assert_memory_equal(few, some, sizeof few);
        lit += has_few;
    }
    assert_true(lit > 10000);
}

static fm_sky *urban_sunset(void);

/* The sun table's lookup as it was before its corners were read once for both the bilinear depths
 * and the thick-cell test, before lookups were split in two (sun_irradiance_cell_at), and before the
 * rows' and the directions' fractions were taken by reciprocals (table_rows.per_step, per_horizon,
 * sun_irradiance.per_mu_span): the reference, with divisions.  It reads nodes the lookup under test
 * built.  A reciprocal's product is within 2 ulp of the quotient (1/b rounded, then the product
 * rounded), so the lookups' weights may differ from these by the bound `slack` carries, and each
 * depth by that times its corners' magnitudes (old_interpolate). */
#define ULP_HALF 0x1p-53

/* table_rows_locate with divisions; *slack bounds |t - t_reciprocal|: x within 2 half-ulps (x <= 1)
 * moves t by 2u / step, t's own roundings by 2u more (u = 2^-53) */
static int old_rows_locate(const table_rows *rows, const atmosphere *a, double r, double *t, double *slack)
{
    double rb = a->bottom_radius_m, rho2 = r * r - rb * rb;
    double x = rho2 > 0.0 ? sqrt(rho2) / rows->horizon_m : 0.0;
    x = x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0;
    int j = (int)(x * rows->cells);
    int i = rows->first[j < rows->cells ? j : rows->cells - 1];
    while (i + 2 < rows->count && rows->x[i + 1] <= x)
        i++;
    if (i > rows->count - 2)
        i = rows->count - 2;
    double step = rows->x[i + 1] - rows->x[i];
    *t = (x - rows->x[i]) / step;
    *slack = 4.0 * ULP_HALF * (1.0 + 1.0 / step);
    return i;
}

/* *slack bounds the weights' difference: mu's fraction q within 3u, its square root x within 3u
 * (x <= 1), the node fraction tm = x (n_mu - 1) - im within 3u (n_mu - 1) + 2u */
static int old_locate(const sun_irradiance *t, const atmosphere *a, double r, double mu_s, double w[4], size_t idx[4],
                      double *slack)
{
    double tr, slack_r;
    int ir = old_rows_locate(&t->rows, a, r, &tr, &slack_r), dark = 0;
    for (int row = 0; row < 2; row++) {
        double lo = t->mu_lo[ir + row];
        double x = mu_s <= lo ? 0.0 : sqrt((mu_s - lo) / (1.0 - lo));
        double fm = (x > 1.0 ? 1.0 : x < 0.0 ? 0.0 : x) * (t->n_mu - 1);
        int im = (int)fm;
        if (im > t->n_mu - 2)
            im = t->n_mu - 2;
        double tm = mu_s <= lo ? -1.0 : fm - im, wr = row == 0 ? 1.0 - tr : tr;
        dark |= tm < 0.0;
        idx[2 * row] = ((size_t)(ir + row) * t->n_mu + im) * t->count;
        idx[2 * row + 1] = idx[2 * row] + t->count;
        w[2 * row] = tm < 0.0 ? 0.0 : wr * (1.0 - tm);
        w[2 * row + 1] = tm < 0.0 ? 0.0 : wr * tm;
    }
    *slack = slack_r + ULP_HALF * (3.0 * (t->n_mu - 1) + 4.0);
    return dark;
}

/* the bilinear depths and, in slack_d, their bound: the weights' slack times the corners' sum of
 * magnitudes, plus 4u of the depth for the sum's own roundings */
static void old_interpolate(const float *v, const double w[4], const size_t idx[4], int K, double slack, double *d,
                            double *slack_d)
{
    for (int k = 0; k < K; k++) {
        d[k] = w[0] * v[idx[0] + k] + w[1] * v[idx[1] + k] + w[2] * v[idx[2] + k] + w[3] * v[idx[3] + k];
        double mass = fabs(v[idx[0] + k]) + fabs(v[idx[1] + k]) + fabs(v[idx[2] + k]) + fabs(v[idx[3] + k]);
        slack_d[k] = slack * mass + 4.0 * ULP_HALF * fabs(d[k]);
    }
}

static int old_thick_cell(const sun_irradiance *t, const atmosphere *a, double r, double mu_s, const double w[4],
                          const size_t idx[4], double *depth, double *slack_d)
{
    const int K = t->count;
    const float *v = t->normal;
    double w_lo = w[0] + w[1], w_hi = w[2] + w[3];
    if (!(w_lo > 0.0 && w_hi > 0.0))
        return 0;
    int row_up = (int)(idx[2] / ((size_t)t->n_mu * (size_t)K)), thick = 0, lit = 0;
    if (!(mu_s > 0.1) && !t->dense_cell[row_up - 1])
        return 0;
    for (int k = 0; k < K; k++) {
        double lo = (w[0] * v[idx[0] + k] + w[1] * v[idx[1] + k]) / w_lo;
        double hi = (w[2] * v[idx[2] + k] + w[3] * v[idx[3] + k]) / w_hi;
        thick |= fabs(lo - hi) > 0.05;
        lit |= hi < 50.0;
    }
    if (!thick || !lit)
        return 0;
    double r_up = table_rows_radius(&t->rows, a, row_up);
    if (!(r_up > r) || ray_hits_ground(a, r, mu_s))
        return 0;
    double s = -r * mu_s + sqrt(fmax(0.0, r * r * (mu_s * mu_s - 1.0) + r_up * r_up));
    double mu_up = clamp_cosine((r * mu_s + s) / r_up), w_up[4], col[FM_MAX_SPECIES], piece[FM_MAX_WAVELENGTHS];
    double slack;
    size_t idx_up[4];
    if (old_locate(t, a, r_up, mu_up, w_up, idx_up, &slack))
        return 0;
    old_interpolate(v, w_up, idx_up, K, slack, depth, slack_d);
    column_exact(a, r, mu_s, s, col);
    atmosphere_optical_depths(a, col, piece);
    for (int k = 0; k < K; k++) {
        depth[k] += piece[k];
        slack_d[k] += 2.0 * ULP_HALF * fabs(depth[k]);
    }
    return 1;
}

/* the old sun_irradiance_lookup_depth, the bound of each depth's difference from the lookup's in
 * slack_d; 2 where it took the thick cell's exact piece */
static int old_lookup_depth(const sun_irradiance *t, const atmosphere *a, double r, double mu_s, double *depth,
                            double *slack_d)
{
    double w[4], slack;
    size_t idx[4];
    if (old_locate(t, a, r, mu_s, w, idx, &slack)) {
        for (int k = 0; k < t->count; k++) {
            depth[k] = INFINITY;
            slack_d[k] = 0.0;
        }
        return 0;
    }
    int thick = old_thick_cell(t, a, r, mu_s, w, idx, depth, slack_d);
    if (!thick)
        old_interpolate(t->normal, w, idx, t->count, slack, depth, slack_d);
    for (int k = 0; k < t->count; k++)
        depth[k] = depth[k] < 200.0 ? depth[k] : INFINITY;
    return 1 + thick;
}

/* Depths against the old lookup's within its bound; the largest share of the bound used goes to
 * *used.  Infinite (dark) from 200 up: within the bound of 200 either may be dark, the other
 * finite (a transmittance of e^-200 against 0). */
static void depths_within(const double *got, const double *want, const double *slack_d, int K, double *used)
{
    for (int k = 0; k < K; k++) {
        if (isinf(want[k]) || isinf(got[k])) {
            double finite = isinf(want[k]) ? got[k] : want[k];
            if (!(isinf(finite) || finite >= 200.0 - slack_d[k]))
                fail_msg("sun lookup %.17g, the old %.17g (k %d)", got[k], want[k], k);
            continue;
        }
        double diff = fabs(got[k] - want[k]);
        if (!(diff <= slack_d[k]))
            fail_msg("sun lookup %.17g, the old %.17g: %.3g apart, bound %.3g", got[k], want[k], diff, slack_d[k]);
        if (slack_d[k] > 0.0)
            *used = fmax(*used, diff / slack_d[k]);
    }
}

/* The sun table's lookups (depths, transmittances, the few depths; whole or in two steps, cells
 * located ahead of their reading) against the old lookup within the reciprocals' bound: urban haze
 * at sunset, and an altostratus deck (thick cells at every sun), over altitudes and suns from below
 * the horizon up.  The transmittances are exp_array of the lookup's depths and the few depths the
 * full lookup's, bit for bit. */
static void sun_lookups_are_the_old_ones(void **state)
{
    fm_sky_params p = test_params(3.0, 0.0);
    p.clouds = "altostratus";
    fm_sky *skies[2] = {urban_sunset(), test_sky(&p)};
    rng r = rng_for(20, 21, 22);
    int lit = 0, thick = 0, moved = 0;
    double used = 0.0;
    for (int s = 0; s < 2; s++) {
        const atmosphere *a = &skies[s]->atm;
        const sun_irradiance *t = &skies[s]->sun_table;
        const int K = t->count;
        int ks[SUN_FEW], nk = sun_irradiance_few_wavelengths(K, ks);
        sun_cell ahead;
        double r_ahead = 0.0, mu_ahead = 0.0;
        for (int i = 0; i < 5000; i++) {
            /* half the points in the lowest 6 km (haze and the deck), suns from -0.3 to 1 */
            double z = i % 2 ? 6000.0 * rng_uniform(&r) : 100000.0 * pow(rng_uniform(&r), 2.0);
            double rr = a->bottom_radius_m + z, mu = -0.3 + 1.3 * pow(rng_uniform(&r), 1.5);
            double got[FM_MAX_WAVELENGTHS], want[FM_MAX_WAVELENGTHS], slack_d[FM_MAX_WAVELENGTHS];
            double tr[FM_MAX_WAVELENGTHS], depth[FM_MAX_WAVELENGTHS];
            int has = sun_irradiance_lookup_depth(t, a, &skies[s]->sun, rr, mu, depth);
            int old = old_lookup_depth(t, a, rr, mu, want, slack_d);
            assert_int_equal(has, old > 0);
            depths_within(depth, want, slack_d, K, &used);
            moved += memcmp(depth, want, sizeof(double) * (size_t)K) != 0;
            lit += has;
            thick += old == 2;
            sun_irradiance_lookup(t, a, &skies[s]->sun, rr, mu, got);
            for (int k = 0; k < K; k++)
                tr[k] = -depth[k];
            exp_array(tr, tr, K);
            assert_memory_equal(got, tr, sizeof(double) * (size_t)K);
            double few[SUN_FEW];
            sun_irradiance_lookup_few_depths(t, a, &skies[s]->sun, rr, mu, few);
            for (int j = 0; j < nk && old != 2; j++) /* the few are bilinear everywhere */
                assert_memory_equal(&few[j], &depth[ks[j]], sizeof(double));
            /* in two steps, the next point's cell located before this one's is read */
            sun_cell cell;
            sun_irradiance_cell(t, a, rr, mu, &cell);
            if (i > 0) {
                double behind[FM_MAX_WAVELENGTHS], ref[FM_MAX_WAVELENGTHS], ref_slack[FM_MAX_WAVELENGTHS];
                int has_behind = sun_irradiance_cell_depths(t, a, &skies[s]->sun, &ahead, r_ahead, mu_ahead, behind);
                assert_int_equal(has_behind, old_lookup_depth(t, a, r_ahead, mu_ahead, ref, ref_slack) > 0);
                depths_within(behind, ref, ref_slack, K, &used);
            }
            ahead = cell;
            r_ahead = rr;
            mu_ahead = mu;
        }
    }
    print_message("sun lookups against the old: %d lit, %d through a thick cell, %d not to the bit, worst %.2f of "
                  "the bound\n",
                  lit, thick, moved, used);
    assert_true(lit > 5000 && thick > 500);
    fm_sky_destroy(skies[0]);
    fm_sky_destroy(skies[1]);
}

/* Delta tracking's majorant bounds the extinction everywhere, for every wavelength. */
static void majorants_bound_the_medium(void **state)
{
    const atmosphere *a = &sky->atm;
    double ss[FM_MAX_WAVELENGTHS], st[FM_MAX_WAVELENGTHS];
    for (double z = 0.0; z < FM_ATMOSPHERE_HEIGHT_M; z += 37.0) {
        double rr = a->bottom_radius_m + z;
        atmosphere_coefficients(a, rr, ss, st);
        int s = atmosphere_shell_of(a, rr);
        for (int k = 0; k < a->grid.count; k++)
            if (st[k] > a->shell_majorant[s][k])
                fail_msg("z=%g k=%d: sigma_t %g > majorant %g", z, k, st[k], a->shell_majorant[s][k]);
    }
}

/* free_flight_majorant_depth sums majorant columns per species and expands them per wavelength at
 * the end (free_flight.c): against the majorant table itself summed along the ray by a fine
 * midpoint rule, every wavelength, rays from 0 to 60 km in every direction. */
static void majorant_depth_sums_the_shells(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    p.biome = "urban";
    p.turbidity = 2.0;
    fm_sky *urban = test_sky(&p);
    rng r = rng_for(11, 12, 13);
    for (int i = 0; i < 40; i++) {
        const atmosphere *a = i % 2 ? &urban->atm : &sky->atm; /* molecules and ozone; and aerosol layers */
        const int K = a->grid.count;
        double z = 60000.0 * rng_uniform(&r), mu = 2.0 * rng_uniform(&r) - 1.0;
        vec3 origin = v3(0.0, 0.0, a->bottom_radius_m + z), dir = v3(sqrt(1.0 - mu * mu), 0.0, mu);
        ray_segment seg;
        ray_segment_init(&seg, a, origin, dir);
        double depth[FM_MAX_WAVELENGTHS], fine[FM_MAX_WAVELENGTHS] = {0};
        free_flight_majorant_depth(a, &seg, 0.0, seg.t_end, depth);
        const int steps = 2000000;
        const double dt = seg.t_end / steps;
        double length[FM_MAX_SHELLS] = {0}; /* m of the ray in each shell, by midpoints */
        for (int j = 0; j < steps; j++)
            length[atmosphere_shell_of(a, ray_segment_radius(&seg, (j + 0.5) * dt))] += dt;
        for (int s = 0; s < a->shell_count; s++)
            for (int k = 0; k < K; k++)
                fine[k] += a->shell_majorant[s][k] * length[s];
        for (int k = 0; k < K; k++)
            check_rel(depth[k], fine[k], 2e-5, "majorant depth against the shells summed finely");
    }
    fm_sky_destroy(urban);
}


static fm_sky *urban_sunset(void)
{
    fm_sky_params p = test_params(2.0, 0.0);
    p.biome = "urban";
    p.turbidity = 2.0;
    return test_sky(&p);
}

/* The tables' rows (table_rows.h): ascending from the ground to the top, a row on every edge of a
 * species' profile and on the profile nodes of each ramp (urban: 1950, 2000, 2050 m; 11950 ...
 * 12050; 34950 ... 35050), and table_rows_locate brackets any radius between two rows. */
static void table_rows_hold_the_edges(void **state)
{
    fm_sky *urban = urban_sunset();
    const atmosphere *a = &urban->atm;
    const table_rows *rows = &urban->columns.rows;
    const double rb = a->bottom_radius_m;
    assert_int_equal(a->edge_count, 6);
    assert_int_equal(rows->count, 128 + 9);
    assert_true(rows->x[0] == 0.0 && rows->x[rows->count - 1] == 1.0);
    for (int i = 0; i + 1 < rows->count; i++)
        assert_true(rows->x[i] < rows->x[i + 1]);
    const double ramp_nodes_m[] = {1950, 2000, 2050, 11950, 12000, 12050, 34950, 35000, 35050};
    for (int e = 0; e < 9; e++) {
        double t;
        int i = table_rows_locate(rows, a, rb + ramp_nodes_m[e], &t);
        double z = table_rows_radius(rows, a, t < 0.5 ? i : i + 1) - rb;
        check_abs(z, ramp_nodes_m[e], 1e-6, "a row on the ramp's node");
        check_abs(fmin(t, 1.0 - t), 0.0, 1e-9, "the node is a row, not between two");
    }
    rng r = rng_for(21, 22, 23);
    for (int n = 0; n < 20000; n++) {
        double z = 100000.0 * pow(rng_uniform(&r), 3.0), t;
        int i = table_rows_locate(rows, a, rb + z, &t);
        assert_true(i >= 0 && i <= rows->count - 2);
        double z0 = table_rows_radius(rows, a, i) - rb, z1 = table_rows_radius(rows, a, i + 1) - rb;
        if (!(z0 <= z + 1e-6 && z <= z1 + 1e-6 && t >= -1e-9 && t <= 1.0 + 1e-9))
            fail_msg("z = %.6f m: rows at %.6f and %.6f m, t = %g", z, z0, z1, t);
    }
    fm_sky_destroy(urban);
}

/* The sun table across the top of the urban haze (its 100 m ramp at 1950-2050 m) at sunset,
 * against the transmittance integrated along the disk's chords without tables, every wavelength
 * whose transmittance exceeds 1%: rows 200 m apart across the ramp had the sunlight 18% too dark
 * at 1950 m (550 nm), which made the whole sky 0.8% too dark. */
static void sun_table_across_a_layer_top(void **state)
{
    fm_sky *urban = urban_sunset();
    const atmosphere *a = &urban->atm;
    double tab[FM_MAX_WAVELENGTHS], direct[FM_MAX_WAVELENGTHS], worst = 0.0, worst_z = 0.0;
    for (double z = 1800.0; z <= 2300.0; z += 5.0) {
        double r = a->bottom_radius_m + z, mu_s = sin(2.0 * FM_DEG);
        sun_irradiance_lookup(&urban->sun_table, a, &urban->sun, r, mu_s, tab);
        sun_transmittance_direct(a, NULL, &urban->sun, r, mu_s, direct, NULL);
        for (int k = 0; k < a->grid.count; k++)
            if (direct[k] > 0.01 && fabs(tab[k] / direct[k] - 1.0) > worst) {
                worst = fabs(tab[k] / direct[k] - 1.0);
                worst_z = z;
            }
    }
    print_message("sun table across the haze's top at sun 2: worst %.2f%% at %.0f m\n", 100.0 * worst, worst_z);
    check_abs(worst, 0.0, 0.05, "sun table across the haze's top");
    fm_sky_destroy(urban);
}

/* Optical depth at grid wavelength k along the ray from (r, mu) to the top, by Simpson's rule on the
 * densities evaluated pointwise: fine steps up to 5 km (the deck below it, its edges' ramps bending
 * every 50 m), coarser above in the smooth clear air. */
static double simpson_depth(const atmosphere *a, int k, double r, double mu)
{
    double r_split = a->bottom_radius_m + 5000.0, t_end = ray_distance_to_top(a, r, mu);
    double t_split = -r * mu + sqrt(r * r * (mu * mu - 1.0) + r_split * r_split);
    const double from[2] = {0.0, t_split}, to[2] = {t_split, t_end};
    const int steps[2] = {40000, 20000};
    double tau = 0.0;
    for (int p = 0; p < 2; p++) {
        double h = (to[p] - from[p]) / steps[p];
        for (int i = 0; i <= steps[p]; i++) {
            double t = from[p] + i * h, rr = sqrt(r * r + t * t + 2.0 * r * mu * t);
            double w = (i == 0 || i == steps[p]) ? 1.0 : (i % 2 ? 4.0 : 2.0);
            for (int c = 0; c < a->species_count; c++)
                tau += w * h / 3.0 * a->species_sigma_t[c][k] *
                       profile_density(&a->species[c].profile, rr - a->bottom_radius_m);
        }
    }
    return tau;
}

/* The sun table's transmittance inside the altostratus deck (3-4 km, optical depth 10) at suns 2-8
 * degrees up, where the beam falls by e in 10-30 m of the deck's top, against the disk's 12 chords
 * each integrated through the sphere by simpson_depth, wherever the sunlight is above 3e-3.  The
 * exact piece goes along the disk's centre only: at sun 2 the disk's spread over it leaves up to
 * 1.9 % (sunlight below 1 %).  Fails with the piece left to suns above 5.7 degrees in cloud too (the
 * bilinear depth across the deck's cells: up to 58 % too dark at sun 2, 30 % at sun 5). */
static void sun_table_inside_a_cloud(void **state)
{
    fm_sky_params p = test_params(3.0, 0.0);
    p.clouds = "altostratus";
    p.wavelength_nm = 550.0;
    fm_sky *deck = test_sky(&p);
    const atmosphere *a = &deck->atm;
    const sun_chord_rule *rule = &deck->sun.full;
    const double suns_deg[] = {2.0, 3.0, 5.0, 8.0};
    double worst = 0.0, worst_z = 0.0, worst_sun = 0.0;
    int compared = 0;
    for (int s = 0; s < 4; s++) {
        double theta_s = FM_PI / 2.0 - suns_deg[s] * FM_DEG, mu_s = cos(theta_s);
        for (double z = 3500.0; z <= 4100.0; z += 3.0) {
            double r = a->bottom_radius_m + z, tab[FM_MAX_WAVELENGTHS];
            sun_irradiance_lookup(&deck->sun_table, a, &deck->sun, r, mu_s, tab);
            double exact = 0.0;
            for (int j = 0; j < rule->n; j++)
                exact += rule->weight[j][0] * exp(-simpson_depth(a, 0, r, cos(theta_s - rule->delta[j])));
            if (exact < 3e-3)
                continue;
            compared++;
            if (fabs(tab[0] / exact - 1.0) > worst) {
                worst = fabs(tab[0] / exact - 1.0);
                worst_z = z;
                worst_sun = suns_deg[s];
            }
        }
    }
    print_message("sun table in altostratus: %d points, worst %.2f%% at %.0f m, sun %.0f\n", compared, 100.0 * worst,
                  worst_z, worst_sun);
    assert_true(compared > 20);
    check_abs(worst, 0.0, 0.025, "sun table inside a cloud at a low sun");
    fm_sky_destroy(deck);
}

/* The columns along a view ray (view_ray_vertices.h) against the closed form, for rays from the
 * ground near the horizon through the urban haze, where the column table's difference of two
 * columns to the top is off by 0.02 to 0.06 in optical depth at 550 nm (at depths 5 to 47). */
static void view_ray_columns_are_exact(void **state)
{
    fm_sky *urban = urban_sunset();
    const atmosphere *a = &urban->atm;
    path_context pc = sky_path_context(urban, 2, 64);
    const double elevation_deg[] = {0.0, 0.1, 0.3, 0.6, 1.0, 2.0, 5.0, 20.0, 90.0};
    double worst = 0.0;
    for (int e = 0; e < 9; e++) {
        double el = elevation_deg[e] * FM_DEG;
        view_ray_vertices v;
        assert_true(view_ray_vertices_init(&v, &pc, urban->observer, v3(cos(el), 0.0, sin(el))));
        double r0 = v3_length(urban->observer), mu0 = sin(el);
        for (int i = 1; i <= 50; i++) {
            double t = v.seg.t_end * pow(i / 50.0, 2.0), col[FM_MAX_SPECIES], exact[FM_MAX_SPECIES];
            view_ray_columns(&v, a, t, col);
            column_exact(a, r0, mu0, t, exact);
            double tau = atmosphere_optical_depth(a, col, 17), tau_exact = atmosphere_optical_depth(a, exact, 17);
            worst = fmax(worst, fabs(tau - tau_exact) / fmax(1.0, tau_exact));
        }
    }
    print_message("view ray columns: worst optical-depth error %.2g (absolute below 1, relative above)\n", worst);
    check_abs(worst, 0.0, 1e-5, "view ray columns against the closed form");
    fm_sky_destroy(urban);
}

/* An opaque medium at the atmosphere file's bounds (a coefficient of 1 m^-1 times a tabulated
 * profile of 1000, up to 10000 km): the vertical ray's last piece, 5000 to 10000 km, is 5e9 deep,
 * beyond an int.  The single-scattering quadrature splits every piece into the most subdivisions
 * it allows (SS_MAX_SPLIT, 32: each piece is over 32 deep), not into a count converted from that
 * depth. */
static void opaque_pieces_split_the_most(void **state)
{
    char *path = test_write_temp("atmosphere",
                                 "{\"planet_radius_km\": 6360, \"top_altitude_km\": 10000, \"solar_irradiance\": 1, "
                                 "\"constituents\": [{\"profile\": {\"type\": \"tabulated\", \"altitudes_km\": [0, "
                                 "10000], \"values\": [1000, 1000]}, \"scattering\": 1, \"phase\": {\"type\": "
                                 "\"rayleigh\"}}]}");
    spectral_grid grid;
    spectral_grid_single(&grid, 550.0);
    atmosphere atm;
    fm_error err = {0};
    assert_int_equal(atmosphere_init_from_file(&atm, path, &grid, 1.0, 0.2, &err), FM_OK);
    const path_context pc = {.atm = &atm};
    const vec3 origin = v3(0.0, 0.0, atm.bottom_radius_m), up = v3(0.0, 0.0, 1.0);
    double bounds[140];
    int nb = ray_pieces(&atm, atm.bottom_radius_m, 1.0, atm.top_radius_m - atm.bottom_radius_m, bounds, 140);
    single_scatter_ray ray;
    assert_int_equal(single_scatter_ray_init(&ray, &pc, origin, up, 6), FM_OK);
    print_message("opaque vertical ray: %d pieces between breakpoints, %d quadrature points\n", nb - 1, ray.n);
    assert_int_equal(ray.n, 6 * 32 * (nb - 1));
    for (int i = 0; i < ray.n; i++) /* the points' view depths are finite */
        assert_true(isfinite(ray.point[(size_t)i * (3 + atm.species_count + 1) + 3 + atm.species_count]));
    single_scatter_ray_free(&ray);
    atmosphere_free(&atm);
    unlink(path);
    free(path);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ray_geometry),
        cmocka_unit_test(closed_form_matches_fine_quadrature),
        cmocka_unit_test(quadrature_breaks_at_layer_edges),
        cmocka_unit_test(column_table_accuracy),
        cmocka_unit_test(depth_table_is_the_columns_depth),
        cmocka_unit_test(sun_table_accuracy),
        cmocka_unit_test(sun_table_builds_what_it_reads),
        cmocka_unit_test(few_depths_are_the_tables),
        cmocka_unit_test(sun_lookups_are_the_old_ones),
        cmocka_unit_test(majorants_bound_the_medium),
        cmocka_unit_test(majorant_depth_sums_the_shells),
        cmocka_unit_test(table_rows_hold_the_edges),
        cmocka_unit_test(sun_table_across_a_layer_top),
        cmocka_unit_test(sun_table_inside_a_cloud),
        cmocka_unit_test(view_ray_columns_are_exact),
        cmocka_unit_test(opaque_pieces_split_the_most),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
