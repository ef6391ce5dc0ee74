#include "transport/deck_base.h"

#include "base/quadrature.h"
#include "base/rng.h"
#include "base/threads.h"
#include "base/units.h"
#include "transport/sun_frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define ITEM_DECK 0x400000000ull

/* ---- the column as layers ---------------------------------------------------------------------- */

/* Layers 1 km thick up to 12 km, 4 km above, broken at the base and at every edge of a species'
 * profile (a cloud's bottom and top); each with the mean density of every species over it, so
 * that its optical depth is the column's.  How the scattering is spread within a layer hardly
 * matters under a deck (in a plane-parallel layer of one kind of scatterer only its optical depth
 * does), and few layers keep the walk's steps through the clear air above few. */
#define LOW_DZ_M 1000.0
#define LOW_TOP_M 12000.0
#define HIGH_DZ_M 4000.0
#define MAX_LAYERS (64 + FM_MAX_EDGES)

typedef struct layers {
    int count, base;              /* layers; the first layer above the deck's base */
    const atmosphere *atm;
    double z[MAX_LAYERS + 1];     /* boundaries (m above the ground) */
    double n[MAX_LAYERS][FM_MAX_SPECIES]; /* mean densities (m^-3) */
    double sig_s[MAX_LAYERS][FM_MAX_WAVELENGTHS], sig_t[MAX_LAYERS][FM_MAX_WAVELENGTHS];
} layers;

/* The mean densities over [z0, z1]: Gauss-Legendre on pieces of at most PIECE_M, so that the kinks
 * of the profiles' 50 m cells fall between the nodes. */
#define PIECE_M 25.0
static void mean_densities(const atmosphere *atm, double z0, double z1, double *n)
{
    const gauss_rule *g = gauss_legendre_cached(4);
    const int pieces = (int)ceil((z1 - z0) / PIECE_M - 1e-9);
    const double h = (z1 - z0) / pieces;
    double m[FM_MAX_SPECIES];
    for (int c = 0; c < atm->species_count; c++)
        n[c] = 0.0;
    for (int p = 0; p < pieces; p++)
        for (int i = 0; i < g->n; i++) {
            atmosphere_densities(atm, atm->bottom_radius_m + z0 + h * (p + 0.5 + 0.5 * g->x[i]), m);
            for (int c = 0; c < atm->species_count; c++)
                n[c] += 0.5 * g->w[i] * m[c] / pieces;
        }
}

static int by_altitude(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The layers of atm's column, a boundary at the base (boundaries closer than 1 mm merged). */
static void layers_build(layers *l, const atmosphere *atm, double base_m)
{
    const double top = atm->top_radius_m - atm->bottom_radius_m;
    double z[MAX_LAYERS + 1];
    int n = 0;
    for (double h = 0.0; h < top && n < MAX_LAYERS - FM_MAX_EDGES; h += h < LOW_TOP_M ? LOW_DZ_M : HIGH_DZ_M)
        z[n++] = h;
    z[n++] = base_m;
    for (int e = 0; e < atm->edge_count; e++)
        if (atm->edge_altitude_m[e] > 0.0 && atm->edge_altitude_m[e] < top)
            z[n++] = atm->edge_altitude_m[e];
    qsort(z, (size_t)n, sizeof *z, by_altitude);
    l->atm = atm;
    l->count = 0;
    l->base = 0; /* a base at the ground: the loop skips its repeated 0 */
    l->z[0] = 0.0;
    for (int i = 1; i <= n; i++) {
        double next = i < n ? z[i] : top;
        if (next - l->z[l->count] <= 1e-3)
            continue;
        l->z[++l->count] = next;
        if (fabs(next - base_m) <= 1e-3)
            l->base = l->count;
    }
    for (int i = 0; i < l->count; i++) {
        mean_densities(atm, l->z[i], l->z[i + 1], l->n[i]);
        atmosphere_coefficients_from_densities(atm, l->n[i], l->sig_s[i], l->sig_t[i]);
    }
}

/* ---- the basis ----------------------------------------------------------------------------------- */

/* B_j(mu) = sum_i c_i mu^(i/2): polynomials in sqrt(mu), which follow the base's radiance down to the
 * horizon with three terms where polynomials in mu need four (docs/decisions/2026-12-06-deck-base.md);
 * orthonormal by Gram-Schmidt for the inner product integral_0^1 f g mu dmu (Gauss-Legendre). */
static double poly(const double *c, double mu)
{
    double v = 0.0, s = sqrt(mu);
    for (int i = DECK_MU_TERMS - 1; i >= 0; i--)
        v = v * s + c[i];
    return v;
}

static double inner(const double *a, const double *b)
{
    const gauss_rule *g = gauss_legendre_cached(8); /* in s = sqrt(mu): mu dmu = 2 s^3 ds, exact */
    double sum = 0.0;
    for (int i = 0; i < g->n; i++) {
        double s = 0.5 * (1.0 + g->x[i]);
        sum += g->w[i] * s * s * s * poly(a, s * s) * poly(b, s * s);
    }
    return sum;
}

static void basis_build(double B[DECK_MU_TERMS][DECK_MU_TERMS])
{
    memset(B, 0, sizeof(double) * DECK_MU_TERMS * DECK_MU_TERMS);
    for (int j = 0; j < DECK_MU_TERMS; j++) {
        B[j][j] = 1.0;
        for (int i = 0; i < j; i++) {
            double p = inner(B[j], B[i]);
            for (int t = 0; t < DECK_MU_TERMS; t++)
                B[j][t] -= p * B[i][t];
        }
        double norm = sqrt(inner(B[j], B[j]));
        for (int t = 0; t < DECK_MU_TERMS; t++)
            B[j][t] /= norm;
    }
}

/* The basis functions' values for the view (mu, cos phi): out[j * DECK_AZ_TERMS + m]. */
static void basis_values(const double B[DECK_MU_TERMS][DECK_MU_TERMS], double mu, double cos_phi, double *out)
{
    double az[DECK_AZ_TERMS];
    az[0] = 1.0;
    for (int m = 1; m < DECK_AZ_TERMS; m++) /* Chebyshev: cos(m phi) */
        az[m] = m == 1 ? cos_phi : 2.0 * cos_phi * az[m - 1] - az[m - 2];
    for (int j = 0; j < DECK_MU_TERMS; j++) {
        double b = poly(B[j], mu);
        for (int m = 0; m < DECK_AZ_TERMS; m++)
            out[j * DECK_AZ_TERMS + m] = b * az[m];
    }
}

/* ---- the photons --------------------------------------------------------------------------------- */

/* A direction at angle acos(c) from d, azimuth 2 pi u about it. */
static vec3 turn(vec3 d, double c, double u)
{
    frame f = frame_from_normal(d);
    double s = sqrt(fmax(0.0, 1.0 - c * c)), phi = 2.0 * FM_PI * u;
    return v3_normalize(frame_to_world(&f, v3(s * cos(phi), s * sin(phi), c)));
}

/* Scatters a photon at wavelength k in layer i: its species by its share of the scattering, then
 * the angle from that species' phase function. */
static vec3 scatter(const layers *l, int i, int k, vec3 d, rng *r)
{
    const atmosphere *atm = l->atm;
    double pick = rng_uniform(r) * l->sig_s[i][k];
    int c = 0;
    for (; c < atm->scattering_count - 1; c++) {
        pick -= l->n[i][c] * atm->species[c].sigma_s[k];
        if (pick < 0.0)
            break;
    }
    return turn(d, phase_sample(&atm->species[c].phase, k, rng_uniform(r)), rng_uniform(r));
}

/* Russian roulette below this weight; survivors are raised to it. */
#define ROULETTE_W 0.1

/* Whether the photon lives on, its weight w raised if it survived roulette. */
static int survives(double *w, rng *r)
{
    if (*w >= ROULETTE_W)
        return 1;
    if (!(*w > 0.0) || rng_uniform(r) * ROULETTE_W >= *w)
        return 0;
    *w = ROULETTE_W;
    return 1;
}

/* One photon at wavelength k from the top along -s (the sun's direction s in the frame whose z is
 * up and whose x points to the sun); each downward crossing of the base after a scattering adds
 * w B(mu, phi) to acc. */
static void photon(const layers *l, const double B[DECK_MU_TERMS][DECK_MU_TERMS], int k, vec3 s, rng *r,
                   double *acc)
{
    const double albedo = l->atm->ground_albedo[k];
    vec3 d = v3_scale(s, -1.0);
    int i = l->count - 1, scattered = 0;
    double z = l->z[l->count], w = 1.0;
    for (;;) {
        double tau = -log1p(-rng_uniform(r));
        for (;;) { /* fly through the layers until tau is spent */
            double st = l->sig_t[i][k];
            double dist = d.z < 0.0 ? (z - l->z[i]) / -d.z : d.z > 0.0 ? (l->z[i + 1] - z) / d.z : HUGE_VAL;
            if (st * dist > tau) {
                z += d.z * tau / st;
                break;
            }
            if (dist == HUGE_VAL)
                return; /* level in clear air: never arrives */
            tau -= st * dist;
            if (d.z > 0.0) {
                if (++i == l->count)
                    return; /* out through the top */
                z = l->z[i];
                continue;
            }
            if (i == l->base && scattered) {
                double v[DECK_TERMS], h = sqrt(d.x * d.x + d.y * d.y);
                basis_values(B, -d.z, h > 0.0 ? -d.x / h : 0.0, v);
                for (int t = 0; t < DECK_TERMS; t++)
                    acc[t] += w * v[t];
            }
            if (i == 0) { /* the ground: Lambertian */
                w *= albedo;
                if (!survives(&w, r))
                    return;
                frame up = frame_from_normal(v3(0.0, 0.0, 1.0));
                double u1 = rng_uniform(r), u2 = rng_uniform(r);
                d = frame_cosine_direction(&up, u1, u2);
                z = 0.0;
                scattered = 1;
                tau = -log1p(-rng_uniform(r));
                continue;
            }
            z = l->z[i--]; /* the boundary: the top of the layer below */
        }
        w *= l->sig_s[i][k] / l->sig_t[i][k];
        if (!survives(&w, r))
            return;
        d = scatter(l, i, k, d, r);
        scattered = 1;
    }
}

/* ---- the build ----------------------------------------------------------------------------------- */

#define BLOCK 4096

typedef struct build_job {
    deck_base *d;
    const layers *l;
    int photons, blocks;
    uint64_t seed;
    double *sums; /* [node][K][block][DECK_TERMS] */
} build_job;

static double node_theta(const deck_base *d, int node) { return d->theta0 + node * d->dtheta; }

static void build_blocks(void *ctx, int64_t begin, int64_t end, int thread)
{
    const build_job *job = ctx;
    (void)thread;
    for (int64_t item = begin; item < end; item++) {
        int block = (int)(item % job->blocks), k = (int)(item / job->blocks % job->d->K);
        int node = (int)(item / job->blocks / job->d->K);
        double theta = node_theta(job->d, node), *acc = &job->sums[item * DECK_TERMS];
        vec3 s = v3(sin(theta), 0.0, cos(theta));
        int first = block * BLOCK, last = first + BLOCK < job->photons ? first + BLOCK : job->photons;
        for (int p = first; p < last && !parallel_cancelled(); p++) {
            rng r = rng_for(job->seed, ITEM_DECK + (uint64_t)(node * job->d->K + k), (uint64_t)p);
            photon(job->l, (const double(*)[DECK_MU_TERMS])job->d->basis, k, s, &r, acc);
        }
    }
}

fm_status deck_base_build(deck_base *d, const atmosphere *atm, double base_altitude_m, double theta_lo,
                          double theta_hi, int photons, uint64_t seed, int threads, const atomic_int *cancel)
{
    memset(d, 0, sizeof *d);
    const int K = atm->grid.count, blocks = (photons + BLOCK - 1) / BLOCK;
    d->base_radius_m = atm->bottom_radius_m + base_altitude_m;
    d->K = K;
    d->nodes = theta_hi > theta_lo ? DECK_SUN_NODES : 1;
    d->theta0 = theta_lo;
    d->dtheta = d->nodes > 1 ? (theta_hi - theta_lo) / (d->nodes - 1) : 0.0;
    basis_build(d->basis);
    layers *l = malloc(sizeof *l);
    const size_t items = (size_t)d->nodes * K * blocks;
    double *sums = calloc(items * DECK_TERMS, sizeof(double));
    d->coef = calloc((size_t)d->nodes * K * DECK_TERMS, sizeof(double));
    if (!l || !sums || !d->coef) {
        free(l);
        free(sums);
        deck_base_free(d);
        return FM_ERR_OUT_OF_MEMORY;
    }
    layers_build(l, atm, base_altitude_m);
    build_job job = {d, l, photons, blocks, seed, sums};
    fm_status s = parallel_for(threads, (int64_t)items, 1, build_blocks, &job, cancel, NULL);
    for (size_t item = 0; item < items && !s; item++) { /* the blocks summed in a fixed order */
        size_t nk = item / (size_t)blocks;
        int k = (int)(nk % (size_t)K), node = (int)(nk / (size_t)K);
        double e = atm->grid.solar_irradiance[k] * cos(node_theta(d, node)) / photons;
        for (int t = 0; t < DECK_TERMS; t++)
            d->coef[nk * DECK_TERMS + t] += sums[item * DECK_TERMS + t] * e / (t % DECK_AZ_TERMS ? FM_PI : 2.0 * FM_PI);
    }
    free(l);
    free(sums);
    if (s)
        deck_base_free(d);
    return s;
}

void deck_base_free(deck_base *d)
{
    free(d->coef);
    memset(d, 0, sizeof *d);
}

void deck_base_radiance(const deck_base *d, vec3 x, vec3 dir, vec3 sun_dir, double scale, double *L)
{
    sun_frame f = sun_frame_at(x, sun_dir);
    double mu = fmax(0.0, v3_dot(dir, f.up)), hx = v3_dot(dir, f.sun_h), hy = v3_dot(dir, f.side);
    double h = sqrt(hx * hx + hy * hy), v[DECK_TERMS];
    basis_values((const double(*)[DECK_MU_TERMS])d->basis, mu, h > 0.0 ? hx / h : 0.0, v);
    /* linear in the local sun zenith angle between the nodes, held at the ends */
    double a = d->nodes > 1 ? (acos(clamp_cosine(v3_dot(sun_dir, f.up))) - d->theta0) / d->dtheta : 0.0;
    a = fmin(fmax(a, 0.0), d->nodes - 1.0);
    int n0 = (int)fmin(a, d->nodes - 2.0 >= 0.0 ? d->nodes - 2.0 : 0.0);
    double t = a - n0;
    for (int k = 0; k < d->K; k++) {
        const double *c0 = &d->coef[((size_t)n0 * d->K + k) * DECK_TERMS];
        const double *c1 = d->nodes > 1 ? c0 + (size_t)d->K * DECK_TERMS : c0;
        double sum = 0.0;
        for (int j = 0; j < DECK_TERMS; j++)
            sum += ((1.0 - t) * c0[j] + t * c1[j]) * v[j];
        L[k] += scale * sum;
    }
}

int deck_base_cut(const deck_base *d, ray_segment *seg)
{
    if (!d || seg->hits_ground)
        return 0;
    double t = -seg->s0 + sqrt(fmax(0.0, d->base_radius_m * d->base_radius_m - seg->p2));
    if (!(t < seg->t_end))
        return 0;
    seg->t_end = fmax(t, 0.0);
    return 1;
}

/* The base of the lowest layer that the truncated copy cuts (m above the ground), or -1. */
static double lowest_deck_base(const fm_sky *sky)
{
    double base = -1.0;
    for (int i = 0; i < sky->composition.cloud_count; i++)
        if (sky->composition.cloud[i].tau550 >= SKY_TRUNCATE_TAU && (base < 0.0 || sky->composition.cloud[i].base_m < base))
            base = sky->composition.cloud[i].base_m;
    return base;
}

fm_status deck_base_for_sky(deck_base *d, const fm_sky *sky, int photons, uint64_t seed, int threads,
                            const atomic_int *cancel, int *built)
{
    const atmosphere *atm = &sky_scattering_media(sky)->atm;
    const double base = lowest_deck_base(sky), r_obs = v3_length(sky->observer);
    *built = 0;
    if (!sky->truncated || base <= 0.0 || r_obs >= atm->bottom_radius_m + base ||
        sky->sun_dir.z < sin(DECK_MIN_SUN_DEG * FM_DEG))
        return FM_OK;
    /* the paths reach the base from ground points out to the observer's horizon, and from there up to
     * the base's horizon: the local sun zenith angle moves by at most the arcs to both */
    const double rg = atm->bottom_radius_m, reach = acos(rg / r_obs) + acos(rg / (rg + base));
    const double theta = acos(clamp_cosine(sky->sun_dir.z));
    fm_status s = deck_base_build(d, atm, base, fmax(theta - reach, 0.0), fmin(theta + reach, 0.5 * FM_PI - 0.01),
                                  photons, seed, threads, cancel);
    *built = !s;
    return s;
}
