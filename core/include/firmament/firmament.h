/* firmament: a physically based, spectral sky generator.
 *
 * The library path-traces sunlight through a spherical, horizontally homogeneous atmosphere
 * (U.S. Standard Atmosphere 1976 molecules, ozone; aerosols come as further constituents) and
 * returns the sky's radiance as seen from one observer.
 *
 * Usage:
 *     fm_sky_params sp = fm_sky_params_default();      sp.sun_elevation_deg = 10;
 *     fm_sky *sky;  fm_error err;
 *     if (fm_sky_create(&sp, &sky, &err) != FM_OK) { puts(err.message); ... }
 *     fm_render_params rp = fm_render_params_default();  rp.width = 1024;
 *     fm_output *out;
 *     fm_output_open("sky.exr", "sky.json", &out, &err);  (fails early on an unwritable path)
 *     fm_image *img;
 *     fm_render(sky, &rp, &img, &err);                    (CIE XYZ or spectral radiance)
 *     fm_image_to_rec709(img, &err);
 *     fm_output_commit(out, img, NULL, &err);
 *     fm_output_close(out);  fm_image_destroy(img);  fm_sky_destroy(sky);
 *
 * Conventions (ARCHITECTURE.md section 4): right-handed axes, +Z up, +Y north, +X east; azimuth from
 * north toward east.  Radiance is spectral radiance in W m^-2 sr^-1 nm^-1; colour images hold
 * CIE-weighted radiance (Y * 683 = luminance in cd/m^2).  Equirectangular maps use Blender's
 * Environment Texture layout: column u = 0.25 + azimuth/360, top row = zenith.
 *
 * Errors: every function that can fail returns an fm_status and fills an fm_error with one line
 * naming the problem.  The library never prints and never exits.
 */
#ifndef FIRMAMENT_H
#define FIRMAMENT_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum fm_status {
    FM_OK = 0,
    FM_ERR_INVALID_ARGUMENT, /* a parameter outside its physical or practical range */
    FM_ERR_IO,               /* a file could not be created, written or read */
    FM_ERR_OUT_OF_MEMORY,
    FM_ERR_CANCELLED,        /* the caller's cancel flag was raised */
    FM_ERR_INTERNAL
} fm_status;

typedef struct fm_error {
    fm_status status;
    char parameter[48]; /* the offending fm_sky_params / fm_render_params field, or "" */
    char message[512];  /* one line; for a parameter it starts with "<field>: " */
} fm_error;

/* Name of a status code, e.g. "invalid argument". */
const char *fm_status_name(fm_status status);

/* The range of a numeric parameter, by the name fm_error.parameter gives it ("sun_elevation_deg",
 * "width", "camera.fov_deg"): the one table that the library's validation, the sky-preset reader
 * and the executable's options (`firmament options --json`) read. */
typedef struct fm_param_range {
    const char *field;
    double min, max;
    int min_open;     /* nonzero: min itself is outside, (min, max] */
    const char *unit; /* "degrees", "m", ... or "" */
} fm_param_range;

/* NULL when the library checks no interval for field. */
const fm_param_range *fm_param_range_of(const char *field);

/* ---------------------------------------------------------------------------------------------
 * The sky: atmosphere, sun and observer.  Shared read-only by render threads; only fm_sky_set_sun and
 * fm_sky_set_time (below) change it, between renders. */

typedef enum fm_aerosol_phase {
    FM_AEROSOL_PHASE_MIE = 0, /* the tabulated Mie phase function of the mixture, per wavelength */
    FM_AEROSOL_PHASE_HG       /* Henyey-Greenstein with the mixture's Mie asymmetry parameter g */
} fm_aerosol_phase;

/* sun_elevation_deg, sun_azimuth_deg: from the date, time and place; earth_sun_distance_au: the
 * date's, with or without a time (1 AU without a date). */
#define FM_SUN_FROM_TIME (-1000.0)
/* hour: no time of day. */
#define FM_NO_TIME (-1)
/* delta_t_s: the Espenak & Meeus estimate for the date. */
#define FM_DELTA_T_ESTIMATE (-1.0e9)
/* ozone_column_du: take the column from the climatology for the date and place. */
#define FM_OZONE_FROM_CLIMATOLOGY (-1.0)
/* humidity_percent: the biome's own default humidity. */
#define FM_HUMIDITY_BIOME_DEFAULT (-1.0)
/* cloud_base_km: the cloud file's own base. */
#define FM_CLOUD_BASE_FROM_FILE (-1.0)
/* At most this many cloud layers (clouds, fog_visibility_m). */
#define FM_MAX_CLOUD_LAYERS 4

typedef struct fm_sky_params {
    double sun_elevation_deg;     /* of the sun disk's centre above the horizontal, [-90, 90] */
    double sun_azimuth_deg;       /* from north toward east, [-360, 360] */
    double observer_altitude_m;   /* above the ground, [0, 20000] */
    double ground_albedo;         /* Lambertian reflectance, [0, 1] */
    double ozone_column_du;       /* total ozone column, [0, 1000] Dobson units; 0 disables ozone;
                                   * FM_OZONE_FROM_CLIMATOLOGY: from the date and place below */
    double earth_sun_distance_au; /* scales solar irradiance (1/d^2) and disk size (1/d), [0.95, 1.05];
                                   * default FM_SUN_FROM_TIME: the date's (below), 1 AU without one */
    double wavelength_nm;         /* 0: colour render over 380-780 nm; else one wavelength in [300, 1000] */
    int threads;                  /* for building the sky's tables, [0, 256]; 0 = one per online core */

    /* Date and place (Gregorian calendar; year 0 = no date): the ozone climatology's inputs; the date
     * also gives the Earth-Sun distance (at 12:00 UT) when earth_sun_distance_au is
     * FM_SUN_FROM_TIME, whether the sun is placed by a time or by its angles. */
    int year, month, day;         /* [1900, 2100], [1, 12], [1, days in month] */
    double latitude_deg;          /* [-90, 90], north positive */
    double longitude_deg;         /* [-180, 180], east positive */

    /* Time of day at that date and place (see "Solar position" below).  With a time, every one of
     * sun_elevation_deg, sun_azimuth_deg and earth_sun_distance_au that holds FM_SUN_FROM_TIME is
     * computed: the apparent (refracted, when refraction is on) topocentric elevation and azimuth of
     * the sun's centre (the distance is the date's, as without a time).  A value given instead of
     * FM_SUN_FROM_TIME overrides. */
    int hour;                     /* local clock time [0, 23]; FM_NO_TIME: none */
    int minute;                   /* [0, 59] */
    double second;                /* [0, 60) */
    int utc_offset_min;           /* local time minus UTC in minutes, [-720, 840] (-12:00 to +14:00) */
    int refraction;               /* nonzero: atmospheric refraction lifts the sun (default on) */
    double pressure_mbar;         /* air pressure at the observer for refraction, [0, 2000] (default 1010) */
    double temperature_c;         /* air temperature at the observer for refraction, [-100, 100] (default 10) */
    double delta_t_s;             /* TT - UT in seconds, [-8000, 8000]; FM_DELTA_T_ESTIMATE: estimated */

    /* Aerosols. */
    const char *biome;            /* NULL or "none": no aerosols; else a name in presets/biomes/
                                   * (background, desert-dust, ..., urban) or a path to a biome JSON */
    double turbidity;             /* multiplier of the biome's aerosol number densities, [0, 50]; 1 = nominal */
    double aod550;                /* 0: use turbidity; else scale the biome to this aerosol optical depth
                                   * at 550 nm, (0, 10] */
    double humidity_percent;      /* relative humidity for hygroscopic growth, [0, 99];
                                   * FM_HUMIDITY_BIOME_DEFAULT: the biome's own */
    fm_aerosol_phase aerosol_phase;

    /* Clouds (docs/clouds.md): horizontally uniform layers over the built-in or a custom atmosphere.
     * The numbers below set the first listed layer (its file gives the rest); 0 / the sentinel: the
     * file's own. */
    const char *clouds;           /* NULL or "": none; else comma-separated cloud layers, each a name
                                   * in presets/clouds/ (stratus, ..., cirrus) or a cloud JSON file */
    double cloud_tau550;          /* optical depth at 550 nm, (0, 100] */
    double cloud_lwp_gm2;         /* instead of cloud_tau550: liquid water path, (0, 1000] g m^-2 */
    double cloud_base_km;         /* above the ground, [0, 20]; FM_CLOUD_BASE_FROM_FILE: the file's */
    double cloud_thickness_km;    /* [0.1, 10] */
    double fog_visibility_m;      /* 0: no fog; else a fog layer on the ground (presets/clouds/fog.json,
                                   * or the listed fog) of this visibility, [10, 10000] m (Koschmieder:
                                   * extinction 3.912 / V at 550 nm) */

    /* A custom atmosphere (docs/atmosphere-file.md): replaces the built-in molecules, ozone and
     * aerosols.  NULL = the built-in Earth atmosphere. */
    const char *atmosphere_file;
    /* Where biome names are looked up; NULL = $FIRMAMENT_PRESETS, else the presets/ shipped beside the
     * executable, else the source tree's (docs/packaging.md). */
    const char *presets_dir;
    /* Where computed cloud optics are kept between builds (docs/clouds.md, "Optics"): the folder
     * (created when missing) of files keyed by everything they depend on; NULL or "": computed at
     * every build.  The executable gives $XDG_CACHE_HOME/firmament, as `serve` does. */
    const char *cache_dir;
} fm_sky_params;

fm_sky_params fm_sky_params_default(void);

/* The usual cache folder (cache_dir above; `firmament serve`'s atmospheres): $XDG_CACHE_HOME/firmament,
 * else ~/.cache/firmament (Windows: %LOCALAPPDATA%\firmament); 0, or -1 when none of those variables
 * is set. */
int fm_default_cache_dir(char *out, size_t size);

/* A ready-made sky (README, "Sky presets"): presets/skies/NAME.json, or a file, a flat JSON
 * object of render options (the keys of fm_sky_preset_keys) plus "name" and an optional
 * "description".  Loading checks keys, types and ranges (fm_param_range_of); each setting comes
 * back as text, in the order of fm_sky_preset_keys, for the caller to apply as options. */
typedef struct fm_preset_setting {
    char key[32];   /* "turbidity" */
    char value[64]; /* "2" */
} fm_preset_setting;

typedef struct fm_sky_preset {
    char name[96];  /* "Golden hour" */
    char path[1024];
    int count;
    fm_preset_setting settings[32];
} fm_sky_preset;

/* presets_dir: where names are looked up (NULL: $FIRMAMENT_PRESETS, else the presets/ shipped beside
 * the executable, else the source tree's); a malformed file fails with "preset: FILE: $.key: problem". */
fm_status fm_sky_preset_load(const char *name_or_path, const char *presets_dir, fm_sky_preset *out, fm_error *err);
/* The keys a preset may hold besides "name" and "description", NULL-terminated: each is an option of
 * `firmament render` written with '_' for '-' ("sun_elevation" for --sun-elevation). */
const char *const *fm_sky_preset_keys(void);
/* "background, desert-dust, ...": the names of the built-in biomes (presets/biomes/), sorted;
 * presets_dir as in fm_sky_params.  No presets folder or no biome in it: FM_ERR_INVALID_ARGUMENT
 * with one line naming the folder, out empty. */
fm_status fm_biome_names(const char *presets_dir, char *out, size_t size, fm_error *err);
/* "altostratus, cirrostratus, ...": the cloud layers of presets/clouds/, alike. */
fm_status fm_cloud_names(const char *presets_dir, char *out, size_t size, fm_error *err);

typedef struct fm_sky fm_sky;

/* The sky keeps params' strings (biome, clouds, file and folder paths) by pointer: they must outlive
 * it.  fm_sky_live_create copies them (a live sky outlives the request that made it). */
fm_status fm_sky_create(const fm_sky_params *params, fm_sky **out, fm_error *err);
void fm_sky_destroy(fm_sky *sky); /* accepts NULL */
const fm_sky_params *fm_sky_get_params(const fm_sky *sky);

/* Direct sunlight at the observer, integrated over the visible part of the limb-darkened disk and
 * attenuated along each line of sight.  For a colour sky the three values are CIE X, Y, Z of the
 * irradiance (W m^-2, Y * 683 = lux); for a monochromatic sky [0] is the spectral irradiance in
 * W m^-2 nm^-1 and [1], [2] are 0. */
typedef struct fm_sun_light {
    double direction[3];          /* unit vector toward the disk's centre, map axes (+X east, +Y north, +Z up) */
    double angular_radius_deg;    /* of the disk at the given Earth-Sun distance */
    double normal_irradiance[3];  /* on a surface facing the sun */
    double horizontal_irradiance[3]; /* on a horizontal surface */
    double cloud_transmittance;   /* exp(-optical depth at 550 nm) of the cloud layers along the line to
                                   * the disk's centre; 1 without clouds, 0 with the sun below the horizon
                                   * (the irradiances above already include it, at every wavelength) */
} fm_sun_light;

void fm_sky_sun_light(const fm_sky *sky, fm_sun_light *out);

/* What the atmosphere holds, as the sidecar reports it.  Optical depths are vertical, from the
 * ground to the top, at 550 nm (computed at 550 nm whatever the render's spectral grid). */
typedef struct fm_composition {
    double rayleigh_tau550;
    double ozone_tau550;
    double aerosol_tau550;
    double aerosol_angstrom;      /* -dln(tau)/dln(lambda) between 440 and 870 nm; 0 without aerosols */
    double aerosol_ssa550;        /* column single-scattering albedo at 550 nm; 1 without aerosols */
    double aerosol_g550;          /* column asymmetry parameter at 550 nm */
    double ozone_column_du;       /* used (from the climatology or as given) */
    char ozone_profile[32];       /* AFGL profile shape: "us-standard", "tropical", "midlatitude-summer", ... */
    double humidity_percent;      /* used for hygroscopic growth; -1 without aerosols */
    double turbidity;             /* number-density multiplier actually applied (also when aod550 set it) */
    double rayleigh_ext550_ground_per_km; /* extinction coefficients at 550 nm at the ground (altitude 0) */
    double aerosol_ext550_ground_per_km;
    double visibility_km;         /* Koschmieder: 3.912 / the two above (2% contrast); 0 when unknown */
    char biome[64];               /* "none", a biome name, or "custom" for an atmosphere file */
    int cloud_count;              /* cloud layers, bottom to top as listed */
    struct {
        char type[32];            /* stratus, ..., cirrus */
        double tau550;            /* vertical optical depth at 550 nm */
        double base_m, thickness_m;
    } cloud[FM_MAX_CLOUD_LAYERS];
} fm_composition;

void fm_sky_composition(const fm_sky *sky, fm_composition *out);
/* The composition fm_sky_create would give, without its tables (milliseconds): the parameters
 * checked alike, the atmosphere built at 550 nm only. */
fm_status fm_composition_compute(const fm_sky_params *params, fm_composition *out, fm_error *err);

/* ---------------------------------------------------------------------------------------------
 * Solar position: NREL's Solar Position Algorithm (I. Reda and A. Andreas, Solar Energy 76 (2004)
 * 577-589; NREL/TP-560-34302), uncertainty +-0.0003 degrees for the years -2000 to 6000 with the
 * right Delta T (the estimate's error, e.g. 1 s, moves the sun by 1 s / 240 s per degree = 0.004
 * degrees).  Refraction: SPA's Saemundsson-type formula scaled by pressure and temperature, applied
 * while the true elevation is at least -0.8333 degrees (below, none).  Sunrise and sunset: the sun's
 * centre at -0.8333 degrees apparent elevation (refraction 34' plus the radius 16'), for the local
 * date. */

typedef struct fm_solar_params {
    int year, month, day;         /* local date, years [-2000, 6000]: Gregorian calendar from
                                   * 1582-10-15, Julian before (as SPA) */
    int hour, minute;             /* local clock time, [0, 23], [0, 59] */
    double second;                /* [0, 60) */
    int utc_offset_min;           /* local time minus UTC in minutes, [-720, 840] */
    double latitude_deg;          /* [-90, 90], north positive */
    double longitude_deg;         /* [-180, 180], east positive */
    double elevation_m;           /* observer above sea level, [-1000, 100000] */
    double pressure_mbar;         /* for refraction, [0, 2000] */
    double temperature_c;         /* for refraction, [-100, 100] */
    double delta_t_s;             /* TT - UT, [-8000, 8000] s, or FM_DELTA_T_ESTIMATE */
    int refraction;               /* nonzero: apply refraction */
} fm_solar_params;

/* 2000-01-01 12:00 UTC at 0 N 0 E, sea level, 1010 mbar, 10 C, Delta T estimated, refraction on. */
fm_solar_params fm_solar_params_default(void);

typedef enum fm_daylight {
    FM_DAYLIGHT_NORMAL = 0,       /* the sun rises and sets on this date */
    FM_DAYLIGHT_POLAR_DAY,        /* it stays above -0.8333 degrees all day */
    FM_DAYLIGHT_POLAR_NIGHT       /* it stays below all day */
} fm_daylight;

typedef struct fm_solar_position {
    double zenith_deg;            /* topocentric, of the sun's centre; refracted when refraction is on */
    double azimuth_deg;           /* [0, 360), from north toward east */
    double elevation_deg;         /* 90 - zenith_deg: the apparent elevation with refraction on */
    double elevation_true_deg;    /* topocentric elevation without refraction */
    double declination_deg;       /* geocentric apparent declination */
    double right_ascension_deg;   /* geocentric apparent right ascension, [0, 360) */
    double earth_sun_distance_au; /* at the given time */
    double equation_of_time_min;  /* apparent minus mean solar time */
    double delta_t_s;             /* the Delta T used */
    double julian_day;            /* of the given time, UT */
    fm_daylight daylight;
    double sunrise_h;             /* local clock hours of the date, [0, 24); -1 in polar day or night */
    double transit_h;             /* solar noon (the sun on the meridian), always given */
    double sunset_h;              /* as sunrise_h */
} fm_solar_position;

/* Computes the sun's position for the time and place; fails naming the field of a bad input
 * ("date", "time", "utc_offset_min", "latitude_deg", ...). */
fm_status fm_solar_position_compute(const fm_solar_params *params, fm_solar_position *out, fm_error *err);

/* ---------------------------------------------------------------------------------------------
 * Changing the sun of an existing sky.  What depends on the sun's direction is only the direction
 * itself (and the parameters that record it): the atmosphere, the aerosol optics, the column and
 * sun-transmittance tables (tabulated over every sun zenith angle) and the sun disk (its size
 * depends on the Earth-Sun distance only) are kept, so a time series renders from one fm_sky.  A
 * render after a change is bit-identical to one from a new fm_sky with that sun.  Not while a render
 * of this sky runs. */

/* Puts the sun's centre at the given elevation and azimuth (ranges as in fm_sky_params); from now
 * on the sun counts as given, not computed from the time. */
fm_status fm_sky_set_sun(fm_sky *sky, double elevation_deg, double azimuth_deg, fm_error *err);

/* Sets a new local time of day on the sky's date (it needs a date and a place, and keeps them):
 * the sun's elevation and azimuth follow when they came from the time (FM_SUN_FROM_TIME); the
 * Earth-Sun distance is the day's and stays. */
fm_status fm_sky_set_time(fm_sky *sky, int hour, int minute, double second, fm_error *err);

/* params with each of sun_elevation_deg, sun_azimuth_deg and earth_sun_distance_au that holds
 * FM_SUN_FROM_TIME computed from the date, time and place (the distance from the date alone, 1 AU
 * without a date), as fm_sky_create computes them; the rest copied.  For callers that place the sun themselves (fm_sky_live_render). */
fm_status fm_sky_params_resolve_sun(const fm_sky_params *params, fm_sky_params *out, fm_error *err);

/* Which sky parameters came from the solar position. */
#define FM_SUN_COMPUTED_ELEVATION 1u
#define FM_SUN_COMPUTED_AZIMUTH 2u
#define FM_SUN_COMPUTED_DISTANCE 4u /* the date's distance (with or without a time) */
#define FM_SUN_MEAN_DISTANCE 8u     /* not a bit of the above: 1 AU, for want of a date */

/* The solar position of a sky with a time of day: fills *out and returns 1; returns 0 for a sky
 * without a time.  Either way *computed (may be NULL) gets the FM_SUN_COMPUTED_* bits and
 * FM_SUN_MEAN_DISTANCE (without a time only the distance's can be set). */
int fm_sky_solar_position(const fm_sky *sky, fm_solar_position *out, unsigned *computed);

/* ---------------------------------------------------------------------------------------------
 * Rendering. */

typedef enum fm_quality {
    FM_QUALITY_PREVIEW = 0,  /* fast path, coarse: seconds */
    FM_QUALITY_FINAL,        /* fast path, converged: the default */
    FM_QUALITY_REFERENCE     /* per-pixel path tracing, no tables of radiance: slow, for validation */
} fm_quality;

/* Called from the rendering thread that owns the call, never concurrently. */
typedef void (*fm_progress_fn)(void *user, double fraction, const char *stage);

/* Cameras (docs/output.md, "Cameras").  Every camera is a view of the same radiance: a pixel holds the mean
 * radiance over the directions it covers (its footprint), the sun disk included with its energy. */
typedef enum fm_camera_type {
    FM_CAMERA_EQUIRECT = 0, /* the whole sphere in Blender's Environment Texture layout; height = width/2 */
    FM_CAMERA_FISHEYE,      /* the upper hemisphere looking up, square: zenith at the centre, the horizontal
                             * on the inscribed circle, north up and east LEFT (as seen looking up, the
                             * equirect map's unmirrored view); pixels wholly outside the circle are 0 */
    FM_CAMERA_PINHOLE       /* a rectilinear view along a look direction, level horizon (no roll) */
} fm_camera_type;

typedef enum fm_fisheye_projection {
    FM_FISHEYE_EQUIDISTANT = 0, /* radius proportional to the zenith angle theta: r = R theta / 90 deg */
    FM_FISHEYE_EQUISOLID        /* equal-area: r = R sqrt(2) sin(theta / 2) */
} fm_fisheye_projection;

typedef struct fm_camera {
    fm_camera_type type;
    fm_fisheye_projection fisheye_projection; /* fisheye only */
    double fov_deg;            /* pinhole: horizontal field of view, (0, 170] */
    double look_azimuth_deg;   /* pinhole: image centre, from north toward east, [-360, 360] */
    double look_elevation_deg; /* pinhole: image centre, [-90, 90]; the image's up is toward the zenith */
    double aspect;             /* pinhole: width / height > 0; height = width / aspect rounded to an even
                                * number in [8, 16384] */
} fm_camera;

/* Image height for a camera and width (width / 2, width, or width / aspect rounded to even);
 * 0 when the camera's parameters give none. */
int fm_camera_height(const fm_camera *camera, int width);

typedef struct fm_render_params {
    int width;                /* image width in pixels, even, [8, 16384]; height from the camera */
    fm_camera camera;         /* default: equirect (and, for a pinhole, 90 deg looking south 15 deg up, 16:9) */
    fm_quality quality;
    uint64_t seed;            /* same seed and thread count: bit-identical output */
    int threads;              /* worker threads, [0, 256]; 0 = one per online core */
    int sun_disk;             /* nonzero: the sun disk is part of the map */
    int spectral;             /* colour skies: keep the spectral radiance at every wavelength of the
                               * grid (FM_IMAGE_SPECTRAL_GRID, 41 channels: 41 x the memory) */
    double sample_scale;      /* multiplies every sample count of the quality level, (0, 1024] */
    int reference_samples;    /* reference quality: paths per pixel; 0 = default */
    fm_progress_fn progress;  /* may be NULL */
    void *progress_user;
    const atomic_int *cancel; /* may be NULL; when it becomes nonzero the render stops early */
} fm_render_params;

fm_render_params fm_render_params_default(void);

typedef enum fm_image_content {
    FM_IMAGE_XYZ = 0,          /* 3 channels, CIE 1931 XYZ of spectral radiance (Y * 683 = cd/m^2) */
    FM_IMAGE_RGB_REC709,       /* 3 channels, linear Rec.709 / sRGB primaries, D65, same scale */
    FM_IMAGE_SPECTRAL_RADIANCE, /* 1 channel, W m^-2 sr^-1 nm^-1 at the sky's single wavelength */
    FM_IMAGE_RGB,               /* 3 channels, the linear colour space named in fm_image.colorspace */
    FM_IMAGE_SPECTRAL_GRID      /* `wavelengths` channels, W m^-2 sr^-1 nm^-1 at lambda_nm[] */
} fm_image_content;

#define FM_IMAGE_MAX_WAVELENGTHS 48

/* What a map reports of the render that made it (the sidecar and the EXR header): gathered once by
 * fm_render, from the sky and the render parameters as they were then, and carried by the image,
 * so that writing the map calls nothing back. */
typedef struct fm_render_record {
    int rendered;                /* 1 when fm_render filled it; 0 for an image read from a file */
    fm_sky_params sky;           /* the sky's resolved parameters, their string fields NULL: */
    char atmosphere_file[4096];  /* the custom atmosphere's path, "" for the built-in one */
    fm_composition composition;
    fm_sun_light sun;            /* direct sunlight at the observer */
    int has_solar;               /* the sky had a time of day: */
    fm_solar_position solar;     /* its solar position, and which of the sun's */
    unsigned sun_computed;       /* parameters came from it (FM_SUN_COMPUTED_* bits, FM_SUN_MEAN_DISTANCE) */
    fm_quality quality;
    uint64_t seed;
    double sample_scale;
    int threads;                 /* the render's worker threads (not reported: the writer's too) */
} fm_render_record;

typedef struct fm_image {
    int width, height, channels;
    fm_image_content content;
    float *pixels;        /* row-major, top row first, channels interleaved */
    float *sun_disk;      /* the disk's share of `pixels` (same layout) or NULL when none was drawn */
    double sun_direction[3]; /* toward the sun in map axes when known (rendered, or read from the
                              * firmament.sun.direction attribute), else 0, 0, 0 */
    float *std_error;     /* reference quality only: standard error of each pixel's XYZ (or spectral)
                           * value, left in XYZ by fm_image_to_rec709; else NULL */
    fm_camera camera;     /* the camera that made it (read back from firmament's attributes; equirect
                           * for other files) */
    int paths_per_node;   /* preview and final renders: the multiple-scattering table's paths per
                           * node (the quality's, x the sample scale, more in deep twilight at final
                           * quality); else 0 */
    /* FM_IMAGE_RGB only (set by fm_image_to_colorspace): the OpenColorIO colour space, its CIE xy
     * chromaticities R, G, B, W (XYZ spaces: R (1,0), G (0,1), B (0,0), W (1/3,1/3)) and the
     * matrix from its values to CIE XYZ (rows X, Y, Z). */
    char colorspace[64];
    float chromaticities[8];
    double rgb_to_xyz[3][3];
    /* FM_IMAGE_SPECTRAL_GRID only: the wavelengths of the channels and the weights that integrate
     * them to XYZ (XYZ = sum over k of L_k xyz_weight[k], the renderer's own quadrature). */
    int wavelengths;
    double lambda_nm[FM_IMAGE_MAX_WAVELENGTHS];
    double xyz_weight[FM_IMAGE_MAX_WAVELENGTHS][3];
    fm_render_record record;
} fm_image;

/* Renders the sky through the camera of params (an equirectangular map by default).  The result holds
 * XYZ (colour skies) or spectral radiance. */
fm_status fm_render(const fm_sky *sky, const fm_render_params *params, fm_image **out, fm_error *err);

/* The reference estimate of chosen pixels of the equirect map only (what the reference quality
 * renders there, at the same seed: params->reference_samples paths per pixel through jittered
 * positions in it, default 256): for a converged reference of a few hundred pixels (bench/).  out
 * gets each pixel's channels (CIE XYZ for colour skies, else spectral radiance), se (may be NULL)
 * their standard errors; count x channels floats each. */
fm_status fm_render_pixels(const fm_sky *sky, const fm_render_params *params, int count, const int *x, const int *y,
                           float *out, float *se, fm_error *err);
void fm_image_destroy(fm_image *image); /* accepts NULL */

/* ---------------------------------------------------------------------------------------------
 * The live sky (docs/rendering.md, "Live sky"): what makes any sun position cheap, built once per
 * atmosphere, then a map per sun in milliseconds.  The atmosphere is every field of fm_sky_params
 * but the sun's position and the time of day (the date still counts: the ozone profile and the
 * Earth-Sun distance of the day). */

typedef struct fm_sky_live fm_sky_live;

/* Builds the live sky for the atmosphere of params (its sun position and time of day ignored):
 * every sun elevation's tables but those below the horizon (suns below 1 degree read them), which the
 * first map that reads them builds (about half the whole build; fm_sky_live_complete builds
 * them now).  Maps are the same bits whenever that band is built.  cancel (may be NULL) stops the
 * build early with FM_ERR_CANCELLED. */
fm_status fm_sky_live_create(const fm_sky_params *params, const atomic_int *cancel, fm_sky_live **out,
                             fm_error *err);
/* A map for one sun position (ranges as in fm_sky_params), laid out as fm_render gives it and with
 * its render record, so that fm_output writes it with its sidecar.  render: width, camera, sun disk,
 * threads, progress and cancel as for fm_render (cancel also stops the build of the tables the map
 * reads first: fm_sky_live_prepare).  Threads may render one live sky at once: one builds what the
 * others' maps wait for. */
fm_status fm_sky_live_render(fm_sky_live *live, double sun_elevation_deg, double sun_azimuth_deg,
                             const fm_render_params *render, fm_image **out, fm_error *err);
/* Builds the tables that a map for a sun at sun_elevation_deg reads and that are not built yet (the
 * twilight band, left by fm_sky_live_create), as fm_sky_live_render does first; *built (may be
 * NULL) says whether it built them: so a caller times that build apart from the map, or saves the
 * tables after it.  On failure the band stays to be built. */
fm_status fm_sky_live_prepare(fm_sky_live *live, double sun_elevation_deg, const atomic_int *cancel, int *built,
                              fm_error *err);
/* Builds every table left for first use (nothing when there is none). */
fm_status fm_sky_live_complete(fm_sky_live *live, const atomic_int *cancel, fm_error *err);
/* Whether every table is built. */
int fm_sky_live_is_complete(const fm_sky_live *live);
/* The twilight band's tables (suns from -20 to -1 degrees) refined by one more round of paths: each
 * round draws the band's paths again with new seeds, adds them to every band node's estimates
 * before their fit (weighted by paths), refits them and smooths deep twilight again, so that a
 * server idle between requests lowers its noise as a viewport's samples do (docs/rendering.md "Live
 * sky").  A round takes about the band's own build time; a cancelled or failed one leaves the
 * tables as they were, so maps depend only on the number of whole rounds.  Nothing to do (FM_OK)
 * while the band is pending or after the last round (fm_sky_live_refinable).  Not while another
 * thread renders from the live sky. */
fm_status fm_sky_live_refine(fm_sky_live *live, const atomic_int *cancel, fm_error *err);
/* Whether fm_sky_live_refine has a round to add: the band built, of paths, and fewer rounds than
 * the most. */
int fm_sky_live_refinable(const fm_sky_live *live);
/* The rounds of refinement in the twilight band's tables (0: as built; kept in the live sky's file). */
int fm_sky_live_rounds(const fm_sky_live *live);
/* Whether a map at the sun elevation reads the twilight band's tables (suns from -20 to below 1
 * degree): what refinement changes. */
int fm_sky_live_reads_refined(const fm_sky_live *live, double sun_elevation_deg);
/* The atmosphere's key: 32 hex digits (and a NUL) hashing every field that changes the live sky's
 * tables, not the sun, and the library's table version; for cache file names. */
void fm_sky_live_key(const fm_sky_params *params, char out[33]);
/* Writes the live sky to path (a temporary file beside it, renamed when complete: an existing file
 * is replaced whole or kept): the tables built so far, the others marked to be built on first use
 * after fm_sky_live_load.  Safe while another thread renders or builds (it waits for the build). */
fm_status fm_sky_live_save(const fm_sky_live *live, const char *path, fm_error *err);
/* Reads a live sky that fm_sky_live_save wrote for the atmosphere of params.  A file of another
 * atmosphere or version, truncated or corrupt (its checksum) is refused with FM_ERR_INVALID_ARGUMENT
 * and one line saying why; a missing or unreadable one with FM_ERR_IO. */
fm_status fm_sky_live_load(const fm_sky_params *params, const char *path, fm_sky_live **out, fm_error *err);
void fm_sky_live_destroy(fm_sky_live *live); /* accepts NULL */

/* Takes the sun disk out of a map that holds it: its plane (fm_image.sun_disk) is subtracted from
 * the pixels and freed; the map then reports no disk.  Nothing to do for a map without one. */
void fm_image_remove_sun_disk(fm_image *image);

/* The XYZ image of a spectral map (FM_IMAGE_SPECTRAL_GRID): a new image, sun disk plane included,
 * integrated with the image's own weights, so that it equals a colour render's XYZ from the same
 * spectra. */
fm_status fm_image_spectral_to_xyz(const fm_image *spectral, fm_image **xyz, fm_error *err);

/* Converts an XYZ image to linear Rec.709 in place (the fixed sRGB/D65 matrix, no adaptation). */
fm_status fm_image_to_rec709(fm_image *image, fm_error *err);

/* Colour management: every conversion goes through OpenColorIO.  The config is the given path,
 * else $OCIO when set, else firmament's own presets/ocio/config.ocio ("CIE XYZ D65" reference,
 * "CIE XYZ E", "Linear Rec.709", "ACEScg", "ACES2065-1", "sRGB"; display "sRGB", view "Standard").
 * The config must hold the space of the rendered XYZ: a colour space named "CIE XYZ D65" or the
 * role cie_xyz_d65_interchange.  An unreadable config fails with FM_ERR_INVALID_ARGUMENT. */
typedef struct fm_colour_config fm_colour_config;
fm_status fm_colour_config_open(const char *path, fm_colour_config **out, fm_error *err);
void fm_colour_config_close(fm_colour_config *cfg); /* accepts NULL */
const char *fm_colour_config_path(const fm_colour_config *cfg);
int fm_colour_config_count(const fm_colour_config *cfg);
const char *fm_colour_config_name(const fm_colour_config *cfg, int index);

/* Converts an XYZ image in place to a scene-linear colour space of the config (name or alias); the
 * image becomes FM_IMAGE_RGB.  An unknown name fails with a message listing the config's spaces; a
 * non-linear (display-encoded) space is refused: the EXR holds radiance.  std_error stays in XYZ. */
fm_status fm_image_to_colorspace(fm_image *image, const fm_colour_config *cfg, const char *name, fm_error *err);
/* The same checks on the name alone (before a render): FM_OK when fm_image_to_colorspace accepts it. */
fm_status fm_colour_config_check(const fm_colour_config *cfg, const char *name, fm_error *err);

/* Converts n float triples in place between two colour spaces of the config. */
fm_status fm_colour_convert(const fm_colour_config *cfg, const char *src, const char *dst, float *rgb, size_t n,
                            fm_error *err);

/* Applies the config's display/view transform (e.g. "sRGB", "Standard") to n triples in place;
 * src is a colour space of the config, or NULL for the rendered XYZ. */
fm_status fm_colour_display(const fm_colour_config *cfg, const char *src, const char *display, const char *view,
                            float *rgb, size_t n, fm_error *err);

/* Previews: an 8-bit sRGB PNG through the config's display "sRGB", view "Standard", of a colour
 * image (XYZ or FM_IMAGE_RGB) scaled by 2^exposure_ev before the display transform.  Written to
 * a temporary file beside path and renamed: complete or not at all. */
fm_status fm_image_write_preview(const fm_image *image, const fm_colour_config *cfg, const char *path,
                                 double exposure_ev, fm_error *err);
/* The automatic exposure: EV that maps the log-average (geometric mean) luminance of the sky above
 * the horizon, weighted by solid angle and without the sun disk, to 0.18 (18% grey). */
double fm_image_auto_exposure(const fm_image *image);

/* Illuminance-like integral of the sky part (sun disk excluded) over the upper hemisphere seen by a
 * horizontal surface: sum of L cos(zenith) dOmega per channel, in the image's units.  Returns 1 for
 * the cameras that hold the whole upper hemisphere (equirect, fisheye); 0, with out = 0, for a
 * pinhole view. */
int fm_image_diffuse_horizontal(const fm_image *image, double out[3]);

/* Reads a scanline EXR with R, G, B (linear Rec.709) or Y channels, float or half (and the sun's
 * direction from firmament's attributes, when present). */
fm_status fm_image_read_exr(const char *path, fm_image **out, fm_error *err);

/* Comparing a map with a reference b of the same size: per-pixel relative error of luminance (CIE Y,
 * or the value of a one-channel image), e = (Y_a - Y_b) / max(Y_b, F) over pixels with Y_b > 0, where
 * F = 1e-6 times b's mean luminance keeps black pixels (both 0 up to rounding) from dividing by
 * nothing; chromaticity over pixels brighter than F. */
typedef struct fm_comparison {
    long pixels;         /* compared */
    double rms;          /* root mean square of e */
    double p99;          /* 99th percentile of |e| */
    double mean;         /* mean of e: the bias */
    double max;          /* largest |e| */
    double chromaticity; /* mean distance of CIE xy chromaticities (colour images), else 0 */
} fm_comparison;

/* Pixels within exclude_sun_deg of the reference's sun direction are left out (the disk and its
 * immediate surroundings); 0 keeps every pixel. */
fm_status fm_image_compare(const fm_image *a, const fm_image *b, double exclude_sun_deg, fm_comparison *out,
                           fm_error *err);

/* ---------------------------------------------------------------------------------------------
 * Output files.  Both files are written to temporary names in their directories and renamed into
 * place only when complete, so a failure or cancellation never leaves a partial file and never
 * replaces an existing one. */

typedef struct fm_output fm_output;

/* Checks that both paths can be created (before a long render) and reserves temporary files. */
fm_status fm_output_open(const char *exr_path, const char *json_path, fm_output **out, fm_error *err);
/* Writes the EXR (32-bit float) and the JSON sidecar into the temporary files, then renames both.
 * The image must come from fm_render (directly or through the conversions above): what the files
 * report is its record. */
fm_status fm_output_commit(fm_output *output, const fm_image *image, const atomic_int *cancel, fm_error *err);
/* Removes any temporary file left and frees the handle (accepts NULL). */
void fm_output_close(fm_output *output);
/* fm_output_commit in two steps, for files that appear together: _stage writes the EXR and sidecar
 * into their temporary files; _stage_spectral and _stage_preview add a spectral map or a preview PNG
 * (as fm_output_write_spectral and fm_image_write_preview write them) to the output's files; then
 * fm_output_publish renames every staged file of n outputs into place, the sidecars last.  Nothing
 * is renamed until all are complete, and when a rename fails the files replaced before it are put
 * back (from hard links to them; a file system without links loses those) and the new ones removed:
 * all appear, or none, and no existing file is lost. */
fm_status fm_output_stage(fm_output *output, const fm_image *image, const atomic_int *cancel, fm_error *err);
fm_status fm_output_stage_spectral(fm_output *output, const char *path, const fm_image *spectral,
                                   const fm_image *colour, const atomic_int *cancel, fm_error *err);
fm_status fm_output_stage_preview(fm_output *output, const char *path, const fm_image *image,
                                  const fm_colour_config *cfg, double exposure_ev, fm_error *err);
fm_status fm_output_publish(fm_output *const *outputs, int n, fm_error *err);
/* Fails (FM_ERR_IO, one line naming the path) where an output could not be written: an empty path,
 * a directory, an existing file that is not a regular file (a device such as /dev/null, which the
 * final rename would replace), or a directory that refuses a new file.  Leaves nothing behind; for
 * the outputs written beside the map (preview, spectral map), so that they fail before the render. */
fm_status fm_output_check_path(const char *path, fm_error *err);

/* Writes a spectral map (FM_IMAGE_SPECTRAL_GRID) as an EXR in the layout of Fichet, Pacanowski &
 * Wilkie (JCGT 10(3), 2021): one float channel per wavelength, "S0.550,000000nm", header
 * emissiveUnits = "W.m^-2.sr^-1.nm^-1" and spectralLayoutVersion = "1.0", plus the firmament.*
 * attributes of the colour image made from it.  Temporary file renamed: complete or nothing. */
fm_status fm_output_write_spectral(const char *path, const fm_image *spectral, const fm_image *colour,
                                   const atomic_int *cancel, fm_error *err);

/* Every header attribute of an EXR's first part as text (name, OpenEXR type, value): the standard
 * ones (channels, compression, chromaticities, ...) first, then firmament.*, each alphabetically.
 * An unreadable file fails with FM_ERR_INVALID_ARGUMENT. */
typedef void (*fm_exr_attribute_fn)(void *user, const char *name, const char *type, const char *value);
fm_status fm_exr_attributes(const char *path, fm_exr_attribute_fn fn, void *user, fm_error *err);

/* ZIP and PIZ are lossless; DWAA (OpenEXR's default level 45) is lossy and quantises colour
 * channels through half precision, so like half-float output it is refused at commit (parameter
 * "compression") for a map with values beyond 65504 (the sun disk). */
typedef enum fm_exr_compression { FM_EXR_ZIP = 0, FM_EXR_PIZ, FM_EXR_DWAA } fm_exr_compression;
/* The EXR's pixel format, before fm_output_commit: half-float (16-bit) instead of 32-bit float,
 * and the compression (default ZIP).
 * A half map whose values exceed the half range (65504, e.g. the sun disk) is refused at commit
 * with FM_ERR_INVALID_ARGUMENT (parameter "half"), nothing written. */
fm_status fm_output_set_format(fm_output *output, int half, fm_exr_compression compression, fm_error *err);
/* A JSON object (text) written into the sidecar as "job", before fm_output_stage: the batch job that
 * asked for the map (`firmament batch run`), so that a rerun can tell a finished job from another
 * one's file.  Not a JSON object: FM_ERR_INVALID_ARGUMENT. */
fm_status fm_output_set_job(fm_output *output, const char *json_object, fm_error *err);
/* The map as a Radiance RGBE picture (.hdr: image/image_hdr.h) instead of an EXR, before
 * fm_output_stage; its values are the EXR's (firmament's units: luminance = 683 x Y), the header
 * gives the factor 683/179 to Radiance's.  The EXR's compression does not apply; half floats are
 * refused (parameter "format"). */
fm_status fm_output_set_radiance(fm_output *output, fm_error *err);

#ifdef __cplusplus
}
#endif

#endif /* FIRMAMENT_H */
