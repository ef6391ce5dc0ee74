#include "transport/sunlit_segment.h"

#include "atmosphere/optical_depth.h"
#include "base/exp_array.h"
#include "base/units.h"
#include "spectrum/spectral.h"

#include <math.h>

#define PROXY_CELLS 8  /* cells of the proxy density over the sunlit length (at most) */
#define RISING_CELLS 4 /* for SEGMENT_SUNLIGHT_RISING: urban sunset, 2 / 4 / 8 cells: node variance 1.04 /
                          * 1 / 0.95, CPU 0.93 / 1 / 1.07 (as efficient; the fewer, the less time) */
#define SUN_SAMPLES 2  /* stratified evaluations per segment */
#define DEFENSIVE 0.2 /* share of the uniform density in the mixture */
#define UMBRA_MARGIN 1.0 /* m taken off each end of the umbra interval */

/* The umbra of a sun of angular radius a at infinity behind a sphere of radius R, with
 * z = -p . s (distance behind the terminator plane) and rho the distance from the shadow's axis:
 * a point sees no part of the disk above its horizon iff asin(R / r) >= psi + a, psi the angle of p
 * from -s, which is  z >= r sin a  and  rho cos a + z sin a <= R  (a cone tangent to the sphere,
 * apex R / sin a behind it; convex).  Inside the atmosphere z >= r_top sin a implies the first; the
 * second is the quadratic  cos^2 a |p|^2 - z^2 + 2 R sin a z - R^2 <= 0  along the line. */
int segment_umbra(const path_context *ctx, const ray_segment *seg, double *t0, double *t1)
{
    const atmosphere *atm = ctx->atm;
    const double R = atm->bottom_radius_m, alpha = ctx->sun->angular_radius;
    const double ca2 = cos(alpha) * cos(alpha), sa = sin(alpha);
    vec3 s = ctx->sun_dir;
    double z0 = -v3_dot(seg->origin, s), zd = -v3_dot(seg->dir, s);
    double a = ca2 - zd * zd;
    if (!(a > 1e-9))
        return 0; /* a segment along the shadow's axis: left to the point estimate */
    double b = 2.0 * (ca2 * seg->s0 - z0 * zd + R * sa * zd);
    double c = ca2 * v3_dot(seg->origin, seg->origin) - z0 * z0 + 2.0 * R * sa * z0 - R * R;
    double disc = b * b - 4.0 * a * c;
    if (!(disc > 0.0))
        return 0;
    double q = -0.5 * (b + copysign(sqrt(disc), b));
    double lo = fmin(q / a, c / q), hi = fmax(q / a, c / q);
    double zmin = atm->top_radius_m * sa, tz = (zmin - z0) / zd;
    if (zd > 0.0)
        lo = fmax(lo, tz);
    else if (zd < 0.0)
        hi = fmin(hi, tz);
    else if (z0 < zmin)
        return 0;
    lo = fmax(lo, 0.0) + UMBRA_MARGIN;
    hi = fmin(hi, seg->t_end) - UMBRA_MARGIN;
    if (!(hi > lo))
        return 0;
    /* both ends in the table's shadow, so (convexity) everything between */
    for (int e = 0; e < 2; e++) {
        double t = e ? hi : lo, rad = ray_segment_radius(seg, t);
        vec3 x = v3_madd(seg->origin, seg->dir, t);
        if (!sun_in_umbra(atm, ctx->sun, rad, v3_dot(x, s) / rad))
            return 0;
    }
    *t0 = lo;
    *t1 = hi;
    return 1;
}

/* Whether the segment passes through a cell of the sun table that holds cloud or fog
 * (sun_irradiance.dense_cell): between its lowest and highest radius. */
static int segment_meets_dense(const path_context *ctx, const ray_segment *seg)
{
    const sun_irradiance *table = ctx->sun_table;
    double r0 = v3_length(seg->origin), r1 = ray_segment_radius(seg, seg->t_end), t;
    double lo = seg->s0 < 0.0 && seg->t_end > -seg->s0 ? sqrt(seg->p2) : fmin(r0, r1);
    int first = table_rows_locate(&table->rows, ctx->atm, lo, &t);
    int last = table_rows_locate(&table->rows, ctx->atm, fmax(r0, r1), &t);
    for (int i = first; i <= last; i++)
        if (table->dense_cell[i])
            return 1;
    return 0;
}

/* Rays that do not hit the ground: column to the top from the origin minus that from x_t.  Rays that
 * do: the reversed ray from x_t passes the origin and never meets the ground, so the difference the
 * other way. */
void segment_columns_init(segment_columns *sc, const path_context *ctx, const ray_segment *seg)
{
    sc->ctx = ctx;
    sc->seg = seg;
    sc->reversed = seg->hits_ground;
    sc->dense = segment_meets_dense(ctx, seg);
    double r0 = v3_length(seg->origin), mu0 = seg->s0 / r0;
    sc->ok = column_table_lookup(ctx->columns, ctx->atm, r0, sc->reversed ? -mu0 : mu0, sc->start);
}

/* The cell of the column table at distance t along the segment (t > 0; sc->ok). */
static void column_cell_at(const segment_columns *sc, double t, column_cell *cell)
{
    const ray_segment *seg = sc->seg;
    double rad = ray_segment_radius(seg, t), mu = (t + seg->s0) / rad;
    column_table_cell(sc->ctx->columns, sc->ctx->atm, rad, sc->reversed ? -mu : mu, cell);
}

/* The columns to t from the table's cell there (cell->ok 0: none, or the table not to be read). */
static void columns_in(const segment_columns *sc, double t, const column_cell *cell, double *col)
{
    const atmosphere *atm = sc->ctx->atm;
    const ray_segment *seg = sc->seg;
    if (t == 0.0) { /* the segment's origin (the proxy's first cell end) */
        for (int c = 0; c < atm->species_count; c++)
            col[c] = 0.0;
        return;
    }
    if (cell->ok) {
        double here[FM_MAX_SPECIES];
        column_table_cell_columns(sc->ctx->columns, cell, here);
        /* a ternary, not fmax: glibc's fmax is a call per species (its NaN rules) */
        for (int c = 0; c < atm->species_count; c++) {
            double d = sc->reversed ? here[c] - sc->start[c] : sc->start[c] - here[c];
            col[c] = d > 0.0 ? d : 0.0;
        }
        return;
    }
    /* cloud or fog, or a ray grazing the ground, where the table's ground test and the segment's
     * disagree */
    double r0 = v3_length(seg->origin);
    column_quadrature(atm, r0, seg->s0 / r0, t, col);
}

/* The columns to t: in cloud or fog by quadrature when `exact`, else from the table there too (a
 * density's proxy, which need not be exact, at a fraction of the cost). */
static void columns_at(const segment_columns *sc, double t, int exact, double *col)
{
    column_cell cell = {.ok = 0};
    if (t != 0.0 && sc->ok && !(exact && sc->dense))
        column_cell_at(sc, t, &cell);
    columns_in(sc, t, &cell, col);
}

void segment_columns_at(const segment_columns *sc, double t, double *col) { columns_at(sc, t, 1, col); }

void segment_depth_init(segment_depth *sd, const path_context *ctx, const ray_segment *seg)
{
    sd->ctx = ctx;
    sd->seg = seg;
    sd->reversed = seg->hits_ground;
    double r0 = v3_length(seg->origin), mu0 = seg->s0 / r0;
    sd->ok = depth_table_lookup(ctx->mid_depth, ctx->atm, r0, sd->reversed ? -mu0 : mu0, &sd->start);
}

double segment_depth_at(const segment_depth *sd, double t)
{
    const atmosphere *atm = sd->ctx->atm;
    const ray_segment *seg = sd->seg;
    if (t == 0.0)
        return 0.0;
    double rad = ray_segment_radius(seg, t), mu = (t + seg->s0) / rad, here;
    if (sd->ok && depth_table_lookup(sd->ctx->mid_depth, atm, rad, sd->reversed ? -mu : mu, &here)) {
        double d = sd->reversed ? here - sd->start : sd->start - here;
        return d > 0.0 ? d : 0.0;
    }
    double r0 = v3_length(seg->origin), col[FM_MAX_SPECIES]; /* grazing the ground: as segment_columns_at */
    column_quadrature(atm, r0, seg->s0 / r0, t, col);
    return atmosphere_optical_depth(atm, col, sd->ctx->mid_depth->k);
}

/* Position along the segment of the sunlit length l (the umbra [u0, u1] skipped). */
static double lit_to_t(double l, double u0, double u1) { return l < u0 ? l : l + (u1 - u0); }

/* The density of the sample positions over the sunlit length: per cell a proxy of the integrand,
 * mixed with a uniform share DEFENSIVE so that it is positive wherever the integrand can be. */
typedef struct lit_proxy {
    int cells;
    double lit, cell;                   /* m: the sunlit length and a cell's */
    double h[PROXY_CELLS + 1];          /* the proxy at the cells' ends */
    double rate[PROXY_CELLS];           /* 1/m: exponential within the cell, or 0: constant */
    double mass[PROXY_CELLS], total;    /* the proxy's integral per cell and over all */
    double cdf[PROXY_CELLS + 1];        /* of the mixture, over the cells */
} lit_proxy;

/* A cell's proxy: exponential between its two ends when both are lit and the ends move the same
 * way as their neighbours (the integrand falls with the air's density and rises with the
 * sunlight, nearly exponentially over a cell; docs/decisions/2026-12-06-sampling-densities.md);
 * else, near a peak where the chord would pass below it, or next to the dark, the larger end as a
 * constant. */
static void proxy_cells(lit_proxy *p)
{
    const double *h = p->h, cell = p->cell;
    const int n = p->cells;
    p->total = 0.0;
    for (int j = 0; j < n; j++) {
        int rising = h[j + 1] > h[j];
        int monotone = (j == 0 || (h[j] > h[j - 1]) == rising) && (j + 2 > n || (h[j + 2] > h[j + 1]) == rising);
        double lr = monotone && h[j] > 0.0 && h[j + 1] > 0.0 ? log(h[j + 1] / h[j]) : 0.0;
        p->rate[j] = fabs(lr) > 1e-6 ? lr / cell : 0.0;
        p->mass[j] = p->rate[j] != 0.0 ? (h[j + 1] - h[j]) / p->rate[j] : fmax(h[j], h[j + 1]) * cell;
        p->total += p->mass[j];
    }
    p->cdf[0] = 0.0;
    for (int j = 0; j < n; j++) {
        double share = p->total > 0.0 ? (1.0 - DEFENSIVE) * p->mass[j] / p->total + DEFENSIVE / n : 1.0 / n;
        p->cdf[j + 1] = p->cdf[j] + share;
    }
}

/* The sunlit length for the uniform number u in [0, 1), and the mixture's density there (1/m). */
static double proxy_sample(const lit_proxy *p, double u, double *density)
{
    const int n = p->cells;
    const double cell = p->cell;
    u *= p->cdf[n];
    int j = 0;
    while (j < n - 1 && u >= p->cdf[j + 1])
        j++;
    double pj = p->cdf[j + 1] - p->cdf[j];
    /* within the cell the proxy's part or the uniform part, by their shares of pj */
    double v = clamp_between((u - p->cdf[j]) / pj, 0.0, 1.0 - 1e-12), x;
    double share = p->total > 0.0 ? (1.0 - DEFENSIVE) * p->mass[j] / p->total / pj : 0.0;
    if (v < share) {
        double w = v / share;
        x = p->rate[j] != 0.0 ? log1p(w * expm1(p->rate[j] * cell)) / p->rate[j] : w * cell;
    } else {
        x = (v - share) / (1.0 - share) * cell;
    }
    x = clamp_between(x, 0.0, cell);
    if (p->total > 0.0) {
        double proxy = p->rate[j] != 0.0 ? p->h[j] * exp(p->rate[j] * x) : p->mass[j] / cell;
        *density = ((1.0 - DEFENSIVE) * proxy / p->total + DEFENSIVE / p->lit) / p->cdf[n];
    } else {
        *density = 1.0 / p->lit / p->cdf[n];
    }
    return cell * j + x;
}

/* The proxy over the lit length [0, lit] of seg (umbra [u0, u1] left out): its cells and their ends'
 * values, the sum over three wavelengths of T sigma_s Tbar. */
static void proxy_init(lit_proxy *p, const path_context *ctx, const ray_segment *seg, const segment_columns *sc,
                       double u0, double u1, double lit)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    double col[FM_MAX_SPECIES], n[FM_MAX_SPECIES];
    p->cells = ctx->segment_sunlight == SEGMENT_SUNLIGHT_RISING ? RISING_CELLS : PROXY_CELLS;
    p->lit = lit;
    p->cell = lit / p->cells;
    int ks[SUN_FEW], nk = sun_irradiance_few_wavelengths(K, ks);
    /* per cell end and wavelength: sigma_s, and the optical depth from the sun to there and on to the
     * segment's origin, whose exps are then taken all at once in vector lanes */
    double ds[SUN_FEW], sigma_at[PROXY_CELLS + 1][SUN_FEW] = {{0}}, light[PROXY_CELLS + 1][SUN_FEW] = {{0}};
    /* every cell end's place in the sun table first, so that their nodes come from memory together */
    double t_at[PROXY_CELLS + 1], rad_at[PROXY_CELLS + 1];
    sun_cell cells[PROXY_CELLS + 1];
    column_cell column_cells[PROXY_CELLS + 1];
    for (int j = 0; j <= p->cells; j++) {
        double t = t_at[j] = lit_to_t(p->cell * j, u0, u1), rad = rad_at[j] = ray_segment_radius(seg, t);
        vec3 x = v3_madd(seg->origin, seg->dir, t);
        sun_irradiance_few_cell(ctx->sun_table, atm, rad, v3_dot(x, ctx->sun_dir) / rad, &cells[j]);
        column_cells[j].ok = 0; /* as columns_at, not `exact` */
        if (!cells[j].dark && t != 0.0 && sc->ok)
            column_cell_at(sc, t, &column_cells[j]);
    }
    for (int j = 0; j <= p->cells; j++) {
        double t = t_at[j], rad = rad_at[j];
        if (!sun_irradiance_few_cell_depths(ctx->sun_table, &cells[j], ds) ||
            (isinf(ds[0]) && isinf(ds[nk - 1]) && isinf(ds[nk / 2])))
            continue;
        columns_in(sc, t, &column_cells[j], col);
        atmosphere_densities(atm, rad, n);
        for (int i = 0; i < nk; i++) {
            double sigma = 0.0;
            for (int c = 0; c < atm->scattering_count; c++)
                sigma += atm->species[c].sigma_s[ks[i]] * n[c];
            sigma_at[j][i] = sigma;
            light[j][i] = -(ds[i] + atmosphere_optical_depth(atm, col, ks[i]));
        }
    }
    exp_array(&light[0][0], &light[0][0], SUN_FEW * (p->cells + 1));
    for (int j = 0; j <= p->cells; j++) {
        p->h[j] = 0.0;
        for (int i = 0; i < nk; i++)
            p->h[j] += sigma_at[j][i] * light[j][i];
    }
    proxy_cells(p);
}

/* Adds to S the sunlight scattered toward the segment's origin at SUN_SAMPLES points of the lit
 * length, stratified, drawn from the proxy p. */
static void add_lit_air(const path_context *ctx, const ray_segment *seg, const segment_columns *sc, double u0,
                        double u1, const lit_proxy *p, rng *r, double *S)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    const double *E0 = atm->grid.solar_irradiance;
    const double cos_sun = v3_dot(seg->dir, ctx->sun_dir);
    double col[FM_MAX_SPECIES], n[FM_MAX_SPECIES];
    /* the angle to the sun is the same all along the segment: each species' phase once, when a
     * sample first meets the species (an aerosol layer is absent from most samples) */
    double phase[FM_MAX_SPECIES][FM_MAX_WAVELENGTHS];
    int have_phase[FM_MAX_SPECIES] = {0};
    /* the samples' places first, so that their nodes of the sun table come from memory together */
    double density_at[SUN_SAMPLES], t_at[SUN_SAMPLES], rad_at[SUN_SAMPLES], mu_at[SUN_SAMPLES];
    sun_cell cells[SUN_SAMPLES];
    column_cell column_cells[SUN_SAMPLES];
    for (int i = 0; i < SUN_SAMPLES; i++) {
        double l = proxy_sample(p, (i + rng_uniform(r)) / SUN_SAMPLES, &density_at[i]);
        double t = t_at[i] = lit_to_t(l, u0, u1), rad = rad_at[i] = ray_segment_radius(seg, t);
        vec3 x = v3_madd(seg->origin, seg->dir, t);
        mu_at[i] = v3_dot(x, ctx->sun_dir) / rad;
        sun_irradiance_cell_at(ctx->sun_table, sun_irradiance_row_place(ctx->sun_table, atm, rad), mu_at[i], &cells[i]);
        column_cells[i].ok = 0; /* as segment_columns_at (`exact`) */
        if (!cells[i].dark && t != 0.0 && sc->ok && !sc->dense)
            column_cell_at(sc, t, &column_cells[i]);
    }
    for (int i = 0; i < SUN_SAMPLES; i++) {
        double density = density_at[i], t = t_at[i], rad = rad_at[i];
        double depth[FM_MAX_WAVELENGTHS]; /* the sunlight's, then the path's to here added */
        if (!sun_irradiance_cell_depths(ctx->sun_table, atm, ctx->sun, &cells[i], rad, mu_at[i], depth))
            continue;
        double inv_pdf = 1.0 / density / SUN_SAMPLES;
        columns_in(sc, t, &column_cells[i], col);
        atmosphere_densities(atm, rad, n);
        double scatter[FM_MAX_WAVELENGTHS] = {0}; /* sigma_s p over the species, 1/(m sr) */
        for (int c = 0; c < atm->scattering_count; c++) {
            if (n[c] == 0.0)
                continue;
            if (!have_phase[c]) {
                phase_evaluate_all(&atm->species[c].phase, K, cos_sun, phase[c]);
                have_phase[c] = 1;
            }
            for (int k = 0; k < K; k++)
                scatter[k] += atm->species[c].sigma_s[k] * n[c] * phase[c][k];
        }
        double path[FM_MAX_WAVELENGTHS];
        atmosphere_optical_depths(atm, col, path);
        for (int k = 0; k < K; k++)
            depth[k] = -(depth[k] + path[k]);
        exp_array(depth, depth, K); /* from the sun to here and on to the segment's origin */
        for (int k = 0; k < K; k++)
            S[k] += inv_pdf * scatter[k] * E0[k] * depth[k];
    }
}

/* Adds to S the sunlight the ground at the segment's end reflects toward its origin. */
static void add_lit_ground(const path_context *ctx, const ray_segment *seg, const segment_columns *sc, double *S)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    const double *E0 = atm->grid.solar_irradiance;
    vec3 x = v3_madd(seg->origin, seg->dir, seg->t_end);
    double rad = v3_length(x), tbar[FM_MAX_WAVELENGTHS], thor[FM_MAX_WAVELENGTHS];
    sun_irradiance_lookup_ground(ctx->sun_table, atm, ctx->sun, v3_dot(x, ctx->sun_dir) / rad, tbar, thor);
    if (!(spectral_sum(thor, K) > 0.0))
        return;
    double col[FM_MAX_SPECIES], tr[FM_MAX_WAVELENGTHS];
    segment_columns_at(sc, seg->t_end, col);
    atmosphere_transmittances(atm, col, tr);
    for (int k = 0; k < K; k++)
        S[k] += tr[k] * atm->ground_albedo[k] / FM_PI * E0[k] * thor[k];
}

void segment_sunlight(const path_context *ctx, const ray_segment *seg, double u0, double u1, rng *r, double *S)
{
    const double lit = u0 + (seg->t_end - u1);
    segment_columns sc;
    segment_columns_init(&sc, ctx, seg);
    if (lit > 0.0) {
        lit_proxy p;
        proxy_init(&p, ctx, seg, &sc, u0, u1, lit);
        add_lit_air(ctx, seg, &sc, u0, u1, &p, r, S);
    }
    if (seg->hits_ground)
        add_lit_ground(ctx, seg, &sc, S);
}
