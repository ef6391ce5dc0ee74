#include "render/render.h"

#include "atmosphere/optical_depth.h"
#include "base/param_range.h"
#include "base/rng.h"
#include "base/status.h"
#include "base/threads.h"
#include "base/units.h"
#include "camera/camera.h"
#include "camera/equirect.h"
#include "camera/footprint.h"
#include "image/image.h"
#include "render/record.h"
#include "transport/sky_path.h"
#include "transport/ground_irradiance.h"
#include "transport/single_scatter.h"
#include "transport/twilight.h"
#include "transport/sky_grid.h"
#include "transport/next_order_shape.h"
#include "transport/sky_grid_fit.h"

#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

quality_settings render_quality_settings(fm_quality quality, double scale)
{
    quality_settings q;
    switch (quality) {
    case FM_QUALITY_PREVIEW:
        q = (quality_settings){64, 32, 48, 12, 8, 12, 512, 4096, 2, 64, 3, 24, 32, 1};
        break;
    case FM_QUALITY_REFERENCE:
    case FM_QUALITY_FINAL:
    default:
        q = (quality_settings){128, 64, 96, 20, 12, 16, 2048, 16384, 3, 256, 3, 32, 32, SKY_GUIDE_MAX_OFFSETS};
        break;
    }
    q.ms_paths = (int)fmax(1.0, round(q.ms_paths * scale));
    q.ground_paths = (int)fmax(1.0, round(q.ground_paths * scale));
    q.reference_paths = (int)fmax(1.0, round(q.reference_paths * scale));
    return q;
}

/* Deep twilight's final maps: more paths per multiple-scattering node as the sun sinks, from 1 at
 * sun -11 degrees to 2 times at -18 (linear in between), since less and less of the sky's light is
 * found per path.  (4 times until the light-led split, path.c, which costs about twice the time per
 * path there: rural 256 x 128 at -18, four seeds, luminance / R / G / B / G 1.25 / 3.40 / 0.98% in
 * 25.8 s with 4 times before, 1.36 / 3.02 / 0.97% in 22.5 s with the split and 2 times.)  Before the
 * split, with 4 times:  Rural, 256 x 128 final, the relative SD of one map over twelve seeds: sun -12
 * 1.27 -> 1.10%, -14 1.63 -> 1.11%, -18 2.51 -> 1.39% (R / G 5.57 -> 3.09%; the horizon's first 2
 * degrees, the stretch that showed, 4.5-5.3 -> 2.1-3.2%); a 1024 x 512 final map at -18 7.7 ->
 * 26.8 s on two cores (with the flights' depth table, optical_depth.h).  Below -18, night by
 * definition (the scattered sunlight fainter than the night sky's own light, which is not
 * modelled), back to 1 by -21: a night's time series need not spend 4 times on maps that tend to
 * black.  The preview keeps its paths: it is there to be quick. */
#define MORE_PATHS_FROM_DEG -11.0
#define MORE_PATHS_FULL_DEG -18.0
#define MORE_PATHS_UNTIL_DEG -21.0
#define MORE_PATHS_MAX 2.0
/* 1 down to sun -18 degrees, 0 from -21 (night), linear in between. */
static double before_night(double sun_elevation_deg)
{
    const double e = sun_elevation_deg;
    return e >= MORE_PATHS_FULL_DEG   ? 1.0
           : e <= MORE_PATHS_UNTIL_DEG ? 0.0
                                       : (e - MORE_PATHS_UNTIL_DEG) / (MORE_PATHS_FULL_DEG - MORE_PATHS_UNTIL_DEG);
}

static double twilight_path_scale(fm_quality quality, double sun_elevation_deg)
{
    const double e = sun_elevation_deg;
    if (quality != FM_QUALITY_FINAL || !(e < MORE_PATHS_FROM_DEG && e > MORE_PATHS_UNTIL_DEG))
        return 1.0;
    double f = e > MORE_PATHS_FULL_DEG ? (MORE_PATHS_FROM_DEG - e) / (MORE_PATHS_FROM_DEG - MORE_PATHS_FULL_DEG)
                                       : before_night(e);
    return 1.0 + (MORE_PATHS_MAX - 1.0) * f;
}

/* Footprint samples per pixel and axis no denser than the tables need: three per node spacing of
 * the single-scattering table across a pixel follow the tables' bilinear pieces; a 4096-wide map's
 * 0.09-degree pixels need one (9 times fewer table lookups: 13.9 -> 10.0 s for the default sky),
 * a 256-wide map keeps the quality's three.  (Rows at the horizon are sampled finer anyway:
 * row_samples.) */
static void fit_footprint_to_pixels(quality_settings *q, const camera *cam, const fm_render_params *p)
{
    double pixel = cam->type == FM_CAMERA_EQUIRECT ? 2.0 * FM_PI / cam->width
                   : cam->type == FM_CAMERA_FISHEYE ? FM_PI / cam->width
                                                    : p->camera.fov_deg * FM_DEG / cam->width;
    double spacing = FM_PI / (q->ss_cols - 1);
    int n = (int)ceil(3.0 * pixel / spacing);
    q->subpixels = n < 1 ? 1 : (n < q->subpixels ? n : q->subpixels);
}

/* Seeds: every random stream is (seed, item, sample) with disjoint item ranges per use, and the
 * wavelength set mixed into the seed so renders at different wavelengths draw independent numbers. */
#define ITEM_MS_NODE 0x100000000ull
#define ITEM_PIXEL 0x200000000ull

typedef struct render_job {
    const fm_sky *sky;
    const fm_render_params *params;
    quality_settings q;
    uint64_t seed;
    int channels;
    camera cam;
    const twilight_sampling *twilight; /* below the horizon only (twilight.h) */
    sky_grid ss, ms;
    ground_irradiance ground;
    fm_image *img;
    atomic_int no_memory; /* a worker could not allocate */
    int rising_segments;  /* the table's paths: SEGMENT_SUNLIGHT_RISING (rising_segments) */
    double *ms_y, *ms_var; /* per node of ms: the luminance estimate and its variance (sky_grid_fit) */
    double *ms_sum;        /* per node of ms: the sum of its paths' estimates at every grid wavelength,
                            * [node][K] */
    node_moments *ms_moments; /* per node of ms: its paths' moments */
    int ms_pass, ms_pass_paths; /* the table's pass (0, or 1 for deep twilight's extra paths) and its
                                 * paths per node */
    int ms_paths;               /* paths per node so far (ms_finish) */
    double *ms_shape;      /* per node of ms: in deep twilight its view ray's light_integral
                            * (twilight_node_paths), else the shape of the part being fitted (fit_table) */
    /* Except in deep twilight the table's order 2 and its orders 3 and up are fitted apart
     * (fit_table): per node its light parted by order (else NULL), and the table of orders 3 and up,
     * whose luminance estimates and variances are ms_later_y and ms_later_var (ms, ms_y and ms_var
     * then hold order 2 until fit_table adds the two) */
    node_orders *ms_orders;
    double *ms_later_sum; /* [node][K] */
    sky_grid ms_later;
    double *ms_later_y, *ms_later_var;
    double *ms_ratio[2], *ms_ratio_var[2]; /* twilight, colour: per node of ms, X / Y and Z / Y and their
                                            * variances (sky_grid_fit_chroma); else NULL */
} render_job;

/* Spectral radiance (K values) -> C image channels: XYZ (colour, C = 3), else the K values
 * themselves (monochromatic C = K = 1; spectral maps C = K). */
static void to_channels(const atmosphere *atm, int C, const double *L, float *out)
{
    if (atm->grid.colour && C == 3) {
        double xyz[3];
        spectral_grid_to_xyz(&atm->grid, L, xyz);
        out[0] = (float)xyz[0];
        out[1] = (float)xyz[1];
        out[2] = (float)xyz[2];
    } else {
        for (int c = 0; c < C; c++)
            out[c] = (float)L[c];
    }
}

static vec3 view_direction(const fm_sky *sky, double elevation, double rel_azimuth)
{
    return direction_from_elevation_azimuth(elevation, sky->params.sun_azimuth_deg * FM_DEG + rel_azimuth);
}

/* Work item: one row of the single-scattering table; the view ray's part once per row
 * (single_scatter.h), the sun's part per column. */
static void ss_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    const fm_sky *sky = job->sky;
    path_context pc = sky_path_context(sky, 1, 1);
    pc.ground_diffuse = &job->ground;
    const int cols = job->ss.cols;
    for (int64_t row = begin; row < end; row++) {
        double e, phi;
        sky_grid_node_angles(&job->ss, (int)row * cols, &e, &phi);
        single_scatter_ray ray;
        if (single_scatter_ray_init(&ray, &pc, sky->observer, view_direction(sky, e, phi), job->q.ss_points)) {
            atomic_store(&job->no_memory, 1);
            return;
        }
        for (int col = 0; col < cols; col++) {
            int i = (int)row * cols + col;
            double L[FM_MAX_WAVELENGTHS] = {0};
            sky_grid_node_angles(&job->ss, i, &e, &phi);
            single_scatter_ray_radiance(&ray, &pc, view_direction(sky, e, phi), L);
            float v[FM_MAX_WAVELENGTHS];
            to_channels(&sky->atm, job->channels, L, v);
            for (int c = 0; c < job->channels; c++)
                sky_grid_set(&job->ss, i, c, v[c]);
        }
        single_scatter_ray_free(&ray);
    }
}

/* Whether the multiple-scattering table's paths take the sunlight of every rising segment as its
 * expected value along the segment (SEGMENT_SUNLIGHT_RISING; twilight has every segment).  With a
 * low sun behind thick haze the air around the observer lies in the haze's own shadow and the sky's
 * light comes from the sunlit air above, which few paths reach by scattering there; the integral
 * along each climbing segment counts it for every path, at about 1.6 times the CPU of a render.
 * Gain in 1 / (node variance x CPU of the whole render), 128 x 64 final, T = the sun's transmittance
 * to the observer at the grid's middle wavelength:
 *     taken:     urban T 2 sun 2 (T 3e-11) 1.76, urban T 1 sun 2 (2e-6) 1.67, rural T 4 sun 2 (6e-6) 1.57,
 *                rural T 2 sun 2 (9e-4) 1.59, desert dust T 2 sun 3 (2e-5) 1.5, rural sun 0.5 (3e-4)
 *                1.4, urban T 2 sun 4 (1e-6) 1.24;
 *     not taken: rural sun 2 (0.011) 0.93-1.07, urban T 2 sun 6 (8e-5) 0.95, desert dust T 4 sun 10
 *                (1e-3) 0.95, urban T 3 sun 8 (3e-5) 0.78, urban T 4 sun 15 0.76, rural sun 5 0.70,
 *                rural sun 30 0.63.
 * So: the sun below RISING_SUN_DEG and T below RISING_BELOW. */
#define RISING_SUN_DEG 4.5
#define RISING_BELOW 1e-3
static int rising_segments(const fm_sky *sky, const twilight_sampling *twilight)
{
    if (twilight)
        return 0;
    const path_context pc = sky_path_context(sky, 1, 1);
    double r = v3_length(sky->observer), mu_s = v3_dot(sky->observer, sky->sun_dir) / r, T[FM_MAX_WAVELENGTHS];
    if (!(mu_s > 0.0 && asin(clamp_cosine(mu_s)) < RISING_SUN_DEG * FM_DEG))
        return 0; /* a higher sun, or night (no twilight sampling: a black sky) */
    sun_irradiance_lookup(pc.sun_table, &sky->atm, pc.sun, r, mu_s, T);
    return T[sky->atm.grid.count / 2] < RISING_BELOW;
}

/* Item numbers of deep twilight's extra paths (twilight_extra_paths): after the nodes' own. */
#define ITEM_MS_EXTRA 0x80000000ull

/* Work item: one node of the multiple-scattering table, the pass's paths added to its sums. */
static void ms_nodes(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    const fm_sky *sky = job->sky;
    const int K = sky->atm.grid.count;
    path_context pc = twilight_path_context(job->sky, job->twilight, 2, 0);
    pc.skip_ground_first = 1;
    if (job->rising_segments)
        pc.segment_sunlight = SEGMENT_SUNLIGHT_RISING;
    for (int64_t i = begin; i < end; i++) {
        double e, phi;
        sky_grid_node_angles(&job->ms, (int)i, &e, &phi);
        vec3 d = view_direction(sky, e, phi);
        /* the hero wavelengths go round the grid; the extra paths go on where the first pass ended */
        uint64_t offset = mix64(job->seed ^ (uint64_t)i) + (job->ms_pass ? (uint64_t)job->q.ms_paths : 0);
        uint64_t item = ITEM_MS_NODE + (job->ms_pass ? ITEM_MS_EXTRA : 0) + (uint64_t)i;
        twilight_node_paths(sky, &pc, d, job->ms_pass_paths, job->seed, item, (int)(offset % (uint64_t)K),
                            &job->ms_sum[i * K], &job->ms_moments[i], job->ms_pass ? NULL : &job->ms_shape[i],
                            job->ms_orders ? &job->ms_orders[i] : NULL);
    }
}

/* A luminance's variance of the mean over n paths from the sum of its squares over them, yy. */
static double variance_of_mean(double yy, double y, double n)
{
    return n > 1.0 ? fmax(0.0, yy / n - y * y) / (n - 1.0) : 0.0;
}

/* The table's nodes from their sums over `paths` paths each: estimates, luminance variances and, at
 * twilight in colour, the chromaticity ratios and their variances; except in deep twilight, order 2
 * in ms and the orders above in ms_later. */
static void ms_finish(render_job *job, int paths)
{
    const fm_sky *sky = job->sky;
    const int K = sky->atm.grid.count, nodes = sky_grid_nodes(&job->ms);
    const double n = paths;
    job->ms_paths = paths;
    for (int i = 0; i < nodes; i++) {
        double L[FM_MAX_WAVELENGTHS];
        for (int k = 0; k < K; k++)
            L[k] = job->ms_sum[i * K + k] / n;
        double yy = job->ms_moments[i].yy; /* the whole's, or order 2's once parted */
        if (job->ms_orders) {
            double later[FM_MAX_WAVELENGTHS];
            for (int k = 0; k < K; k++) {
                later[k] = job->ms_later_sum[i * K + k] / n;
                L[k] -= later[k];
            }
            double y3 = spectral_grid_luminance(&sky->atm.grid, later);
            job->ms_later_y[i] = y3;
            job->ms_later_var[i] = variance_of_mean(job->ms_orders[i].yy[1], y3, n);
            to_channels(&sky->atm, job->channels, later, &job->ms_later.values[i * job->channels]);
            yy = job->ms_orders[i].yy[0];
        }
        double y = spectral_grid_luminance(&sky->atm.grid, L);
        job->ms_y[i] = y;
        job->ms_var[i] = variance_of_mean(yy, y, n);
        for (int c = 0; c < 2 && job->ms_ratio[0]; c++)
            node_moments_ratio(&job->ms_moments[i], 2 * c, &job->ms_ratio[c][i], &job->ms_ratio_var[c][i]);
        to_channels(&sky->atm, job->channels, L, &job->ms.values[i * job->channels]);
    }
}

/* Deep twilight's final maps aim at a noise, not only at a number of paths: once the table's first
 * pass is done, its sky nodes' relative standard error (root mean square over the nodes, every
 * node alike: the rows crowd toward the horizon, where the fit keeps raw nodes) is measured, and if
 * a second pass of at least a quarter more paths would bring it to TWILIGHT_NODE_NOISE (divided by
 * the square root of the sample scale), that pass runs, with at most TWILIGHT_EXTRA_MAX times the
 * first pass's paths (falling to none from sun -18 to -21, as twilight_path_scale falls: night).
 * Haze makes the paths noisier, and the fit gains less on them: at sun -18, 4096 paths per node,
 * 256 x 128 final, four seeds, the nodes' noise is 5.0-5.3% for the default rural sky (one map's
 * luminance 1.36%: no second pass), 6.5-7.0% for desert dust (2.24%, R / G 4.99%), 8.6-8.9% for
 * urban air at turbidity 2 (3.21%, R / G 2.93%) and at -12 7.5-8.2% (2.57%), so that the default
 * sky's noise-free criterion (one map's luminance within 2%, CIEDE2000 between two seeds below 1 on
 * average: test_twilight) was missed by the hazy skies.  With the second pass urban -18 takes
 * 12026-13014 paths per node: luminance 1.70%, R / G 1.85%, B / G 0.72% (before 1.37%), in 187 s
 * instead of 56 (2 cores).  The decision is one number for the whole table, from its 320 sky nodes,
 * which a node's own first paths hardly sway (a count per node from its own variance would be
 * biased low: a node whose first paths missed the rare bright ones would stop early); the nodes'
 * noise per path hardly changes over the sky (urban -18: 4.3-6.9 from the zenith to the horizon),
 * so a count per node would gain little. */
#define TWILIGHT_NODE_NOISE 0.05
#define TWILIGHT_EXTRA_MAX 3.0
static int may_add_twilight_paths(const render_job *job)
{
    return job->twilight && job->twilight->deep && job->params->quality == FM_QUALITY_FINAL;
}

static int twilight_extra_paths(const render_job *job, double sample_scale, double sun_elevation_deg)
{
    if (!may_add_twilight_paths(job))
        return 0;
    /* below -18 degrees (night: twilight_path_scale) the most falls to none by -21 */
    const double most = TWILIGHT_EXTRA_MAX * before_night(sun_elevation_deg);
    const int nodes = job->ms.rows_sky * job->ms.cols;
    double sum = 0.0;
    int used = 0;
    for (int i = 0; i < nodes; i++)
        if (job->ms_y[i] > 0.0) {
            sum += job->ms_var[i] / (job->ms_y[i] * job->ms_y[i]);
            used++;
        }
    if (!used)
        return 0;
    double noise = sqrt(sum / used), target = TWILIGHT_NODE_NOISE / sqrt(sample_scale);
    double more = fmin((noise / target) * (noise / target) - 1.0, most);
    /* a pass of less than a quarter more would take the noise down by less than a tenth */
    return more > 0.25 ? (int)ceil(more * job->q.ms_paths) : 0;
}

/* An azimuth (rad, from north toward east) relative to the sun's, folded into [0, pi]. */
static double relative_azimuth(const fm_sky *sky, double azimuth)
{
    double phi = fmod(azimuth - sky->params.sun_azimuth_deg * FM_DEG, 2.0 * FM_PI);
    if (phi < 0.0)
        phi += 2.0 * FM_PI;
    return phi > FM_PI ? 2.0 * FM_PI - phi : phi;
}

/* The field that a table part's shape scatters once more (next_order_shape.h): the single-scattering
 * table (order 2's shape) or, above the horizon, the fitted order-2 table (the shape of the orders
 * above), in the channel nearest the middle grid wavelength (luminance in colour). */
typedef struct shape_field {
    const render_job *job;
    const sky_grid *above; /* the table read above the horizon; the single-scattering table below */
    int channel;
} shape_field;

static double table_field(void *ctx, vec3 d)
{
    const shape_field *f = ctx;
    double elevation = asin(clamp_cosine(d.z));
    const sky_grid *g = elevation > f->job->ms.horizon_elevation ? f->above : &f->job->ss;
    return sky_grid_lookup_channel(g, elevation, relative_azimuth(f->job->sky, atan2(d.x, d.y)), f->channel);
}

/* Work item: the shape (next_order_shape.h) of one sky node of a table part, into ms_shape. */
static void part_shapes(void *ctx, int64_t begin, int64_t end, int thread)
{
    const shape_field *field = ctx;
    const render_job *job = field->job;
    const fm_sky *sky = job->sky;
    (void)thread;
    for (int64_t i = begin; i < end; i++) {
        double e, phi;
        sky_grid_node_angles(&job->ms, (int)i, &e, &phi);
        job->ms_shape[i] = next_order_shape(&sky->atm, sky->observer, view_direction(sky, e, phi), sky->sun_dir,
                                            sky->atm.grid.count / 2, table_field, (void *)field);
    }
}

/* Fits one part of the table (order 2, or the orders above it) through its shape: that of the
 * field `above` scattered once more. */
static fm_status fit_part(render_job *job, sky_grid *part, const sky_grid *above, double sun_elevation, const double *y,
                          const double *var)
{
    const int K = job->sky->atm.grid.count;
    shape_field field = {job, above, job->channels == 3 ? 1 : (job->channels == K ? K / 2 : 0)};
    fm_status s = parallel_for(job->params->threads, job->ms.rows_sky * job->ms.cols, 4, part_shapes, &field,
                               job->params->cancel, NULL);
    return s ? s : sky_grid_fit(part, sun_elevation, y, var, job->ms_shape, NULL);
}

/* The table's noise averaged over many nodes where a smooth fit is expected to be closer to the
 * truth than the nodes themselves (sky_grid_fit.h).  By day and in twilight down to deep twilight
 * (the sun 4.5 degrees down) order 2 and the orders above it are fitted apart and added: the
 * aerosols' aureole is order 2's (desert dust at sun 30, 16 times the paths: in the sky row nearest
 * the sun the 5th cosine of the azimuth is 0.29 of the row's mean in order 2, 0.03 in the orders
 * above), and each part is fitted divided by its shape
 * (next_order_shape.h: order 2's from the single-scattering table, the orders above from the fitted
 * order 2), which holds the aureole, so that SURE keeps few cosines for either.  1024 x 512 final
 * maps at sun 30, five seeds, RMS error against 16 times the samples, fitted whole / apart / order
 * 2 through its shape / both parts through theirs: clear air 0.070 / 0.064 / 0.061 / 0.055%, rural
 * 0.167 / 0.155 / 0.132 / 0.130%, desert dust 0.298 / 0.271 / 0.237 / 0.184%, urban 0.268 / 0.235 /
 * 0.233 / 0.243%; the urban sunset (sun 2, turbidity 2, three seeds) 0.688 / 0.646 / 0.657 / 0.614%.
 * Rural sky, 512 x 256 final, four seeds: at sun -2 the noise of one map's sky 0.33 -> 0.23%, at
 * -4 0.60 -> 0.42% (its bias against 16 times the samples, with their noise, 0.29 -> 0.34%).  In
 * deep twilight the table is fitted whole, its nodes divided by their own shapes
 * (twilight_node_paths); at twilight the colour then goes through its ratios to the luminance. */
static fm_status fit_table(render_job *job, double sun_elevation)
{
    fm_status s;
    if (job->ms_orders) {
        if ((s = fit_part(job, &job->ms, &job->ss, sun_elevation, job->ms_y, job->ms_var)) ||
            (s = fit_part(job, &job->ms_later, &job->ms, sun_elevation, job->ms_later_y, job->ms_later_var)))
            return s;
        for (size_t i = 0; i < (size_t)sky_grid_nodes(&job->ms) * (size_t)job->channels; i++)
            job->ms.values[i] += job->ms_later.values[i];
    } else if ((s = sky_grid_fit(&job->ms, sun_elevation, job->ms_y, job->ms_var, job->ms_shape, NULL))) {
        return s;
    }
    return job->ms_ratio[0] ? sky_grid_fit_chroma(&job->ms, sun_elevation, (const double *const *)job->ms_ratio,
                                                  (const double *const *)job->ms_ratio_var)
                            : FM_OK;
}

/* Observer on the ground: the diffuse irradiance of orders >= 2 there is the integral of the
 * multiple-scattering table's sky half times cos(zenith), since its upward nodes estimate exactly
 * that radiance (no ground between the observer and the air).  The table's paths are 40 times the
 * ground's own and spread over the whole sky: urban sunset, the spread of that irradiance over six
 * seeds 1.2 -> 0.5% at final quality, 3.4 -> 1.3% at preview (of the ground's luminance, eight
 * seeds: 0.70 -> 0.39%, 2.1 -> 0.87%); at 16 times the samples both agree with it within their noise.
 * The raw nodes, not the fit: the sum is linear in them and no fit is needed to make it smooth. */
static fm_status ground_from_table(render_job *job)
{
    const int K = job->sky->atm.grid.count, n = job->ms.rows_sky * job->ms.cols;
    double *w = malloc(sizeof(double) * (size_t)n), E[FM_MAX_WAVELENGTHS] = {0};
    if (!w)
        return FM_ERR_OUT_OF_MEMORY;
    sky_grid_irradiance_weights(&job->ms, w);
    for (int i = 0; i < n; i++)
        for (int k = 0; k < K; k++)
            E[k] += w[i] * (job->ms_sum[(size_t)i * K + k] / job->ms_paths);
    free(w);
    ground_irradiance_add(&job->ground, E);
    return FM_OK;
}

/* Footprint samples of one pixel row: elevations and weights (summing to 1) of the midpoints of
 * equal sub-intervals.  Away from the horizon the quality's count is enough.  Near it, radiance climbs
 * steeply toward the horizon and jumps to the ground, so sub-intervals are 0.2 degrees or finer and
 * the row is split exactly at the horizon elevation: each side is sampled on its own and weighted
 * by its share of the row (pixels are averages over image area, i.e. uniform in elevation). */
#define MAX_SUB_ROWS 256

static int row_samples(const render_job *job, int y, int H, double *elevation, double *weight)
{
    const double fine = 0.2 * FM_DEG, band_below = 3.0 * FM_DEG, band_above = 10.0 * FM_DEG;
    double top = FM_PI * (0.5 - (double)y / H), bottom = FM_PI * (0.5 - (double)(y + 1) / H);
    double h = job->ss.horizon_elevation;
    double cuts[3] = {top, bottom, bottom};
    int parts = 1;
    if (h < top && h > bottom) {
        cuts[1] = h;
        parts = 2;
    }
    int near = bottom < h + band_above && top > h - band_below;
    int count = 0;
    for (int p = 0; p < parts; p++) {
        double hi = cuts[p], lo = cuts[p + 1];
        int n = job->q.subpixels;
        if (near) {
            int needed = (int)ceil((hi - lo) / fine);
            if (needed > n)
                n = needed;
        }
        if (n > MAX_SUB_ROWS / parts)
            n = MAX_SUB_ROWS / parts;
        for (int j = 0; j < n; j++) {
            elevation[count] = hi - (hi - lo) * (j + 0.5) / n;
            weight[count] = (hi - lo) / (top - bottom) / n;
            count++;
        }
    }
    return count;
}

static void fast_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    fm_image *img = job->img;
    const int W = img->width, H = img->height, C = job->channels, n = job->q.subpixels;
    double elevation[MAX_SUB_ROWS], weight[MAX_SUB_ROWS];
    for (int64_t y = begin; y < end; y++) {
        const int ny = row_samples(job, (int)y, H, elevation, weight);
        for (int x = 0; x < W; x++) {
            double acc[FM_MAX_WAVELENGTHS] = {0};
            float v[FM_MAX_WAVELENGTHS];
            for (int sy = 0; sy < ny; sy++) {
                for (int sx = 0; sx < n; sx++) {
                    double e, a;
                    equirect_angles(W, H, x + (sx + 0.5) / n, (double)y, &e, &a);
                    double phi = relative_azimuth(job->sky, a), w = weight[sy] / n;
                    sky_grid_lookup(&job->ss, elevation[sy], phi, v);
                    for (int c = 0; c < C; c++)
                        acc[c] += w * v[c];
                    sky_grid_lookup(&job->ms, elevation[sy], phi, v);
                    for (int c = 0; c < C; c++)
                        acc[c] += w * v[c];
                }
            }
            float *px = &img->pixels[((size_t)y * W + x) * C];
            for (int c = 0; c < C; c++)
                px[c] = (float)acc[c];
        }
    }
}

/* Both tables' radiance toward d (footprint_radiance). */
static void table_radiance(void *ctx, vec3 d, double elevation, float *out)
{
    const render_job *job = ctx;
    double phi = relative_azimuth(job->sky, atan2(d.x, d.y));
    float ss[3], ms[3];
    sky_grid_lookup(&job->ss, elevation, phi, ss);
    sky_grid_lookup(&job->ms, elevation, phi, ms);
    for (int c = 0; c < job->channels; c++)
        out[c] = (float)((double)ss[c] + ms[c]);
}

/* The fast path through the fisheye and pinhole cameras: footprint averages of the tables with the
 * equirect rows' rule (the quality's samples per axis, fine steps near the horizon, the horizon split
 * exactly; camera/footprint.h). */
static void fast_rows_camera(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    fm_image *img = job->img;
    const int W = img->width, C = job->channels;
    footprint_settings fs = footprint_default_settings(job->q.subpixels, job->ss.horizon_elevation);
    double v[3];
    for (int64_t y = begin; y < end; y++)
        for (int x = 0; x < W; x++) {
            footprint_average(&job->cam, x, (int)y, &fs, table_radiance, job, C, v);
            float *px = &img->pixels[((size_t)y * W + x) * C];
            for (int c = 0; c < C; c++)
                px[c] = (float)v[c];
        }
}

/* One equirect pixel of the reference: N paths through uniformly jittered positions in it; the mean
 * and its standard error per channel. */
static void reference_pixel(const render_job *job, const path_context *pc, int x, int y, int N, float *mean_out,
                            float *se_out)
{
    const fm_sky *sky = job->sky;
    const int W = job->cam.width, H = job->cam.height, C = job->channels, K = sky->atm.grid.count;
    uint64_t item = ITEM_PIXEL + (uint64_t)y * W + x;
    int offset = (int)(mix64(job->seed ^ item) % (uint64_t)K);
    double sum[FM_MAX_WAVELENGTHS] = {0}, sum2[FM_MAX_WAVELENGTHS] = {0};
    for (int p = 0; p < N; p++) {
        rng r = rng_for(job->seed, item, (uint64_t)p);
        double jx = rng_uniform(&r), jy = rng_uniform(&r);
        vec3 d = equirect_direction(W, H, x + jx, y + jy);
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(pc, sky->observer, d, (p + offset) % K, &r, L);
        float v[FM_MAX_WAVELENGTHS];
        to_channels(&sky->atm, C, L, v);
        for (int c = 0; c < C; c++) {
            sum[c] += v[c];
            sum2[c] += (double)v[c] * v[c];
        }
    }
    for (int c = 0; c < C; c++) {
        double mean = sum[c] / N;
        double var = N > 1 ? fmax(0.0, (sum2[c] - N * mean * mean) / (N - 1)) : 0.0;
        mean_out[c] = (float)mean;
        se_out[c] = (float)sqrt(var / N);
    }
}

static void reference_rows(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    fm_image *img = job->img;
    const int W = img->width, C = job->channels;
    path_context pc = twilight_path_context(job->sky, job->twilight, 1, 0);
    for (int64_t y = begin; y < end; y++)
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + x) * C;
            reference_pixel(job, &pc, x, (int)y, job->q.reference_paths, &img->pixels[i], &img->std_error[i]);
        }
}

/* Reference through the fisheye and pinhole cameras: paths through uniformly jittered positions in
 * the pixel, weighted by the camera's solid angle per pixel area (the pixel's value is the
 * solid-angle mean of radiance over its footprint, as in the fast path); positions outside the
 * fisheye's circle carry no weight.  Standard error of the weighted mean from the weighted spread. */
static void reference_rows_camera(void *ctx, int64_t begin, int64_t end, int thread)
{
    render_job *job = ctx;
    const fm_sky *sky = job->sky;
    fm_image *img = job->img;
    const int W = img->width, C = job->channels, K = sky->atm.grid.count;
    const int N = job->q.reference_paths;
    path_context pc = twilight_path_context(job->sky, job->twilight, 1, 0);
    for (int64_t y = begin; y < end; y++) {
        for (int x = 0; x < W; x++) {
            uint64_t item = ITEM_PIXEL + (uint64_t)y * W + x;
            int offset = (int)(mix64(job->seed ^ item) % (uint64_t)K);
            /* sums of w v, and of w^2, w^2 v, w^2 v^2 for the spread */
            double wsum = 0.0, w2sum = 0.0, sum[FM_MAX_WAVELENGTHS] = {0}, w2v[FM_MAX_WAVELENGTHS] = {0};
            double w2v2[FM_MAX_WAVELENGTHS] = {0};
            int used = 0;
            for (int p = 0; p < N; p++) {
                rng r = rng_for(job->seed, item, (uint64_t)p);
                double jx = rng_uniform(&r), jy = rng_uniform(&r);
                vec3 d;
                double w = camera_sample(&job->cam, x + jx, y + jy, &d);
                if (!(w > 0.0))
                    continue; /* outside the fisheye's circle */
                double L[FM_MAX_WAVELENGTHS] = {0};
                path_trace(&pc, sky->observer, d, (p + offset) % K, &r, L);
                float v[FM_MAX_WAVELENGTHS];
                to_channels(&sky->atm, C, L, v);
                for (int c = 0; c < C; c++) {
                    sum[c] += w * v[c];
                    w2v[c] += w * w * v[c];
                    w2v2[c] += w * w * (double)v[c] * v[c];
                }
                wsum += w;
                w2sum += w * w;
                used++;
            }
            size_t i = ((size_t)y * W + x) * C;
            for (int c = 0; c < C; c++) {
                double mean = wsum > 0.0 ? sum[c] / wsum : 0.0;
                /* sum w^2 (v - mean)^2 / (sum w)^2, with the n / (n - 1) of the unweighted case */
                double spread = w2v2[c] - 2.0 * mean * w2v[c] + mean * mean * w2sum;
                double var = used > 1 ? fmax(0.0, spread) / (wsum * wsum) * used / (used - 1) : 0.0;
                img->pixels[i + c] = (float)mean;
                img->std_error[i + c] = (float)sqrt(var);
            }
        }
    }
}

/* The sun disk, integrated over each pixel's footprint: a regular grid of points over the disk
 * (much finer than the pixels), each carrying its limb-darkened, attenuated share of the disk's
 * irradiance into the pixel that contains it, divided by that pixel's solid angle.  The disk's
 * energy in the map is thereby exact at any resolution, and a horizon cutting the disk is resolved
 * to a fraction of a percent.  Seen from the observer, the optical depth toward a point of the disk
 * depends only on its elevation: it is tabulated across the disk first. */
#define DISK_DEPTH_SAMPLES 257

/* Angular size (rad) of the camera's pixels around direction d: the smaller of the angles spanned by
 * one pixel across and down at d's position; 0 when the camera cannot place d. */
static double pixel_angle_at(const camera *cam, vec3 d)
{
    double x, y;
    if (!camera_project(cam, d, &x, &y))
        return 0.0;
    vec3 a, b, c, e;
    camera_direction(cam, x - 0.5, y, &a);
    camera_direction(cam, x + 0.5, y, &b);
    camera_direction(cam, x, y - 0.5, &c);
    camera_direction(cam, x, y + 0.5, &e);
    return fmin(v3_length(v3_sub(a, b)), v3_length(v3_sub(c, e)));
}

/* Pixel solid angles for the disk's points: direct-mapped by pixel index, since the disk covers few
 * pixels and the fisheye's are computed by quadrature. */
#define OMEGA_CACHE 4096

typedef struct omega_cache {
    int64_t pixel[OMEGA_CACHE];
    double inv_omega[OMEGA_CACHE];
} omega_cache;

static double inverse_pixel_solid_angle(const camera *cam, omega_cache *cache, int px, int py)
{
    if (cam->type == FM_CAMERA_EQUIRECT) /* the closed form, exactly as before cameras existed */
        return 1.0 / equirect_pixel_solid_angle(cam->width, cam->height, py);
    int64_t index = (int64_t)py * cam->width + px;
    int slot = (int)(index % OMEGA_CACHE);
    if (cache->pixel[slot] != index) {
        cache->pixel[slot] = index;
        cache->inv_omega[slot] = 1.0 / camera_pixel_solid_angle(cam, px, py);
    }
    return cache->inv_omega[slot];
}

static fm_status render_sun_disk(const fm_sky *sky, const camera *cam, fm_image *img)
{
    const atmosphere *atm = &sky->atm;
    const sun_disk *sun = &sky->sun;
    const int K = atm->grid.count, W = img->width, H = img->height, C = img->channels;
    const double a = sun->angular_radius;
    /* points 8 per pixel across the disk (within 256 to 2048 across it) */
    int n;
    if (cam->type == FM_CAMERA_EQUIRECT) {
        n = (int)ceil(2.0 * a / (2.0 * FM_PI / W) * 8.0);
    } else {
        double pixel = pixel_angle_at(cam, sky->sun_dir);
        if (!(pixel > 0.0))
            return FM_OK; /* behind the camera */
        n = (int)fmin(4096.0, ceil(2.0 * a / pixel * 8.0));
    }
    n = n < 256 ? 256 : (n > 2048 ? 2048 : n);
    omega_cache *cache = NULL;
    if (cam->type != FM_CAMERA_EQUIRECT) {
        if (!(cache = malloc(sizeof *cache)))
            return FM_ERR_OUT_OF_MEMORY;
        for (int i = 0; i < OMEGA_CACHE; i++)
            cache->pixel[i] = -1;
    }

    /* optical depth (every wavelength) versus the cosine of the zenith angle across the disk */
    double robs = v3_length(sky->observer);
    double e0 = asin(clamp_cosine(sky->sun_dir.z));
    double mu_lo = sin(e0 - 1.01 * a), mu_hi = sin(fmin(e0 + 1.01 * a, 0.5 * FM_PI));
    double *depth = malloc(sizeof(double) * DISK_DEPTH_SAMPLES * (size_t)K);
    if (!depth) {
        free(cache);
        return FM_ERR_OUT_OF_MEMORY;
    }
    double col[FM_MAX_SPECIES];
    for (int i = 0; i < DISK_DEPTH_SAMPLES; i++) {
        double mu = mu_lo + (mu_hi - mu_lo) * i / (DISK_DEPTH_SAMPLES - 1);
        int blocked = ray_hits_ground(atm, robs, mu);
        if (!blocked)
            column_quadrature(atm, robs, mu, ray_distance_to_top(atm, robs, mu), col);
        for (int k = 0; k < K; k++)
            depth[i * K + k] = blocked ? INFINITY : atmosphere_optical_depth(atm, col, k);
    }

    /* limb-darkening weights per wavelength, normalised to sum to 1 over the disk's points */
    double norm[FM_MAX_WAVELENGTHS] = {0};
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i + 0.5) / n * 2.0 - 1.0, y = (j + 0.5) / n * 2.0 - 1.0, rr = x * x + y * y;
            if (rr < 1.0)
                for (int k = 0; k < K; k++)
                    norm[k] += sun_limb_darkening(sun, k, sqrt(1.0 - rr));
        }
    frame f = frame_from_normal(sky->sun_dir);
    double L[FM_MAX_WAVELENGTHS];
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i + 0.5) / n * 2.0 - 1.0, y = (j + 0.5) / n * 2.0 - 1.0, rr = x * x + y * y;
            if (rr >= 1.0)
                continue;
            vec3 d = v3_normalize(frame_to_world(&f, v3(tan(a) * x, tan(a) * y, 1.0)));
            if (ray_hits_ground(atm, robs, d.z)) /* the observer's zenith is +Z */
                continue;
            int px, py;
            if (!camera_pixel(cam, d, &px, &py))
                continue;
            double fd = (d.z - mu_lo) / (mu_hi - mu_lo) * (DISK_DEPTH_SAMPLES - 1);
            int id = (int)fd;
            id = id < 0 ? 0 : (id > DISK_DEPTH_SAMPLES - 2 ? DISK_DEPTH_SAMPLES - 2 : id);
            double td = fd - id;
            double inv_omega = inverse_pixel_solid_angle(cam, cache, px, py);
            double mu2 = sqrt(1.0 - rr);
            for (int k = 0; k < K; k++) {
                double d0 = depth[id * K + k], d1 = depth[(id + 1) * K + k];
                /* next to the horizon one sample may be blocked: use the visible neighbour */
                double dk = isinf(d0) ? d1 : (isinf(d1) ? d0 : d0 + (d1 - d0) * td);
                L[k] = atm->grid.solar_irradiance[k] * sun_limb_darkening(sun, k, mu2) / norm[k] * exp(-dk) *
                       inv_omega;
            }
            float v[FM_MAX_WAVELENGTHS];
            to_channels(atm, C, L, v);
            size_t idx = ((size_t)py * W + px) * C;
            for (int c = 0; c < C; c++)
                img->sun_disk[idx + c] += v[c];
        }
    free(depth);
    free(cache);
    size_t total = (size_t)W * H * C;
    for (size_t i = 0; i < total; i++)
        img->pixels[i] += img->sun_disk[i];
    return FM_OK;
}

static fm_status validate(const fm_render_params *p, camera *cam, fm_error *err)
{
    fm_status s;
    if ((s = param_check(err, "width", p->width)))
        return s;
    if (p->width % 2)
        return fm_fail_parameter(err, "width", "%d is odd (it must be even)", p->width);
    if ((s = camera_init(cam, &p->camera, p->width, err)))
        return s;
    if (p->spectral && p->camera.type != FM_CAMERA_EQUIRECT)
        return fm_fail_parameter(err, "spectral", "spectral maps are equirectangular only (the camera is %s)",
                                 camera_type_name(p->camera.type));
    if (p->quality < FM_QUALITY_PREVIEW || p->quality > FM_QUALITY_REFERENCE)
        return fm_fail_parameter(err, "quality", "unknown level %d", (int)p->quality);
    if ((s = param_check(err, "threads", p->threads)) || (s = param_check(err, "sample_scale", p->sample_scale)))
        return s;
    /* 0: the quality level's default */
    return p->reference_samples == 0 ? FM_OK : param_check(err, "reference_samples", p->reference_samples);
}

fm_render_params fm_render_params_default(void)
{
    return (fm_render_params){
        .width = 2048,
        .quality = FM_QUALITY_FINAL,
        .seed = 0,
        .threads = 0,
        .sun_disk = 1,
        .sample_scale = 1.0,
        .reference_samples = 0,
        .camera = {.type = FM_CAMERA_EQUIRECT,
                   .fisheye_projection = FM_FISHEYE_EQUIDISTANT,
                   .fov_deg = 90.0,
                   .look_azimuth_deg = 180.0,
                   .look_elevation_deg = 15.0,
                   .aspect = 16.0 / 9.0},
    };
}

static void report(const fm_render_params *p, double fraction, const char *stage)
{
    if (p->progress)
        p->progress(p->progress_user, fraction, stage);
}

/* The seed of a render: the wavelengths are part of it, so different wavelengths draw independent
 * random numbers. */
static uint64_t render_seed(const atmosphere *atm, uint64_t seed)
{
    for (int k = 0; k < atm->grid.count; k++)
        seed = mix64(seed ^ (uint64_t)llround(atm->grid.lambda_nm[k] * 1000.0));
    return seed;
}

/* The twilight sampling when the sun is below the observer's horizon plane (NULL otherwise, and for
 * a black sky). */
static fm_status make_twilight(const fm_sky *sky, const quality_settings *q, int threads, twilight_sampling **tw,
                               fm_error *err)
{
    int no_memory;
    *tw = twilight_sampling_create(sky, q->guide_offsets, threads, &no_memory);
    return no_memory ? fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the twilight guide") : FM_OK;
}

fm_status fm_render(const fm_sky *sky, const fm_render_params *params, fm_image **out, fm_error *err)
{
    *out = NULL;
    render_job job = {.sky = sky, .params = params};
    fm_status s = validate(params, &job.cam, err);
    if (s)
        return s;
    const atmosphere *atm = &sky->atm;
    job.q = render_quality_settings(params->quality, params->sample_scale);
    const double sun_elevation = asin(clamp_cosine(sky->sun_dir.z)); /* rad */
    job.q.ms_paths = (int)round(job.q.ms_paths * twilight_path_scale(params->quality, sun_elevation / FM_DEG));
    if (params->quality == FM_QUALITY_REFERENCE && params->reference_samples > 0)
        job.q.reference_paths = params->reference_samples;
    const int spectral = atm->grid.colour && params->spectral;
    job.channels = spectral ? atm->grid.count : (atm->grid.colour ? 3 : 1);
    job.seed = render_seed(atm, params->seed);
    const int W = job.cam.width, H = job.cam.height;
    const int equirect = job.cam.type == FM_CAMERA_EQUIRECT;
    const int reference = params->quality == FM_QUALITY_REFERENCE;
    job.img = image_create(W, H, job.channels,
                           spectral ? FM_IMAGE_SPECTRAL_GRID
                                    : (atm->grid.colour ? FM_IMAGE_XYZ : FM_IMAGE_SPECTRAL_RADIANCE),
                           params->sun_disk, reference);
    if (!job.img)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for a %d x %d image", W, H);
    job.img->camera = params->camera;
    render_record_fill(&job.img->record, sky, params);
    job.img->paths_per_node = reference ? 0 : job.q.ms_paths;
    if (spectral)
        image_set_wavelengths(job.img, atm->grid.count, atm->grid.lambda_nm, &atm->grid.xyz_weight[0][0]);
    job.img->sun_direction[0] = sky->sun_dir.x;
    job.img->sun_direction[1] = sky->sun_dir.y;
    job.img->sun_direction[2] = sky->sun_dir.z;

    double horizon = asin(horizon_mu(atm, v3_length(sky->observer))); /* elevation, <= 0 */
    twilight_sampling *twilight = NULL;
    if (v3_dot(sky->sun_dir, sky->observer) < 0.0)
        report(params, 0.0, "twilight guide");
    if ((s = make_twilight(sky, &job.q, params->threads, &twilight, err)))
        goto done;
    job.twilight = twilight;
    job.rising_segments = rising_segments(sky, twilight);
    if (reference) {
        parallel_progress pr = {params->progress, params->progress_user, "path tracing", 0.0, 0.98};
        s = parallel_for(params->threads, H, 1, equirect ? reference_rows : reference_rows_camera, &job, params->cancel,
                         &pr);
    } else {
        fit_footprint_to_pixels(&job.q, &job.cam, params);
        const quality_settings *q = &job.q;
        /* deterministic single scattering interpolates in log space; the noisy higher orders do not
         * (the logarithm of a noisy mean is biased) */
        if (sky_grid_init(&job.ss, horizon, q->ss_rows_sky, q->ss_rows_ground, q->ss_cols, job.channels, 1) ||
            sky_grid_init(&job.ms, horizon, q->ms_rows_sky, q->ms_rows_ground, q->ms_cols, job.channels, 0) ||
            !(job.ms_y = malloc((size_t)sky_grid_nodes(&job.ms) * sizeof(double))) ||
            !(job.ms_var = malloc((size_t)sky_grid_nodes(&job.ms) * sizeof(double))) ||
            !(job.ms_sum = calloc((size_t)sky_grid_nodes(&job.ms) * atm->grid.count, sizeof(double))) ||
            !(job.ms_moments = calloc((size_t)sky_grid_nodes(&job.ms), sizeof(node_moments))) ||
            !(job.ms_shape = malloc((size_t)sky_grid_nodes(&job.ms) * sizeof(double)))) {
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the radiance tables");
            goto done;
        }
        if (!job.twilight || !job.twilight->deep) {
            const size_t nodes = (size_t)sky_grid_nodes(&job.ms);
            if (sky_grid_init(&job.ms_later, horizon, q->ms_rows_sky, q->ms_rows_ground, q->ms_cols, job.channels, 0) ||
                !(job.ms_orders = calloc(nodes, sizeof(node_orders))) ||
                !(job.ms_later_sum = calloc(nodes * atm->grid.count, sizeof(double))) ||
                !(job.ms_later_y = malloc(nodes * sizeof(double))) ||
                !(job.ms_later_var = malloc(nodes * sizeof(double)))) {
                s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the radiance tables");
                goto done;
            }
            for (size_t i = 0; i < nodes; i++)
                job.ms_orders[i].later = &job.ms_later_sum[i * atm->grid.count];
        }
        for (int c = 0; c < 2 && job.twilight && job.channels == 3; c++)
            if (!(job.ms_ratio[c] = malloc((size_t)sky_grid_nodes(&job.ms) * sizeof(double))) ||
                !(job.ms_ratio_var[c] = malloc((size_t)sky_grid_nodes(&job.ms) * sizeof(double)))) {
                s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the radiance tables");
                goto done;
            }
        report(params, 0.0, "ground irradiance");
        path_context all = twilight_path_context(sky, job.twilight, 1, 0);
        /* The ground's diffuse light: every segment's sunlight along its length (sunlit_segment.h),
         * not at one point.  With a low sun behind thick haze the light comes from the few
         * vertices above the haze: urban sunset (sun 2, turbidity 2), the ground's bias against the
         * reference mode +1.6% (mean z 0.71) -> +0.4% (0.03), for 12% more time there; noon
         * unchanged. */
        all.segment_sunlight = SEGMENT_SUNLIGHT_ALL;
        double r_obs = v3_length(sky->observer);
        double visible = acos(fmin(1.0, atm->bottom_radius_m / r_obs)); /* ground seen up to the horizon */
        ground_quadrature gq = {q->ground_rows, q->ground_cols, q->ss_points};
        double theta_s = acos(clamp_cosine(sky->sun_dir.z));
        const int on_ground = ground_irradiance_angle_count(theta_s, visible) == 1;
        s = ground_irradiance_build(&job.ground, &all, theta_s, visible, gq, on_ground ? 0 : q->ground_paths, job.seed,
                                    params->threads, params->cancel);
        if (s == FM_ERR_OUT_OF_MEMORY) {
            s = fm_fail(err, s, "out of memory for the ground irradiance");
            goto done;
        }
        parallel_progress pms = {params->progress, params->progress_user, "multiple scattering", 0.05, 0.75};
        parallel_progress pss = {params->progress, params->progress_user, "single scattering", 0.80, 0.10};
        parallel_progress ppx = {params->progress, params->progress_user, "pixels", 0.9, 0.08};
        /* the multiple-scattering table first: on the ground it completes the ground's irradiance,
         * which the single-scattering table's downward rows reflect; where more paths may follow
         * (twilight_extra_paths) the first pass reports half the stage */
        parallel_progress first = pms, more = pms;
        if (may_add_twilight_paths(&job)) {
            first.span = more.span = pms.span / 2.0;
            more.start = pms.start + first.span;
            more.stage = "multiple scattering (more paths)";
        }
        job.ms_pass_paths = q->ms_paths;
        if (!s)
            s = parallel_for(params->threads, sky_grid_nodes(&job.ms), 1, ms_nodes, &job, params->cancel, &first);
        if (!s)
            ms_finish(&job, q->ms_paths);
        int extra = s ? 0 : twilight_extra_paths(&job, params->sample_scale, sun_elevation / FM_DEG);
        if (extra) {
            job.ms_pass = 1;
            job.ms_pass_paths = extra;
            s = parallel_for(params->threads, sky_grid_nodes(&job.ms), 1, ms_nodes, &job, params->cancel, &more);
            if (!s)
                ms_finish(&job, q->ms_paths + extra);
            job.img->paths_per_node = q->ms_paths + extra;
        }
        if (!s && on_ground)
            s = ground_from_table(&job);
        if (!s && !(s = parallel_for(params->threads, job.ss.rows_sky + job.ss.rows_ground, 1, ss_rows, &job,
                                     params->cancel, &pss)) &&
            atomic_load(&job.no_memory))
            s = FM_ERR_OUT_OF_MEMORY;
        if (!s && !(s = fit_table(&job, sun_elevation))) {
            sky_grid_average_poles(&job.ms);
            s = parallel_for(params->threads, H, 4, equirect ? fast_rows : fast_rows_camera, &job, params->cancel, &ppx);
        }
    }
    if (s == FM_ERR_CANCELLED) {
        s = fm_fail(err, FM_ERR_CANCELLED, "render cancelled");
        goto done;
    }
    if (s) {
        s = fm_fail(err, s, "render failed: %s", fm_status_name(s));
        goto done;
    }
    if (params->sun_disk) {
        report(params, 0.98, "sun disk");
        if (render_sun_disk(sky, &job.cam, job.img)) {
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the sun disk");
            goto done;
        }
    }
    report(params, 1.0, "done");
done:
    free(twilight);
    sky_grid_free(&job.ss);
    sky_grid_free(&job.ms);
    free(job.ms_y);
    free(job.ms_var);
    free(job.ms_sum);
    free(job.ms_moments);
    free(job.ms_shape);
    sky_grid_free(&job.ms_later);
    free(job.ms_orders);
    free(job.ms_later_sum);
    free(job.ms_later_y);
    free(job.ms_later_var);
    for (int c = 0; c < 2; c++) {
        free(job.ms_ratio[c]);
        free(job.ms_ratio_var[c]);
    }
    ground_irradiance_free(&job.ground);
    if (s) {
        fm_image_destroy(job.img);
        return s;
    }
    *out = job.img;
    return FM_OK;
}

typedef struct pixels_job {
    render_job job;
    const int *x, *y;
    float *out, *se;
} pixels_job;

static void reference_pixels(void *ctx, int64_t begin, int64_t end, int thread)
{
    pixels_job *pj = ctx;
    const int C = pj->job.channels;
    path_context pc = twilight_path_context(pj->job.sky, pj->job.twilight, 1, 0);
    float se[FM_MAX_WAVELENGTHS];
    for (int64_t i = begin; i < end; i++)
        reference_pixel(&pj->job, &pc, pj->x[i], pj->y[i], pj->job.q.reference_paths, &pj->out[i * C],
                        pj->se ? &pj->se[i * C] : se);
}

fm_status fm_render_pixels(const fm_sky *sky, const fm_render_params *params, int count, const int *x, const int *y,
                           float *out, float *se, fm_error *err)
{
    pixels_job pj = {.job = {.sky = sky, .params = params}, .x = x, .y = y, .out = out, .se = se};
    render_job *job = &pj.job;
    fm_status s = validate(params, &job->cam, err);
    if (s)
        return s;
    if (job->cam.type != FM_CAMERA_EQUIRECT || params->spectral)
        return fm_fail_parameter(err, "camera", "reference pixels are of the equirect map (no spectral channels)");
    if (count < 0)
        return fm_fail_parameter(err, "count", "%d pixels", count);
    for (int i = 0; i < count; i++)
        if (x[i] < 0 || x[i] >= job->cam.width || y[i] < 0 || y[i] >= job->cam.height)
            return fm_fail_parameter(err, "pixels", "(%d, %d) is outside the %d x %d map", x[i], y[i], job->cam.width,
                                     job->cam.height);
    const atmosphere *atm = &sky->atm;
    job->q = render_quality_settings(FM_QUALITY_REFERENCE, params->sample_scale);
    if (params->reference_samples > 0)
        job->q.reference_paths = params->reference_samples;
    job->channels = atm->grid.colour ? 3 : 1;
    job->seed = render_seed(atm, params->seed);
    twilight_sampling *twilight = NULL;
    if ((s = make_twilight(sky, &job->q, params->threads, &twilight, err)))
        return s;
    job->twilight = twilight;
    parallel_progress pr = {params->progress, params->progress_user, "path tracing", 0.0, 1.0};
    s = parallel_for(params->threads, count, 1, reference_pixels, &pj, params->cancel, &pr);
    free(twilight);
    if (s == FM_ERR_CANCELLED)
        return fm_fail(err, FM_ERR_CANCELLED, "render cancelled");
    return s ? fm_fail(err, s, "render failed: %s", fm_status_name(s)) : FM_OK;
}
