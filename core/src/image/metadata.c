#include "image/metadata.h"

#include "base/units.h"
#include "camera/camera.h"
#include "colour/colour.h"

#include <math.h>

#include <stdio.h>
#include <string.h>

static meta_entry *add(metadata *m, const char *group, const char *key, meta_type type)
{
    meta_entry *e = &m->e[m->count < FM_META_MAX ? m->count++ : FM_META_MAX - 1];
    memset(e, 0, sizeof *e);
    e->group = group;
    e->key = key;
    e->type = type;
    return e;
}

static void add_double(metadata *m, const char *group, const char *key, double v)
{
    add(m, group, key, META_DOUBLE)->v[0] = v;
}

static void add_int(metadata *m, const char *group, const char *key, int v)
{
    add(m, group, key, META_INT)->v[0] = v;
}

static void add_string(metadata *m, const char *group, const char *key, const char *s)
{
    add(m, group, key, META_STRING)->s = s;
}

static void add_vec3(metadata *m, const char *group, const char *key, const double v[3])
{
    meta_entry *e = add(m, group, key, META_VEC3);
    memcpy(e->v, v, sizeof e->v);
}

static const char *quality_name(fm_quality q)
{
    return q == FM_QUALITY_PREVIEW ? "preview" : (q == FM_QUALITY_REFERENCE ? "reference" : "final");
}

/* "HH:MM:SS" of local clock hours (rounded to the second). */
static void clock_text(char *buf, size_t size, double hours)
{
    long t = lround(hours * 3600.0) % 86400;
    snprintf(buf, size, "%02ld:%02ld:%02ld", t / 3600, t / 60 % 60, t % 60);
}

/* The date's time of day and the solar position it gives (docs/physics.md, "Solar position"). */
static void collect_solar_position(metadata *m, const fm_render_record *r)
{
    const fm_sky_params *sp = &r->sky;
    const fm_solar_position o = r->solar;
    const unsigned computed = r->sun_computed;
    if (!r->has_solar)
        return;
    clock_text(m->time_text, sizeof m->time_text, sp->hour + sp->minute / 60.0 + sp->second / 3600.0);
    int off = sp->utc_offset_min < 0 ? -sp->utc_offset_min : sp->utc_offset_min;
    snprintf(m->offset_text, sizeof m->offset_text, "%c%02d:%02d", sp->utc_offset_min < 0 ? '-' : '+', off / 60 % 100,
             off % 60);
    add_string(m, "parameters", "time", m->time_text);
    add_string(m, "parameters", "utc_offset", m->offset_text);
    add_string(m, "parameters", "refraction", sp->refraction ? "on" : "off");
    add_double(m, "parameters", "pressure_mbar", sp->pressure_mbar);
    add_double(m, "parameters", "temperature_c", sp->temperature_c);
    add_double(m, "parameters", "delta_t_s", o.delta_t_s);

    /* which of the sky's sun parameters came from this position, e.g. "elevation, azimuth" */
    static const char *const names[3] = {"elevation", "azimuth", "earth_sun_distance"};
    m->from_time_text[0] = '\0';
    for (int i = 0; i < 3; i++)
        if (computed & (1u << i)) {
            size_t n = strlen(m->from_time_text);
            snprintf(m->from_time_text + n, sizeof m->from_time_text - n, "%s%s", n ? ", " : "", names[i]);
        }
    if (!computed)
        snprintf(m->from_time_text, sizeof m->from_time_text, "none (the sun was given)");
    add_string(m, "solar_position", "algorithm", "NREL SPA (Reda & Andreas 2004)");
    add_string(m, "solar_position", "used_for", m->from_time_text);
    add_double(m, "solar_position", "elevation_deg", o.elevation_deg);
    add_double(m, "solar_position", "elevation_without_refraction_deg", o.elevation_true_deg);
    add_double(m, "solar_position", "azimuth_deg", o.azimuth_deg);
    add_double(m, "solar_position", "zenith_deg", o.zenith_deg);
    add_double(m, "solar_position", "earth_sun_distance_au", o.earth_sun_distance_au);
    add_double(m, "solar_position", "equation_of_time_min", o.equation_of_time_min);
    add_string(m, "solar_position", "day",
               o.daylight == FM_DAYLIGHT_POLAR_DAY ? "polar day"
                                                   : (o.daylight == FM_DAYLIGHT_POLAR_NIGHT ? "polar night" : "normal"));
    clock_text(m->noon_text, sizeof m->noon_text, o.transit_h);
    if (o.daylight == FM_DAYLIGHT_NORMAL) { /* polar day or night: no sunrise or sunset keys */
        clock_text(m->sunrise_text, sizeof m->sunrise_text, o.sunrise_h);
        clock_text(m->sunset_text, sizeof m->sunset_text, o.sunset_h);
        add_string(m, "solar_position", "sunrise", m->sunrise_text);
    }
    add_string(m, "solar_position", "solar_noon", m->noon_text);
    if (o.daylight == FM_DAYLIGHT_NORMAL)
        add_string(m, "solar_position", "sunset", m->sunset_text);
}

/* The camera: image.projection and image.layout say how to read the pixels, the "camera" group holds
 * the camera's parameters (docs/output.md, "Cameras"). */
/* Each cloud layer (bottom to top as listed) and their total optical depth, in "atmosphere". */
static void add_clouds(metadata *m)
{
    static const char *const keys[FM_MAX_CLOUD_LAYERS][4] = {
        {"cloud_1_type", "cloud_1_optical_depth_550nm", "cloud_1_base_km", "cloud_1_thickness_km"},
        {"cloud_2_type", "cloud_2_optical_depth_550nm", "cloud_2_base_km", "cloud_2_thickness_km"},
        {"cloud_3_type", "cloud_3_optical_depth_550nm", "cloud_3_base_km", "cloud_3_thickness_km"},
        {"cloud_4_type", "cloud_4_optical_depth_550nm", "cloud_4_base_km", "cloud_4_thickness_km"},
    };
    const fm_composition *c = &m->composition;
    if (c->cloud_count == 0)
        return;
    double total = 0.0;
    for (int i = 0; i < c->cloud_count; i++)
        total += c->cloud[i].tau550;
    add_int(m, "atmosphere", "cloud_layers", c->cloud_count);
    add_double(m, "atmosphere", "cloud_optical_depth_550nm", total);
    for (int i = 0; i < c->cloud_count; i++) {
        add_string(m, "atmosphere", keys[i][0], c->cloud[i].type);
        add_double(m, "atmosphere", keys[i][1], c->cloud[i].tau550);
        add_double(m, "atmosphere", keys[i][2], c->cloud[i].base_m / 1000.0);
        add_double(m, "atmosphere", keys[i][3], c->cloud[i].thickness_m / 1000.0);
    }
}

static void add_camera(metadata *m, const fm_image *img)
{
    const fm_camera *p = &img->camera;
    add_string(m, "camera", "type", camera_type_name(p->type));
    switch (p->type) {
    case FM_CAMERA_FISHEYE: {
        int equisolid = p->fisheye_projection == FM_FISHEYE_EQUISOLID;
        add_string(m, "image", "projection", equisolid ? "fisheye equisolid" : "fisheye equidistant");
        add_string(m, "image", "layout",
                   equisolid ? "upward hemisphere in the inscribed circle: zenith at the centre, horizontal on the "
                               "circle, r/R = sqrt(2) sin(zenith angle / 2); north up, east LEFT (as seen looking "
                               "up); pixels outside the circle are 0; axes +X east, +Y north, +Z up"
                             : "upward hemisphere in the inscribed circle: zenith at the centre, horizontal on the "
                               "circle, r/R = zenith angle / 90 deg; north up, east LEFT (as seen looking up); "
                               "pixels outside the circle are 0; axes +X east, +Y north, +Z up");
        add_string(m, "camera", "fisheye_projection", camera_fisheye_projection_name(p->fisheye_projection));
        add_double(m, "camera", "field_of_view_deg", 180.0);
        break;
    }
    case FM_CAMERA_PINHOLE: {
        camera cam;
        double vertical = 0.0;
        if (camera_init(&cam, p, img->width, NULL) == FM_OK)
            vertical = pinhole_vertical_fov(&cam.pin) / FM_DEG;
        double look[3] = {cos(p->look_elevation_deg * FM_DEG) * sin(p->look_azimuth_deg * FM_DEG),
                          cos(p->look_elevation_deg * FM_DEG) * cos(p->look_azimuth_deg * FM_DEG),
                          sin(p->look_elevation_deg * FM_DEG)};
        add_string(m, "image", "projection", "pinhole (rectilinear)");
        add_string(m, "image", "layout",
                   "the image centre looks along camera.look_direction; level horizon (no roll), up toward the "
                   "zenith; square pixels; axes +X east, +Y north, +Z up");
        add_double(m, "camera", "horizontal_fov_deg", p->fov_deg);
        add_double(m, "camera", "vertical_fov_deg", vertical);
        add_double(m, "camera", "look_azimuth_deg", p->look_azimuth_deg);
        add_double(m, "camera", "look_elevation_deg", p->look_elevation_deg);
        add_vec3(m, "camera", "look_direction", look);
        add_double(m, "camera", "aspect", (double)img->width / img->height);
        break;
    }
    case FM_CAMERA_EQUIRECT:
    default:
        add_string(m, "image", "projection", "equirectangular");
        add_string(m, "image", "layout",
                   "Blender Environment Texture: column u = 0.25 + azimuth/360 (north at u = 0.25, east at the "
                   "centre), top row = zenith; axes +X east, +Y north, +Z up");
        add_double(m, "image", "azimuth_at_center_deg", 90.0);
        break;
    }
}

/* The film exposure (EV, values x 2^EV) that shows a white Lambertian surface under the global
 * horizontal illuminance E as 1.0, so an 18% grey card as 0.18: its radiance in map units is
 * E / (683 pi), hence EV = log2(683 pi / E).  100 klx gives -5.54 (the -5 EV of daylight in
 * Blender); clamped to Blender's range of the film exposure, [-32, 32] (astronomical twilight,
 * sun -18, needs about +26; a night sky, E below 5e-7 lux, gets the end of the range). */
static double suggested_exposure_ev(double global_lux)
{
    double ev = log2(FM_LUMINOUS_EFFICACY * FM_PI / fmax(global_lux, 1e-9));
    return fmin(32.0, fmax(-32.0, ev));
}

void metadata_collect(metadata *m, const fm_image *img, const char *exr_path)
{
    memset(m, 0, sizeof *m);
    const fm_render_record *r = &img->record;
    const fm_sky_params *sp = &r->sky;
    const int colour = img->content != FM_IMAGE_SPECTRAL_RADIANCE;
    const char *slash = strrchr(exr_path, '/');
    snprintf(m->out_name, sizeof m->out_name, "%s", slash ? slash + 1 : exr_path);
    snprintf(m->seed_text, sizeof m->seed_text, "%llu", (unsigned long long)r->seed);
    m->composition = r->composition;

    add_string(m, "", "version", FIRMAMENT_VERSION);
    add_string(m, "image", "file", m->out_name);
    add_int(m, "image", "width", img->width);
    add_int(m, "image", "height", img->height);
    add_camera(m, img);
    if (img->content == FM_IMAGE_RGB) {
        add_string(m, "image", "colorspace", img->colorspace);
        add_string(m, "image", "units", "CIE-weighted radiance, W m^-2 sr^-1 (Y x 683 = luminance in cd/m^2)");
    } else if (colour) {
        add_string(m, "image", "colorspace", "Linear Rec.709 (sRGB primaries, D65 white)");
        add_string(m, "image", "units", "CIE-weighted radiance, W m^-2 sr^-1 (Y x 683 = luminance in cd/m^2)");
    } else {
        add_string(m, "image", "colorspace", "none (spectral radiance)");
        add_string(m, "image", "units", "spectral radiance, W m^-2 sr^-1 nm^-1");
    }
    add_int(m, "image", "contains_sun_disk", img->sun_disk ? 1 : 0);

    add_double(m, "parameters", "sun_elevation_deg", sp->sun_elevation_deg);
    add_double(m, "parameters", "sun_azimuth_deg", sp->sun_azimuth_deg);
    add_double(m, "parameters", "observer_altitude_m", sp->observer_altitude_m);
    add_double(m, "parameters", "ground_albedo", sp->ground_albedo);
    if (sp->ozone_column_du == FM_OZONE_FROM_CLIMATOLOGY) /* the column used is atmosphere.ozone_column_du */
        add_string(m, "parameters", "ozone_column_du", "climatology");
    else
        add_double(m, "parameters", "ozone_column_du", sp->ozone_column_du);
    add_double(m, "parameters", "earth_sun_distance_au", sp->earth_sun_distance_au);
    add_string(m, "parameters", "earth_sun_distance_from",
               r->sun_computed & FM_SUN_COMPUTED_DISTANCE ? "date"
               : r->sun_computed & FM_SUN_MEAN_DISTANCE   ? "mean (no date)"
                                                          : "given");
    if (!colour)
        add_double(m, "parameters", "wavelength_nm", sp->wavelength_nm);
    add_string(m, "parameters", "quality", quality_name(r->quality));
    if (r->seed <= (1ull << 53)) /* exact as a JSON number and an EXR double */
        add_double(m, "parameters", "seed", (double)r->seed);
    else
        add_string(m, "parameters", "seed", m->seed_text);
    add_double(m, "parameters", "sample_scale", r->sample_scale);
    if (img->paths_per_node > 0)
        add_int(m, "parameters", "paths_per_node", img->paths_per_node);
    add_string(m, "parameters", "biome", m->composition.biome);
    add_double(m, "parameters", "turbidity", sp->turbidity);
    if (sp->aod550 > 0.0)
        add_double(m, "parameters", "aod550", sp->aod550);
    add_string(m, "parameters", "aerosol_phase", sp->aerosol_phase == FM_AEROSOL_PHASE_HG ? "hg" : "mie");
    if (sp->year != 0) {
        snprintf(m->date_text, sizeof m->date_text, "%04d-%02d-%02d", sp->year, sp->month, sp->day);
        add_string(m, "parameters", "date", m->date_text);
        add_double(m, "parameters", "latitude_deg", sp->latitude_deg);
        add_double(m, "parameters", "longitude_deg", sp->longitude_deg);
        collect_solar_position(m, r);
    }
    if (r->atmosphere_file[0]) {
        add_string(m, "parameters", "atmosphere_file", r->atmosphere_file);
        add_string(m, "parameters", "atmosphere", "custom atmosphere file (docs/atmosphere-file.md)");
    } else {
        add_string(m, "parameters", "atmosphere", "U.S. Standard Atmosphere 1976 molecules (Bucholtz Rayleigh), "
                                                  "ozone (Bogumil 2003 cross sections, AFGL profiles by latitude and "
                                                  "season), OPAC aerosol components (Mie theory)");
    }

    const fm_composition *c = &m->composition;
    add_double(m, "atmosphere", "rayleigh_optical_depth_550nm", c->rayleigh_tau550);
    add_double(m, "atmosphere", "ozone_optical_depth_550nm", c->ozone_tau550);
    add_double(m, "atmosphere", "ozone_column_du", c->ozone_column_du);
    add_string(m, "atmosphere", "ozone_profile", c->ozone_profile);
    add_string(m, "atmosphere", "biome", c->biome);
    add_double(m, "atmosphere", "aerosol_optical_depth_550nm", c->aerosol_tau550);
    if (c->visibility_km > 0.0) {
        add_double(m, "atmosphere", "extinction_550nm_ground_per_km",
                   c->rayleigh_ext550_ground_per_km + c->aerosol_ext550_ground_per_km);
        add_double(m, "atmosphere", "visibility_km", c->visibility_km);
    }
    if (c->aerosol_tau550 > 0.0) {
        add_double(m, "atmosphere", "aerosol_angstrom_exponent_440_870nm", c->aerosol_angstrom);
        add_double(m, "atmosphere", "aerosol_single_scattering_albedo_550nm", c->aerosol_ssa550);
        add_double(m, "atmosphere", "aerosol_asymmetry_parameter_550nm", c->aerosol_g550);
        add_double(m, "atmosphere", "humidity_percent", c->humidity_percent);
        add_double(m, "atmosphere", "turbidity", c->turbidity);
    }

    add_clouds(m);

    const fm_sun_light sun = r->sun;
    double diffuse[3];
    int hemisphere = fm_image_diffuse_horizontal(img, diffuse); /* 0 for a pinhole view */
    add_vec3(m, "sun", "direction", sun.direction);
    add_double(m, "sun", "elevation_deg", sp->sun_elevation_deg);
    add_double(m, "sun", "azimuth_deg", sp->sun_azimuth_deg);
    add_double(m, "sun", "angular_diameter_deg", 2.0 * sun.angular_radius_deg);
    if (m->composition.cloud_count > 0)
        add_double(m, "sun", "cloud_direct_transmittance_550nm", sun.cloud_transmittance);
    /* the RGB values are in the image's colour space (image.colorspace) */
    double xyz_to_rgb[3][3] = {{0.0}};
    if (img->content == FM_IMAGE_RGB)
        colour_matrix_inverse(&img->rgb_to_xyz[0][0], xyz_to_rgb);
    if (colour) {
        double rgb[3];
        if (img->content == FM_IMAGE_RGB)
            colour_matrix_apply(&xyz_to_rgb[0][0], sun.normal_irradiance, rgb);
        else
            colour_xyz_to_rec709(sun.normal_irradiance, rgb);
        add_vec3(m, "sun", "direct_normal_irradiance_rgb", rgb);
        add_double(m, "sun", "direct_normal_illuminance_lux", FM_LUMINOUS_EFFICACY * sun.normal_irradiance[1]);
        add_double(m, "sun", "direct_horizontal_illuminance_lux", FM_LUMINOUS_EFFICACY * sun.horizontal_irradiance[1]);
    }
    if (colour && hemisphere) {
        double diffuse_xyz[3];
        if (img->content == FM_IMAGE_RGB_REC709)
            colour_rec709_to_xyz(diffuse, diffuse_xyz);
        else if (img->content == FM_IMAGE_RGB)
            colour_matrix_apply(&img->rgb_to_xyz[0][0], diffuse, diffuse_xyz);
        else
            memcpy(diffuse_xyz, diffuse, sizeof diffuse_xyz);
        double diffuse_rgb[3];
        if (img->content == FM_IMAGE_RGB)
            colour_matrix_apply(&xyz_to_rgb[0][0], diffuse_xyz, diffuse_rgb);
        else
            colour_xyz_to_rec709(diffuse_xyz, diffuse_rgb);
        add_vec3(m, "sky", "diffuse_horizontal_irradiance_rgb", diffuse_rgb);
        add_double(m, "sky", "diffuse_horizontal_illuminance_lux", FM_LUMINOUS_EFFICACY * diffuse_xyz[1]);
        double global_lux = FM_LUMINOUS_EFFICACY * (diffuse_xyz[1] + sun.horizontal_irradiance[1]);
        add_double(m, "sky", "global_horizontal_illuminance_lux", global_lux);
        add_double(m, "sky", "suggested_exposure_ev", suggested_exposure_ev(global_lux));
    }
    if (!colour) {
        add_double(m, "sun", "direct_normal_spectral_irradiance", sun.normal_irradiance[0]);
        add_double(m, "sun", "direct_horizontal_spectral_irradiance", sun.horizontal_irradiance[0]);
    }
    if (!colour && hemisphere) {
        add_double(m, "sky", "diffuse_horizontal_spectral_irradiance", diffuse[0]);
        add_double(m, "sky", "global_horizontal_spectral_irradiance", diffuse[0] + sun.horizontal_irradiance[0]);
    }
}
