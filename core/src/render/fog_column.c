#include "render/fog_column.h"

#include "base/quadrature.h"
#include "render/render_job.h"
#include "sky.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Panels uniform in scattering angle for the moments: 0.09 degrees, a fifth of the droplets'
 * diffraction peak at 380 nm. */
#define MOMENT_PANELS 2000
/* The air above the fog in layers broken here (m above the fog's top).  A layer is one mixture (one
 * phase function, its scattering and absorption spread evenly) under one beam cosine, while the
 * aerosols thin out within a kilometre or two and the ozone lies at 15-35 km above most of the air
 * that scatters: at a low sun the beam through a thick layer lights its scattering as if it were
 * all halfway down the ozone. */
static const double air_breaks_m[] = {1000.0, 2000.0, 4000.0, 7000.0, 11000.0, 16000.0, 22000.0, 30000.0};
/* The horizon row's view cosine: the plane-parallel radiance at grazing views tends to the source
 * function at the bottom, reached within a milliradian. */
#define VIEW_MU_MIN 1e-3

/* The integral of a piecewise-linear profile from z0 to z1 (m^-2): exact, cell by cell. */
static double column_between(const density_profile *p, double z0, double z1)
{
    double sum = 0.0, a = z0;
    while (a < z1) {
        double b = fmin(z1, (floor(a / p->dz_m) + 1.0) * p->dz_m);
        sum += 0.5 * (profile_density(p, a) + profile_density(p, b)) * (b - a);
        a = b;
    }
    return sum;
}

static int add_break(double *z, int n, double v, double lo, double hi)
{
    if (!(v > lo && v < hi) || n >= PLANE_COLUMN_MAX_LAYERS)
        return n;
    for (int i = 0; i < n; i++)
        if (fabs(z[i] - v) < 1.0)
            return n;
    z[n] = v;
    return n + 1;
}

static int ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The layers' boundaries and every species' column in each (top layer first): the column's cloud
 * from base to fog_top (its top), the air below its base broken as above (none in fog), up to toa (m
 * above the ground: the atmosphere's top, or the fog's profile's for the fog alone). */
void fog_column_layers(fog_column *fc, const fm_sky *sky, double base, double fog_top, double toa)
{
    const atmosphere *atm = &sky->atm;
    double z[PLANE_COLUMN_MAX_LAYERS + 1] = {0.0, fog_top, toa};
    int n = fog_top < toa ? 3 : 2;
    if (n == 2)
        z[1] = toa;
    /* the observer's level and the clouds' edges first: the air's breaks take what room is left */
    const double altitude = v3_length(sky->observer) - atm->bottom_radius_m;
    n = add_break(z, n, altitude, 0.0, toa);
    for (int i = 0; i < sky->composition.cloud_count; i++) {
        const double b = sky->composition.cloud[i].base_m;
        n = add_break(z, n, b, 0.0, toa);
        n = add_break(z, n, b + sky->composition.cloud[i].thickness_m, 0.0, toa);
        /* a layer below the observer: its droplets above its top (cloud_layer.c's edge node holds half,
         * the next none) in a layer of their own, not spread through the air up to the next break,
         * where views down near the horizon would cross them as a haze */
        const double ramp = b + sky->composition.cloud[i].thickness_m + FM_PROFILE_SPACING_M;
        if (ramp <= altitude)
            n = add_break(z, n, ramp, 0.0, toa);
    }
    n = add_break(z, n, base, 0.0, fog_top);
    for (size_t i = 0; i < sizeof air_breaks_m / sizeof air_breaks_m[0]; i++) {
        n = add_break(z, n, air_breaks_m[i], 0.0, base);
        n = add_break(z, n, fog_top + air_breaks_m[i], fog_top, toa);
    }
    qsort(z, (size_t)n, sizeof z[0], ascending);
    fc->layers = n - 1;
    fc->fog_layers = 1;
    fc->level = fc->layers;
    for (int i = 1; i < n - 1; i++) {
        fc->fog_layers += z[i] < fog_top - 0.5;
        if (fabs(z[i] - altitude) < 1.0)
            fc->level = n - 1 - i;
    }
    fc->on_ground = fc->level == fc->layers;
    for (int l = 0; l < fc->layers; l++) {
        const double z0 = z[n - 2 - l], z1 = z[n - 1 - l]; /* top first */
        fc->top_m[l] = z1;
        for (int c = 0; c < atm->species_count; c++)
            fc->column[l][c] = column_between(&atm->species[c].profile, z0, z1);
    }
}

/* Legendre polynomials P_0..P_lmax at x. */
static void legendre(int lmax, double x, double *p)
{
    p[0] = 1.0;
    p[1] = x;
    for (int l = 2; l <= lmax; l++)
        p[l] = ((2.0 * l - 1.0) * x * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
}

/* chi[c][k][l] = (1/2) int P_c,k(x) P_l(x) dx / (1/2) int P_c,k(x) dx, l = 0 .. FOG_MOMENTS, by 4-point
 * Gauss on panels uniform in the scattering angle (the forward peak resolved). */
fm_status fog_species_moments(fog_column *fc, const atmosphere *atm)
{
    const int K = atm->grid.count, L = FOG_MOMENTS + 1, S = atm->scattering_count;
    fc->chi = calloc((size_t)S * (size_t)K * (size_t)L, sizeof(double));
    if (!fc->chi)
        return FM_ERR_OUT_OF_MEMORY;
    const gauss_rule *g = gauss_legendre_cached(4);
    const double h = FM_PI / MOMENT_PANELS;
    double pl[FOG_MOMENTS + 1], val[FM_MAX_WAVELENGTHS];
    for (int i = 0; i < MOMENT_PANELS; i++)
        for (int q = 0; q < 4; q++) {
            const double th = h * (i + 0.5 * (1.0 + g->x[q])), x = cos(th), wq = sin(th) * 0.5 * h * g->w[q];
            legendre(FOG_MOMENTS, x, pl);
            for (int c = 0; c < S; c++) {
                phase_evaluate_all(&atm->species[c].phase, K, x, val);
                for (int k = 0; k < K; k++) {
                    double *chi = fc->chi + ((size_t)c * K + k) * L, v = val[k] * wq;
                    for (int l = 0; l < L; l++)
                        chi[l] += v * pl[l];
                }
            }
        }
    for (size_t j = 0; j < (size_t)S * K; j++) {
        double *chi = fc->chi + j * L, c0 = chi[0];
        for (int l = 0; l < L && c0 > 0.0; l++)
            chi[l] /= c0;
    }
    return FM_OK;
}

/* The scaled phase function sum_l (2l + 1) chi_l P_l(x) / (4 pi) for l < FOG_MOMENTS. */
double fog_scaled_phase(const double *chi, double x)
{
    double p[FOG_MOMENTS + 1], sum = 0.0;
    legendre(FOG_MOMENTS, x, p);
    for (int l = 0; l < FOG_MOMENTS; l++)
        sum += (2.0 * l + 1.0) * chi[l] * p[l];
    return sum / (4.0 * FM_PI);
}


/* Layer l's optical properties at wavelength k, delta-M scaled for the column (pl). */
void fog_layer_at(const fog_column *fc, const atmosphere *atm, int l, int k, scaled_layer *sl, plane_layer *pl)
{
    const int K = atm->grid.count, L = FOG_MOMENTS + 1;
    double ts = 0.0, tt = 0.0;
    memset(sl->chi, 0, sizeof sl->chi);
    for (int c = 0; c < atm->species_count; c++) {
        const double col = fc->column[l][c], s = col * atm->species[c].sigma_s[k];
        tt += col * (atm->species[c].sigma_s[k] + atm->species[c].sigma_a[k]);
        if (c < atm->scattering_count && s > 0.0) {
            ts += s;
            const double *chi = fc->chi + ((size_t)c * K + k) * L;
            for (int j = 0; j < L; j++)
                sl->chi[j] += s * chi[j];
        }
    }
    for (int j = 0; j < L; j++)
        sl->chi[j] = ts > 0.0 ? sl->chi[j] / ts : (j == 0);
    sl->tau = tt;
    sl->ssa = tt > 0.0 ? ts / tt : 0.0;
    sl->f = fmin(fmax(sl->chi[FOG_MOMENTS], 0.0), 0.999);
    for (int j = 0; j < FOG_MOMENTS; j++)
        sl->chi[j] = (sl->chi[j] - sl->f) / (1.0 - sl->f);
    const double wf = sl->ssa * sl->f;
    *pl = (plane_layer){.tau = (1.0 - wf) * tt, .ssa = wf < 1.0 ? sl->ssa * (1.0 - sl->f) / (1.0 - wf) : 0.0,
                        .chi = sl->chi};
}

/* The sun's zenith cosine at radius r along the ray toward it from the fog's top (ray), or mu0 (the
 * points above one another). */
static double ray_cosine(const fog_column *fc, double r, double mu0, int ray)
{
    const double q = fc->top_radius / r;
    return ray ? sqrt(fmax(0.0, 1.0 - q * q * (1.0 - mu0 * mu0))) : mu0;
}

/* Pseudo-spherical beam in the air above the fog (as DISORT's): each layer's beam cosine is its
 * optical depth over the sphere's slant optical depth across it (from the sun table, at the layer's
 * top and bottom), so the beam reaching and crossing it is dimmed as in the sphere.  At a low sun
 * the plane's 1 / mu0 overstates the slant path high up, where the air scatters the light that
 * enters the fog (1 / mu0 is 5.8 air masses at 10 degrees, the sphere's 5.6; at 1 degree 57 against 26).
 * The slants are those along the one ray that reaches the fog's top (at each radius the cosine it
 * has there): a cloud layer high above is crossed more steeply from lower down, so that the
 * transmittances toward the sun from the points above one another grow downward below it, which no
 * plane column holds (their negative differences fell back to the plane's 1 / mu0, and the sum missed
 * the fog top's transmittance, which scales the column, by a factor of 10 at sun 3 under a
 * cirrostratus: docs/decisions/2026-12-07-two-layers-low-sun.md). */
void fog_air_beam_cosines(const fog_column *fc, const fm_sky *sky, int k, const scaled_layer *sl, plane_layer *pl)
{
    const atmosphere *atm = &sky->atm;
    const double mu0 = sky->sun_dir.z;
    const int ray = sky->composition.cloud_count > 1; /* a cloud above the fog (else as before: above one another) */
    double T_top[FM_MAX_WAVELENGTHS], T_bottom[FM_MAX_WAVELENGTHS];
    sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, atm->top_radius_m, ray_cosine(fc, atm->top_radius_m, mu0, ray),
                          T_top);
    for (int l = 0; l < fc->layers - fc->fog_layers; l++) {
        const double r = atm->bottom_radius_m + fc->top_m[l + 1];
        sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, ray_cosine(fc, r, mu0, ray), T_bottom);
        const double slant = log(T_top[k]) - log(T_bottom[k]);
        if (sl[l].tau > 1e-9 && slant > 0.0 && T_bottom[k] > 0.0)
            pl[l].mu0 = fmin(1.0, sl[l].tau / slant);
        memcpy(T_top, T_bottom, sizeof T_top);
    }
}

/* The fog's and the ground's diffuse albedo seen from above at every grid wavelength (the column of
 * the fog alone under an isotropic field): the ground of the sky that lights it (fog_incident.h). */
fm_status fog_albedo(const fog_column *fc, double *albedo)
{
    const atmosphere *atm = &fc->job->sky->atm;
    const int M = FOG_MOMENTS;
    double mu[FOG_STREAMS], field[FOG_STREAMS * FOG_MOMENTS] = {0}, up[FOG_STREAMS * FOG_MOMENTS];
    plane_column_nodes(FOG_STREAMS, mu);
    for (int j = 0; j < FOG_STREAMS; j++)
        field[j * M] = 1.0;
    const gauss_rule *g = gauss_legendre_cached(FOG_STREAMS);
    for (int k = 0; k < atm->grid.count; k++) {
        scaled_layer sl[PLANE_COLUMN_MAX_LAYERS];
        plane_layer pl[PLANE_COLUMN_MAX_LAYERS];
        for (int l = 0; l < fc->layers; l++)
            fog_layer_at(fc, atm, l, k, &sl[l], &pl[l]);
        plane_column col = {.streams = FOG_STREAMS, .layer_count = fc->layers, .layer = pl,
                            .ground_albedo = atm->ground_albedo[k], .mu0 = 1.0, .n_mu = FOG_STREAMS, .mu = mu};
        fm_status s = plane_column_diffuse_level(&col, 0, field, NULL, up, NULL);
        if (s)
            return s;
        albedo[k] = 0.0; /* the upward flux over the downward pi */
        for (int j = 0; j < FOG_STREAMS; j++)
            albedo[k] += 2.0 * 0.5 * g->w[j] * mu[j] * up[j * M];
    }
    return FM_OK;
}

/* The view cosines of the table's rows: the sky's looking up, the ground's looking down. */
void fog_view_cosines(fog_column *fc, const sky_grid *g)
{
    double e, phi;
    fc->n_mu = g->rows_sky + g->rows_ground;
    for (int r = 0; r < fc->n_mu; r++) {
        sky_grid_node_angles(g, r * g->cols, &e, &phi);
        fc->mu[r] = fmax(fabs(sin(e)), VIEW_MU_MIN);
    }
}

/* Above every layer the column holds, the sky's rows look up through the sphere's air, whose slant
 * depth toward the horizon is finite, where the plane's grows as 1 / mu and holds air lit by the deck
 * without end (a tenth too bright 2-5 degrees up): each sky row takes the cosine whose plane slant
 * depth is the sphere's, from the sun table's transmittance to the top at the middle grid
 * wavelength.  Rows below the horizontal that dip into the deck keep a grazing cosine. */
void fog_sphere_sky_cosines(fog_column *fc, const fm_sky *sky, const sky_grid *g)
{
    const atmosphere *atm = &sky->atm;
    const int k = atm->grid.count / 2;
    const double r = v3_length(sky->observer);
    double T[FM_MAX_WAVELENGTHS];
    sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, 1.0, T);
    const double vertical = -log(T[k]);
    for (int row = 0; row < g->rows_sky && vertical > 0.0; row++) {
        double e, phi;
        sky_grid_node_angles(g, row * g->cols, &e, &phi);
        sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, sin(e), T);
        if (T[k] > 0.0 && -log(T[k]) > vertical)
            fc->mu[row] = fmax(vertical / -log(T[k]), VIEW_MU_MIN);
    }
}
