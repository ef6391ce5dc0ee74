#include "render/record.h"

#include <stdio.h>
#include <string.h>

void render_record_fill(fm_render_record *r, const fm_sky *sky, const fm_render_params *params)
{
    memset(r, 0, sizeof *r);
    r->rendered = 1;
    r->sky = *fm_sky_get_params(sky);
    if (r->sky.atmosphere_file)
        snprintf(r->atmosphere_file, sizeof r->atmosphere_file, "%s", r->sky.atmosphere_file);
    /* the image may outlive the strings the parameters point to */
    r->sky.atmosphere_file = r->sky.biome = r->sky.presets_dir = r->sky.clouds = r->sky.cache_dir = NULL;
    fm_sky_composition(sky, &r->composition);
    fm_sky_sun_light(sky, &r->sun);
    r->has_solar = fm_sky_solar_position(sky, &r->solar, &r->sun_computed);
    r->quality = params->quality;
    r->seed = params->seed;
    r->sample_scale = params->sample_scale;
    r->threads = params->threads;
}
