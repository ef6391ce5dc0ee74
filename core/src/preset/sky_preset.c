/* Sky presets: presets/skies/NAME.json or a file, one flat JSON object whose keys are render
 * options (README, "Sky presets").  The loader checks keys, types and numeric ranges against the
 * file so that a bad preset is reported with its file and JSON path; the executable then applies the
 * settings as if they were options given before the user's own. */
#include "firmament/firmament.h"

#include "base/date.h"
#include "base/json_file.h"
#include "base/status.h"
#include "presets.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef enum { VALUE_STRING, VALUE_NUMBER } value_kind;

/* Every key a preset may hold besides name and description: the option it stands for, its type and,
 * for numbers, the range the library accepts (repeated here so the message names the file). */
typedef struct preset_key {
    const char *key;
    value_kind kind;
    json_interval range;
} preset_key;

static const preset_key keys[] = {
    {"date", VALUE_STRING, {0, 0, 0, 0}},
    {"time", VALUE_STRING, {0, 0, 0, 0}},
    {"utc_offset", VALUE_STRING, {0, 0, 0, 0}},
    {"latitude", VALUE_NUMBER, {-90.0, 90.0, 0, 0}},
    {"longitude", VALUE_NUMBER, {-180.0, 180.0, 0, 0}},
    {"sun_elevation", VALUE_NUMBER, {-90.0, 90.0, 0, 0}},
    {"sun_azimuth", VALUE_NUMBER, {-360.0, 360.0, 0, 0}},
    {"biome", VALUE_STRING, {0, 0, 0, 0}},
    {"turbidity", VALUE_NUMBER, {0.0, 50.0, 0, 0}},
    {"aod550", VALUE_NUMBER, {0.0, 10.0, 1, 0}},
    {"humidity", VALUE_NUMBER, {0.0, 99.0, 0, 0}},
    {"ozone_du", VALUE_NUMBER, {0.0, 1000.0, 0, 0}},
    {"albedo", VALUE_NUMBER, {0.0, 1.0, 0, 0}},
    {"altitude", VALUE_NUMBER, {0.0, 20000.0, 0, 0}},
    /* the view: a job such as a figure of scenes/thesis/ (the add-on, which always makes a world
     * map, leaves these out) */
    {"camera", VALUE_STRING, {0, 0, 0, 0}},
    {"fisheye_projection", VALUE_STRING, {0, 0, 0, 0}},
    {"fov", VALUE_NUMBER, {0.0, 170.0, 1, 0}},
    {"look_azimuth", VALUE_NUMBER, {-360.0, 360.0, 0, 0}},
    {"look_elevation", VALUE_NUMBER, {-90.0, 90.0, 0, 0}},
    {"aspect", VALUE_STRING, {0, 0, 0, 0}},
    {"width", VALUE_NUMBER, {8.0, 16384.0, 0, 0}},
};
#define KEY_COUNT ((int)(sizeof keys / sizeof keys[0]))

static const char *const allowed[] = {"name",      "description", "date",      "time",     "utc_offset",
                                      "latitude",  "longitude",   "sun_elevation", "sun_azimuth",
                                      "biome",     "turbidity",   "aod550",    "humidity", "ozone_du",
                                      "albedo",    "altitude",    "camera",    "fisheye_projection",
                                      "fov",       "look_azimuth", "look_elevation", "aspect", "width",
                                      NULL};

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
        if (keys[i].kind == VALUE_STRING) {
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
            double x;
            if ((s = json_get_number(rd, v, path, keys[i].range, &x)))
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
    if (is_path(name_or_path)) {
        snprintf(out->path, sizeof out->path, "%s", name_or_path);
    } else {
        char dir[900];
        fm_status found = presets_locate(presets_directory, dir, sizeof dir - 8, err);
        if (found)
            return found;
        strcat(dir, "/skies");
        snprintf(out->path, sizeof out->path, "%s/%s.json", dir, name_or_path);
        FILE *f = valid_name(name_or_path) ? fopen(out->path, "r") : NULL;
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
