/* fm_sky: validation of the user's parameters and construction of the atmosphere and tables. */
#include "sky.h"

#include "atmosphere/atmosphere_file.h"
#include "aerosol/aerosol.h"
#include "aerosol/cloud_file.h"
#include "aerosol/cloud_layer.h"
#include "atmosphere/ozone.h"
#include "atmosphere/ozone_climatology.h"
#include "atmosphere/ozone_profile.h"
#include "base/date.h"
#include "atmosphere/rayleigh.h"
#include "presets.h"

#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"
#include "base/vec.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
        .earth_sun_distance_au = FM_SUN_FROM_TIME, /* the date's; 1 AU without a date */
        .wavelength_nm = 0.0,
        .threads = 0,
        .year = 0,
        .month = 0,
        .day = 0,
        .latitude_deg = 0.0,
        .longitude_deg = 0.0,
        .biome = "rural",
        .turbidity = 1.0,
        .aod550 = 0.0,
        .humidity_percent = FM_HUMIDITY_BIOME_DEFAULT,
        .aerosol_phase = FM_AEROSOL_PHASE_MIE,
        .cloud_base_km = FM_CLOUD_BASE_FROM_FILE,
        .atmosphere_file = NULL,
        .presets_dir = NULL,
        .cache_dir = NULL,
        .hour = FM_NO_TIME,
        .minute = 0,
        .second = 0.0,
        .utc_offset_min = 0,
        .refraction = 1,
        .pressure_mbar = 1010.0,
        .temperature_c = 10.0,
        .delta_t_s = FM_DELTA_T_ESTIMATE,
    };
}

static fm_status validate_date(const fm_sky_params *p, fm_error *err)
{
    if (p->year == 0) {
        if (p->ozone_column_du == FM_OZONE_FROM_CLIMATOLOGY)
            return fm_fail_parameter(err, "ozone_column_du", "the ozone climatology needs a date and a place");
        return FM_OK;
    }
    if (!date_is_valid(p->year, p->month, p->day))
        return fm_fail_parameter(err, "date", "%04d-%02d-%02d is not a valid date between 1900 and 2100", p->year,
                                 p->month, p->day);
    return FM_OK;
}

static int has_biome(const fm_sky_params *p)
{
    return p->biome && p->biome[0] && strcmp(p->biome, "none") != 0;
}

/* -ln(0.02): the meteorological range is where a black object's contrast falls to 2% (Koschmieder). */
#define KOSCHMIEDER_CONTRAST 3.912

/* Ozone, molecules and aerosols as the sidecar reports them, all at 550 nm. */
static fm_status compute_composition(fm_sky *sky, const biome *b, double humidity, double turbidity,
                                     double ozone_du, double ozone_t_eff_k, fm_error *err)
{
    fm_composition *c = &sky->composition;
    memset(c, 0, sizeof *c);
    c->rayleigh_tau550 = rayleigh_cross_section_m2(550.0) * profile_column(&sky->atm.species[0].profile);
    c->rayleigh_ext550_ground_per_km = rayleigh_cross_section_m2(550.0) * profile_density(&sky->atm.species[0].profile, 0.0) * 1e3;
    c->ozone_tau550 = ozone_cross_section_m2(550.0, ozone_t_eff_k) * ozone_du * FM_DU_MOLECULES_PER_M2;
    c->ozone_column_du = ozone_du;
    c->aerosol_ssa550 = 1.0;
    c->humidity_percent = -1.0;
    snprintf(c->biome, sizeof c->biome, "none");
    c->visibility_km = KOSCHMIEDER_CONTRAST / c->rayleigh_ext550_ground_per_km;
    if (!b)
        return FM_OK;
    snprintf(c->biome, sizeof c->biome, "%s", b->name);
    aerosol_column col550, col440, col870;
    fm_status s;
    if ((s = aerosol_biome_column(b, humidity, 550.0, &col550, err)) ||
        (s = aerosol_biome_column(b, humidity, 440.0, &col440, err)) ||
        (s = aerosol_biome_column(b, humidity, 870.0, &col870, err)))
        return s;
    c->aerosol_tau550 = turbidity * col550.tau_ext;
    c->aerosol_ext550_ground_per_km = turbidity * col550.ext_ground_per_m * 1e3;
    c->visibility_km = KOSCHMIEDER_CONTRAST / (c->rayleigh_ext550_ground_per_km + c->aerosol_ext550_ground_per_km);
    if (col440.tau_ext > 0.0 && col870.tau_ext > 0.0)
        c->aerosol_angstrom = -log(col870.tau_ext / col440.tau_ext) / log(870.0 / 440.0);
    if (col550.tau_ext > 0.0)
        c->aerosol_ssa550 = col550.tau_sca / col550.tau_ext;
    c->aerosol_g550 = col550.g;
    c->humidity_percent = humidity;
    c->turbidity = turbidity;
    return FM_OK;
}

/* Adds the biome's aerosols; turbidity from aod550 when that is given. */
static fm_status add_aerosols(fm_sky *sky, const fm_sky_params *p, double ozone_du, double ozone_t_eff_k,
                              fm_error *err)
{
    if (!has_biome(p))
        return compute_composition(sky, NULL, 0.0, 0.0, ozone_du, ozone_t_eff_k, err);
    biome b;
    fm_status s = biome_load(p->biome, p->presets_dir, &b, err);
    if (s)
        return s;
    double humidity = p->humidity_percent == FM_HUMIDITY_BIOME_DEFAULT ? b.humidity_percent : p->humidity_percent;
    double turbidity = p->turbidity;
    if (p->aod550 > 0.0) {
        aerosol_column col;
        if ((s = aerosol_biome_column(&b, humidity, 550.0, &col, err)))
            return s;
        if (!(col.tau_ext > 0.0))
            return fm_fail_parameter(err, "aod550", "biome '%s' has no aerosol to scale", b.name);
        turbidity = p->aod550 / col.tau_ext;
    }
    if ((s = aerosol_add_biome(&sky->atm, &b, humidity, turbidity, p->aerosol_phase, err)))
        return s;
    atmosphere_update_majorants(&sky->atm);
    return compute_composition(sky, &b, humidity, turbidity, ozone_du, ozone_t_eff_k, err);
}

/* A custom atmosphere (atmosphere_file.h) replaces molecules, ozone and aerosols: its own planet,
 * constituents, and optionally ground albedo (over params->ground_albedo) and solar spectrum (at
 * 1 AU, scaled by 1/d^2 like the built-in one).  The sidecar's composition sorts its constituents
 * at 550 nm, when the file covers 550 nm: Rayleigh scatterers as "rayleigh", pure absorbers as
 * "ozone", other scatterers as aerosols; biome and ozone profile read "custom".  The built-in
 * constituents' parameters (ozone column, date, biome, turbidity, ...) do not apply and are ignored. */
static fm_status custom_atmosphere(fm_sky *sky, const fm_sky_params *p, const spectral_grid *grid, double inv_d2,
                                   fm_error *err)
{
    fm_status s = atmosphere_init_from_file(&sky->atm, p->atmosphere_file, grid, inv_d2, p->ground_albedo, err);
    if (s)
        return s;
    double top_m = sky->atm.top_radius_m - sky->atm.bottom_radius_m;
    if (p->observer_altitude_m >= top_m) {
        atmosphere_free(&sky->atm);
        return fm_fail_parameter(err, "observer_altitude_m", "%g m is not below the top of the atmosphere in %s (%g m)",
                                 p->observer_altitude_m, p->atmosphere_file, top_m);
    }
    fm_composition *c = &sky->composition;
    memset(c, 0, sizeof *c);
    snprintf(c->biome, sizeof c->biome, "custom");
    snprintf(c->ozone_profile, sizeof c->ozone_profile, "custom");
    c->aerosol_ssa550 = 1.0;
    c->humidity_percent = -1.0;
    spectral_grid g550;
    spectral_grid_single(&g550, 550.0);
    atmosphere a;
    if (atmosphere_init_from_file(&a, p->atmosphere_file, &g550, 1.0, 0.0, NULL) != FM_OK)
        return FM_OK; /* not given at 550 nm: nothing to report */
    double aerosol_sca = 0.0, aerosol_g = 0.0;
    for (int i = 0; i < a.species_count; i++) {
        const species *sp = &a.species[i];
        double col = profile_column(&sp->profile);
        double tau = (sp->sigma_s[0] + sp->sigma_a[0]) * col;
        if (sp->phase.kind == PHASE_RAYLEIGH) {
            c->rayleigh_tau550 += tau;
        } else if (sp->phase.kind == PHASE_NONE) {
            c->ozone_tau550 += tau;
        } else {
            c->aerosol_tau550 += tau;
            aerosol_sca += sp->sigma_s[0] * col;
            aerosol_g += sp->sigma_s[0] * col * phase_asymmetry(&sp->phase, 0);
        }
    }
    if (c->aerosol_tau550 > 0.0)
        c->aerosol_ssa550 = aerosol_sca / c->aerosol_tau550;
    if (aerosol_sca > 0.0)
        c->aerosol_g550 = aerosol_g / aerosol_sca;
    atmosphere_free(&a);
    return FM_OK;
}

static fm_status validate(const fm_sky_params *p, fm_error *err)
{
    fm_status s;
    if ((s = param_check(err, "sun_elevation_deg", p->sun_elevation_deg)) ||
        (s = param_check(err, "sun_azimuth_deg", p->sun_azimuth_deg)) ||
        (s = param_check(err, "observer_altitude_m", p->observer_altitude_m)) ||
        (s = param_check(err, "ground_albedo", p->ground_albedo)) ||
        (s = param_check(err, "latitude_deg", p->latitude_deg)) ||
        (s = param_check(err, "longitude_deg", p->longitude_deg)) ||
        (s = param_check(err, "turbidity", p->turbidity)) ||
        (s = param_check(err, "earth_sun_distance_au", p->earth_sun_distance_au)))
        return s;
    if (p->wavelength_nm != 0.0 && (s = param_check(err, "wavelength_nm", p->wavelength_nm)))
        return s;
    if (p->ozone_column_du != FM_OZONE_FROM_CLIMATOLOGY && (s = param_check(err, "ozone_column_du", p->ozone_column_du)))
        return s;
    if (p->aod550 != 0.0 && (s = param_check(err, "aod550", p->aod550)))
        return s;
    /* aod550 sets the turbidity: a second, different value would be silently dropped */
    if (p->aod550 != 0.0 && p->turbidity != 1.0)
        return fm_fail_parameter(err, "aod550", "give turbidity or aod550, not both");
    if (p->biome && !p->biome[0])
        return fm_fail_parameter(err, "biome", "the name is empty (none for no aerosols)");
    if (p->humidity_percent != FM_HUMIDITY_BIOME_DEFAULT &&
        (s = param_check(err, "humidity_percent", p->humidity_percent)))
        return s;
    if (p->aerosol_phase != FM_AEROSOL_PHASE_MIE && p->aerosol_phase != FM_AEROSOL_PHASE_HG)
        return fm_fail_parameter(err, "aerosol_phase", "%d is not a known phase model", (int)p->aerosol_phase);
    if ((s = cloud_params_validate(p, err)))
        return s;
    return param_check(err, "threads", p->threads);
}

/* The molecules, ozone and aerosols of the built-in atmosphere: the ozone column as given or from the
 * climatology; the profile shape for the date and latitude when there is a date, else the U.S.
 * Standard one. */
static fm_status builtin_atmosphere(fm_sky *sky, const fm_sky_params *p, const spectral_grid *grid, fm_error *err)
{
    double ozone_du = p->ozone_column_du;
    ozone_profile shape = OZONE_PROFILE_US_STANDARD;
    fm_status s;
    if (p->year != 0) {
        shape = ozone_profile_for(p->latitude_deg, date_day_of_year(p->year, p->month, p->day));
        if (ozone_du == FM_OZONE_FROM_CLIMATOLOGY &&
            (s = ozone_climatology_for_date(p->year, p->month, p->day, p->latitude_deg, p->longitude_deg, &ozone_du,
                                            err)))
            return s;
    }
    if ((s = atmosphere_init_clear_sky(&sky->atm, grid, ozone_du, shape, p->ground_albedo, err)) ||
        (s = add_aerosols(sky, p, ozone_du, ozone_profile_effective_temperature_k(shape), err)))
        return s;
    snprintf(sky->composition.ozone_profile, sizeof sky->composition.ozone_profile, "%s", ozone_profile_name(shape));
    return FM_OK;
}

/* The cloud layers (aerosol/cloud_file.h) over the atmosphere, and into the composition. */
static fm_status add_clouds(fm_sky *sky, const fm_sky_params *p, fm_error *err)
{
    cloud_layer layers[FM_MAX_CLOUD_LAYERS];
    int count;
    fm_status s = cloud_layers_from_params(p, layers, &count, err);
    fm_composition *c = &sky->composition;
    for (int i = 0, j = 0; i < count && !s; i++) {
        if (i == sky->skip_cloud - 1)
            continue;
        const cloud_layer *l = &layers[i];
        s = cloud_add_layer(&sky->atm, l->type, l->base_m, l->thickness_m, l->tau550, p->threads, p->cache_dir,
                            sky->truncate_peaks && l->tau550 >= SKY_TRUNCATE_TAU, err);
        if (s == FM_ERR_INVALID_ARGUMENT && err && !err->parameter[0]) { /* a layer outside the atmosphere */
            char what[sizeof err->message];
            snprintf(what, sizeof what, "%s", err->message);
            s = fm_fail_parameter(err, "clouds", "%s", what);
        }
        snprintf(c->cloud[j].type, sizeof c->cloud[j].type, "%s", l->type->name);
        c->cloud[j].tau550 = l->tau550;
        c->cloud[j].base_m = l->base_m;
        c->cloud[j].thickness_m = l->thickness_m;
        c->cloud_count = ++j;
    }
    if (!s && c->cloud_count > 0)
        atmosphere_update_majorants(&sky->atm);
    return s;
}

/* Everything of the sky for its resolved parameters p; on failure fm_sky_destroy frees what was built. */
/* The atmosphere alone (and its composition) on the wavelengths of the grid, wavelength_nm > 0:
 * that one, else the visible grid. */
static fm_status build_atmosphere(fm_sky *sky, const fm_sky_params *p, double wavelength_nm, fm_error *err)
{
    spectral_grid grid;
    if (wavelength_nm > 0.0)
        spectral_grid_single(&grid, wavelength_nm);
    else
        spectral_grid_visible(&grid);
    double inv_d2 = 1.0 / (p->earth_sun_distance_au * p->earth_sun_distance_au);
    for (int k = 0; k < grid.count; k++)
        grid.solar_irradiance[k] *= inv_d2;
    fm_status s = p->atmosphere_file ? custom_atmosphere(sky, p, &grid, inv_d2, err)
                                     : builtin_atmosphere(sky, p, &grid, err);
    return s ? s : add_clouds(sky, p, err);
}

/* shared: NULL, or the column table of a sky whose species have the same profiles (a truncated
 * copy's parent, sky.h): the table holds columns, not optical depths, so it is borrowed, not built. */
static fm_status build_sky(fm_sky *sky, const fm_sky_params *p, const column_table *shared, fm_error *err)
{
    fm_status s = build_atmosphere(sky, p, p->wavelength_nm, err);
    if (s)
        return s;
    sun_disk_init(&sky->sun, &sky->atm.grid, p->earth_sun_distance_au);
    sky->sun_dir = direction_from_elevation_azimuth(p->sun_elevation_deg * FM_DEG, p->sun_azimuth_deg * FM_DEG);
    sky->observer = v3(0.0, 0.0, sky->atm.bottom_radius_m + p->observer_altitude_m);
    assert(fabs(v3_length(sky->sun_dir) - 1.0) < 1e-12);
    assert(v3_length(sky->observer) >= sky->atm.bottom_radius_m && v3_length(sky->observer) < sky->atm.top_radius_m);
    if (shared) {
        assert(shared->species == sky->atm.species_count);
        sky->columns = *shared;
    } else if ((s = column_table_build(&sky->columns, &sky->atm, COLUMN_TABLE_R, COLUMN_TABLE_MU, p->threads, err)))
        return s;
    if ((s = depth_table_build(&sky->mid_depth, &sky->columns, &sky->atm, sky->atm.grid.count / 2, err)) ||
        (s = sun_irradiance_build(&sky->sun_table, &sky->atm, &sky->columns, &sky->sun, SUN_TABLE_R, SUN_TABLE_MU,
                                  err)))
        return s;
    return FM_OK;
}

/* A sky holding the resolved parameters (sun from the date, time and place), nothing built yet. */
static fm_status new_sky(const fm_sky_params *params, fm_sky **out, fm_error *err)
{
    *out = NULL;
    /* the date first: the sun from the date, time and place (sky_sun.c) needs a valid one; from here
     * on params is the resolved copy, whose date is the same */
    fm_sky_params resolved;
    fm_solar_position solar;
    unsigned sun_computed = 0;
    int has_solar = 0;
    fm_status s;
    if ((s = validate_date(params, err)) ||
        (s = sky_resolve_sun(params, &resolved, &solar, &sun_computed, &has_solar, err)) ||
        (s = validate(&resolved, err)))
        return s;
    fm_sky *sky = calloc(1, sizeof *sky);
    if (!sky)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    sky->params = resolved;
    sky->has_solar = has_solar;
    sky->sun_computed = sun_computed;
    if (has_solar)
        sky->solar = solar;
    *out = sky;
    return FM_OK;
}

/* Whether the sky has a layer that its truncated copy (sky.h) cuts. */
static int has_deck(const fm_sky *sky)
{
    for (int i = 0; i < sky->composition.cloud_count; i++)
        if (sky->composition.cloud[i].tau550 >= SKY_TRUNCATE_TAU)
            return 1;
    return 0;
}

fm_status fm_sky_create(const fm_sky_params *params, fm_sky **out, fm_error *err)
{
    fm_sky *sky;
    fm_status s = new_sky(params, &sky, err);
    if (!s)
        s = build_sky(sky, &sky->params, NULL, err);
    if (!s && has_deck(sky) && !(s = new_sky(params, &sky->truncated, err))) {
        sky->truncated->truncate_peaks = 1; /* the layers' optics differ, not their profiles */
        s = build_sky(sky->truncated, &sky->truncated->params, &sky->columns, err);
    }
    if (s) {
        fm_sky_destroy(sky);
        return s;
    }
    *out = sky;
    return s;
}

fm_status sky_create_without_cloud(const fm_sky *sky, int cloud, double altitude_m, fm_sky **out, fm_error *err)
{
    fm_sky_params p = sky->params;
    p.observer_altitude_m = altitude_m;
    fm_sky *copy;
    fm_status s = new_sky(&p, &copy, err);
    if (s)
        return s;
    copy->skip_cloud = cloud + 1;
    if (!(s = build_sky(copy, &copy->params, NULL, err)) && has_deck(copy) && !(s = new_sky(&p, &copy->truncated, err))) {
        copy->truncated->skip_cloud = cloud + 1;
        copy->truncated->truncate_peaks = 1;
        s = build_sky(copy->truncated, &copy->truncated->params, &copy->columns, err);
    }
    if (s) {
        fm_sky_destroy(copy);
        return s;
    }
    copy->sun_dir = sky->sun_dir; /* fm_sky_set_sun may have moved it */
    *out = copy;
    return FM_OK;
}

fm_status fm_composition_compute(const fm_sky_params *params, fm_composition *out, fm_error *err)
{
    fm_sky *sky;
    fm_status s = new_sky(params, &sky, err);
    if (s)
        return s;
    if (!(s = build_atmosphere(sky, &sky->params, 550.0, err)))
        *out = sky->composition;
    fm_sky_destroy(sky);
    return s;
}

void fm_sky_destroy(fm_sky *sky)
{
    if (!sky)
        return;
    fm_sky_destroy(sky->truncated);
    sun_irradiance_free(&sky->sun_table);
    depth_table_free(&sky->mid_depth);
    if (!sky->truncate_peaks) /* a truncated copy borrows its parent's (build_sky) */
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
    /* the clouds' share along the line to the disk's centre, at 550 nm, from the slabs' chords */
    const fm_composition *c = &sky->composition;
    double cloud_depth = 0.0;
    for (int i = 0; i < c->cloud_count; i++) {
        double r_base = atm->bottom_radius_m + c->cloud[i].base_m, r_top = r_base + c->cloud[i].thickness_m;
        cloud_depth += c->cloud[i].tau550 / c->cloud[i].thickness_m * cloud_shell_chord_m(r, sky->sun_dir.z, r_base, r_top);
    }
    out->cloud_transmittance = sky->sun_dir.z > 0.0 ? exp(-cloud_depth) : 0.0;
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

void fm_sky_composition(const fm_sky *sky, fm_composition *out)
{
    *out = sky->composition;
}
