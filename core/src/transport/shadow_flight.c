#include "transport/shadow_flight.h"

#include "base/exp_array.h"
#include "base/units.h"
#include "spectrum/spectral.h"
#include "transport/sunlit_segment.h"

#include <math.h>

const double shadow_flight_level_km[SHADOW_FLIGHT_LEVELS] = {0,  1,  2,  3,  5,  7,  10, 13, 16, 20,
                                                      25, 30, 35, 40, 47, 55, 65, 75, 87, 100};

/* The level below radius r and the fraction *a of the way to the next, clamped to the table.  The
 * search starts at the level below the whole km under r, not at level 0: this runs at every cell end
 * of every flight. */
static int level_below(const shadow_flight_table *t, double r, double *a)
{
    double km = (r - t->bottom_radius) / FM_KM;
    int i = t->level_at_km[(int)clamp_between(km, 0.0, SHADOW_FLIGHT_TOP_KM)];
    while (i < SHADOW_FLIGHT_LEVELS - 2 && km > shadow_flight_level_km[i + 1])
        i++;
    *a = clamp_between((km - shadow_flight_level_km[i]) / (shadow_flight_level_km[i + 1] - shadow_flight_level_km[i]), 0.0, 1.0);
    return i;
}

double shadow_flight_light(const shadow_flight_table *t, double r, double mu_s)
{
    double a;
    int i = level_below(t, r, &a);
    double s = (asin(clamp_cosine(mu_s)) - t->sun0) / t->sun_step;
    s = clamp_between(s, 0.0, SHADOW_FLIGHT_SUNS - 1.0);
    int j = (int)s < SHADOW_FLIGHT_SUNS - 1 ? (int)s : SHADOW_FLIGHT_SUNS - 2;
    double b = s - j;
    return (1.0 - a) * ((1.0 - b) * t->value[i][j] + b * t->value[i][j + 1]) +
           a * ((1.0 - b) * t->value[i + 1][j] + b * t->value[i + 1][j + 1]);
}

/* The sky guide's order-2 light per direction (shadow_flight_order2): a density needs no accurate
 * integral (docs/decisions/2026-12-06-sampling-densities.md). */
#define ORDER2_POINTS 16

/* sigma_s at the middle wavelength (the depth table's) at distance t along the segment of sd */
static double scattering_here(const segment_depth *sd, double t)
{
    const atmosphere *atm = sd->ctx->atm;
    const int k = sd->ctx->mid_depth->k;
    double n[FM_MAX_SPECIES], sigma = 0.0;
    atmosphere_densities(atm, ray_segment_radius(sd->seg, t), n);
    for (int c = 0; c < atm->scattering_count; c++)
        sigma += atm->species[c].sigma_s[k] * n[c];
    return sigma;
}

/* sigma_s T at the middle wavelength at distance t along the segment of sd, T from the segment's
 * origin: the light scattered there out of a unit beam from the origin. */
static double scattered_here(const segment_depth *sd, double t)
{
    return scattering_here(sd, t) * exp(-segment_depth_at(sd, t));
}

/* sigma_s T I at the middle wavelength, integrated along seg from its origin (trapezoids on `points`
 * + 1 points crowded at the origin, where a low point's air is densest). */
double shadow_flight_light_along(const shadow_flight_table *t, const path_context *single, const ray_segment *seg,
                                int points)
{
    segment_depth sd;
    segment_depth_init(&sd, single, seg);
    double prev = 0.0, t_prev = 0.0, sum = 0.0;
    for (int j = 0; j <= points; j++) {
        double v = (double)j / points, tj = seg->t_end * v * v, rad = ray_segment_radius(seg, tj);
        vec3 x = v3_madd(seg->origin, seg->dir, tj);
        double g = scattered_here(&sd, tj) * shadow_flight_light(t, rad, v3_dot(x, single->sun_dir) / rad);
        if (j > 0)
            sum += 0.5 * (g + prev) * (tj - t_prev);
        prev = g;
        t_prev = tj;
    }
    return sum;
}

double shadow_flight_order2(const shadow_flight_table *t, const path_context *single, vec3 origin, vec3 dir)
{
    ray_segment seg;
    ray_segment_init(&seg, single->atm, origin, dir);
    if (!(seg.t_end > 0.0))
        return 0.0;
    return shadow_flight_light_along(t, single, &seg, ORDER2_POINTS);
}

double shadow_flight_light_and_ambient(const shadow_flight_table *t, double r, double mu_s)
{
    double a;
    int i = level_below(t, r, &a);
    return shadow_flight_light(t, r, mu_s) + (1.0 - a) * t->ambient[i] + a * t->ambient[i + 1];
}

#define CELLS 24         /* of the piecewise-constant density */
#define PHYSICAL 0.3     /* share of sigma_s T alone in the mixture */
#define FLOOR 1e-3       /* share of the uniform cell choice */
#define GROUND_MIN 0.05  /* bounds of the probability of reaching the ground */
#define GROUND_MAX 0.7

/* scattered_here at n <= CELLS + 1 distances t, the exps in vector lanes (exp_array.h) */
static void scattered_at(const segment_depth *sd, const double *t, int n, double *out)
{
    double x[CELLS + 1];
    for (int j = 0; j < n; j++)
        x[j] = -segment_depth_at(sd, t[j]);
    exp_array(x, x, n);
    for (int j = 0; j < n; j++)
        out[j] = scattering_here(sd, t[j]) * x[j];
}

/* Cell ends: crowded at the segment's origin (optically thick air near a low vertex) and, when the
 * segment passes its lowest point (densest air) inside, with a cell end there. */
static void cell_ends(const ray_segment *seg, double *t)
{
    double low = -seg->s0; /* closest approach to the Earth's centre */
    if (low > 0.0 && low < seg->t_end) {
        const int n1 = CELLS / 2;
        for (int j = 0; j <= n1; j++) {
            double v = (double)j / n1;
            t[j] = low * v * v;
        }
        for (int j = 1; j <= CELLS - n1; j++) {
            double v = (double)j / (CELLS - n1);
            t[n1 + j] = low + (seg->t_end - low) * v * v;
        }
    } else {
        for (int j = 0; j <= CELLS; j++) {
            double v = (double)j / CELLS;
            t[j] = seg->t_end * v * v;
        }
    }
}

int shadow_flight(const path_context *ctx, const shadow_flight_table *table, const ray_segment *seg, rng *r,
                  double *w, double *t_out)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count; /* the density at the middle wavelength, the same for every hero */
    segment_depth sd;
    segment_depth_init(&sd, ctx, seg);
    double t[CELLS + 1], guided[CELLS + 1], physical[CELLS + 1], col[FM_MAX_SPECIES], n[FM_MAX_SPECIES];
    cell_ends(seg, t);
    scattered_at(&sd, t, CELLS + 1, physical);
    for (int j = 0; j <= CELLS; j++) {
        double rad = ray_segment_radius(seg, t[j]);
        vec3 x = v3_madd(seg->origin, seg->dir, t[j]);
        guided[j] = physical[j] * shadow_flight_light(table, rad, v3_dot(x, ctx->sun_dir) / rad);
    }
    double mass_g[CELLS], mass_p[CELLS], sum_g = 0.0, sum_p = 0.0;
    for (int j = 0; j < CELLS; j++) {
        double len = t[j + 1] - t[j];
        sum_g += mass_g[j] = larger(guided[j], guided[j + 1]) * len;
        sum_p += mass_p[j] = larger(physical[j], physical[j + 1]) * len;
    }
    double share_g = sum_g > 0.0 ? 1.0 - PHYSICAL : 0.0, share_p = sum_p > 0.0 ? 1.0 - share_g : 0.0;
    double cdf[CELLS + 1];
    cdf[0] = 0.0;
    for (int j = 0; j < CELLS; j++) {
        double p = (share_g > 0.0 ? share_g * mass_g[j] / sum_g : 0.0) +
                   (share_p > 0.0 ? share_p * mass_p[j] / sum_p : 0.0);
        if (!(share_g > 0.0) && !(share_p > 0.0))
            p = 1.0 / CELLS;
        cdf[j + 1] = cdf[j] + (1.0 - FLOOR) * p + FLOOR / CELLS;
    }
    /* the exact weights from the columns of every species (segment_columns) */
    segment_columns sc;
    segment_columns_init(&sc, ctx, seg);
    double p_ground = 0.0;
    if (seg->hits_ground) {
        p_ground = clamp_between(exp(-segment_depth_at(&sd, seg->t_end)), GROUND_MIN, GROUND_MAX);
        if (rng_uniform(r) < p_ground) {
            double tr[FM_MAX_WAVELENGTHS];
            segment_columns_at(&sc, seg->t_end, col);
            atmosphere_transmittances(atm, col, tr);
            spectral_mul_ratio(w, tr, p_ground, K);
            *t_out = seg->t_end;
            return 0;
        }
    }
    double u = rng_uniform(r) * cdf[CELLS];
    int j = 0;
    while (j < CELLS - 1 && u >= cdf[j + 1])
        j++;
    double pj = cdf[j + 1] - cdf[j], len = t[j + 1] - t[j];
    double ts = t[j] + len * clamp_between((u - cdf[j]) / pj, 0.0, 1.0);
    double pdf = (1.0 - p_ground) * pj / cdf[CELLS] / len;
    double rad = ray_segment_radius(seg, ts), sig_s[FM_MAX_WAVELENGTHS], sig_t[FM_MAX_WAVELENGTHS];
    segment_columns_at(&sc, ts, col);
    atmosphere_densities(atm, rad, n);
    atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
    double tr[FM_MAX_WAVELENGTHS];
    atmosphere_transmittances(atm, col, tr);
    for (int k = 0; k < K; k++)
        w[k] *= sig_s[k] * tr[k] / pdf;
    *t_out = ts;
    return 1;
}
