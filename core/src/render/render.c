#include "render/render.h"

#include "atmosphere/optical_depth.h"
#include "base/param_range.h"
#include "base/rng.h"
#include "base/status.h"
#include "base/threads.h"
#include "base/units.h"
#include "camera/equirect.h"
#include "camera/footprint.h"
#include "image/image.h"
#include "render/fog_table.h"
#include "render/ms_table.h"
#include "render/record.h"
#include "render/reference.h"
#include "render/render_job.h"
#include "render/sun_disk_raster.h"
#include "transport/ground_irradiance_build.h"
#include "transport/single_scatter.h"

#include <assert.h>
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

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
        if (single_scatter_ray_init(&ray, &pc, sky->observer, render_view_direction(sky, e, phi), job->q.ss_points)) {
            atomic_store(&job->no_memory, 1);
            return;
        }
        for (int col = 0; col < cols; col++) {
            int i = (int)row * cols + col;
            double L[FM_MAX_WAVELENGTHS] = {0};
            sky_grid_node_angles(&job->ss, i, &e, &phi);
            single_scatter_ray_radiance(&ray, &pc, render_view_direction(sky, e, phi), L);
            float v[FM_MAX_WAVELENGTHS];
            render_channels(&sky->atm, job->channels, L, v);
            for (int c = 0; c < job->channels; c++)
                sky_grid_set(&job->ss, i, c, v[c]);
        }
        single_scatter_ray_free(&ray);
    }
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
                    double phi = render_relative_azimuth(job->sky, a), w = weight[sy] / n;
                    sky_grid_lookup(&job->ss, elevation[sy], phi, v);
                    if (job->aureole)
                        aureole_blend(job->aureole, &job->aureole_frame, elevation[sy], phi, job->ss.horizon_elevation, v);
                    for (int c = 0; c < C; c++)
                        acc[c] += w * v[c];
                    sky_grid_lookup(job->ms_grid, elevation[sy], phi, v);
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
    double phi = render_relative_azimuth(job->sky, atan2(d.x, d.y));
    float ss[3], ms[3];
    sky_grid_lookup(&job->ss, elevation, phi, ss);
    if (job->aureole)
        aureole_blend(job->aureole, &job->aureole_frame, elevation, phi, job->ss.horizon_elevation, ss);
    sky_grid_lookup(job->ms_grid, elevation, phi, ms);
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
static fm_status make_twilight(const fm_sky *sky, const quality_settings *q, const fm_render_params *params,
                               const shadow_flight_columns *shared, twilight_sampling **tw, fm_error *err)
{
    fm_status s = twilight_sampling_create(sky, q->guide_offsets, shared, params->threads, params->cancel, tw);
    if (!s && *tw)
        (*tw)->vertex_split_weight = q->deep_vertex_split_weight;
    if (s == FM_ERR_CANCELLED || (params->cancel && atomic_load(params->cancel)))
        return fm_fail(err, FM_ERR_CANCELLED, "render cancelled");
    return s ? fm_fail(err, s, "the twilight guide: %s", fm_status_name(s)) : FM_OK;
}

/* The render's failure as one line: cancelled, or the stage's status. */
static fm_status render_failed(fm_status s, fm_error *err)
{
    return s == FM_ERR_CANCELLED ? fm_fail(err, s, "render cancelled")
                                 : fm_fail(err, s, "render failed: %s", fm_status_name(s));
}

/* The image the render fills, its record and what it says of the render. */
static fm_status create_image(render_job *job, fm_error *err)
{
    const fm_sky *sky = job->sky;
    const fm_render_params *params = job->params;
    const atmosphere *atm = &sky->atm;
    const int spectral = atm->grid.colour && params->spectral;
    const int reference = params->quality == FM_QUALITY_REFERENCE;
    job->channels = spectral ? atm->grid.count : (atm->grid.colour ? 3 : 1);
    job->img = image_create(job->cam.width, job->cam.height, job->channels,
                            spectral ? FM_IMAGE_SPECTRAL_GRID
                                     : (atm->grid.colour ? FM_IMAGE_XYZ : FM_IMAGE_SPECTRAL_RADIANCE),
                            params->sun_disk, reference);
    if (!job->img)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for a %d x %d image", job->cam.width,
                       job->cam.height);
    job->img->camera = params->camera;
    render_record_fill(&job->img->record, sky, params);
    job->img->paths_per_node = reference ? 0 : job->q.ms_paths;
    if (spectral)
        image_set_wavelengths(job->img, atm->grid.count, atm->grid.lambda_nm, &atm->grid.xyz_weight[0][0]);
    job->img->sun_direction[0] = sky->sun_dir.x;
    job->img->sun_direction[1] = sky->sun_dir.y;
    job->img->sun_direction[2] = sky->sun_dir.z;
    return FM_OK;
}

/* The ground seen from the observer (rad: the arc up to its horizon) and the sun's zenith angle;
 * returns whether the ground's irradiance takes orders >= 2 from the table (an observer on it). */
static int ground_from_table(const fm_sky *sky, double *visible, double *theta_s)
{
    double r_obs = v3_length(sky->observer);
    *visible = acos(fmin(1.0, sky->atm.bottom_radius_m / r_obs)); /* ground seen up to the horizon */
    *theta_s = acos(clamp_cosine(sky->sun_dir.z));
    assert(r_obs >= sky->atm.bottom_radius_m && r_obs < sky->atm.top_radius_m);
    assert(*visible >= 0.0 && *visible <= 0.5 * FM_PI && *theta_s >= 0.0 && *theta_s <= FM_PI);
    return ground_irradiance_angle_count(*theta_s, *visible) == 1;
}

/* The diffuse ground irradiance (ground_irradiance.h), with every segment's sunlight along its
 * length (sunlit_segment.h), not at one point: with a low sun behind thick haze the ground's light
 * comes from the few vertices above the haze (docs/decisions/2026-12-06-ground-segment-sunlight.md).
 * An observer on the ground gets orders >= 2 from the multiple-scattering table instead
 * (from_table; ms_table_add_to_ground). */
static fm_status build_ground(render_job *job, int from_table)
{
    const fm_sky *sky = job->sky;
    const quality_settings *q = &job->q;
    path_context all = scattering_path_context(sky, job->twilight, 1, 0);
    all.segment_sunlight = SEGMENT_SUNLIGHT_ALL;
    all.deck = job->under_deck;
    double visible, theta_s;
    ground_from_table(sky, &visible, &theta_s);
    ground_quadrature gq = {q->ground_rows, q->ground_cols, q->ss_points};
    return ground_irradiance_build(&job->ground, &all, theta_s, visible, gq, from_table ? 0 : q->ground_paths,
                                   job->seed, job->params->threads, job->params->cancel);
}

/* Under a deck, the multiple-scattering table takes 1 / DECK_PATH_SHARE of its paths: the light
 * from the deck's base reaches each node the same for all its paths (table_node_paths), and the
 * paths add what the thin air below the base scatters (docs/decisions/2026-12-06-deck-base.md). */
#define DECK_PATH_SHARE 4

fm_status render_fast_tables_begin(render_job *job, fm_error *err)
{
    const fm_render_params *params = job->params;
    const quality_settings *q = &job->q;
    const double horizon = asin(horizon_mu(&job->sky->atm, v3_length(job->sky->observer))); /* elevation, <= 0 */
    report(params, 0.0, "ground irradiance");
    int deck_built;
    fm_status s = deck_base_for_sky(&job->deck, job->sky, q->deck_photons, job->seed, params->threads, params->cancel,
                                    &deck_built);
    job->under_deck = deck_built ? &job->deck : NULL;
    if (deck_built) /* the paths carry only what the air below the base scatters: the rest is the base's */
        job->q.ms_paths = (job->q.ms_paths + DECK_PATH_SHARE - 1) / DECK_PATH_SHARE;
    double visible, theta_s;
    const int on_ground = ground_from_table(job->sky, &visible, &theta_s);
    const int fog = !s && fog_table_applies(job); /* the table from the column, no fit */
    quality_settings table_q = *q;
    if (fog && job->fine_fog_table)
        fog_table_size(&table_q);
    /* deterministic single scattering interpolates in log space */
    if (sky_grid_init(&job->ss, horizon, q->ss_rows_sky, q->ss_rows_ground, q->ss_cols, job->channels, 1) ||
        ms_table_init(job->ms, &table_q, horizon, job->channels, job->sky->atm.grid.count,
                      ms_table_parted(job->twilight), job->twilight && job->channels == 3))
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the radiance tables");
    if (!s) /* on the ground or in fog, orders >= 2 come from the table */
        s = build_ground(job, on_ground || fog);
    if (s == FM_ERR_OUT_OF_MEMORY)
        return fm_fail(err, s, "out of memory for the ground irradiance");
    return s ? render_failed(s, err) : FM_OK;
}

/* The fast tables of the sky above fog (fog_incident.h): its twilight sampling, then its tables. */
static fm_status sky_above_fog_tables(render_job *job, twilight_sampling **tw)
{
    fm_error err;
    fm_status s = render_twilight(job, tw, &err);
    job->twilight = *tw;
    return s ? s : render_fast_tables(job, asin(clamp_cosine(job->sky->sun_dir.z)), &err);
}

fm_status render_fast_tables_fill(render_job *job, double sun_elevation, fm_error *err)
{
    fm_status s = fog_table_applies(job) ? fog_table_fill(job, sky_above_fog_tables)
                                         : ms_table_fill(job, sun_elevation / FM_DEG);
    return s ? render_failed(s, err) : FM_OK;
}

int render_fast_tables_shareable(const render_job *job)
{
    return !fog_table_applies(job) && ms_table_walk_shareable(job);
}

fm_status render_fast_tables_fill_shared(render_job *const *jobs, int count, fm_error *err)
{
    fm_status s = ms_table_fill_shared(jobs, count);
    return s ? render_failed(s, err) : FM_OK;
}

fm_status render_fast_tables_end(render_job *job, double sun_elevation, fm_error *err)
{
    const fm_render_params *params = job->params;
    double visible, theta_s;
    const int on_ground = ground_from_table(job->sky, &visible, &theta_s), fog = fog_table_applies(job);
    parallel_progress pss = {params->progress, params->progress_user, "single scattering", 0.80, 0.10};
    fm_status s;
    if ((on_ground && (s = ms_table_add_to_ground(job))) ||
        (s = parallel_for(params->threads, job->ss.rows_sky + job->ss.rows_ground, 1, ss_rows, job, params->cancel,
                          &pss)) ||
        (s = atomic_load(&job->no_memory) ? FM_ERR_OUT_OF_MEMORY : FM_OK) ||
        (!fog && (s = ms_table_fit(job, sun_elevation))))
        return render_failed(s, err);
    if (fog)
        fog_table_add_peak(job);
    sky_grid_average_poles(&job->ms->grid);
    return FM_OK;
}

fm_status render_fast_tables(render_job *job, double sun_elevation, fm_error *err)
{
    fm_status s;
    if ((s = render_fast_tables_begin(job, err)) || (s = render_fast_tables_fill(job, sun_elevation, err)))
        return s;
    return render_fast_tables_end(job, sun_elevation, err);
}

fm_status render_fast_pixels(render_job *job, const sky_grid *ms, fm_error *err)
{
    const fm_render_params *params = job->params;
    parallel_progress ppx = {params->progress, params->progress_user, "pixels", 0.9, 0.08};
    job->ms_grid = ms;
    fm_status s = parallel_for(params->threads, job->img->height, 4,
                               job->cam.type == FM_CAMERA_EQUIRECT ? fast_rows : fast_rows_camera, job,
                               params->cancel, &ppx);
    return s ? render_failed(s, err) : FM_OK;
}

static fm_status render_reference(render_job *job, fm_error *err)
{
    const fm_render_params *params = job->params;
    parallel_progress pr = {params->progress, params->progress_user, "path tracing", 0.0, 0.98};
    fm_status s = parallel_for(params->threads, job->img->height, 1,
                               job->cam.type == FM_CAMERA_EQUIRECT ? reference_rows : reference_rows_camera, job,
                               params->cancel, &pr);
    return s ? render_failed(s, err) : FM_OK;
}

fm_status render_start(render_job *job, fm_error *err)
{
    fm_status s = validate(job->params, &job->cam, err);
    if (s)
        return s;
    const double sun_elevation = asin(clamp_cosine(job->sky->sun_dir.z)); /* rad */
    job->q = render_quality_for(job->params, &job->cam, sun_elevation / FM_DEG);
    job->seed = render_seed(&job->sky->atm, job->params->seed);
    return create_image(job, err);
}

fm_status render_twilight(render_job *job, twilight_sampling **tw, fm_error *err)
{
    *tw = NULL;
    if (v3_dot(job->sky->sun_dir, job->sky->observer) < 0.0)
        report(job->params, 0.0, "twilight guide");
    return make_twilight(job->sky, &job->q, job->params, job->shared_flights, tw, err);
}

fm_status render_finish(render_job *job, fm_status s, fm_image **out, fm_error *err)
{
    if (!s && job->params->sun_disk) {
        report(job->params, 0.98, "sun disk");
        if (sun_disk_rasterise(job->sky, &job->cam, job->img))
            s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the sun disk");
    }
    if (s) {
        fm_image_destroy(job->img);
        job->img = NULL;
        return s;
    }
    report(job->params, 1.0, "done");
    *out = job->img;
    return FM_OK;
}

fm_status fm_render(const fm_sky *sky, const fm_render_params *params, fm_image **out, fm_error *err)
{
    *out = NULL;
    ms_table ms = {0};
    render_job job = {.sky = sky, .params = params, .ms = &ms, .fine_fog_table = 1, .fog_from_above = 1};
    fm_status s = render_start(&job, err);
    if (s)
        return s;
    twilight_sampling *twilight = NULL;
    if (!(s = render_twilight(&job, &twilight, err))) {
        job.twilight = twilight;
        if (params->quality == FM_QUALITY_REFERENCE)
            s = render_reference(&job, err);
        else if (!(s = render_fast_tables(&job, asin(clamp_cosine(sky->sun_dir.z)), err))) {
            job.img->paths_per_node = job.paths_per_node;
            s = render_fast_pixels(&job, &ms.grid, err);
        }
    }
    free(twilight);
    render_tables_free(&job);
    return render_finish(&job, s, out, err);
}

void render_tables_free(render_job *job)
{
    sky_grid_free(&job->ss);
    if (job->ms)
        ms_table_free(job->ms);
    ground_irradiance_free(&job->ground);
    deck_base_free(&job->deck);
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
    if ((s = make_twilight(sky, &job->q, params, NULL, &twilight, err)))
        return s;
    job->twilight = twilight;
    parallel_progress pr = {params->progress, params->progress_user, "path tracing", 0.0, 1.0};
    s = parallel_for(params->threads, count, 1, reference_pixels, &pj, params->cancel, &pr);
    free(twilight);
    if (s == FM_ERR_CANCELLED)
        return fm_fail(err, FM_ERR_CANCELLED, "render cancelled");
    return s ? fm_fail(err, s, "render failed: %s", fm_status_name(s)) : FM_OK;
}
