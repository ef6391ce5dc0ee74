#include "render/quality.h"

#include "base/units.h"
#include "transport/sky_guide.h"

#include <assert.h>
#include <math.h>

/* The preview's (and so the live sky's) deep twilight paths split at a vertex past this weight x lift
 * (path.c); the final quality keeps path.c's SPLIT_WEIGHT. */
#define PREVIEW_VERTEX_SPLIT_WEIGHT 10.0

quality_settings render_quality_settings(fm_quality quality, double scale)
{
    quality_settings q;
    switch (quality) {
    case FM_QUALITY_PREVIEW:
        q = (quality_settings){
            .ss_rows_sky = 64, .ss_rows_ground = 32, .ss_cols = 48,
            .ms_rows_sky = 12, .ms_rows_ground = 8, .ms_cols = 12, .ms_paths = 512,
            .ground_paths = 4096, .ground_rows = 24, .ground_cols = 32,
            .subpixels = 2, .reference_paths = 64, .ss_points = 3,
            .guide_offsets = 1, /* the offsets' tables would be a third of a preview's time */
            /* fewer copies in haze: less noise per CPU second (docs/decisions/2026-12-07-deep-split-in-haze.md) */
            .deep_vertex_split_weight = PREVIEW_VERTEX_SPLIT_WEIGHT,
            .deck_photons = 4096,
        };
        break;
    case FM_QUALITY_REFERENCE:
    case FM_QUALITY_FINAL:
    default:
        q = (quality_settings){
            .ss_rows_sky = 128, .ss_rows_ground = 64, .ss_cols = 96,
            .ms_rows_sky = 20, .ms_rows_ground = 12, .ms_cols = 16, .ms_paths = 2048,
            .ground_paths = 16384, .ground_rows = 32, .ground_cols = 32,
            .subpixels = 3, .reference_paths = 256, .ss_points = 3,
            .guide_offsets = SKY_GUIDE_MAX_OFFSETS,
            .deep_vertex_split_weight = 0.0, /* path.c's */
            .deck_photons = 32768,
        };
        break;
    }
    q.ms_paths = (int)fmax(1.0, round(q.ms_paths * scale));
    q.ground_paths = (int)fmax(1.0, round(q.ground_paths * scale));
    q.deck_photons = (int)fmax(1.0, round(q.deck_photons * scale));
    q.reference_paths = (int)fmax(1.0, round(q.reference_paths * scale));
    return q;
}

/* Deep twilight's final maps take more paths per multiple-scattering node as the sun sinks, from 1
 * time at sun -11 degrees to 2 times at -18 (linear in between), since each path finds less of the
 * sky's light; back to 1 by -21 (paths_before_night).  The preview keeps its paths: it is there to
 * be quick.  docs/decisions/2026-12-06-twilight-sampling.md */
#define MORE_PATHS_FROM_DEG -11.0
#define MORE_PATHS_FULL_DEG -18.0
#define MORE_PATHS_UNTIL_DEG -21.0
#define MORE_PATHS_MAX 2.0

double paths_before_night(double sun_elevation_deg)
{
    const double e = sun_elevation_deg;
    return e >= MORE_PATHS_FULL_DEG   ? 1.0
           : e <= MORE_PATHS_UNTIL_DEG ? 0.0
                                       : (e - MORE_PATHS_UNTIL_DEG) / (MORE_PATHS_FULL_DEG - MORE_PATHS_UNTIL_DEG);
}

static double deep_twilight_path_scale(fm_quality quality, double sun_elevation_deg)
{
    const double e = sun_elevation_deg;
    if (quality != FM_QUALITY_FINAL || !(e < MORE_PATHS_FROM_DEG && e > MORE_PATHS_UNTIL_DEG))
        return 1.0;
    double f = e > MORE_PATHS_FULL_DEG ? (MORE_PATHS_FROM_DEG - e) / (MORE_PATHS_FROM_DEG - MORE_PATHS_FULL_DEG)
                                       : paths_before_night(e);
    assert(f >= 0.0 && f <= 1.0);
    return 1.0 + (MORE_PATHS_MAX - 1.0) * f;
}

/* Footprint samples per pixel and axis no denser than the tables need: three per node spacing of
 * the single-scattering table across a pixel follow the tables' bilinear pieces, so a wide map's
 * small pixels need fewer than the quality's count (never more; rows at the horizon are sampled
 * finer anyway, render.c's row_samples). */
void render_quality_fit_footprint(quality_settings *q, const camera *cam, const fm_render_params *p)
{
    double pixel = cam->type == FM_CAMERA_EQUIRECT ? 2.0 * FM_PI / cam->width
                   : cam->type == FM_CAMERA_FISHEYE ? FM_PI / cam->width
                                                    : p->camera.fov_deg * FM_DEG / cam->width;
    double spacing = FM_PI / (q->ss_cols - 1);
    int n = (int)ceil(3.0 * pixel / spacing);
    q->subpixels = n < 1 ? 1 : (n < q->subpixels ? n : q->subpixels);
}

quality_settings render_quality_at(fm_quality quality, double scale, double sun_elevation_deg)
{
    quality_settings q = render_quality_settings(quality, scale);
    q.ms_paths = (int)round(q.ms_paths * deep_twilight_path_scale(quality, sun_elevation_deg));
    return q;
}

quality_settings render_quality_for(const fm_render_params *p, const camera *cam, double sun_elevation_deg)
{
    quality_settings q = render_quality_at(p->quality, p->sample_scale, sun_elevation_deg);
    if (p->quality == FM_QUALITY_REFERENCE && p->reference_samples > 0)
        q.reference_paths = p->reference_samples;
    if (p->quality != FM_QUALITY_REFERENCE)
        render_quality_fit_footprint(&q, cam, p);
    return q;
}
