/* The live sky: built once per atmosphere, a map per sun (firmament.h, "The live sky"). */
#include "render/live.h"

#include "base/hash.h"
#include "base/platform.h"
#include "base/status.h"
#include "sky.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

fm_status live_sky_params(const fm_sky_params *params, fm_sky_params *out, fm_error *err)
{
    fm_sky_params p = *params;
    if (p.hour != FM_NO_TIME && p.earth_sun_distance_au == FM_SUN_FROM_TIME) {
        fm_solar_position solar;
        unsigned computed;
        int has_solar;
        fm_status s = sky_resolve_sun(params, &p, &solar, &computed, &has_solar, err);
        if (s)
            return s;
    }
    p.hour = FM_NO_TIME;
    p.sun_elevation_deg = 45.0;
    p.sun_azimuth_deg = 180.0;
    *out = p;
    return FM_OK;
}

fm_status fm_sky_live_create(const fm_sky_params *params, const atomic_int *cancel, fm_sky_live **out,
                             fm_error *err)
{
    *out = NULL;
    fm_sky_live *live = calloc(1, sizeof *live);
    if (!live)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    fm_status s = live_sky_params(params, &live->params, err);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled");
    if (!s)
        s = fm_sky_create(&live->params, &live->sky, err);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled");
    if (s) {
        fm_sky_live_destroy(live);
        return s;
    }
    *out = live;
    return FM_OK;
}

fm_status fm_sky_live_render(const fm_sky_live *live, double sun_elevation_deg, double sun_azimuth_deg,
                             const fm_render_params *render, fm_image **out, fm_error *err)
{
    *out = NULL;
    /* a copy of the sky with this sun: its tables are shared, read-only (sky_sun.c) */
    fm_sky *sky = malloc(sizeof *sky);
    if (!sky)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    *sky = *live->sky;
    fm_status s = fm_sky_set_sun(sky, sun_elevation_deg, sun_azimuth_deg, err);
    if (!s)
        s = fm_render(sky, render, out, err);
    free(sky);
    return s;
}

/* Adds a file's bytes to the key, when path names a readable file. */
static void hash_file(const char *path, uint64_t h[2])
{
    FILE *f = path ? platform_fopen(path, "rb") : NULL;
    if (!f)
        return;
    unsigned char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0) {
        h[0] = hash_bytes(buf, n, h[0]);
        h[1] = hash_bytes(buf, n, h[1]);
    }
    fclose(f);
}

void fm_sky_live_key(const fm_sky_params *params, char out[33])
{
    fm_sky_params resolved = *params;
    if (live_sky_params(params, &resolved, NULL)) /* a bad date: its fields hash as they are */
        resolved = *params;
    const fm_sky_params *p = &resolved;
    char text[8192];
    /* every field that changes the tables; the date and place make the ozone profile (and column from
     * the climatology) and the day's Earth-Sun distance; no sun position, no time of day, no threads */
    int n = snprintf(text, sizeof text,
                     "live %d|alt %.17g|albedo %.17g|ozone %.17g|distance %.17g|wavelength %.17g|biome %s|"
                     "turbidity %.17g|aod %.17g|humidity %.17g|phase %d|atmosphere %s|presets %s",
                     LIVE_TABLE_VERSION, p->observer_altitude_m, p->ground_albedo, p->ozone_column_du,
                     p->earth_sun_distance_au, p->wavelength_nm, p->biome ? p->biome : "none", p->turbidity,
                     p->aod550, p->humidity_percent, (int)p->aerosol_phase,
                     p->atmosphere_file ? p->atmosphere_file : "", p->presets_dir ? p->presets_dir : "");
    /* clouds only when there are some, so that clear skies keep their keys */
    if ((p->clouds || p->fog_visibility_m > 0.0) && n > 0 && (size_t)n < sizeof text)
        n += snprintf(text + n, sizeof text - (size_t)n, "|clouds %s|tau %.17g|lwp %.17g|base %.17g|thick %.17g|fog %.17g",
                      p->clouds ? p->clouds : "", p->cloud_tau550, p->cloud_lwp_gm2, p->cloud_base_km,
                      p->cloud_thickness_km, p->fog_visibility_m);
    if (p->year != 0 && n > 0 && (size_t)n < sizeof text)
        snprintf(text + n, sizeof text - (size_t)n, "|date %d-%d-%d|place %.17g %.17g|utc %d|delta %.17g",
                 p->year, p->month, p->day, p->latitude_deg, p->longitude_deg, p->utc_offset_min, p->delta_t_s);
    uint64_t h[2] = {hash_bytes(text, strlen(text), 1), hash_bytes(text, strlen(text), 2)};
    hash_file(p->atmosphere_file, h);
    hash_file(p->biome, h); /* a biome given as a file; a name reads nothing */
    snprintf(out, 33, "%016llx%016llx", (unsigned long long)h[0], (unsigned long long)h[1]);
}

void fm_sky_live_destroy(fm_sky_live *live)
{
    if (!live)
        return;
    fm_sky_destroy(live->sky);
    free(live);
}

/* Nothing yet: a loaded file's atmosphere is built anew. */
size_t live_payload_size(const fm_sky_live *live)
{
    (void)live;
    return 0;
}

void live_payload_write(const fm_sky_live *live, unsigned char *out)
{
    (void)live;
    (void)out;
}

fm_status live_from_payload(const fm_sky_params *params, const unsigned char *in, size_t n, fm_sky_live **out,
                            fm_error *err)
{
    (void)in;
    if (n != 0)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the tables are %zu bytes, not 0", n);
    return fm_sky_live_create(params, NULL, out, err);
}
