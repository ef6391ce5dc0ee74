/* Quality levels: the sample counts and table sizes of a render, and how they follow the sun into
 * deep twilight and the pixels' size. */
#ifndef FM_RENDER_QUALITY_H
#define FM_RENDER_QUALITY_H

#include "camera/camera.h"
#include "firmament/firmament.h"

typedef struct quality_settings {
    int ss_rows_sky, ss_rows_ground, ss_cols; /* single-scattering table */
    int ms_rows_sky, ms_rows_ground, ms_cols; /* multiple-scattering table */
    int ms_paths;                             /* paths per multiple-scattering node */
    int ground_paths;                         /* paths per diffuse ground irradiance angle */
    int subpixels;                            /* footprint samples per pixel and axis */
    int reference_paths;                      /* reference: paths per pixel */
    int ss_points;                            /* single-scattering quadrature points per piece */
    int ground_rows, ground_cols;             /* the ground irradiance's order-1 quadrature */
    int guide_offsets;                        /* deep twilight: the sky guide's offsets toward the sun */
    double deep_vertex_split_weight;          /* deep twilight: path_context.vertex_split_weight */
    int deck_photons;                         /* under a deck: photons per sun angle and wavelength (deck_base.h) */
} quality_settings;

/* The settings of a quality level, with every sample count scaled by `scale`. */
quality_settings render_quality_settings(fm_quality quality, double scale);

/* The settings of a level for the tables of a sun elevation: scaled, with deep twilight's paths. */
quality_settings render_quality_at(fm_quality quality, double scale, double sun_elevation_deg);

/* The settings of a render: its level's, scaled by the render's sample scale, with the paths per
 * multiple-scattering node of deep twilight, the reference's paths per pixel when given and the
 * footprint samples the camera's pixels need. */
quality_settings render_quality_for(const fm_render_params *p, const camera *cam, double sun_elevation_deg);

/* Footprint samples per pixel and axis no denser than the tables need (never more than q's). */
void render_quality_fit_footprint(quality_settings *q, const camera *cam, const fm_render_params *p);

/* The share of deep twilight's extra effort still spent at a sun elevation: 1 down to sun -18
 * degrees, 0 from -21 (night: the scattered sunlight fainter than the night sky's own light, which
 * is not modelled), linear in between. */
double paths_before_night(double sun_elevation_deg);

#endif
