/* fm_sky: validation of the user's parameters and construction of the atmosphere and tables. */
#include "sky.h"

#include "atmosphere/atmosphere_file.h"
#include "base/status.h"
#include "base/units.h"
#include "base/vec.h"

#include <math.h>
#include <stdlib.h>

/* Observers from the ground to aircraft and balloons.  Higher up, the upper limb (light scattered
 * from the bright atmosphere below into very thin air) makes the path tracer's estimates
 * heavy-tailed; until it samples that light directly, the fast path is verified to 20 km. */
#define FM_MAX_OBSERVER_ALTITUDE_M 20000.0

/* Table resolutions (checked against direct evaluation in tests/physics). */
#define COLUMN_TABLE_R 128
#define COLUMN_TABLE_MU 512
#define SUN_TABLE_R 128
#define SUN_TABLE_MU 512

fm_sky_params fm_sky_params_default(void)
{
    return (fm_sky_params){
        .sun_elevation_deg = 30.0,
        .sun_azimuth_deg = 180.0,
        .observer_altitude_m = 0.0,
        .ground_albedo = 0.2,
        .ozone_column_du = 300.0,
        .earth_sun_distance_au = 1.0,
        .wavelength_nm = 0.0,
        .threads = 0,
    };
}

static fm_status check_range(fm_error *err, const char *field, double v, double lo, double hi, const char *unit)
{
    if (!isfinite(v) || v < lo || v > hi)
        return fm_fail_parameter(err, field, "%g is outside [%g, %g]%s%s", v, lo, hi, unit[0] ? " " : "", unit);
    return FM_OK;
}

static fm_status validate(const fm_sky_params *p, fm_error *err)
{
    fm_status s;
    if ((s = check_range(err, "sun_elevation_deg", p->sun_elevation_deg, -90.0, 90.0, "degrees")) ||
        (s = check_range(err, "sun_azimuth_deg", p->sun_azimuth_deg, -360.0, 360.0, "degrees")) ||
        (s = check_range(err, "observer_altitude_m", p->observer_altitude_m, 0.0, FM_MAX_OBSERVER_ALTITUDE_M, "m")) ||
        (s = check_range(err, "ground_albedo", p->ground_albedo, 0.0, 1.0, "")) ||
        (s = check_range(err, "ozone_column_du", p->ozone_column_du, 0.0, 1000.0, "DU")) ||
        (s = check_range(err, "earth_sun_distance_au", p->earth_sun_distance_au, 0.95, 1.05, "AU")))
        return s;
    if (p->wavelength_nm != 0.0 && (s = check_range(err, "wavelength_nm", p->wavelength_nm, 300.0, 1000.0, "nm")))
        return s;
    if (p->threads < 0 || p->threads > 256)
        return fm_fail_parameter(err, "threads", "%d is outside [0, 256]", p->threads);
    return FM_OK;
}

path_context sky_path_context(const fm_sky *sky, int min_order, int max_order)
{
    return (path_context){
        .atm = &sky->atm,
        .sun = &sky->sun,
        .sun_table = &sky->sun_table,
        .sun_dir = sky->sun_dir,
        .min_order = min_order,
        .max_order = max_order,
        .force_escapes = 1,
        .skip_ground_first = 0,
        .ground_diffuse = NULL,
    };
}

fm_status fm_sky_create(const fm_sky_params *params, fm_sky **out, fm_error *err)
{
    *out = NULL;
    fm_status s = validate(params, err);
    if (s)
        return s;
    fm_sky *sky = calloc(1, sizeof *sky);
    if (!sky)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    sky->params = *params;

    spectral_grid grid;
    if (params->wavelength_nm > 0.0)
        spectral_grid_single(&grid, params->wavelength_nm);
    else
        spectral_grid_visible(&grid);
    double inv_d2 = 1.0 / (params->earth_sun_distance_au * params->earth_sun_distance_au);
    for (int k = 0; k < grid.count; k++)
        grid.solar_irradiance[k] *= inv_d2;

    if (params->atmosphere_file) {
        /* A custom atmosphere: its own geometry, constituents, and optionally albedo and solar
         * spectrum (at 1 AU, scaled by 1/d^2 like the built-in one). */
        s = atmosphere_init_from_file(&sky->atm, params->atmosphere_file, &grid, inv_d2, params->ground_albedo, err);
        if (!s && params->observer_altitude_m >= sky->atm.top_radius_m - sky->atm.bottom_radius_m) {
            s = fm_fail_parameter(err, "observer_altitude_m", "%g m is not below the top of the atmosphere in %s (%g m)",
                                  params->observer_altitude_m, params->atmosphere_file,
                                  sky->atm.top_radius_m - sky->atm.bottom_radius_m);
            atmosphere_free(&sky->atm);
        }
    } else {
        s = atmosphere_init_clear_sky(&sky->atm, &grid, params->ozone_column_du, params->ground_albedo, err);
    }
    if (s) {
        free(sky);
        return s;
    }
    sun_disk_init(&sky->sun, &sky->atm.grid, params->earth_sun_distance_au);
    sky->sun_dir = direction_from_elevation_azimuth(params->sun_elevation_deg * FM_DEG,
                                                    params->sun_azimuth_deg * FM_DEG);
    sky->observer = v3(0.0, 0.0, sky->atm.bottom_radius_m + params->observer_altitude_m);

    if ((s = column_table_build(&sky->columns, &sky->atm, COLUMN_TABLE_R, COLUMN_TABLE_MU, params->threads, err)) ||
        (s = sun_irradiance_build(&sky->sun_table, &sky->atm, &sky->columns, &sky->sun, SUN_TABLE_R,
                                  SUN_TABLE_MU, params->threads, err))) {
        fm_sky_destroy(sky);
        return s;
    }
    *out = sky;
    return FM_OK;
}

void fm_sky_destroy(fm_sky *sky)
{
    if (!sky)
        return;
    sun_irradiance_free(&sky->sun_table);
    column_table_free(&sky->columns);
    atmosphere_free(&sky->atm);
    free(sky);
}

const fm_sky_params *fm_sky_get_params(const fm_sky *sky)
{
    return &sky->params;
}

void fm_sky_sun_light(const fm_sky *sky, fm_sun_light *out)
{
    const atmosphere *atm = &sky->atm;
    const int K = atm->grid.count;
    double normal[FM_MAX_WAVELENGTHS], horizontal[FM_MAX_WAVELENGTHS];
    double r = v3_length(sky->observer);
    /* a single reported number: integrate every chord's optical depth, no table */
    sun_transmittance_direct(atm, NULL, &sky->sun, r, sky->sun_dir.z, normal, horizontal);
    out->direction[0] = sky->sun_dir.x;
    out->direction[1] = sky->sun_dir.y;
    out->direction[2] = sky->sun_dir.z;
    out->angular_radius_deg = sky->sun.angular_radius / FM_DEG;
    for (int j = 0; j < 3; j++)
        out->normal_irradiance[j] = out->horizontal_irradiance[j] = 0.0;
    for (int k = 0; k < K; k++) {
        double en = normal[k] * atm->grid.solar_irradiance[k];
        double eh = horizontal[k] * atm->grid.solar_irradiance[k];
        if (atm->grid.colour) {
            for (int j = 0; j < 3; j++) {
                out->normal_irradiance[j] += en * atm->grid.xyz_weight[k][j];
                out->horizontal_irradiance[j] += eh * atm->grid.xyz_weight[k][j];
            }
        } else {
            out->normal_irradiance[0] = en;
            out->horizontal_irradiance[0] = eh;
        }
    }
}
