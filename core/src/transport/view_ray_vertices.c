#include "transport/view_ray_vertices.h"

#include <math.h>

/* Share of the density spread by length, so that it is positive wherever the integrand can be.  By
 * day the rest, sigma_s T, is where the light is scattered: a sixth by length put a tenth of the
 * vertices above 40 km, where nothing scatters; at 1/25 the relative variance per path is 17% lower
 * for rural and clear air at sun 30 and 10% lower for the urban sunset, in the same time (map noise
 * at 512 x 256, four seeds: 0.48 -> 0.44% and 3.65 -> 3.38% RMS).  At twilight the light reaches the
 * vertices high up, which sigma_s T underrates: a sixth. */
#define SPREAD_DAY (1.0 / 25.0)
#define SPREAD_TWILIGHT (1.0 / 6.0)

/* sigma_s,k T_k(0, t) at the point t of the ray, for every grid wavelength */
static void scattered_fraction(const view_ray_vertices *v, const path_context *ctx, double t, double *f)
{
    const atmosphere *atm = ctx->atm;
    double n[FM_MAX_SPECIES], col[FM_MAX_SPECIES], sig_s[FM_MAX_WAVELENGTHS], sig_t[FM_MAX_WAVELENGTHS];
    atmosphere_densities(atm, ray_segment_radius(&v->seg, t), n);
    atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
    segment_columns_at(&v->columns, t, col);
    atmosphere_transmittances(atm, col, f);
    for (int k = 0; k < atm->grid.count; k++)
        f[k] *= sig_s[k];
}

int view_ray_vertices_init(view_ray_vertices *v, const path_context *ctx, vec3 origin, vec3 dir)
{
    const int K = ctx->atm->grid.count;
    ray_segment_init(&v->seg, ctx->atm, origin, dir);
    if (!(v->seg.t_end > 0.0))
        return 0;
    segment_columns_init(&v->columns, ctx, &v->seg);
    const int ks[3] = {K / 4, K / 2, (3 * K) / 4};
    double mass[VIEW_RAY_CELLS], total = 0.0, f[FM_MAX_WAVELENGTHS];
    for (int j = 0; j <= VIEW_RAY_CELLS; j++) {
        double u = (double)j / VIEW_RAY_CELLS;
        v->edge[j] = v->seg.t_end * u * u;
    }
    for (int j = 0; j < VIEW_RAY_CELLS; j++) {
        scattered_fraction(v, ctx, 0.5 * (v->edge[j] + v->edge[j + 1]), f);
        mass[j] = (f[ks[0]] + f[ks[1]] + f[ks[2]]) * (v->edge[j + 1] - v->edge[j]);
        total += mass[j];
    }
    const double spread = ctx->sky_guide ? SPREAD_TWILIGHT : SPREAD_DAY;
    v->cdf[0] = 0.0;
    for (int j = 0; j < VIEW_RAY_CELLS; j++) {
        double length = (v->edge[j + 1] - v->edge[j]) / v->seg.t_end;
        double p = total > 0.0 ? (1.0 - spread) * mass[j] / total + spread * length : length;
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
    double a = fmin(fmax((u - v->cdf[lo]) / (v->cdf[lo + 1] - v->cdf[lo]), 0.0), 1.0);
    double length = v->edge[lo + 1] - v->edge[lo], t = v->edge[lo] + a * length;
    scattered_fraction(v, ctx, t, weight);
    for (int k = 0; k < ctx->atm->grid.count; k++)
        weight[k] *= length / p;
    return v3_madd(v->seg.origin, v->seg.dir, t);
}
