/* Cloud layers as the user gives them (docs/clouds.md): cloud JSON files (presets/clouds/NAME.json or
 * a path), a list of them in fm_sky_params.clouds with the first layer's overrides and a fog
 * visibility, or the "clouds" array of a custom atmosphere file.  One parser for all of them;
 * numeric ranges are the library's (fm_param_range_of: cloud_tau550, cloud_lwp_gm2, cloud_base_km,
 * cloud_thickness_km, fog_visibility_m). */
#ifndef FM_AEROSOL_CLOUD_FILE_H
#define FM_AEROSOL_CLOUD_FILE_H

#include "aerosol/cloud.h"
#include "base/json_file.h"

/* One layer; its amount is one of tau550, lwp_gm2, visibility_m (the others 0) until
 * cloud_layers_from_params resolves it to tau550. */
typedef struct cloud_layer {
    const cloud_type *type;
    double base_m, thickness_m;
    double tau550, lwp_gm2, visibility_m;
} cloud_layer;

/* A layer object: {"type": T, "base_km": B, "thickness_km": H, and one of "tau550", "lwp_gm2",
 * "visibility_m"} (plus "name", "description").  rd names the file for messages. */
fm_status cloud_layer_parse(const json_reader *rd, const cJSON *node, const char *path, cloud_layer *out);

/* The layers of params (clouds, cloud_*, fog_visibility_m), at most FM_MAX_CLOUD_LAYERS; *count = 0
 * without clouds.  Errors name the parameter ("clouds", "cloud_tau550", ...). */
fm_status cloud_layers_from_params(const fm_sky_params *params, cloud_layer *out, int *count, fm_error *err);

/* Checks the parameters alone (ranges, combinations), without reading any file. */
fm_status cloud_params_validate(const fm_sky_params *params, fm_error *err);

#endif
