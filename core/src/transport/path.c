#include "transport/path.h"

#include "base/exp_array.h"
#include "base/threads.h"
#include "base/units.h"
#include "phase/phase.h"
#include "transport/free_flight.h"
#include "transport/shadow_flight.h"
#include "transport/sky_guide.h"
#include "transport/sunlit_segment.h"

#include <math.h>
#include <stddef.h>

void medium_phase(const atmosphere *atm, const double *n, double cos_theta, double *p, double *sigma_s)
{
    /* One phase_evaluate_all per species (a tabulated phase function then searches its angle grid
     * once, not once per wavelength); the sums run over species in the same order as before. */
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

static double average(const double *q, int K)
{
    double s = 0.0;
    for (int k = 0; k < K; k++)
        s += q[k];
    return s / K;
}

/* The largest of a path's spectral weights q_k w_k (times W / average(q), its scale). */
static double largest_weight(const double *q, const double *w, int K)
{
    double m = 0.0;
    for (int k = 0; k < K; k++)
        m = larger(m, q[k] * w[k]);
    return m;
}

/* Russian roulette on the largest spectral weight; returns 0 if the path dies.  Paths play only once
 * their weight falls below FM_ROULETTE_THRESHOLD, and survivors are raised to that weight, not to 1:
 * a path sent into an unlikely direction by the sun guide (weight << 1) would otherwise come back
 * with weight 1 and undo the guide's gain.  (Measured at 550 nm, sun 30 deg, view 45 deg: relative
 * standard deviation per multiple-scattering path 3.6 -> 1.4 for rural, 4.8 -> 1.9 for desert dust,
 * at 20-30 % more time per path.)  The weight is multiplied by lift (1, or deep twilight's
 * light_lift below) before the comparison, and at least min_survive of the paths live on (0, or
 * deep twilight's LIGHT_LED_MIN_SURVIVAL below). */
#define FM_ROULETTE_THRESHOLD 0.1
static int roulette(double *W, const double *q, const double *w, int K, int order, double lift, double min_survive,
                    rng *r)
{
    double m = largest_weight(q, w, K) * (*W / average(q, K) * lift);
    double survive = fmin(m / FM_ROULETTE_THRESHOLD, order > 8 ? 0.95 : 1.0);
    survive = survive > min_survive ? survive : min_survive;
    if (survive >= 1.0)
        return 1;
    if (!(survive > 0.0) || rng_uniform(r) >= survive)
        return 0;
    *W /= survive;
    return 1;
}

static void renormalise(double *q, int K)
{
    double m = 0.0;
    for (int k = 0; k < K; k++)
        m = larger(m, q[k]);
    if (m > 1e100 || (m < 1e-100 && m > 0.0))
        for (int k = 0; k < K; k++)
            q[k] /= m;
}

/* A direction drawn from the sun guide (path.h) about the sun, at the hero wavelength h. */
static vec3 sun_guide_direction(const path_context *ctx, int h, rng *r)
{
    double cos_sun = phase_sample(ctx->sun_guide, h, rng_uniform(r));
    return rotate_direction(ctx->sun_dir, cos_sun, 2.0 * FM_PI * rng_uniform(r));
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
static vec3 scatter_direction(const path_context *ctx, vec3 x, const double *n, const double *sig_s, vec3 d, int h,
                              rng *r, double *q, double *w)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    const double a = ctx->sun_guide ? ctx->sun_guide_fraction : 0.0;
    const double b = ctx->sky_guide ? ctx->sky_guide_fraction : 0.0;
    double cos_theta, phase[FM_MAX_WAVELENGTHS];
    vec3 nd;
    double technique = (a > 0.0 || b > 0.0) ? rng_uniform(r) : 1.0;
    if (technique < a) {
        nd = sun_guide_direction(ctx, h, r);
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
            phase_evaluate_all(ctx->sun_guide, K, clamp_cosine(v3_dot(nd, ctx->sun_dir)), guide);
        double sky = b > 0.0 ? sky_guide_pdf(ctx->sky_guide, x, ctx->sun_dir, nd) : 0.0;
        for (int k = 0; k < K; k++)
            pdf[k] = (1.0 - a - b) * phase[k] + a * guide[k] + b * sky;
        mis_weigh(K, h, phase, pdf, q, w);
    } else {
        for (int k = 0; k < K; k++)
            q[k] *= phase[k] / phase[h];
    }
    return nd;
}

/* The sun guide at the ground only while the sun is this high above the point's horizon (sine of
 * 10 degrees): lower, the aureole's light comes in grazing (cosine below 0.17) and the guided
 * quarter of the directions is mostly lost to the cosine lobe; at the urban sunset (sun 2, turbidity
 * 2) the fast path's multiple-scattering paths, which bounce, made the 1024 x 512 final map's error
 * against the converged reference 0.45 -> 0.60% RMS with the guide there. */
#define GROUND_GUIDE_MIN_SINE 0.17364817766693033

/* A direction leaving the Lambertian ground at the point whose outward normal is `normal`; updates
 * the spectral pdf ratios q and weights w (albedo_k (cos / pi) / pdf_k).  Cosine-weighted about the
 * normal or, with probability a while the sun is high enough (above), drawn from the sun guide about
 * the sun (one-sample MIS, balance heuristic, as scatter_direction): the ground's light from
 * the aureole is the aerosols' forward peak, which cosine sampling finds only by chance (reference
 * mode at sun 30, a ground pixel's relative standard deviation per path: desert dust 1.2, urban 0.8,
 * rural 0.35, clear air 0.10).  Returns 0 for a guided direction into the ground (no light). */
static int ground_direction(const path_context *ctx, vec3 normal, int h, rng *r, double *q, double *w, vec3 *out)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count;
    const double a =
        ctx->sun_guide && v3_dot(normal, ctx->sun_dir) > GROUND_GUIDE_MIN_SINE ? ctx->sun_guide_fraction : 0.0;
    vec3 d;
    if (a > 0.0 && rng_uniform(r) < a) {
        d = sun_guide_direction(ctx, h, r);
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
        phase_evaluate_all(ctx->sun_guide, K, clamp_cosine(v3_dot(d, ctx->sun_dir)), guide);
        for (int k = 0; k < K; k++) {
            f[k] = atm->ground_albedo[k] * lambert;
            pdf[k] = (1.0 - a) * lambert + a * guide[k];
        }
        mis_weigh(K, h, f, pdf, q, w);
    } else {
        for (int k = 0; k < K; k++)
            w[k] *= atm->ground_albedo[k];
    }
    *out = d;
    return 1;
}

/* The light-led roulette keeps at least a tenth of the paths at each vertex.  The light at a vertex
 * in the shadow says little of what its path will find: a path that began high up in the light
 * (first vertices follow it, view_ray_vertices.h), with a small weight, and then flew into the
 * shadow 30 km up was kept once in 1890 times, and, with its weight raised that much, met the sunlit
 * band a few vertices on: at sun -18 one such path was 1568 times its node's mean.  With the floor
 * a survivor's weight grows at most tenfold per vertex.  Rural, 256 x 128 final, twelve seeds, the
 * relative SD of one map: sun -18 3.53 -> 3.38% (seeds 13-24 3.72 -> 3.27%), -14 2.01 -> 1.91%,
 * -10 1.26 -> 1.25%, in the same time (a floor of 0.3: -18 3.26 / 3.28% in 4% more). */
#define LIGHT_LED_MIN_SURVIVAL 0.1

/* Deep twilight's roulette (path_context.light_led_roulette): a guided flight that lands where the
 * light is bright has a small weight, sigma_s T / pdf with the pdf proportional to that light
 * (shadow_flight.h), and a roulette on the weight alone ended most such paths and multiplied the
 * survivors' weight up to 50 or 200 times: at sun -18 the largest path estimates, up to 6000 times
 * a node's mean, were of that kind, and a single map was 8% darker than the mean of many.  So the
 * roulette plays at the new vertex, on the weight times the light there relative to the
 * light at the path's first point (orders 1 and 2 there: in the shadow, single scattering alone
 * is 3700 times too dark), never below the plain roulette's.  Rural, 128 x 64 final, six seeds, the
 * sky's relative standard deviation of one map (CPU time for the six): sun -10 2.75 -> 2.04%
 * (55 -> 85 s), -14 8.9 -> 4.5% (47 -> 80 s), -18 20.5 -> 13.8% (38 -> 69 s). */
static double light_lift(const path_context *ctx, vec3 x, double start_light)
{
    if (!(start_light > 0.0))
        return 1.0; /* not light-led: the plain roulette */
    double r = v3_length(x), light = shadow_flight_light(ctx->shadow_flights, r, v3_dot(x, ctx->sun_dir) / r);
    return light > start_light ? light / start_light : 1.0;
}

/* Deep twilight splits a path whose weight has grown past SPLIT_WEIGHT into copies (at most
 * SPLIT_COPIES, and SPLIT_BUDGET beyond the first path in all) that share its weight and go on from
 * its new direction each on its own.  A path that bounces in the dark air near the observer by
 * directions and distances that the guides give little density (the phase function's quarter of
 * the directions, the flights' share by scattering alone) gains two to four times its weight a
 * bounce, up to a hundred, before it meets the light: at the horizon 160 degrees from the sun (sun
 * -18), the 3% of paths whose weight passed 3 made half the node's second moment.  The copies take
 * that tail apart; the weight is the path's alone, not led by the light, which would split the
 * paths that the light's guides already sent to bright places.  Rural, 256 x 128 final, twelve
 * seeds, the relative SD of one map: -18 3.37 -> 2.51% (seeds 13-24 3.28 -> 2.55%), the first 2
 * degrees above the horizon 7.5-9.7 -> 4.5-5.3%; -14 1.90 -> 1.63%, -10 1.25 -> 1.06%; a
 * 1024 x 512 final map at -18 in 27% more time (5.0 -> 6.3 s).  Without the budget, at -18: as
 * here 2.63% in 15% more time than with it; led by the light (the roulette's lift) 2.85% in 58%
 * more time than whole paths; above 5 2.88% in 16% more; above 2 in 8 copies 2.65% in 53% more. */
#define SPLIT_WEIGHT 3.0
#define SPLIT_COPIES 4

/* Deep twilight also splits, before its next direction is drawn, a path whose weight times the
 * light at its vertex (relative to its first point's, the roulette's lift) has passed SPLIT_WEIGHT:
 * each copy draws its own direction.  Hazy deep twilight's path estimates had a power-law tail too
 * heavy for a variance (urban at turbidity 2, sun -18, a node 160 degrees from the sun, 409 600
 * paths: tail index 1.4-1.8 by Hill's estimator over the largest 50-1000 paths, so more paths
 * hardly helped: four times the paths took a map's noise only from 5.5 to 4.3%).  The tail was
 * paths whose weight fell more slowly than the light rose as they climbed toward the sunlit air
 * (weight x light up 300 times in three flights), then drew one direction through the brightest
 * of it; the split by weight alone, after the direction, could not take such a path apart (its
 * weight stayed below 3; a larger budget changed nothing).  With both splits and a budget of 32
 * copies: that node's tail index 2.2-2.7, the largest path 726 times the mean instead of 4566, the
 * relative SD per path 15.6 -> 6.3 in 1.42 times the CPU (rural: index 2.1-3.3 -> 2.7-4.4, 4.6 ->
 * 3.3 in 1.28 times); a budget of 64 or 128 gave 6.2 in 1.6-1.8 times, a threshold of 6 12.6, and
 * the light-led split alone (none by weight) 8.1 with index 1.7-3. */
#define SPLIT_BUDGET 32

/* Where a copy of a split path starts: at a segment's origin with these weights (path_trace's);
 * with at_vertex, at the scattering vertex origin, arrived along dir, to draw its own direction. */
typedef struct path_resume {
    const double *q, *w;
    double W, start_light;
    int order, splits_left, at_vertex;
} path_resume;

/* A path's weight as roulette and splitting weigh it: its largest spectral weight q_k w_k W / mean(q). */
static double path_weight(double W, const double *q, const double *w, int K)
{
    return largest_weight(q, w, K) * (W / average(q, K));
}

/* exp(-600): the weight behind an absorption optical depth of 600, far below any light a map holds */
#define OPAQUE_WEIGHT 2.65e-261

/* How many copies a path whose weight (as roulette weighs it, times lift) is m splits into: 1 for
 * none. */
static int split_copies(double m, int splits_left)
{
    if (!(m > SPLIT_WEIGHT) || splits_left <= 0)
        return 1;
    int copies = m < SPLIT_COPIES * SPLIT_WEIGHT ? (int)ceil(m / SPLIT_WEIGHT) : SPLIT_COPIES;
    return copies - 1 < splits_left ? copies : splits_left + 1;
}

/* Where a contribution of the given order goes: L_later, if given, takes orders 3 and up. */
static double *order_sink(double *L, double *L_later, int order)
{
    return L_later && order > 2 ? L_later : L;
}

/* The path from origin along dir; with first_weight, it begins with a scattering at origin (arrived
 * along dir) whose spectral weights are first_weight; with resume, it goes on as a copy of a split
 * path from origin along dir.  Contributions go to L, or those of orders 3 and up to L_later when it
 * is given. */
static void trace(const path_context *ctx, vec3 origin, vec3 dir, int hero, rng *r, double *L, double *L_later,
                  const double *first_weight, const path_resume *resume)
{
    const atmosphere *atm = ctx->atm;
    const int K = atm->grid.count, h = hero;
    const double *E0 = atm->grid.solar_irradiance;
    double q[FM_MAX_WAVELENGTHS], w[FM_MAX_WAVELENGTHS];
    double sig_s[FM_MAX_WAVELENGTHS], sig_t[FM_MAX_WAVELENGTHS], tbar[FM_MAX_WAVELENGTHS];
    double phase[FM_MAX_WAVELENGTHS], depth[FM_MAX_WAVELENGTHS], force[FM_MAX_WAVELENGTHS];
    double n[FM_MAX_SPECIES];
    for (int k = 0; k < K; k++) {
        q[k] = 1.0;
        w[k] = first_weight ? first_weight[k] : 1.0;
    }
    double W = 1.0;
    int order = 0, at_vertex = first_weight != NULL, vertices_done = 0, splits_left = SPLIT_BUDGET;
    int counted = 0; /* a copy at a vertex whose sunlight the split path has counted */
    vec3 pos = origin, d = dir;
    const int light_led = ctx->shadow_flights && ctx->light_led_roulette;
    const double min_survive = light_led ? LIGHT_LED_MIN_SURVIVAL : 0.0;
    double start_light = 0.0; /* light-led roulette: the light at the path's first point, > 0 */
    if (resume) {
        for (int k = 0; k < K; k++) {
            q[k] = resume->q[k];
            w[k] = resume->w[k];
        }
        W = resume->W;
        order = resume->order;
        splits_left = resume->splits_left;
        if (resume->at_vertex) {
            at_vertex = counted = 1;
            order--; /* the vertex counts it again */
        }
        vertices_done = 1;
        start_light = resume->start_light;
    } else if (light_led) {
        double r0 = v3_length(origin);
        start_light = shadow_flight_light_and_ambient(ctx->shadow_flights, r0, v3_dot(origin, ctx->sun_dir) / r0);
        if (!(start_light > 0.0))
            start_light = 1e-300;
    }

    for (;;) {
        if (parallel_cancelled())
            return; /* the render is cancelled: its sums are thrown away */
        ray_segment seg;
        ray_segment_init(&seg, atm, pos, d);
        double t = 0.0, tau, umbra0, umbra1;
        int scattered = 0, along = 0, late_roulette = 0;
        if (at_vertex) {
            /* the given first vertex: a scattering at the segment's origin */
            at_vertex = 0;
            atmosphere_densities(atm, v3_length(pos), n);
            atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
            /* air that scatters nothing at the hero wavelength here (an absorbing-only atmosphere
             * file) has no phase function to draw the next direction from: no light this way */
            if (!(sig_s[h] > 0.0))
                return;
            scattered = 1;
            goto vertex;
        }
        /* Across the Earth's shadow: the next interaction's sunlight as the segment's expected value
         * (before the flight and its forced-collision weight), and no point estimate after the flight. */
        if (ctx->segment_sunlight && order + 1 >= ctx->min_order) {
            along = segment_umbra(ctx, &seg, &umbra0, &umbra1);
            int every = ctx->segment_sunlight == SEGMENT_SUNLIGHT_ALL ||
                        (ctx->segment_sunlight == SEGMENT_SUNLIGHT_RISING && seg.s0 > 0.0);
            if (!along && every) {
                along = 1; /* no umbra to skip */
                umbra0 = umbra1 = seg.t_end;
            }
        }
        if (along) {
            double S[FM_MAX_WAVELENGTHS] = {0};
            segment_sunlight(ctx, &seg, umbra0, umbra1, r, S);
            double scale = W / average(q, K), *sink = order_sink(L, L_later, order + 1);
            for (int k = 0; k < K; k++)
                sink[k] += scale * q[k] * w[k] * S[k];
            if (ctx->max_order > 0 && order + 1 >= ctx->max_order)
                return;
        }
        /* Russian roulette once the light that the last direction found is counted: here when the
         * segment's sunlight was counted along it, else at the next vertex, after its point estimate
         * (late_roulette; sun 30, 256 x 128 final: desert dust 1.6 times the efficiency, README) */
        late_roulette = vertices_done && (light_led || !along);
        if (vertices_done && !late_roulette && !roulette(&W, q, w, K, order, 1.0, 0.0, r))
            return;
        if (ctx->shadow_flights) {
            scattered = shadow_flight(ctx, ctx->shadow_flights, &seg, r, w, &t);
            if (scattered) {
                atmosphere_densities(atm, ray_segment_radius(&seg, t), n);
                atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
            }
            goto vertex;
        }
        if (ctx->force_escapes && !seg.hits_ground) {
            /* Forced collision: the first tentative collision is drawn inside the segment.  Each
             * wavelength's technique would do the same with its own probability F_k of colliding:
             * weight f/p = F_k, and F_k enters that technique's pdf. */
            free_flight_majorant_depth(atm, &seg, 0.0, seg.t_end, depth);
            if (!(depth[h] > 1e-12))
                return;
            for (int k = 0; k < K; k++)
                force[k] = -depth[k];
            expm1_array(force, force, K);
            for (int k = 0; k < K; k++)
                force[k] = -force[k];
            for (int k = 0; k < K; k++) {
                w[k] *= force[k];
                /* a wavelength the medium does not touch cannot produce this path at all */
                q[k] = force[k] > 0.0 ? q[k] * force[h] / force[k] : 0.0;
            }
            tau = -log1p(-rng_uniform(r) * force[h]);
        } else {
            tau = -log1p(-rng_uniform(r));
        }

        /* Delta tracking until a scattering or the end of the segment.  The pdf of a flight for
         * wavelength k is exp(-depth_k) times the probability of the event that ends it. */
        /* The flights' transmittance ratios exp(depth_h - depth_k) are summed as depths and applied
         * once the flight ends: one exp per wavelength per segment, not per tentative collision. */
        double pending[FM_MAX_WAVELENGTHS] = {0};
        for (;;) {
            int shell;
            int collided = free_flight_advance(atm, &seg, t, tau, h, &t, depth, &shell);
            for (int k = 0; k < K; k++)
                pending[k] += depth[h] - depth[k];
            if (!collided)
                break; /* reached the ground or the top */
            double rad = ray_segment_radius(&seg, t);
            atmosphere_densities(atm, rad, n);
            atmosphere_coefficients_from_densities(atm, n, sig_s, sig_t);
            const double *maj = atm->shell_majorant[shell];
            if (rng_uniform(r) * maj[h] < sig_s[h]) {
                for (int k = 0; k < K; k++)
                    q[k] *= sig_s[k] / sig_s[h];
                scattered = 1;
                break;
            }
            /* Not a scattering: absorption and null collisions continue together, chosen with
             * probability (majorant - sigma_s) / majorant; the surviving fraction
             * (majorant - sigma_t) / (majorant - sigma_s) is a weight, not a coin flip, so
             * absorbing layers (ozone, soot) cost no paths. */
            double cont_h = maj[h] - sig_s[h];
            for (int k = 0; k < K; k++) {
                double cont = maj[k] - sig_s[k];
                w[k] *= cont > 0.0 ? larger(maj[k] - sig_t[k], 0.0) / cont : 0.0;
                q[k] *= cont / cont_h;
            }
            /* an opaque medium: a weight that absorption took below e^-600 carries nothing, and
             * tracking it on to the segment's end could take millions of collisions */
            if (!(path_weight(W, q, w, K) > OPAQUE_WEIGHT))
                return;
            tau = -log1p(-rng_uniform(r));
        }
        exp_array(pending, pending, K);
        for (int k = 0; k < K; k++)
            q[k] *= pending[k];
        renormalise(q, K);

    vertex:
        if (scattered) {
            vec3 x = v3_madd(seg.origin, seg.dir, t);
            double rad = v3_length(x);
            order++;
            if (!along && order >= ctx->min_order && !counted) {
                double mu_s = v3_dot(x, ctx->sun_dir) / rad;
                sun_irradiance_lookup(ctx->sun_table, atm, ctx->sun, rad, mu_s, tbar);
                medium_phase(atm, n, v3_dot(d, ctx->sun_dir), phase, NULL);
                double scale = W / average(q, K), *sink = order_sink(L, L_later, order);
                for (int k = 0; k < K; k++)
                    sink[k] += scale * q[k] * w[k] * phase[k] * E0[k] * tbar[k];
            }
            if (ctx->max_order > 0 && order >= ctx->max_order)
                return;
            const double lift = light_lift(ctx, x, start_light); /* 1 unless light-led */
            if (late_roulette && !roulette(&W, q, w, K, order, lift, min_survive, r))
                return;
            counted = 0;
            const int split = ctx->shadow_flights && ctx->split_heavy_paths;
            int copies = split && light_led ? split_copies(path_weight(W, q, w, K) * lift, splits_left) : 1;
            if (copies > 1) { /* led by the light: each copy draws its own direction here */
                W /= copies;
                splits_left -= copies - 1;
                const path_resume copy = {q, w, W, start_light, order, splits_left, 1};
                for (int c = 1; c < copies; c++)
                    trace(ctx, x, d, hero, r, L, L_later, NULL, &copy);
            }
            vec3 nd = scatter_direction(ctx, x, n, sig_s, d, h, r, q, w);
            renormalise(q, K);
            pos = x;
            d = nd;
            copies = split ? split_copies(path_weight(W, q, w, K), splits_left) : 1;
            if (copies > 1) { /* by the weight alone: the copies share the direction */
                W /= copies;
                splits_left -= copies - 1;
                const path_resume copy = {q, w, W, start_light, order, splits_left, 0};
                for (int c = 1; c < copies; c++)
                    trace(ctx, pos, d, hero, r, L, L_later, NULL, &copy);
            }
        } else if (seg.hits_ground) {
            vec3 x = v3_madd(seg.origin, seg.dir, seg.t_end);
            double rad = v3_length(x);
            vec3 normal = v3_scale(x, 1.0 / rad);
            order++;
            if (order == 1 && ctx->skip_ground_first)
                return;
            if (!along && order >= ctx->min_order) {
                double mu_s = v3_dot(normal, ctx->sun_dir);
                double *thor = phase; /* reuse: horizontal transmittance */
                sun_irradiance_lookup_ground(ctx->sun_table, atm, ctx->sun, mu_s, tbar, thor);
                double scale = W / average(q, K), *sink = order_sink(L, L_later, order);
                for (int k = 0; k < K; k++)
                    sink[k] += scale * q[k] * w[k] * atm->ground_albedo[k] / FM_PI * E0[k] * thor[k];
            }
            if (ctx->max_order > 0 && order >= ctx->max_order)
                return;
            if (late_roulette && !roulette(&W, q, w, K, order, light_lift(ctx, x, start_light), min_survive, r))
                return;
            double any = 0.0;
            for (int k = 0; k < K; k++)
                any += w[k] * atm->ground_albedo[k];
            if (!(any > 0.0) || !ground_direction(ctx, normal, h, r, q, w, &d))
                return;
            renormalise(q, K);
            pos = v3_scale(normal, atm->bottom_radius_m);
        } else {
            return; /* left the atmosphere */
        }
        vertices_done = 1;
    }
}

void path_trace(const path_context *ctx, vec3 origin, vec3 dir, int hero, rng *r, double *L)
{
    trace(ctx, origin, dir, hero, r, L, NULL, NULL, NULL);
}

void path_trace_from(const path_context *ctx, vec3 x, vec3 dir, const double *weight, int hero, rng *r, double *L,
                     double *L_later)
{
    trace(ctx, x, dir, hero, r, L, L_later, weight, NULL);
}
