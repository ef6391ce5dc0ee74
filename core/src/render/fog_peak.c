#include "render/fog_peak.h"

#include "base/quadrature.h"
#include "render/fog_column.h"
#include "render/fog_peak_view.h"
#include "render/fog_regime.h"
#include "render/ms_table.h"
#include "render/render_job.h"
#include "sky.h"

#include <math.h>
#include <stdlib.h>

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
    for (int l = 0, small = 0; l < PEAK_MOMENTS; l++) { /* p0, p1: P_l, P_(l+1) */
        double Lam = lambda;
        if (l >= FOG_MOMENTS) {
            Lam = 0.0;
            for (int q = 0; q < Q; q++)
                Lam += v[q] * p0[q];
        }
        M[l] = expm1(Lam) - Lam;
        small = fabs(Lam) < 1e-6 * lambda ? small + 1 : 0;
        if (small == 8) {
            *L = l + 1;
            return;
        }
        for (int q = 0; q < Q; q++) { /* p0, p1 <- P_(l+1), P_(l+2) */
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
 * sin(theta / 2), as ms_table.peak) over the sky, each view's as fog_peak_view weighs it (the
 * weights at wavelength k of K in peak): each ring about the sun by the mean over its part above the
 * horizon of the weight times the cosine of its zenith angle. */
#define FLUX_RING_POINTS 32
static double sky_flux(const double *table, double mu0, const double *peak, int K, int k)
{
    const double s0 = sqrt(fmax(0.0, 1.0 - mu0 * mu0));
    double sum = 0.0;
    for (int j = 0; j < FOG_PEAK_ANGLES; j++) {
        const double u = PEAK_U_MAX * j / (FOG_PEAK_ANGLES - 1.0), th = 2.0 * asin(u);
        const double a = mu0 * cos(th), b = s0 * sin(th); /* cos z = a + b cos(psi) on the ring */
        double ring = 0.0; /* 2 pi times the ring's mean, by the midpoint rule in psi */
        for (int q = 0; q < FLUX_RING_POINTS; q++) {
            const double mu = a + b * cos(FM_PI * (q + 0.5) / FLUX_RING_POINTS);
            ring += mu > 0.0 ? mu * fog_peak_view_at(peak, K, k, mu) : 0.0;
        }
        ring *= 2.0 * FM_PI / FLUX_RING_POINTS;
        /* d(solid angle) = 2 pi sin(theta) d(theta), d(theta) = 2 du / cos(theta / 2) */
        const double w = (j == 0 || j == FOG_PEAK_ANGLES - 1 ? 0.5 : 1.0) * PEAK_U_MAX / (FOG_PEAK_ANGLES - 1.0);
        sum += table[j] * ring * sin(th) * 2.0 / sqrt(1.0 - u * u) * w;
    }
    return sum;
}

/* The weights of the peak's light by view (fog_peak_view.h) at a wavelength in w, for fog around the
 * observer (its base at or below it): its optical depth above the observer, the peak's share of it,
 * and its height there.  None (every weight 1) for other layers: a high layer's slants are the
 * sphere's, not a plane's. */
static void fog_peak_weights(const fog_column *fc, const scaled_layer *sl, double *w)
{
    const fm_sky *sky = fc->job->sky;
    const double base = sky->composition.cloud[fog_regime_cloud(sky)].base_m;
    const double top = fc->top_radius - sky->atm.bottom_radius_m;
    const double h = fc->level < fc->layers ? fc->top_m[fc->level] : 0.0; /* the observer's level, m */
    const int around = base <= h + 0.5 && h <= top + 0.5; /* the fog's base at or below it, its top above */
    double tau = 0.0, peak = 0.0;
    for (int l = 0; around && l < fc->level; l++) {
        const double bottom = l + 1 < fc->layers ? fc->top_m[l + 1] : 0.0;
        if (!(sl[l].f > 0.0) || bottom < base - 0.5 || fc->top_m[l] > top + 0.5)
            continue;
        tau += sl[l].tau;
        peak += sl[l].ssa * sl[l].f * sl[l].tau;
    }
    const double mu0 = sky->sun_dir.z;
    const double top_rad = fmin(asin(fmin(fmax(mu0, 0.0), 1.0)) + PEAK_MAX_DEG * FM_DEG, 0.5 * FM_PI);
    const double shell = 2.0 * (top - h) / (sky->atm.bottom_radius_m + h);
    fog_peak_view_fill(w, tau, tau > 0.0 ? peak / tau : 0.0, shell, mu0, top_rad);
}

/* More peak scatterings along the beam than this on average: the peak's light is nil (above). */
#define PEAK_MAX_COUNT 600.0

/* The peak's light at wavelength k (beam: the unscattered beam's radiance scale at the observer) in
 * ms_table.peak, in two parts: the single-scattering table's nodes (a degree or two apart, in
 * logarithms: positive) take its shape, the multiple-scattering table's (a few degrees apart) a
 * smooth negative remainder. */
fm_status fog_peak_light(fog_column *fc, const scaled_layer *sl, const plane_layer *pl, int k, double beam)
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
    fog_peak_weights(fc, sl, fc->job->ms->peak + 2 * (size_t)K * FOG_PEAK_ANGLES + FOG_PEAK_VIEW_SIZE * (size_t)k);
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
    fc->ground[k] -= sky_flux(rest, mu0, fc->job->ms->peak, K, k);
    free(work);
    return FM_OK;
}

/* The weight of the peak's light at wavelength k of K along view cosine mu (fog_peak_view.h). */
double fog_peak_view_at(const double *peak, int K, int k, double mu)
{
    return fog_peak_view(peak + 2 * (size_t)K * FOG_PEAK_ANGLES + FOG_PEAK_VIEW_SIZE * (size_t)k, mu);
}

/* One of the peak's two tables (fog_peak_light) at wavelength k, at cosine x from the sun. */
double fog_peak_at(const double *table, int k, double x)
{
    const double f = sqrt(fmax(0.0, 0.5 * (1.0 - x))) / PEAK_U_MAX * (FOG_PEAK_ANGLES - 1.0);
    const int j = (int)f;
    if (j >= FOG_PEAK_ANGLES - 1)
        return 0.0;
    const double *t = table + (size_t)k * FOG_PEAK_ANGLES;
    return t[j] + (f - j) * (t[j + 1] - t[j]);
}

/* The peak's light (fog_peak_light), its part with the shape, added to the single-scattering table's sky
 * nodes. */
void fog_table_peak(const render_job *job, vec3 view, float *add)
{
    const atmosphere *atm = &job->sky->atm;
    const double x = v3_dot(view, job->sky->sun_dir);
    double L[FM_MAX_WAVELENGTHS];
    const int K = atm->grid.count;
    fog_peak_view_place at = {0}; /* the view among the weights' nodes: placed once */
    for (int k = 0; k < K; k++) {
        if (!job->ms->peak) {
            L[k] = 0.0;
            continue;
        }
        const double *w = job->ms->peak + 2 * (size_t)K * FOG_PEAK_ANGLES + FOG_PEAK_VIEW_SIZE * (size_t)k;
        if (w[0] > 0.0 && (w[0] != at.spacing || w[1] != at.shell))
            at = fog_peak_view_placed(w, view.z);
        L[k] = fog_peak_at(job->ms->peak, k, x) * fog_peak_view_read(w, &at);
    }
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
