#include "transport/single_scatter.h"

#include "atmosphere/optical_depth.h"
#include "base/exp_array.h"
#include "base/quadrature.h"
#include "base/units.h"
#include "phase/phase.h"
#include "spectrum/spectral.h"
#include "transport/free_flight.h"
#include "transport/ground_irradiance.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#define SS_POINTS 6      /* Gauss-Legendre points per piece (single_scatter_radiance) */
#define SS_SUB_POINTS 4  /* points of the nested column quadratures */
/* Grey majorant optical depth per piece: no piece optically thick, so that 3 Gauss points
 * integrate its exponentials (docs/decisions/2026-12-06-quadrature-accuracy.md). */
#define SS_MAX_PIECE_DEPTH 1.0
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

/* Quadrature pieces of the ray: between altitude breakpoints, split further where the majorant
 * says they are thick.  Returns the count of piece ends in `pieces`. */
static int ray_quadrature_pieces(const atmosphere *atm, const ray_segment *seg, double r0, double *pieces)
{
    const int K = atm->grid.count;
    double bounds[SS_MAX_BOUNDS], depth[FM_MAX_WAVELENGTHS];
    int nb = ray_pieces(atm, r0, seg->s0 / r0, seg->t_end, bounds, SS_MAX_BOUNDS);
    int np = 0;
    for (int i = 0; i + 1 < nb; i++) {
        double ta = bounds[i] - seg->s0, tb = bounds[i + 1] - seg->s0;
        free_flight_majorant_depth(atm, seg, ta, tb, depth);
        double thickest = 0.0;
        for (int k = 0; k < K; k++)
            thickest = fmax(thickest, depth[k]);
        /* clamped before the conversion: an opaque medium's depth overflows an int */
        double pieces_wanted = ceil(thickest / SS_MAX_PIECE_DEPTH);
        int sub = pieces_wanted >= SS_MAX_SPLIT ? SS_MAX_SPLIT : pieces_wanted >= 1.0 ? (int)pieces_wanted : 1;
        for (int j = 0; j < sub; j++)
            pieces[np++] = bounds[i] + (bounds[i + 1] - bounds[i]) * j / sub;
    }
    pieces[np++] = bounds[nb - 1];
    return np;
}

static int point_stride(const atmosphere *atm) { return 3 + atm->species_count + atm->grid.count; }

fm_status single_scatter_ray_init(single_scatter_ray *ray, const path_context *ctx, vec3 origin, vec3 dir,
                                  int points)
{
    const atmosphere *atm = ctx->atm;
    const int C = atm->species_count, stride = point_stride(atm);
    const gauss_rule *g = gauss_legendre_cached(points);
    const gauss_rule *gs = gauss_legendre_cached(SS_SUB_POINTS);
    ray_segment seg;
    ray_segment_init(&seg, atm, origin, dir);
    double r0 = v3_length(origin);
    double pieces[SS_MAX_BOUNDS * SS_MAX_SPLIT + 1];
    int np = ray_quadrature_pieces(atm, &seg, r0, pieces);
    ray->origin = origin;
    ray->sun_table = ctx->sun_table;
    ray->hits_ground = seg.hits_ground;
    ray->t_end = seg.t_end;
    ray->n = 0;
    const size_t most = (size_t)(np > 1 ? np - 1 : 1) * (size_t)g->n;
    ray->point = malloc(sizeof(double) * (size_t)stride * most);
    ray->sun_row = malloc(sizeof(sun_row_place) * most);
    if (!ray->point || !ray->sun_row) {
        single_scatter_ray_free(ray);
        return FM_ERR_OUT_OF_MEMORY;
    }
    double col_start[FM_MAX_SPECIES] = {0}, col[FM_MAX_SPECIES], part[FM_MAX_SPECIES];
    for (int i = 0; i + 1 < np; i++) {
        double sa = pieces[i], sb = pieces[i + 1];
        double half = 0.5 * (sb - sa), mid = 0.5 * (sb + sa);
        if (half <= 0.0)
            continue;
        for (int j = 0; j < g->n; j++) {
            double s = mid + half * g->x[j];
            if (ctx->sun_table) /* at pt[2] */
                ray->sun_row[ray->n] = sun_irradiance_row_place(ctx->sun_table, atm, sqrt(seg.p2 + s * s));
            double *pt = ray->point + (size_t)ray->n++ * stride;
            piece_columns(atm, seg.p2, sa, s, gs, part);
            for (int c = 0; c < C; c++)
                col[c] = col_start[c] + part[c];
            pt[0] = s - seg.s0;
            pt[1] = half * g->w[j];
            pt[2] = sqrt(seg.p2 + s * s);
            atmosphere_densities(atm, pt[2], pt + 3);
            atmosphere_optical_depths(atm, col, pt + 3 + C);
        }
        piece_columns(atm, seg.p2, sa, sb, g, part);
        for (int c = 0; c < C; c++)
            col_start[c] += part[c];
    }
    atmosphere_optical_depths(atm, col_start, ray->ground_transmittance);
    for (int k = 0; k < atm->grid.count && ray->hits_ground; k++) /* once per ray, not per direction */
        ray->ground_transmittance[k] = exp(-ray->ground_transmittance[k]);
    return FM_OK;
}

void single_scatter_ray_free(single_scatter_ray *ray)
{
    free(ray->point);
    free(ray->sun_row);
    ray->point = NULL;
    ray->sun_row = NULL;
}

void single_scatter_ray_radiance(const single_scatter_ray *ray, const path_context *ctx, vec3 dir, double *L)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count, C = atm->species_count, stride = point_stride(atm);
    const double *E0 = atm->grid.solar_irradiance;
    double cos_sun = v3_dot(dir, ctx->sun_dir), origin_sun = v3_dot(ray->origin, ctx->sun_dir);
    /* The scattering angle is the same at every point of the ray: each species' phase function
     * once per direction, as sigma_s,c(k) p_c(k) per unit density. */
    double scatter[FM_MAX_SPECIES][FM_MAX_WAVELENGTHS], value[FM_MAX_WAVELENGTHS];
    for (int c = 0; c < atm->scattering_count; c++) {
        phase_evaluate_all(&atm->species[c].phase, K, cos_sun, value);
        for (int k = 0; k < K; k++)
            scatter[c][k] = atm->species[c].sigma_s[k] * value[k];
    }
    double sun_depth[FM_MAX_WAVELENGTHS], coef[FM_MAX_WAVELENGTHS];
    /* with the ray's own table, each point's cell is located one point ahead, its nodes on their
     * way from memory while the point before is summed */
    const int placed = ray->sun_table == ctx->sun_table;
    sun_cell cells[2];
    if (placed && ray->n > 0)
        sun_irradiance_cell_at(ctx->sun_table, ray->sun_row[0], (origin_sun + ray->point[0] * cos_sun) / ray->point[2],
                               &cells[0]);
    for (int i = 0; i < ray->n; i++) {
        const double *pt = ray->point + (size_t)i * stride;
        double t = pt[0], wgt = pt[1], rad = pt[2];
        const double *n = pt + 3, *view_depth = pt + 3 + C;
        /* sunlight in, transmittance out: one exp of the two optical depths (none in the Earth's shadow) */
        const double mu_s = (origin_sun + t * cos_sun) / rad;
        if (placed && i + 1 < ray->n) {
            const double *next = pt + stride;
            sun_irradiance_cell_at(ctx->sun_table, ray->sun_row[i + 1], (origin_sun + next[0] * cos_sun) / next[2],
                                   &cells[(i + 1) & 1]);
        }
        if (!(placed ? sun_irradiance_cell_depths(ctx->sun_table, atm, ctx->sun, &cells[i & 1], rad, mu_s, sun_depth)
                     : sun_irradiance_lookup_depth(ctx->sun_table, atm, ctx->sun, rad, mu_s, sun_depth)))
            continue;
        spectral_fill(coef, 0.0, K);
        for (int c = 0; c < atm->scattering_count; c++)
            if (n[c] != 0.0) /* aerosol layers are absent at most altitudes */
                spectral_add_scaled(coef, n[c], scatter[c], K);
        double tr[FM_MAX_WAVELENGTHS];
        for (int k = 0; k < K; k++)
            tr[k] = -(view_depth[k] + sun_depth[k]);
        exp_array(tr, tr, K);
        for (int k = 0; k < K; k++)
            L[k] += wgt * tr[k] * coef[k] * E0[k];
    }

    if (ray->hits_ground) {
        vec3 x = v3_madd(ray->origin, dir, ray->t_end);
        double rad = v3_length(x);
        double mu_s = v3_dot(x, ctx->sun_dir) / rad;
        double tbar[FM_MAX_WAVELENGTHS], thor[FM_MAX_WAVELENGTHS];
        sun_irradiance_lookup_ground(ctx->sun_table, atm, ctx->sun, mu_s, tbar, thor);
        double diffuse[FM_MAX_WAVELENGTHS] = {0};
        if (ctx->ground_diffuse)
            ground_irradiance_lookup(ctx->ground_diffuse, mu_s, diffuse);
        for (int k = 0; k < K; k++) {
            L[k] += ray->ground_transmittance[k] * atm->ground_albedo[k] / FM_PI * (E0[k] * thor[k] + diffuse[k]);
        }
    }
}

void single_scatter_radiance(const path_context *ctx, vec3 origin, vec3 dir, double *L)
{
    single_scatter_ray ray;
    if (single_scatter_ray_init(&ray, ctx, origin, dir, SS_POINTS))
        abort(); /* a few hundred kilobytes at most */
    single_scatter_ray_radiance(&ray, ctx, dir, L);
    single_scatter_ray_free(&ray);
}
