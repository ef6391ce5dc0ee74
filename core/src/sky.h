/* The internal state behind fm_sky: everything that depends on the sky parameters but not on the
 * image, built once and shared read-only by all render threads. */
#ifndef FM_SKY_H
#define FM_SKY_H

#include "aerosol/biome.h"
#include "atmosphere/atmosphere.h"
#include "atmosphere/optical_depth.h"
#include "atmosphere/sun_irradiance.h"
#include "base/vec.h"
#include "firmament/firmament.h"
#include "sun/sun_disk.h"

#include <math.h>

struct fm_sky {
    fm_sky_params params;
    atmosphere atm;
    sun_disk sun;
    column_table columns;
    depth_table mid_depth; /* the optical depth at the grid's middle wavelength (shadow_flight.c) */
    sun_irradiance sun_table;
    vec3 sun_dir;      /* toward the sun's centre; at the observer the Earth-centred frame is the map frame */
    vec3 observer;     /* Earth-centred position (0, 0, R + altitude) */
    fm_composition composition;
    /* The sun from the date, time and place (sky_sun.c), when the sky has a time of day. */
    int has_solar;
    unsigned sun_computed; /* FM_SUN_COMPUTED_* bits: which sun parameters came from `solar` (the
                            * distance: from the date, also without a time); FM_SUN_MEAN_DISTANCE */
    fm_solar_position solar;
    /* Under a deck the sun does not pierce (a layer of optical depth SKY_TRUNCATE_TAU or more at 550
     * nm), the same sky with those layers' forward peaks truncated (delta-M, cloud_layer.h), built
     * with it: the fast path's multiple-scattering paths (orders >= 2, and the ground's diffuse light)
     * trace its media, seen with this sky's sun (scattering_path_context, twilight.h), while single
     * scattering, the sun's disk and direct light and the reference mode keep the full phase function
     * (delta-M with exact single scattering: Nakajima & Tanaka 1988).  NULL otherwise. */
    struct fm_sky *truncated;
    int truncate_peaks; /* this sky is such a copy; its column table is its parent's (api.c) */
    int skip_cloud;     /* 1 + the index of the cloud layer (composition.cloud) this sky leaves out, or 0 */
};

/* Layers from this optical depth at 550 nm up are truncated in the copy: with the droplets' peak
 * fraction below 0.45, even the truncated layer's vertical transmittance stays below e^-13.8 = 1e-6,
 * where the add-on turns the sun lamp off, so the light the copy counts as unscattered is nil. */
#define SKY_TRUNCATE_TAU 25.0

/* Cloud layer i's (composition.cloud) mean extinction at 550 nm, per m: its optical depth over its
 * thickness; INFINITY for a layer of no thickness (never thin).  What counts as a cloud for the guides
 * (sky_path.c) and the thin layer deep twilight aims over (twilight.c) both read it. */
static inline double sky_cloud_sigma550_per_m(const struct fm_sky *sky, int i)
{
    const double h = sky->composition.cloud[i].thickness_m;
    return h > 0.0 ? sky->composition.cloud[i].tau550 / h : INFINITY;
}

/* The sky whose media the fast path's multiple scattering traces (above). */
static inline const struct fm_sky *sky_scattering_media(const struct fm_sky *sky)
{
    return sky->truncated ? sky->truncated : sky;
}

/* The same sky without its cloud layer `cloud` (an index of composition.cloud), the observer at
 * altitude_m, the same sun (the fog column's incident field in twilight, render/fog_table.c).  Free
 * with fm_sky_destroy. */
fm_status sky_create_without_cloud(const struct fm_sky *sky, int cloud, double altitude_m, struct fm_sky **out,
                                   fm_error *err);
/* Resolves the FM_SUN_FROM_TIME fields of `in` into `out` (a copy of in) from the solar position
 * of its date, time and place, which also goes to *solar, *computed and *has_solar (the distance
 * from the date alone, or 1 AU without a date: *has_solar 0). */
fm_status sky_resolve_sun(const fm_sky_params *in, fm_sky_params *out, fm_solar_position *solar,
                          unsigned *computed, int *has_solar, fm_error *err);

#endif
