#include "transport/path_direction.h"

#include "base/checks.h"
#include "base/units.h"
#include "phase/phase.h"
#include "spectrum/spectral.h"
#include "transport/sky_guide.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>

void medium_phase(const atmosphere *atm, const double *n, double cos_theta, double *p, double *sigma_s)
{
    /* One phase_evaluate_all per species: a tabulated phase function then searches its angle grid
     * once, not once per wavelength. */
    const int K = atm->grid.count;
    double num[FM_MAX_WAVELENGTHS] = {0}, den[FM_MAX_WAVELENGTHS] = {0}, value[FM_MAX_WAVELENGTHS];
    for (int c = 0; c < atm->scattering_count; c++) {
        const species *sp = &atm->species[c];
        if (n[c] == 0.0)
            continue; /* aerosol layers are absent at most altitudes */
        phase_evaluate_all(&sp->phase, K, cos_theta, value);
        for (int k = 0; k < K; k++) {
            double s = sp->sigma_s[k] * n[c];
            num[k] += s * value[k];
            den[k] += s;
        }
    }
    for (int k = 0; k < K; k++) {
        p[k] = den[k] > 0.0 ? num[k] / den[k] : 0.0;
        if (sigma_s)
            sigma_s[k] = den[k];
    }
}

static vec3 rotate_direction(vec3 d, double cos_theta, double phi)
{
    frame f = frame_from_normal(d);
    double sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    return v3_normalize(frame_to_world(&f, v3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta)));
}

/* A direction drawn from the sun guide (path.h) about the sun sun_dir, at the hero wavelength h. */
static vec3 sun_guide_direction(const path_context *ctx, vec3 sun_dir, int h, rng *r)
{
    double cos_sun = phase_sample(ctx->sun_guide, h, rng_uniform(r));
    return rotate_direction(sun_dir, cos_sun, 2.0 * FM_PI * rng_uniform(r));
}

/* The sun guide's share of the directions at x: sun_guide_fraction where the sun's transmittance
 * there is at least e^-GUIDE_FULL_DEPTH (or x lies in the Earth's shadow in thin air: twilight's
 * guide aims at the sunlit air), falling as the transmittance below that.  The guide finds the next
 * vertex's sunlight through the forward peak; deep in a thick cloud there is none to find, and a
 * guided direction's small weight, paid at each of a path's hundreds of vertices there, would leave
 * its weight to the roulette (docs/decisions/2026-12-06-thick-media.md).  In cloud or fog in the
 * Earth's shadow it takes no share: the next vertex lies a free path away, in the shadow too. */
#define GUIDE_FULL_DEPTH 2.3
static double sun_guide_share(const path_context *ctx, vec3 sun_dir, vec3 x, int h, double sigma_s)
{
    if (!ctx->sun_guide)
        return 0.0;
    if (sigma_s < path_cloud_sigma(ctx)) /* no path in haze takes enough vertices for the weights to matter */
        return ctx->sun_guide_fraction;
    double r = v3_length(x), depth;
    if (!sun_irradiance_lookup_some_depths(ctx->sun_table, ctx->atm, ctx->sun, r, v3_dot(x, sun_dir) / r, 1, &h,
                                           &depth))
        return 0.0; /* in the shadow */
    if (depth <= GUIDE_FULL_DEPTH)
        return ctx->sun_guide_fraction;
    return ctx->sun_guide_fraction * exp(GUIDE_FULL_DEPTH - depth);
}

/* Twilight's guides (the sky guide, the sun guide in the Earth's shadow) take no share of the
 * directions at a vertex in cloud or fog (path_cloud_sigma: a thin layer too): the light they aim at
 * is beyond the layer, and the next vertex a free path away.  With them, a direction drawn from the
 * phase function weighs p / ((1 - a - b) p + ...), up to 1 / (1 - a - b) = 4, at each vertex: the
 * second moment of a path's weight grows by that factor per vertex of the forward peak, and over the
 * tens of vertices of a path in fog a rare path carried a map's light
 * (docs/decisions/2026-12-07-fog-reference.md).  The exception: in deep twilight a thin layer's
 * vertices within CLOUD_TOP_BAND_M of its top (path_context.h), where the sky guide's levels see the
 * sunlit band through the layer's air above them, take cloud_top_guide_fraction. */
static double sky_guide_share(const path_context *ctx, vec3 x, double sigma_s)
{
    if (!ctx->sky_guide)
        return 0.0;
    if (sigma_s < path_cloud_sigma(ctx))
        return ctx->sky_guide_fraction;
    return ctx->cloud_top_guide_fraction > 0.0 && v3_length(x) > ctx->cloud_top_radius_m - CLOUD_TOP_BAND_M
               ? ctx->cloud_top_guide_fraction
               : 0.0;
}

/* The sun guide's share about each of the walk's suns (path_context.suns) at x, each sun's
 * sun_guide_share divided by their number (0 where usable, if given, says a sun may not guide);
 * returns their sum.  A walk whose first sun takes its rising segments' light along them is that
 * sun's walk, the others scored on it: the guide aims at the first alone, so that its table is the one
 * it would have alone. */
static double sun_guide_shares(const path_context *ctx, vec3 x, int h, double sigma_s, const int *usable,
                               double *share)
{
    const int S = path_sun_count(ctx), first_only = S > 1 && ctx->segment_sunlight == SEGMENT_SUNLIGHT_RISING;
    double total = 0.0;
    for (int s = 0; s < S; s++) {
        const int guides = (!usable || usable[s]) && (!first_only || s == 0);
        share[s] = guides ? sun_guide_share(ctx, path_sun(ctx, s), x, h, sigma_s) / (first_only ? 1 : S) : 0.0;
        total += share[s];
    }
    return total;
}

/* A direction from the sun guide about the sun whose share holds u (in [0, the shares' sum)). */
static vec3 shared_sun_guide_direction(const path_context *ctx, const double *share, double u, int h, rng *r)
{
    int s = 0;
    while (s + 1 < path_sun_count(ctx) && u >= share[s]) {
        u -= share[s];
        s++;
    }
    return sun_guide_direction(ctx, path_sun(ctx, s), h, r);
}

/* The sun guides' density toward nd, each weighted by its share, summed into guide (K values). */
static void sun_guide_pdf(const path_context *ctx, const double *share, vec3 nd, double *guide)
{
    const int K = ctx->atm->grid.count;
    double one[FM_MAX_WAVELENGTHS];
    for (int k = 0; k < K; k++)
        guide[k] = 0.0;
    for (int s = 0; s < path_sun_count(ctx); s++) {
        if (!(share[s] > 0.0))
            continue;
        phase_evaluate_all(ctx->sun_guide, K, clamp_cosine(v3_dot(nd, path_sun(ctx, s))), one);
        for (int k = 0; k < K; k++)
            guide[k] += share[s] * one[k];
    }
}

/* One-sample MIS over the techniques of a direction, balance heuristic: with f[k] the directional
 * factor and pdf[k] the mixture's density for wavelength k, w[k] *= f / pdf and q[k] *= pdf / pdf_h. */
static void mis_weigh(int K, int h, const double *f, const double *pdf, double *q, double *w)
{
    for (int k = 0; k < K; k++) {
        w[k] *= pdf[k] > 0.0 ? f[k] / pdf[k] : 0.0;
        q[k] *= pdf[k] / pdf[h];
    }
}

/* A new direction at a scattering vertex with densities n, arriving along d; updates the spectral
 * pdf ratios q and weights w.  Local technique: choose a species in proportion to its sigma_s at the
 * hero wavelength, then draw from its phase function; the mixture's pdf for wavelength k is the
 * medium phase p_k.  With probability a the sun guide draws instead, about the sun's direction, so the
 * next vertex's sunlight is sampled where its forward peak makes it large (one-sample MIS, balance
 * heuristic over both techniques: pdf_k = (1 - a) p_k + a guide_k, weight p_k / pdf_k). */
vec3 scatter_direction(const path_context *ctx, vec3 x, const double *n, const double *sig_s, vec3 d, int h, rng *r,
                       double *q, double *w)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    double share[PATH_SUNS_MAX];
    const double a = sun_guide_shares(ctx, x, h, sig_s[h], NULL, share);
    const double b = sky_guide_share(ctx, x, sig_s[h]);
    assert(is_probability(a) && is_probability(b) && is_probability(a + b) && is_unit(d));
    double cos_theta, phase[FM_MAX_WAVELENGTHS];
    vec3 nd;
    double technique = (a > 0.0 || b > 0.0) ? rng_uniform(r) : 1.0;
    if (technique < a) {
        nd = shared_sun_guide_direction(ctx, share, technique, h, r);
        cos_theta = clamp_cosine(v3_dot(d, nd));
    } else if (technique < a + b) {
        double u1 = rng_uniform(r), u2 = rng_uniform(r), u3 = rng_uniform(r);
        nd = sky_guide_sample(ctx->sky_guide, x, ctx->sun_dir, u1, u2, u3);
        cos_theta = clamp_cosine(v3_dot(d, nd));
    } else {
        double pick = rng_uniform(r) * sig_s[h];
        int c = 0;
        while (c < atm->scattering_count - 1) {
            pick -= atm->species[c].sigma_s[h] * n[c];
            if (pick < 0.0)
                break;
            c++;
        }
        cos_theta = phase_sample(&atm->species[c].phase, h, rng_uniform(r));
        nd = rotate_direction(d, cos_theta, 2.0 * FM_PI * rng_uniform(r));
    }
    medium_phase(atm, n, cos_theta, phase, NULL);
    if (a > 0.0 || b > 0.0) {
        double guide[FM_MAX_WAVELENGTHS] = {0}, pdf[FM_MAX_WAVELENGTHS];
        if (a > 0.0)
            sun_guide_pdf(ctx, share, nd, guide);
        double sky = b > 0.0 ? sky_guide_pdf(ctx->sky_guide, x, ctx->sun_dir, nd) : 0.0;
        for (int k = 0; k < K; k++)
            pdf[k] = (1.0 - a - b) * phase[k] + guide[k] + b * sky;
        mis_weigh(K, h, phase, pdf, q, w);
    } else {
        spectral_mul_ratio(q, phase, phase[h], K);
    }
    assert(is_unit(nd));
    return nd;
}

/* The sun guide at the ground only while the sun is 10 degrees or more above the point's horizon:
 * lower, the aureole's light comes in grazing (cosine below 0.17) and the guided directions are
 * mostly lost to the cosine lobe (docs/decisions/2026-12-06-ground-sun-guide.md). */
#define GROUND_GUIDE_MIN_SINE 0.17364817766693033

/* A direction leaving the Lambertian ground at the point whose outward normal is `normal`; updates
 * the spectral pdf ratios q and weights w (albedo_k (cos / pi) / pdf_k).  Cosine-weighted about the
 * normal or, with probability a while the sun is high enough (above), drawn from the sun guide about
 * the sun (one-sample MIS, balance heuristic, as scatter_direction): the ground's light from the
 * aureole is the aerosols' forward peak, which cosine sampling finds only by chance.  Returns 0 for
 * a guided direction into the ground (no light). */
int ground_direction(const path_context *ctx, vec3 normal, int h, rng *r, double *q, double *w, vec3 *out)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    int high[PATH_SUNS_MAX];
    double share[PATH_SUNS_MAX];
    for (int s = 0; s < path_sun_count(ctx); s++)
        high[s] = v3_dot(normal, path_sun(ctx, s)) > GROUND_GUIDE_MIN_SINE;
    const double a = sun_guide_shares(ctx, v3_scale(normal, ctx->atm->bottom_radius_m), h, INFINITY, high, share);
    assert(is_probability(a) && is_unit(normal));
    vec3 d;
    double u = a > 0.0 ? rng_uniform(r) : 1.0;
    if (u < a) {
        d = shared_sun_guide_direction(ctx, share, u, h, r);
    } else {
        double u1 = rng_uniform(r), u2 = rng_uniform(r);
        frame f = frame_from_normal(normal);
        d = frame_cosine_direction(&f, u1, u2); /* strictly upward: it leaves the ground */
    }
    double cos_n = v3_dot(d, normal);
    if (!(cos_n > 0.0))
        return 0;
    if (a > 0.0) {
        double guide[FM_MAX_WAVELENGTHS], pdf[FM_MAX_WAVELENGTHS], f[FM_MAX_WAVELENGTHS], lambert = cos_n / FM_PI;
        sun_guide_pdf(ctx, share, d, guide);
        for (int k = 0; k < K; k++) {
            f[k] = atm->ground_albedo[k] * lambert;
            pdf[k] = (1.0 - a) * lambert + guide[k];
        }
        mis_weigh(K, h, f, pdf, q, w);
    } else {
        spectral_mul(w, atm->ground_albedo, K);
    }
    *out = d;
    return 1;
}
