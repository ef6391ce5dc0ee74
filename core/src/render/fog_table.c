#include "render/fog_table.h"

#include "aerosol/cloud.h"
#include "base/quadrature.h"
#include "base/threads.h"
#include "base/units.h"
#include "render/fog_incident.h"
#include "render/fog_local_sun.h"
#include "render/ms_table.h"
#include "render/render_job.h"
#include "sky.h"
#include "transport/plane_column.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* 12 streams (24 moments) with delta-M: the multiple scattering of orders >= 2 in the fog to well
 * under a percent of the 24-stream solution's (docs/decisions/2026-12-06-fog-column.md). */
#define FOG_STREAMS 12
#define FOG_MOMENTS (2 * FOG_STREAMS)
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

/* The column lit from above as a linear map of the field at its top (plane_column_diffuse_response)
 * at every grid wavelength: the same for each sun where the column's layers are (local_sun_sums). */
typedef struct column_response {
    double *values; /* [K][FOG_MOMENTS][rows_sky][FOG_STREAMS] */
    int ready;      /* filled by a column lit from above */
} column_response;

typedef struct fog_column {
    render_job *job;
    int layers;                    /* top first */
    int fog_layers;                /* the bottom fog_layers are the cloud and the air below it */
    int level;                     /* the observer's: the boundary below the first `level` layers */
    int on_ground;                 /* the observer on the ground (level == layers) */
    double column[PLANE_COLUMN_MAX_LAYERS][FM_MAX_SPECIES]; /* m^-2 */
    double *chi;                   /* [species][K][FOG_MOMENTS + 1] */
    int n_mu;
    double mu[512];                /* the sky rows' view cosines, then the ground rows' (looking down) */
    double top_radius;             /* the fog's top, m from the planet's centre */
    double top_m[PLANE_COLUMN_MAX_LAYERS]; /* each layer's top, m above the ground */
    double ground[FM_MAX_WAVELENGTHS]; /* what the column adds to the ground's irradiance */
    const fog_incident *incident;  /* at a low sun (fog_table_from_above): the light on the fog's top,
                                    * and the column the fog alone; else NULL */
    column_response *response;     /* with incident: its map of the field, or NULL (solved per field) */
} fog_column;

/* ---- where it applies ------------------------------------------------------------------------ */

/* The observer's height above the ground (m). */
static double observer_altitude_m(const fm_sky *sky)
{
    return v3_length(sky->observer) - sky->atm.bottom_radius_m;
}

/* The cloud layer the column is for, or -1: the one on the ground that holds the observer with a
 * visibility of FOG_TABLE_MAX_VISIBILITY_M or less (fog), else the lowest whose top is above the
 * observer (who is below or inside it) of optical depth min_tau or more, else the highest layer of
 * FOG_TABLE_MIN_TAU or more below the observer (docs/decisions/2026-12-07-above-deck.md): the column
 * holds the observer's level wherever it is, its views down the upward radiance there. */
static int column_cloud_from(const fm_sky *sky, double min_tau)
{
    const double altitude = observer_altitude_m(sky);
    int lowest = -1, below = -1;
    for (int i = 0; i < sky->composition.cloud_count; i++) {
        const double base = sky->composition.cloud[i].base_m, h = sky->composition.cloud[i].thickness_m;
        const double tau = sky->composition.cloud[i].tau550;
        if (!(h > 0.0))
            continue;
        if (altitude >= base + h) {
            if (tau >= FOG_TABLE_MIN_TAU && (below < 0 || base > sky->composition.cloud[below].base_m))
                below = i;
            continue;
        }
        if (base <= 0.0)
            return tau / h >= 3.912 / FOG_TABLE_MAX_VISIBILITY_M ? i : -1;
        if (tau >= min_tau && (lowest < 0 || base < sky->composition.cloud[lowest].base_m))
            lowest = i;
    }
    return lowest >= 0 ? lowest : below;
}

/* The thick layer (FOG_TABLE_MIN_TAU) where there is one, else a thin one (FOG_TABLE_MIN_TAU_THIN):
 * the column is for that. */
static int column_cloud(const fm_sky *sky)
{
    const int thick = column_cloud_from(sky, FOG_TABLE_MIN_TAU);
    return thick >= 0 ? thick : column_cloud_from(sky, FOG_TABLE_MIN_TAU_THIN);
}

int fog_table_sky(const fm_sky *sky)
{
    if (column_cloud_from(sky, FOG_TABLE_MIN_TAU) < 0)
        return 0;
    /* a deck that the deck base takes (from DECK_MIN_SUN_DEG up) leaves the day's nodes to paths */
    const double altitude = observer_altitude_m(sky);
    for (int i = 0; i < sky->composition.cloud_count && sky->truncated; i++)
        if (sky->composition.cloud[i].tau550 >= SKY_TRUNCATE_TAU && sky->composition.cloud[i].base_m > altitude)
            return 0;
    return 1;
}

static int thin_layers_above(const fm_sky *sky, int cloud);

/* Whether the layer is fog alone around the observer (from the ground up, its top above the
 * observer) of FOG_TABLE_MIN_TAU_FOG or more: its forward light near the sun is the fog's around the
 * observer, not a distant layer's under another sun (docs/decisions/2026-12-07-shallow-fog.md). */
static int fog_alone_around_observer(const fm_sky *sky, int cloud)
{
    const double altitude = observer_altitude_m(sky);
    return sky->composition.cloud_count == 1 && sky->composition.cloud[cloud].base_m <= 0.0 &&
           altitude < sky->composition.cloud[cloud].base_m + sky->composition.cloud[cloud].thickness_m &&
           sky->composition.cloud[cloud].tau550 >= FOG_TABLE_MIN_TAU_FOG;
}

/* Shallow fog (FOG_TABLE_MIN_TAU_FOG up to FOG_TABLE_MIN_TAU) around the observer under thin layers
 * only (cirrostratus): the column lit from above (the sky without the fog holds them) takes it from
 * FOG_TABLE_FOG_UNDER_THIN_MIN_SUN_DEG, the day's column above the blend
 * (docs/decisions/2026-12-07-fog-under-thin-layers.md). */
static int shallow_fog_under_thin(const fm_sky *sky, int cloud)
{
    const double altitude = observer_altitude_m(sky);
    if (cloud < 0 || sky->composition.cloud_count < 2)
        return 0;
    const double base = sky->composition.cloud[cloud].base_m, tau = sky->composition.cloud[cloud].tau550;
    return base <= 0.0 && altitude < sky->composition.cloud[cloud].thickness_m && tau >= FOG_TABLE_MIN_TAU_FOG &&
           tau < FOG_TABLE_MIN_TAU && thin_layers_above(sky, cloud);
}

/* The sun (degrees) below which the column lit from above is the table: where the day's column
 * starts, FOG_TABLE_MIN_SUN_DEG in fog, FOG_TABLE_MIN_SUN_DEG_PER_KM per km of a deck's base; the
 * blend ends FOG_TABLE_BLEND_DEG above it. */
static double from_above_below_deg(const fm_sky *sky, int cloud)
{
    if (shallow_fog_under_thin(sky, cloud))
        return FOG_TABLE_FOG_UNDER_THIN_SUN_DEG;
    return fmax(FOG_TABLE_MIN_SUN_DEG, FOG_TABLE_MIN_SUN_DEG_PER_KM * sky->composition.cloud[cloud].base_m / 1000.0);
}

/* Whether every cloud layer but `cloud` is thin (below FOG_TABLE_MIN_TAU) and lies above its top: the
 * sky without it (fog_incident.h), which lights the column lit from above, holds them (cirrostratus
 * over an altostratus deck; docs/decisions/2026-12-07-two-layers-low-sun.md).  A thick layer above
 * (altostratus over stratocumulus) left that sky's paths 40 % dark at sun 2. */
static int thin_layers_above(const fm_sky *sky, int cloud)
{
    const double top = sky->composition.cloud[cloud].base_m + sky->composition.cloud[cloud].thickness_m;
    for (int i = 0; i < sky->composition.cloud_count; i++)
        if (i != cloud && (sky->composition.cloud[i].base_m < top || sky->composition.cloud[i].tau550 >= FOG_TABLE_MIN_TAU))
            return 0;
    return 1;
}

/* Whether the column lit from above takes layer `cloud`: alone, an elevated deck or shallow fog under
 * thin layers. */
static int from_above_cloud(const fm_sky *sky, int cloud)
{
    return cloud >= 0 && (sky->composition.cloud_count == 1 || shallow_fog_under_thin(sky, cloud) ||
                          (sky->composition.cloud[cloud].base_m > 0.0 && thin_layers_above(sky, cloud)));
}

int fog_table_from_above(const render_job *job)
{
    const fm_sky *sky = job->sky;
    const double z = sky->sun_dir.z, altitude = observer_altitude_m(sky);
    const int cloud = column_cloud_from(sky, FOG_TABLE_MIN_TAU);
    return job->fog_from_above && !job->under_deck && job->params->quality != FM_QUALITY_REFERENCE &&
           from_above_cloud(sky, cloud) && altitude < FOG_TABLE_ON_GROUND_M &&
           z < sin((from_above_below_deg(sky, cloud) + FOG_TABLE_BLEND_DEG) * FM_DEG) &&
           z >= sin((shallow_fog_under_thin(sky, cloud) ? FOG_TABLE_FOG_UNDER_THIN_MIN_SUN_DEG
                                                         : FOG_TABLE_TWILIGHT_MIN_SUN_DEG) * FM_DEG);
}

int fog_table_local_sun(const render_job *job)
{
    return fog_table_from_above(job) &&
           job->sky->composition.cloud[column_cloud(job->sky)].base_m > FOG_TABLE_FROM_ABOVE_MAX_BASE_M;
}

/* A thin layer of ice (below FOG_TABLE_MIN_TAU) alone, elevated, over an observer on the ground:
 * the column at several suns takes it from FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG (FOG_TABLE_THIN_LOW_SUN_DEG
 * from FOG_TABLE_THIN_LOW_SUN_MIN_TAU up). */
static int thin_ice_alone(const fm_sky *sky)
{
    const int cloud = column_cloud(sky);
    const double altitude = observer_altitude_m(sky);
    if (cloud < 0 || sky->composition.cloud_count != 1 || altitude >= FOG_TABLE_ON_GROUND_M)
        return 0;
    const cloud_type *type = cloud_type_find(sky->composition.cloud[cloud].type);
    return sky->composition.cloud[cloud].tau550 < FOG_TABLE_MIN_TAU && sky->composition.cloud[cloud].base_m > 0.0 &&
           type && type->ice;
}

int fog_table_applies(const render_job *job)
{
    if (fog_table_from_above(job))
        return 1;
    const fm_sky *sky = job->sky;
    const int cloud = column_cloud(sky);
    if (cloud < 0 || job->twilight || job->under_deck || job->params->quality == FM_QUALITY_REFERENCE)
        return 0;
    if (shallow_fog_under_thin(sky, cloud)) /* the day's column alone above the blend */
        return sky->sun_dir.z >= sin((FOG_TABLE_FOG_UNDER_THIN_SUN_DEG + FOG_TABLE_BLEND_DEG) * FM_DEG);
    /* thin layers above a deck that the column lit from above takes below its bound: as one deck */
    const int as_one = from_above_cloud(sky, column_cloud_from(sky, FOG_TABLE_MIN_TAU)) && job->fog_from_above &&
                       observer_altitude_m(sky) < FOG_TABLE_ON_GROUND_M;
    double min_sun = sky->composition.cloud_count > 1 && !as_one ? FOG_TABLE_MIN_SUN_DEG_CLOUDS : FOG_TABLE_MIN_SUN_DEG;
    if (thin_ice_alone(sky)) {
        const int low = sky->composition.cloud[cloud].tau550 >= FOG_TABLE_THIN_LOW_SUN_MIN_TAU;
        return sky->sun_dir.z >= sin((low ? FOG_TABLE_THIN_LOW_SUN_DEG : FOG_TABLE_THIN_LOCAL_MIN_SUN_DEG) * FM_DEG);
    }
    min_sun = fmax(min_sun, FOG_TABLE_MIN_SUN_DEG_PER_KM * sky->composition.cloud[cloud].base_m / 1000.0);
    if (sky->composition.cloud[cloud].tau550 < FOG_TABLE_MIN_TAU)
        min_sun = fmax(min_sun, fog_alone_around_observer(sky, cloud) ? FOG_TABLE_SHALLOW_FOG_MIN_SUN_DEG
                                                                       : FOG_TABLE_THIN_MIN_SUN_DEG);
    return sky->sun_dir.z >= sin(min_sun * FM_DEG);
}

void fog_table_size(quality_settings *q)
{
    q->ms_rows_sky = q->ms_rows_sky > FOG_TABLE_ROWS_SKY ? q->ms_rows_sky : FOG_TABLE_ROWS_SKY;
    q->ms_cols = q->ms_cols > FOG_TABLE_COLS ? q->ms_cols : FOG_TABLE_COLS;
}

/* ---- the column ------------------------------------------------------------------------------ */

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
static void column_layers(fog_column *fc, const fm_sky *sky, double base, double fog_top, double toa)
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
static fm_status species_moments(fog_column *fc, const atmosphere *atm)
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
static double scaled_phase(const double *chi, double x)
{
    double p[FOG_MOMENTS + 1], sum = 0.0;
    legendre(FOG_MOMENTS, x, p);
    for (int l = 0; l < FOG_MOMENTS; l++)
        sum += (2.0 * l + 1.0) * chi[l] * p[l];
    return sum / (4.0 * FM_PI);
}

/* ---- one wavelength -------------------------------------------------------------------------- */

typedef struct scaled_layer {
    double tau, ssa, f;               /* unscaled optical depth and albedo; the truncated fraction */
    double chi[FOG_MOMENTS + 1];      /* the scaled moments */
} scaled_layer;

/* Layer l's optical properties at wavelength k, delta-M scaled for the column (pl). */
static void layer_at(const fog_column *fc, const atmosphere *atm, int l, int k, scaled_layer *sl, plane_layer *pl)
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

/* Single scattering at the bottom looking up along mu, per unit F0, from one homogeneous layer of
 * optical depth tau lit at its top, with albedo times phase function ssa_phase. */
static double single_bottom(double tau, double ssa_phase, double mu, double mu0)
{
    const double d = mu - mu0;
    const double f = fabs(d) < 1e-12 ? tau / (mu * mu0) * exp(-tau / mu0) : (exp(-tau / mu) - exp(-tau / mu0)) / d;
    return ssa_phase * mu0 * f;
}

/* The light scattered two or more times within the truncated peak and never wider: the scaled
 * column counts it as unscattered.  Along the beam each layer's peak scatterings are Poisson with
 * mean lambda_i = ssa f tau / mu0 and turn the light by the peak's residual phase function P''_i
 * (P = f P'' + (1 - f) P*: Legendre moments 1 below FOG_MOMENTS, chi_l / f above), so n of them by
 * its n-fold convolution, whose moments are powers; the light's moments are then
 * exp(Lambda_l) - 1 - Lambda_l with Lambda_l = sum_i lambda_i g_i,l (all n >= 2; Nakajima & Tanaka's
 * 1988 IMS correction is its n = 2 term).  Light scattered both in and outside the peak the column
 * holds as it should (P'' leaves the column's band of moments unchanged).  Within a few degrees of
 * the sun the sum is positive; beyond it, negative: it takes back what the truncated phase function's
 * smooth forward lobe put there (about 5 % of the sky 8 degrees from the sun). */
#define FOG_PEAK_ANGLES 512          /* the table ms_table.peak: uniform in sin(theta / 2) */
#define PEAK_PANELS 600             /* 0.3 degrees: the droplets' peak and P_l to the moments that count */
#define PEAK_MOMENTS 2048
/* The sum tabulated to PEAK_MAX_DEG from the sun, tapered to 0 from PEAK_TAPER_DEG: beyond, it is a
 * ripple of a few tenths of a percent of the sky. */
#define PEAK_TAPER_DEG 30.0
#define PEAK_MAX_DEG 45.0
#define PEAK_U_MAX 0.38268343236508977 /* sin(PEAK_MAX_DEG / 2) */
/* The bump: a Gaussian of PEAK_BUMP_DEG about the sun (u = sin(theta / 2)), PEAK_LEND times what
 * the lobe needs at its deepest. */
#define PEAK_BUMP_DEG 15.0
#define PEAK_LEND 1.25
static double peak_bump(double u)
{
    const double s = sin(0.5 * PEAK_BUMP_DEG * FM_DEG);
    return exp(-0.5 * u * u / (s * s));
}

static double peak_taper(double theta)
{
    const double t = (theta / FM_DEG - PEAK_TAPER_DEG) / (PEAK_MAX_DEG - PEAK_TAPER_DEG);
    return t <= 0.0 ? 1.0 : t >= 1.0 ? 0.0 : 0.5 * (1.0 + cos(FM_PI * t));
}

/* M_l = exp(Lambda_l) - 1 - Lambda_l for l < *L (returned): Lambda_l = lambda below FOG_MOMENTS, above
 * it the Legendre moments of the phase functions weighted by w (the species' slant scattering
 * optical depths), by quadrature; they end where Lambda_l has vanished for a while. */
static void peak_moments(const atmosphere *atm, int k, const double *w, double lambda, double *work, double *M, int *L)
{
    enum { Q = 4 * PEAK_PANELS };
    double *x = work, *v = x + Q, *p0 = v + Q, *p1 = p0 + Q;
    const gauss_rule *g = gauss_legendre_cached(4);
    const double h = FM_PI / PEAK_PANELS;
    for (int i = 0; i < PEAK_PANELS; i++)
        for (int q = 0; q < 4; q++) {
            const double th = h * (i + 0.5 * (1.0 + g->x[q]));
            double p = 0.0;
            for (int c = 0; c < atm->scattering_count; c++)
                p += w[c] > 0.0 ? w[c] * phase_evaluate(&atm->species[c].phase, k, cos(th)) : 0.0;
            x[4 * i + q] = p1[4 * i + q] = cos(th);
            v[4 * i + q] = 2.0 * FM_PI * sin(th) * 0.5 * h * g->w[q] * p;
            p0[4 * i + q] = 1.0;
        }
    *L = PEAK_MOMENTS;
    for (int l = 0, small = 0; l < PEAK_MOMENTS; l++) {
        double Lam = lambda;
        if (l >= FOG_MOMENTS) {
            Lam = 0.0;
            for (int q = 0; q < Q; q++)
                Lam += v[q] * p1[q];
        }
        M[l] = expm1(Lam) - Lam;
        small = fabs(Lam) < 1e-6 * lambda ? small + 1 : 0;
        if (small == 8) {
            *L = l + 1;
            return;
        }
        for (int q = 0; q < Q; q++) { /* p0, p1 <- P_l, P_{l+1} */
            const double next = ((2.0 * l + 3.0) * x[q] * p1[q] - (l + 1.0) * p0[q]) / (l + 2.0);
            p0[q] = p1[q];
            p1[q] = next;
        }
    }
}

/* sum_l (2l + 1) M_l P_l(cos theta_j) at the table's angles, uniform in sin(theta / 2). */
static void peak_sum(const double *M, int L, double *work, double *out)
{
    double *x = work, *c0 = x + FOG_PEAK_ANGLES, *c1 = c0 + FOG_PEAK_ANGLES;
    for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
        const double u = PEAK_U_MAX * j / (FOG_PEAK_ANGLES - 1.0);
        x[j] = c1[j] = 1.0 - 2.0 * u * u;
        c0[j] = 1.0;
        out[j] = M[0];
    }
    for (int l = 1; l < L; l++)
        for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
            out[j] += (2.0 * l + 1.0) * M[l] * c1[j];
            const double next = ((2.0 * l + 1.0) * x[j] * c1[j] - l * c0[j]) / (l + 1.0);
            c0[j] = c1[j];
            c1[j] = next;
        }
}

/* The irradiance on the ground of a table of radiance by angle from the sun (uniform in
 * sin(theta / 2), as ms_table.peak) over the sky: each ring about the sun by the mean of the
 * cosine of its zenith angle over its part above the horizon. */
static double sky_flux(const double *table, double mu0)
{
    const double s0 = sqrt(fmax(0.0, 1.0 - mu0 * mu0));
    double sum = 0.0;
    for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
        const double u = PEAK_U_MAX * j / (FOG_PEAK_ANGLES - 1.0), th = 2.0 * asin(u);
        const double a = mu0 * cos(th), b = s0 * sin(th); /* cos z = a + b cos(psi) on the ring */
        const double psi = b > fabs(a) ? acos(-a / b) : a > 0.0 ? FM_PI : 0.0;
        const double ring = 2.0 * (a * psi + b * sin(psi)); /* 2 pi times the ring's mean */
        /* d(solid angle) = 2 pi sin(theta) d(theta), d(theta) = 2 du / cos(theta / 2) */
        const double w = (j == 0 || j == FOG_PEAK_ANGLES - 1 ? 0.5 : 1.0) * PEAK_U_MAX / (FOG_PEAK_ANGLES - 1.0);
        sum += table[j] * ring * sin(th) * 2.0 / sqrt(1.0 - u * u) * w;
    }
    return sum;
}

/* More peak scatterings along the beam than this on average: the peak's light is nil (above). */
#define PEAK_MAX_COUNT 600.0

/* The peak's light at wavelength k (beam: the unscattered beam's radiance scale at the observer) in
 * ms_table.peak, in two parts: the single-scattering table's nodes (a degree or two apart, in
 * logarithms: positive) take its shape, the multiple-scattering table's (a few degrees apart) a
 * smooth negative remainder. */
static fm_status peak_light(fog_column *fc, const scaled_layer *sl, const plane_layer *pl, int k, double beam)
{
    const atmosphere *atm = &fc->job->sky->atm;
    const double mu0 = fc->job->sky->sun_dir.z;
    double w[FM_MAX_SPECIES] = {0}, lambda = 0.0;
    for (int l = 0; l < fc->level; l++) {
        if (!(sl[l].f > 0.0))
            continue;
        const double mu_l = pl[l].mu0 > 0.0 ? pl[l].mu0 : mu0;
        lambda += sl[l].ssa * sl[l].f * sl[l].tau / mu_l;
        for (int c = 0; c < atm->scattering_count; c++)
            w[c] += fc->column[l][c] * atm->species[c].sigma_s[k] / mu_l;
    }
    const int K = atm->grid.count;
    double *out = fc->job->ms->peak + (size_t)k * FOG_PEAK_ANGLES, *rest = out + (size_t)K * FOG_PEAK_ANGLES;
    /* its flux on the ground, which the table's nodes do not hold; with the sun near the horizon
     * beam e^lambda is the beam dimmed by (1 - 2 ssa f) of the fog's slant depth, nil (e^-200) long
     * before e^lambda overflows */
    const int nil = !(lambda > 0.0 && beam > 0.0) || lambda > PEAK_MAX_COUNT;
    fc->ground[k] = nil ? 0.0 : mu0 * beam * (expm1(lambda) - lambda);
    if (nil)
        return FM_OK;
    double *work = malloc(sizeof(double) * (16 * (size_t)PEAK_PANELS + PEAK_MOMENTS));
    if (!work)
        return FM_ERR_OUT_OF_MEMORY;
    double *M = work + 16 * (size_t)PEAK_PANELS;
    int L;
    peak_moments(atm, k, w, lambda, work, M, &L);
    peak_sum(M, L, work, out);
    /* a smooth bump b added (it keeps the sum positive for the logarithms) and taken from the
     * multiple-scattering table's nodes, which interpolate it well where they would smooth the lobe */
    double lend = 0.0;
    for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
        out[j] *= beam / (4.0 * FM_PI);
        lend = fmax(lend, -PEAK_LEND * out[j] / peak_bump(PEAK_U_MAX * j / (FOG_PEAK_ANGLES - 1.0)));
    }
    for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
        const double u = PEAK_U_MAX * j / (FOG_PEAK_ANGLES - 1.0), taper = peak_taper(2.0 * asin(u));
        rest[j] = -lend * peak_bump(u) * taper;
        out[j] = out[j] * taper - rest[j];
    }
    /* on the ground the table's sky half counts its part of the flux already */
    fc->ground[k] -= sky_flux(rest, mu0);
    free(work);
    return FM_OK;
}

/* One of the peak's two tables (peak_light) at wavelength k, at cosine x from the sun. */
static double peak_at(const double *table, int k, double x)
{
    const double f = sqrt(fmax(0.0, 0.5 * (1.0 - x))) / PEAK_U_MAX * (FOG_PEAK_ANGLES - 1.0);
    const int j = (int)f;
    if (j >= FOG_PEAK_ANGLES - 1)
        return 0.0;
    const double *t = table + (size_t)k * FOG_PEAK_ANGLES;
    return t[j] + (f - j) * (t[j + 1] - t[j]);
}

/* Single scattering looking down along mu from the top of one homogeneous layer lit at its top,
 * per unit F0 (as single_bottom). */
static double single_top(double tau, double ssa_phase, double mu, double mu0)
{
    return ssa_phase * mu0 / (mu + mu0) * -expm1(-tau * (mu + mu0) / (mu * mu0));
}

/* The column's radiance at one node from its Fourier modes, less the part of its order 1 that is
 * order 1 (one scattering by the truncated phase function, at the true optical depths; the rest of
 * the scaled order 1 was also scattered within the peak): the single-scattering table holds it.
 * Looking up (down 0) the layers above the observer scatter it, looking down those below. */
static double node_radiance(const fog_column *fc, const scaled_layer *sl, const plane_layer *pl, const double *above,
                            const double *modes, double mu, double phi, double mu_sun, int down)
{
    double L = modes[0];
    for (int m = 1; m < FOG_MOMENTS; m++)
        L += 2.0 * modes[m] * cos(m * phi);
    double between = 0.0; /* optical depth from the layer to the observer */
    for (int l = down ? fc->level : fc->level - 1; down ? l < fc->layers : l >= 0; l += down ? 1 : -1) {
        const double mu0 = pl[l].mu0 > 0.0 ? pl[l].mu0 : mu_sun; /* the layer's beam, as the column's */
        const double x = (down ? -mu : mu) * mu0 + sqrt(fmax(0.0, (1.0 - mu * mu) * (1.0 - mu0 * mu0))) * cos(phi);
        const double sp = sl[l].ssa * (1.0 - sl[l].f) * scaled_phase(sl[l].chi, x);
        L -= exp(-above[l] / mu_sun - between / mu) *
             (down ? single_top(sl[l].tau, sp, mu, mu0) : single_bottom(sl[l].tau, sp, mu, mu0));
        between += sl[l].tau;
    }
    return L;
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
static void air_beam_cosines(const fog_column *fc, const fm_sky *sky, int k, const scaled_layer *sl, plane_layer *pl)
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

/* The light from above (fc->incident) at the sky nodes at wavelength k added to the table's sums: the
 * light the fog and the ground scatter, and the field seen through the fog along the view less its
 * single scattering seen so (the single-scattering table's).  The field's scatterings within the
 * droplets' truncated peak go with it through the scaled optical depth (it is smooth over their few
 * degrees).  work: n_mu x FOG_MOMENTS.  Nonzero: no memory. */
static int diffuse_nodes(const fog_column *fc, const scaled_layer *sl, const plane_layer *pl, int k, double *work)
{
    const fog_incident *in = fc->incident;
    ms_table *t = fc->job->ms;
    const int K = in->K, M = FOG_MOMENTS, cols = t->grid.cols, rows = t->grid.rows_sky;
    plane_column col = {.streams = FOG_STREAMS, .layer_count = fc->layers, .layer = pl,
                        .ground_albedo = fc->job->sky->atm.ground_albedo[k], .mu0 = 1.0, .n_mu = rows, .mu = fc->mu};
    const double *field = in->field + (size_t)k * FOG_STREAMS * M;
    if (fc->response) {
        const int N = FOG_STREAMS;
        double *map = fc->response->values + (size_t)k * M * rows * N;
        if (!fc->response->ready && plane_column_diffuse_response(&col, fc->level, map))
            return 1;
        for (int r = 0; r < rows; r++)
            for (int m = 0; m < M; m++) {
                const double *row = map + ((size_t)m * rows + r) * N;
                double sum = 0.0;
                for (int j = 0; j < N; j++)
                    sum += row[j] * field[j * M + m];
                work[r * M + m] = sum;
            }
    } else if (plane_column_diffuse_level(&col, fc->level, field, work, NULL, NULL)) {
        return 1;
    }
    double scaled = 0.0, depth = 0.0;
    for (int l = 0; l < fc->level; l++) {
        scaled += pl[l].tau;
        depth += sl[l].tau;
    }
    for (int i = 0; i < rows * cols; i++) {
        double e, phi;
        sky_grid_node_angles(&t->grid, i, &e, &phi);
        const double *modes = work + (size_t)(i / cols) * M, mu = fc->mu[i / cols];
        double L = modes[0];
        for (int m = 1; m < M; m++)
            L += 2.0 * modes[m] * cos(m * phi);
        L += exp(-scaled / mu) * in->seen[(size_t)i * K + k] - exp(-depth / mu) * in->single[(size_t)i * K + k];
        t->sum[(size_t)i * K + k] += L;
    }
    return 0;
}

/* Work item: the table's sums at one grid wavelength. */
static void wavelength_nodes(void *ctx, int64_t begin, int64_t end, int thread)
{
    fog_column *fc = ctx;
    render_job *job = fc->job;
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, M = FOG_MOMENTS, cols = t->grid.cols, rows = t->grid.rows_sky;
    /* the beam: none with the sun at or below the horizon (the light from above alone; mu0 then
     * stands in for the beam's cosine in what the beam's nil scale takes out) */
    const int beam = sky->sun_dir.z > 0.0;
    const double mu0 = beam ? sky->sun_dir.z : 1.0;
    (void)thread;
    for (int64_t k = begin; k < end; k++) {
        scaled_layer sl[PLANE_COLUMN_MAX_LAYERS];
        plane_layer pl[PLANE_COLUMN_MAX_LAYERS];
        double above[PLANE_COLUMN_MAX_LAYERS + 1], above_fog = 0.0;
        above[0] = 0.0;
        for (int l = 0; l < fc->layers; l++)
            layer_at(fc, atm, l, (int)k, &sl[l], &pl[l]);
        if (beam)
            air_beam_cosines(fc, sky, (int)k, sl, pl);
        for (int l = 0; l < fc->layers; l++) {
            const double mu_l = pl[l].mu0 > 0.0 ? pl[l].mu0 : mu0; /* the beam's depth: tau mu0 / mu_l */
            above[l + 1] = above[l] + sl[l].tau * mu0 / mu_l;
            if (l < fc->layers - fc->fog_layers)
                above_fog += sl[l].tau * mu0 / mu_l;
        }
        plane_column col = {.streams = FOG_STREAMS, .layer_count = fc->layers, .layer = pl,
                            .ground_albedo = atm->ground_albedo[k], .mu0 = mu0,
                            .n_mu = fc->on_ground ? rows : fc->n_mu, .mu = fc->mu}; /* on the ground: the views up */
        double *down = calloc((size_t)(2 * fc->n_mu * M), sizeof(double)), *up = down + fc->n_mu * M, ground;
        if (!down || (beam && plane_column_level(&col, fc->level, down, fc->on_ground ? NULL : up, NULL)) ||
            (!fc->on_ground && plane_column_level(&col, fc->layers, NULL, NULL, &ground))) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        /* the beam at the fog's top the sun table's (the layers' cosines make it so but for the
         * table's interpolation) */
        double T_sph[FM_MAX_WAVELENGTHS] = {0};
        if (beam)
            sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, fc->top_radius, mu0, T_sph);
        const double scale = atm->grid.solar_irradiance[k] * T_sph[k] / exp(-above_fog / mu0);
        if (peak_light(fc, sl, pl, (int)k, exp(-above[fc->level] / mu0) * scale)) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        const double *rest = t->peak + (size_t)K * FOG_PEAK_ANGLES;
        for (int r = 0; r < (scale > 0.0 ? rows + (fc->on_ground ? 0 : t->grid.rows_ground) : 0); r++)
            for (int c = 0; c < cols; c++) {
                double e, phi;
                sky_grid_node_angles(&t->grid, r * cols + c, &e, &phi);
                const int looking_down = r >= rows;
                double L = node_radiance(fc, sl, pl, above, (looking_down ? up : down) + r * M, fc->mu[r], phi, mu0,
                                         looking_down);
                /* looking down: less the ground's light the single-scattering table reflects (the
                 * column's irradiance there, all of it, seen through the air below) */
                if (looking_down)
                    L -= atm->ground_albedo[k] / FM_PI * mu0 * ground * exp(-(above[fc->layers] - above[fc->level]) / fc->mu[r]);
                else /* the peak's light: its smooth negative part */
                    L += peak_at(rest, (int)k, v3_dot(render_view_direction(sky, e, phi), sky->sun_dir)) / scale;
                t->sum[(size_t)(r * cols + c) * K + k] = L * scale;
            }
        /* above the ground, its diffuse irradiance comes from the column (the peak's light in it): all
         * of it but the direct beam and order 1, which the ground's own quadrature holds */
        if (!fc->on_ground)
            fc->ground[k] = scale * mu0 * (ground - exp(-above[fc->layers] / mu0));
        if (fc->incident && diffuse_nodes(fc, sl, pl, (int)k, down)) {
            free(down);
            atomic_store(&job->no_memory, 1);
            return;
        }
        free(down);
    }
}

/* ---- the table ------------------------------------------------------------------------------- */

/* The fog's and the ground's diffuse albedo seen from above at every grid wavelength (the column of
 * the fog alone under an isotropic field): the ground of the sky that lights it (fog_incident.h). */
static fm_status fog_albedo(const fog_column *fc, double *albedo)
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
            layer_at(fc, atm, l, k, &sl[l], &pl[l]);
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
static void view_cosines(fog_column *fc, const sky_grid *g)
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
static void sphere_sky_cosines(fog_column *fc, const fm_sky *sky, const sky_grid *g)
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

/* The column's sums into the table (t->sum and t->peak) and what it adds to the ground's irradiance
 * (ground; on_ground: whether the observer is there), lit by the beam and the air above the fog, or
 * (from_above) the column of the fog alone lit by the sky above it. */
static fm_status column_sums(render_job *job, int from_above, fog_tables_fn tables, column_response *response,
                             double *ground, int *on_ground)
{
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, nodes = sky_grid_nodes(&t->grid);
    fog_column *fc = calloc(1, sizeof *fc);
    if (!fc)
        return FM_ERR_OUT_OF_MEMORY;
    fc->job = job;
    const int cloud = column_cloud(sky);
    const double base = sky->composition.cloud[cloud].base_m;
    double fog_top = base + sky->composition.cloud[cloud].thickness_m;
    if (from_above) {
        /* the layer and the air under it: its droplets thin out to the profile's next node above its
         * top (the layer's density is half at its top node, cloud_layer.c), a sixteenth of the optical
         * depth of fog 200 m deep */
        column_layers(fc, sky, fmax(base, 0.0), fog_top, fog_top + FM_PROFILE_SPACING_M);
        fog_top += FM_PROFILE_SPACING_M;
        fc->fog_layers = fc->layers; /* the beam as the sun table has it at the column's top */
    } else {
        column_layers(fc, sky, fmax(base, 0.0), fog_top, atm->top_radius_m - atm->bottom_radius_m);
    }
    fc->top_radius = atm->bottom_radius_m + fog_top;
    view_cosines(fc, &t->grid);
    if (fc->level <= fc->layers - fc->fog_layers) /* the observer above the layer */
        sphere_sky_cosines(fc, sky, &t->grid);
    fm_status s = species_moments(fc, atm);
    fog_incident incident = {0};
    if (!s && from_above) {
        double albedo[FM_MAX_WAVELENGTHS];
        s = fog_albedo(fc, albedo);
        if (!s)
            s = fog_incident_build(job, tables, cloud, fog_top, albedo, FOG_STREAMS, FOG_MOMENTS, &t->grid, &incident);
        fc->incident = &incident;
        fc->response = response;
    }
    free(t->peak);
    if (!s && !(t->peak = calloc(2 * (size_t)K * FOG_PEAK_ANGLES, sizeof(double))))
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s) {
        memset(t->sum, 0, sizeof(double) * (size_t)nodes * K);
        const fm_render_params *p = job->params;
        parallel_progress pp = {p->progress, p->progress_user, "multiple scattering (fog column)", 0.05, 0.75};
        s = parallel_for(p->threads, K, 1, wavelength_nodes, fc, p->cancel, &pp);
        if (!s && atomic_load(&job->no_memory))
            s = FM_ERR_OUT_OF_MEMORY;
        if (!s && fc->response)
            fc->response->ready = 1;
    }
    memcpy(ground, fc->ground, sizeof(double) * (size_t)K);
    *on_ground = fc->on_ground;
    fog_incident_free(&incident);
    free(fc->chi);
    free(fc);
    return s;
}

/* The column lit from above's share of the table at the sky's sun (from_above_below_deg and the
 * blend above it). */
static double above_share_at(const fm_sky *sky)
{
    const double e = asin(clamp_cosine(sky->sun_dir.z)) / FM_DEG;
    const double below = from_above_below_deg(sky, column_cloud(sky));
    return e < below ? 1.0 : e > below + FOG_TABLE_BLEND_DEG ? 0.0 : (below + FOG_TABLE_BLEND_DEG - e) / FOG_TABLE_BLEND_DEG;
}

double fog_table_above_share(const render_job *job)
{
    return fog_table_from_above(job) ? above_share_at(job->sky) : 0.0;
}

/* The table's sums (t->sum, t->peak) and the ground's at the job's sky's sun: the column lit from
 * above (with response, where not NULL) and the day's blended by share. */
static fm_status table_sums(render_job *job, double share, fog_tables_fn tables, column_response *response,
                            double *ground, int *on_ground)
{
    ms_table *t = job->ms;
    const size_t n = (size_t)sky_grid_nodes(&t->grid) * job->sky->atm.grid.count;
    double day_ground[FM_MAX_WAVELENGTHS];
    fm_status s = FM_OK;
    double *day = NULL; /* between the thresholds: the column lit by the beam and the air, to blend */
    if (share > 0.0 && share < 1.0 && !(s = column_sums(job, 0, tables, NULL, day_ground, on_ground)) &&
        (day = malloc(sizeof(double) * n)))
        memcpy(day, t->sum, sizeof(double) * n);
    else if (share > 0.0 && share < 1.0 && !s)
        s = FM_ERR_OUT_OF_MEMORY;
    if (!s)
        s = column_sums(job, share > 0.0, tables, response, ground, on_ground);
    for (size_t i = 0; i < n && day && !s; i++)
        t->sum[i] = share * t->sum[i] + (1.0 - share) * day[i];
    for (int k = 0; k < job->sky->atm.grid.count && day && !s; k++)
        ground[k] = share * ground[k] + (1.0 - share) * day_ground[k];
    free(day);
    return s;
}

/* The incident skies' paths, a share of the quality's: the deck sees each through its whole sky, whose
 * noise it averages. */
#define LOCAL_SUN_PATH_SHARE 4

/* A thin layer of ice alone by day below FOG_TABLE_THIN_MIN_SUN_DEG: the day's column at several
 * suns, each view at the sun where it meets the layer. */
static int thin_local_sun(const render_job *job)
{
    return thin_ice_alone(job->sky) && job->sky->sun_dir.z < sin(FOG_TABLE_THIN_MIN_SUN_DEG * FM_DEG);
}

/* Under a thin layer the suns' shift and the views' tilt fade over FOG_TABLE_BLEND_DEG below
 * FOG_TABLE_THIN_MIN_SUN_DEG, where one sun takes the table: without the fade the map moved by 0.40 %
 * RMS (3.3 % at most) from 23.99 to 24.01 degrees under cirrostratus. */
static double thin_shift(double sun_rad)
{
    return fmin(1.0, (FOG_TABLE_THIN_MIN_SUN_DEG - sun_rad / FM_DEG) / FOG_TABLE_BLEND_DEG);
}

/* Above a deck (the column's layer below the observer) by day below FOG_TABLE_ABOVE_LOCAL_SUN_DEG:
 * the day's column at several suns, each view down at the sun where it meets the deck's top. */
static int above_local_sun(const render_job *job)
{
    const fm_sky *sky = job->sky;
    const int cloud = column_cloud(sky);
    const double altitude = observer_altitude_m(sky);
    return cloud >= 0 && !fog_table_from_above(job) && sky->composition.cloud_count == 1 &&
           altitude >= sky->composition.cloud[cloud].base_m + sky->composition.cloud[cloud].thickness_m &&
           sky->sun_dir.z < sin(FOG_TABLE_ABOVE_LOCAL_SUN_DEG * FM_DEG);
}

/* Its shift fades over FOG_TABLE_BLEND_DEG below the bound, where one sun takes the table. */
static double above_shift(double sun_rad)
{
    return fmin(1.0, (FOG_TABLE_ABOVE_LOCAL_SUN_DEG - sun_rad / FM_DEG) / FOG_TABLE_BLEND_DEG);
}

enum { LOCAL_DECK, LOCAL_THIN, LOCAL_ABOVE };

/* Under an elevated deck (fog_table_local_sun), a thin layer (thin_local_sun) or above a deck
 * (above_local_sun): the table at the
 * suns fog_local_sun.h spans, each node's along its view.  The observer's sun goes last: the peak
 * and the ground are its.  Under a deck the shift fades with the column lit from above's share, so
 * that where the day's column (one sun) takes the table alone the views do not jump (3.4 % at the
 * horizon across 5.8 degrees under altostratus).  Under a thin layer (the day's column alone) the
 * suns are no farther apart than the observer's is above FOG_TABLE_MIN_SUN_DEG, where the day's
 * column has its beam (views beyond them take the nearest), the arcs toward the sun count
 * FOG_LOCAL_SUN_THIN_TOWARD times, and each point takes the view at its own elevation
 * (fog_local_sun.h; decks as measured before, without). */
static fm_status local_sun_sums(render_job *job, int mode, fog_tables_fn tables, double *ground, int *on_ground)
{
    const fm_sky *own = job->sky;
    const size_t n = (size_t)sky_grid_nodes(&job->ms->grid) * own->atm.grid.count;
    const double base = own->composition.cloud[column_cloud(own)].base_m;
    const double top = base + own->composition.cloud[column_cloud(own)].thickness_m;
    const double altitude = v3_length(own->observer) - own->atm.bottom_radius_m;
    const int thin = mode == LOCAL_THIN, day = mode != LOCAL_DECK;
    const double R = own->atm.bottom_radius_m; /* from above, the arc to the deck top's horizon */
    const double span = mode == LOCAL_ABOVE ? acos((R + top) / (R + altitude)) : fog_local_sun_span(&own->atm, base);
    const double e0 = asin(clamp_cosine(own->sun_dir.z));
    const double step = day ? fmin(span, e0 - FOG_TABLE_MIN_SUN_DEG * FM_DEG) : span;
    double *at = malloc(sizeof(double) * n * FOG_LOCAL_SUNS);
    fm_sky *local = malloc(sizeof *local); /* read alone: the same atmosphere and tables, another sun */
    /* the suns' columns lit from above share their layers (the fog's alone, no beam in them) */
    column_response response = {calloc((size_t)own->atm.grid.count * FOG_MOMENTS * job->ms->grid.rows_sky * FOG_STREAMS,
                                       sizeof(double)), 0};
    if (!at || !local || !response.values) {
        free(at);
        free(local);
        free(response.values);
        return FM_ERR_OUT_OF_MEMORY;
    }
    *local = *own;
    static const int order[FOG_LOCAL_SUNS] = {0, 2, 1};
    fm_status s = FM_OK;
    for (int j = 0; j < FOG_LOCAL_SUNS && !s; j++) {
        const double e = e0 + (order[j] - 1) * step;
        local->params.sun_elevation_deg = e / FM_DEG;
        local->sun_dir = direction_from_elevation_azimuth(e, own->params.sun_azimuth_deg * FM_DEG);
        const int paths = job->q.ms_paths;
        job->sky = order[j] == 1 ? own : local;
        job->q.ms_paths = (paths + LOCAL_SUN_PATH_SHARE - 1) / LOCAL_SUN_PATH_SHARE;
        s = table_sums(job, day ? 0.0 : above_share_at(job->sky), tables, &response, ground, on_ground);
        job->sky = own;
        job->q.ms_paths = paths;
        if (!s)
            memcpy(at + order[j] * n, job->ms->sum, sizeof(double) * n);
    }
    const double *const tables_at[FOG_LOCAL_SUNS] = {at, at + n, at + 2 * n};
    if (!s && mode == LOCAL_ABOVE)
        fog_local_sun_combine_down(&own->atm, &job->ms->grid, altitude, top, step, above_shift(e0), tables_at,
                                   job->ms->sum);
    else if (!s)
        fog_local_sun_combine(&own->atm, &job->ms->grid, base, step, thin ? thin_shift(e0) : above_share_at(own),
                              thin ? FOG_LOCAL_SUN_THIN_TOWARD : 1.0, thin ? thin_shift(e0) : 0.0, tables_at,
                              job->ms->sum);
    free(response.values);
    free(local);
    free(at);
    return s;
}

fm_status fog_table_fill(render_job *job, fog_tables_fn tables)
{
    const fm_sky *sky = job->sky;
    const atmosphere *atm = &sky->atm;
    ms_table *t = job->ms;
    const int K = atm->grid.count, nodes = sky_grid_nodes(&t->grid);
    if (t->grid.rows_sky + t->grid.rows_ground > (int)(sizeof ((fog_column *)0)->mu / sizeof(double)))
        return FM_ERR_INVALID_ARGUMENT;
    double ground[FM_MAX_WAVELENGTHS];
    int on_ground;
    const int mode = thin_local_sun(job) ? LOCAL_THIN : above_local_sun(job) ? LOCAL_ABOVE : LOCAL_DECK;
    fm_status s = fog_table_local_sun(job) || mode != LOCAL_DECK ? local_sun_sums(job, mode, tables, ground, &on_ground)
                                           : table_sums(job, fog_table_above_share(job), tables, NULL, ground, &on_ground);
    if (!s) {
        /* the nodes as one path each, already the whole of orders >= 2: no fit */
        t->paths = 1;
        for (int i = 0; i < nodes; i++) {
            const double *L = &t->sum[(size_t)i * K];
            t->y[i] = spectral_grid_luminance(&atm->grid, L);
            t->var[i] = 0.0;
            render_channels(atm, job->channels, L, &t->grid.values[(size_t)i * job->channels]);
        }
        job->paths_per_node = 0;
        if (!on_ground) { /* the ground's quadrature holds order 1 (render.c builds it without paths) */
            double order1[FM_MAX_WAVELENGTHS];
            ground_irradiance_lookup(&job->ground, sky->sun_dir.z, order1);
            for (int k = 0; k < K; k++)
                ground[k] -= order1[k];
        }
        ground_irradiance_add(&job->ground, ground);
    }
    return s;
}

/* The peak's light (peak_light), its part with the shape, added to the single-scattering table's sky
 * nodes. */
void fog_table_peak(const render_job *job, vec3 view, float *add)
{
    const atmosphere *atm = &job->sky->atm;
    const double x = v3_dot(view, job->sky->sun_dir);
    double L[FM_MAX_WAVELENGTHS];
    for (int k = 0; k < atm->grid.count; k++)
        L[k] = job->ms->peak ? peak_at(job->ms->peak, k, x) : 0.0;
    render_channels(atm, job->channels, L, add);
}

void fog_table_add_peak(render_job *job)
{
    const fm_sky *sky = job->sky;
    const ms_table *t = job->ms;
    const int C = job->channels, n = job->ss.rows_sky * job->ss.cols;
    for (int i = 0; i < n && t->peak; i++) {
        double e, phi;
        sky_grid_node_angles(&job->ss, i, &e, &phi);
        float add[FM_MAX_WAVELENGTHS];
        fog_table_peak(job, render_view_direction(sky, e, phi), add);
        for (int c = 0; c < C; c++) {
            float *v = &job->ss.values[(size_t)i * C + c];
            sky_grid_set(&job->ss, i, c, expf(*v) + add[c]);
        }
    }
}
