#include "transport/single_scatter.h"

#include "atmosphere/optical_depth.h"
#include "base/quadrature.h"
#include "base/units.h"
#include "transport/free_flight.h"
#include "transport/ground_irradiance.h"

#include <math.h>
#include <stddef.h>

#define SS_POINTS 6      /* Gauss-Legendre points per piece */
#define SS_SUB_POINTS 4  /* points of the nested column quadratures */
#define SS_MAX_PIECE_DEPTH 0.5 /* grey majorant optical depth per piece */
#define SS_MAX_BOUNDS 140      /* altitude breakpoints along a ray (ray_pieces) */
#define SS_MAX_SPLIT 32        /* subdivisions of one piece */

/* Species columns over [sa, sb] (in s) by Gauss-Legendre with `points` nodes. */
static void piece_columns(const atmosphere *atm, double p2, double sa, double sb, const gauss_rule *g,
                          double *col)
{
    double n[FM_MAX_SPECIES];
    double half = 0.5 * (sb - sa), mid = 0.5 * (sb + sa);
    for (int c = 0; c < atm->species_count; c++)
        col[c] = 0.0;
    for (int i = 0; i < g->n; i++) {
        double s = mid + half * g->x[i];
        atmosphere_densities(atm, sqrt(p2 + s * s), n);
        for (int c = 0; c < atm->species_count; c++)
            col[c] += half * g->w[i] * n[c];
    }
}

void single_scatter_radiance(const path_context *ctx, vec3 origin, vec3 dir, double *L)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count, C = atm->species_count;
    const double *E0 = atm->grid.solar_irradiance;
    const gauss_rule *g = gauss_legendre_cached(SS_POINTS);
    const gauss_rule *gs = gauss_legendre_cached(SS_SUB_POINTS);
    ray_segment seg;
    ray_segment_init(&seg, atm, origin, dir);
    double r0 = v3_length(origin);
    double mu0 = seg.s0 / r0;
    double cos_sun = v3_dot(dir, ctx->sun_dir);

    /* Pieces between altitude breakpoints, split further where the majorant says they are thick. */
    double bounds[SS_MAX_BOUNDS];
    int nb = ray_pieces(atm, r0, mu0, seg.t_end, bounds, SS_MAX_BOUNDS);
    double pieces[SS_MAX_BOUNDS * SS_MAX_SPLIT + 1], depth[FM_MAX_WAVELENGTHS];
    int np = 0;
    for (int i = 0; i + 1 < nb; i++) {
        double ta = bounds[i] - seg.s0, tb = bounds[i + 1] - seg.s0;
        free_flight_majorant_depth(atm, &seg, ta, tb, depth);
        double thickest = 0.0;
        for (int k = 0; k < K; k++)
            thickest = fmax(thickest, depth[k]);
        int sub = (int)ceil(thickest / SS_MAX_PIECE_DEPTH);
        if (sub < 1)
            sub = 1;
        if (sub > SS_MAX_SPLIT)
            sub = SS_MAX_SPLIT;
        for (int j = 0; j < sub; j++)
            pieces[np++] = bounds[i] + (bounds[i + 1] - bounds[i]) * j / sub;
    }
    pieces[np++] = bounds[nb - 1];

    double col_start[FM_MAX_SPECIES] = {0}, col[FM_MAX_SPECIES], part[FM_MAX_SPECIES];
    double n[FM_MAX_SPECIES], phase[FM_MAX_WAVELENGTHS], sig_s[FM_MAX_WAVELENGTHS], tbar[FM_MAX_WAVELENGTHS];
    double sun_depth[FM_MAX_WAVELENGTHS];
    for (int i = 0; i + 1 < np; i++) {
        double sa = pieces[i], sb = pieces[i + 1];
        double half = 0.5 * (sb - sa), mid = 0.5 * (sb + sa);
        if (half <= 0.0)
            continue;
        for (int j = 0; j < g->n; j++) {
            double s = mid + half * g->x[j];
            piece_columns(atm, seg.p2, sa, s, gs, part);
            for (int c = 0; c < C; c++)
                col[c] = col_start[c] + part[c];
            double rad = sqrt(seg.p2 + s * s);
            atmosphere_densities(atm, rad, n);
            medium_phase(atm, n, cos_sun, phase, sig_s);
            vec3 x = v3_madd(origin, dir, s - seg.s0);
            /* sunlight in, transmittance out: one exp of the two optical depths */
            sun_irradiance_lookup_depth(ctx->sun_table, atm, ctx->sun, rad, v3_dot(x, ctx->sun_dir) / rad, sun_depth);
            double wgt = half * g->w[j];
            for (int k = 0; k < K; k++) {
                double t = exp(-(atmosphere_optical_depth(atm, col, k) + sun_depth[k]));
                L[k] += wgt * t * sig_s[k] * phase[k] * E0[k];
            }
        }
        piece_columns(atm, seg.p2, sa, sb, g, part);
        for (int c = 0; c < C; c++)
            col_start[c] += part[c];
    }

    if (seg.hits_ground) {
        vec3 x = v3_madd(origin, dir, seg.t_end);
        double rad = v3_length(x);
        double mu_s = v3_dot(x, ctx->sun_dir) / rad;
        double thor[FM_MAX_WAVELENGTHS];
        sun_irradiance_lookup(ctx->sun_table, atm, ctx->sun, atm->bottom_radius_m, mu_s, tbar, thor);
        double diffuse[FM_MAX_WAVELENGTHS] = {0};
        if (ctx->ground_diffuse)
            ground_irradiance_lookup(ctx->ground_diffuse, mu_s, diffuse);
        for (int k = 0; k < K; k++) {
            double tv = exp(-atmosphere_optical_depth(atm, col_start, k));
            L[k] += tv * atm->ground_albedo[k] / FM_PI * (E0[k] * thor[k] + diffuse[k]);
        }
    }
}
