/* Sky presets: presets/skies/NAME.json or a file, one flat JSON object whose keys are render
 * options (docs/cli.md, "Sky presets").  The loader checks keys, types and numeric ranges against
 * the file so that a bad preset is reported with its file and JSON path; the executable then
 * applies the settings as if they were options given before the user's own. */
#include "firmament/firmament.h"

#include "base/date.h"
#include "base/json_file.h"
#include "base/platform.h"
#include "base/status.h"
#include "presets.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* Every key a preset may hold besides name and description, in the order settings come back; a
 * number's range is the library's for its field (fm_param_range_of), checked here so that the
 * message names the file. */
typedef struct preset_key {
    const char *key;
    const char *number_field; /* NULL: a string */
} preset_key;

static const preset_key keys[] = {
    {"date", NULL},
    {"time", NULL},
    {"utc_offset", NULL},
    {"latitude", "latitude_deg"},
    {"longitude", "longitude_deg"},
    {"sun_elevation", "sun_elevation_deg"},
    {"sun_azimuth", "sun_azimuth_deg"},
    {"biome", NULL},
    {"turbidity", "turbidity"},
    {"aod550", "aod550"},
    {"humidity", "humidity_percent"},
    {"cloud", NULL},
    {"cloud_tau", "cloud_tau550"},
    {"cloud_lwp", "cloud_lwp_gm2"},
    {"cloud_base", "cloud_base_km"},
    {"cloud_thickness", "cloud_thickness_km"},
    {"fog_visibility", "fog_visibility_m"},
    {"ozone_du", "ozone_column_du"},
    {"albedo", "ground_albedo"},
    {"altitude", "observer_altitude_m"},
    /* the view: a job such as a figure of scenes/thesis/ (the add-on, which always makes a world
     * map, leaves these out) */
    {"camera", NULL},
    {"fisheye_projection", NULL},
    {"fov", "camera.fov_deg"},
    {"look_azimuth", "camera.look_azimuth_deg"},
    {"look_elevation", "camera.look_elevation_deg"},
    {"aspect", NULL},
    {"width", "width"},
};
#define KEY_COUNT ((int)(sizeof keys / sizeof keys[0]))

const char *const *fm_sky_preset_keys(void)
{
    static const char *names[KEY_COUNT + 1];
    for (int i = 0; i < KEY_COUNT; i++)
        names[i] = keys[i].key;
    return names;
}

static int is_path(const char *s)
{
    size_t n = strlen(s);
    return strchr(s, '/') != NULL || (n > 5 && strcmp(s + n - 5, ".json") == 0);
}

static int valid_name(const char *s)
{
    int ok = s[0] != '\0';
    for (const char *c = s; *c; c++)
        ok = ok && ((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_');
    return ok;
}

static fm_status parse_preset(const json_reader *rd, const cJSON *root, fm_sky_preset *out)
{
    fm_status s;
    const char *name = NULL, *description = NULL;
    const char *allowed[KEY_COUNT + 3] = {"name", "description"};
    for (int i = 0; i < KEY_COUNT; i++)
        allowed[i + 2] = keys[i].key;
    if ((s = json_require_object(rd, root, "$")) || (s = json_check_keys(rd, root, "$", allowed)) ||
        (s = json_get_string(rd, root, "$", "name", 1, &name)) ||
        (s = json_get_string(rd, root, "$", "description", 0, &description)))
        return s;
    if (strlen(name) == 0 || strlen(name) >= sizeof out->name)
        return json_bad(rd, "$.name", "must be 1 to %zu characters", sizeof out->name - 1);
    snprintf(out->name, sizeof out->name, "%s", name);
    for (int i = 0; i < KEY_COUNT; i++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, keys[i].key);
        if (!v)
            continue;
        char path[JSON_PATH_CHARS];
        json_child_path(path, "$", ".%s", keys[i].key);
        fm_preset_setting *set = &out->settings[out->count];
        snprintf(set->key, sizeof set->key, "%s", keys[i].key);
        if (!keys[i].number_field) {
            if (!cJSON_IsString(v))
                return json_bad(rd, path, "must be a string, not %s", json_type_name(v));
            if (strlen(v->valuestring) == 0 || strlen(v->valuestring) >= sizeof set->value)
                return json_bad(rd, path, "must be 1 to %zu characters", sizeof set->value - 1);
            snprintf(set->value, sizeof set->value, "%s", v->valuestring);
            int y, m, d;
            char end;
            if (!strcmp(keys[i].key, "date") &&
                (sscanf(v->valuestring, "%4d-%2d-%2d%c", &y, &m, &d, &end) != 3 || !date_is_valid(y, m, d)))
                return json_bad(rd, path, "'%s' is not a date YYYY-MM-DD between %d and %d", v->valuestring,
                                FM_DATE_MIN_YEAR, FM_DATE_MAX_YEAR);
        } else {
            const fm_param_range *r = fm_param_range_of(keys[i].number_field);
            double x;
            if ((s = json_get_number(rd, v, path, (json_interval){r->min, r->max, r->min_open, 0}, &x)))
                return s;
            snprintf(set->value, sizeof set->value, "%.17g", x);
        }
        out->count++;
    }
    if (cJSON_GetObjectItemCaseSensitive(root, "turbidity") && cJSON_GetObjectItemCaseSensitive(root, "aod550"))
        return json_bad(rd, "$.aod550", "give turbidity or aod550, not both");
    return FM_OK;
}


fm_status fm_sky_preset_load(const char *name_or_path, const char *presets_directory, fm_sky_preset *out,
                             fm_error *err)
{
    memset(out, 0, sizeof *out);
    /* never a shortened path: that would read another file */
    if (strlen(name_or_path) >= sizeof out->path - 16)
        return fm_fail_parameter(err, "preset", "'%.60s...' is %zu bytes, longer than the %zu a preset name or path "
                                                "may have",
                                 name_or_path, strlen(name_or_path), sizeof out->path - 17);
    if (is_path(name_or_path)) {
        snprintf(out->path, sizeof out->path, "%s", name_or_path);
    } else {
        char dir[900];
        fm_status found = presets_locate(presets_directory, dir, sizeof dir - 8, err);
        if (found)
            return found;
        strcat(dir, "/skies");
        snprintf(out->path, sizeof out->path, "%s/%s.json", dir, name_or_path);
        FILE *f = valid_name(name_or_path) ? platform_fopen(out->path, "r") : NULL;
        if (!f) {
            char names[700];
            presets_list(dir, "preset", names, sizeof names);
            return fm_fail_parameter(err, "preset", "unknown sky preset '%s' (known: %s)", name_or_path,
                                     names);
        }
        fclose(f);
    }
    json_reader rd = {out->path, "preset", err};
    fm_status s;
    cJSON *root = json_reader_load(&rd, &s);
    if (!root)
        return s;
    s = parse_preset(&rd, root, out);
    cJSON_Delete(root);
    return s;
}
