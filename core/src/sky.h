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
    unsigned sun_computed; /* FM_SUN_COMPUTED_* bits: which sun parameters came from `solar` */
    fm_solar_position solar;
};

/* Resolves the FM_SUN_FROM_TIME fields of `in` into `out` (a copy of in) from the solar position
 * of its date, time and place, which also goes to *solar, *computed and *has_solar. */
fm_status sky_resolve_sun(const fm_sky_params *in, fm_sky_params *out, fm_solar_position *solar,
                          unsigned *computed, int *has_solar, fm_error *err);

#endif
