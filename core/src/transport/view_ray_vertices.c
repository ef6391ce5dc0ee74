#include "transport/view_ray_vertices.h"

#include "atmosphere/optical_depth.h"
#include "base/vec.h"
#include "spectrum/spectral.h"
#include "transport/deck_base.h"
#include "transport/shadow_flight.h"

#include <math.h>

/* Share of the density spread by length, so that it is positive wherever the integrand can be.  By
 * day the rest, sigma_s T, is where the light is scattered, and a larger share would put vertices
 * high up where nothing scatters; at twilight the light reaches the vertices high up, which
 * sigma_s T underrates (docs/decisions/2026-12-06-sampling-densities.md). */
#define SPREAD_DAY (1.0 / 25.0)
#define SPREAD_TWILIGHT (1.0 / 6.0)

/* The species' columns from the edge of cell j to the point t of the ray, by quadrature. */
static void columns_in_cell(const view_ray_vertices *v, const atmosphere *atm, int j, double t, double *col)
{
    double r = ray_segment_radius(&v->seg, v->edge[j]);
    double mu = clamp_cosine((v->edge[j] + v->seg.s0) / r);
    column_quadrature(atm, r, mu, t - v->edge[j], col);
}

/* The species' columns from the origin to the point t of cell j. */
static void columns_to(const view_ray_vertices *v, const atmosphere *atm, int j, double t, double *col)
{
    columns_in_cell(v, atm, j, t, col);
    for (int c = 0; c < atm->species_count; c++)
        col[c] += v->column[j][c];
}

/* sigma_s,k T_k(0, t) at the point t of the ray, for every grid wavelength, given the columns to t */
static void scattered_fraction(const view_ray_vertices *v, const path_context *ctx, double t, const double *col,
                               double *f)
{
    const atmosphere *atm = ctx->atm;
    double n[FM_MAX_SPECIES], sig_s[FM_MAX_WAVELENGTHS], sig_t[FM_MAX_WAVELENGTHS];
    atmosphere_densities(atm, ray_segment_radius(&v->seg, t), n);
    atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
    atmosphere_transmittances(atm, col, f);
    spectral_mul(f, sig_s, atm->grid.count);
}

void view_ray_columns(const view_ray_vertices *v, const atmosphere *atm, double t, double *col)
{
    /* the edges are t_end (j / CELLS)^2 */
    int j = (int)(VIEW_RAY_CELLS * sqrt(fmax(t, 0.0) / v->seg.t_end));
    j = j < 0 ? 0 : (j > VIEW_RAY_CELLS - 1 ? VIEW_RAY_CELLS - 1 : j);
    while (j > 0 && v->edge[j] > t)
        j--;
    while (j + 1 < VIEW_RAY_CELLS && v->edge[j + 1] <= t)
        j++;
    columns_to(v, atm, j, t, col);
}

int view_ray_vertices_init(view_ray_vertices *v, const path_context *ctx, vec3 origin, vec3 dir)
{
    const int K = ctx->atm->grid.count;
    ray_segment_init(&v->seg, ctx->atm, origin, dir);
    v->at_deck = deck_base_cut(ctx->deck, &v->seg);
    if (!(v->seg.t_end > 0.0))
        return 0;
    const int ks[3] = {K / 4, K / 2, (3 * K) / 4};
    double mass[VIEW_RAY_CELLS], total = 0.0, f[FM_MAX_WAVELENGTHS];
    double lit[VIEW_RAY_CELLS], total_lit = 0.0; /* mass x the light at the cell's middle */
    const double share = ctx->shadow_flights ? ctx->first_vertex_light_share : 0.0;
    const int S = ctx->atm->species_count;
    for (int j = 0; j <= VIEW_RAY_CELLS; j++) {
        double u = (double)j / VIEW_RAY_CELLS;
        v->edge[j] = v->seg.t_end * u * u;
    }
    for (int c = 0; c < S; c++)
        v->column[0][c] = 0.0;
    for (int j = 0; j < VIEW_RAY_CELLS; j++) {
        double cell[FM_MAX_SPECIES];
        columns_in_cell(v, ctx->atm, j, v->edge[j + 1], cell);
        for (int c = 0; c < S; c++)
            v->column[j + 1][c] = v->column[j][c] + cell[c];
    }
    for (int j = 0; j < VIEW_RAY_CELLS; j++) {
        double mid = 0.5 * (v->edge[j] + v->edge[j + 1]), col[FM_MAX_SPECIES];
        columns_to(v, ctx->atm, j, mid, col);
        scattered_fraction(v, ctx, mid, col, f);
        mass[j] = (f[ks[0]] + f[ks[1]] + f[ks[2]]) * (v->edge[j + 1] - v->edge[j]);
        total += mass[j];
        if (share > 0.0) {
            vec3 x = v3_madd(v->seg.origin, v->seg.dir, mid);
            double r = v3_length(x);
            lit[j] = mass[j] * shadow_flight_light_and_ambient(ctx->shadow_flights, r, v3_dot(x, ctx->sun_dir) / r);
            total_lit += lit[j];
        }
    }
    v->light_integral = total_lit;
    const double spread = ctx->sky_guide ? SPREAD_TWILIGHT : SPREAD_DAY;
    v->cdf[0] = 0.0;
    for (int j = 0; j < VIEW_RAY_CELLS; j++) {
        double length = (v->edge[j + 1] - v->edge[j]) / v->seg.t_end;
        double p = length;
        if (total > 0.0 && total_lit > 0.0)
            p = (1.0 - spread) * ((1.0 - share) * mass[j] / total + share * lit[j] / total_lit) + spread * length;
        else if (total > 0.0)
            p = (1.0 - spread) * mass[j] / total + spread * length;
        v->cdf[j + 1] = v->cdf[j] + p;
    }
    return 1;
}

vec3 view_ray_vertex(const view_ray_vertices *v, const path_context *ctx, double u, double *weight)
{
    u *= v->cdf[VIEW_RAY_CELLS];
    int lo = 0, hi = VIEW_RAY_CELLS - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (v->cdf[mid] <= u)
            lo = mid;
        else
            hi = mid - 1;
    }
    double p = (v->cdf[lo + 1] - v->cdf[lo]) / v->cdf[VIEW_RAY_CELLS];
    double a = clamp_between((u - v->cdf[lo]) / (v->cdf[lo + 1] - v->cdf[lo]), 0.0, 1.0);
    double length = v->edge[lo + 1] - v->edge[lo], t = v->edge[lo] + a * length;
    double col[FM_MAX_SPECIES];
    columns_to(v, ctx->atm, lo, t, col);
    scattered_fraction(v, ctx, t, col, weight);
    for (int k = 0; k < ctx->atm->grid.count; k++)
        weight[k] *= length / p;
    return v3_madd(v->seg.origin, v->seg.dir, t);
}
