#include "aerosol/cloud_file.h"

#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"
#include "presets.h"

#include <stdio.h>
#include <string.h>

/* The library's range of a parameter as a JSON interval (one source for files and options). */
static json_interval interval_of(const char *field)
{
    const fm_param_range *r = fm_param_range_of(field);
    return (json_interval){r->min, r->max, r->min_open, 0};
}

fm_status cloud_layer_parse(const json_reader *rd, const cJSON *node, const char *path, cloud_layer *out)
{
    static const char *const keys[] = {"name",   "description", "type",   "base_km", "thickness_km",
                                       "tau550", "lwp_gm2",     "visibility_m", NULL};
    memset(out, 0, sizeof *out);
    fm_status s;
    const char *type;
    if ((s = json_require_object(rd, node, path)) || (s = json_check_keys(rd, node, path, keys)) ||
        (s = json_get_string(rd, node, path, "type", 1, &type)))
        return s;
    out->type = cloud_type_find(type);
    if (!out->type) {
        char names[256], p[JSON_PATH_CHARS];
        cloud_type_names(names, sizeof names);
        json_child_path(p, path, ".type");
        return json_bad(rd, p, "\"%s\" is not a cloud type (%s)", type, names);
    }
    double base_km, thickness_km;
    if ((s = json_required_number(rd, node, path, "base_km", interval_of("cloud_base_km"), &base_km)) ||
        (s = json_required_number(rd, node, path, "thickness_km", interval_of("cloud_thickness_km"), &thickness_km)))
        return s;
    out->base_m = base_km * FM_KM;
    out->thickness_m = thickness_km * FM_KM;
    const char *amounts[] = {"tau550", "lwp_gm2", "visibility_m"};
    const char *fields[] = {"cloud_tau550", "cloud_lwp_gm2", "fog_visibility_m"};
    double *values[] = {&out->tau550, &out->lwp_gm2, &out->visibility_m};
    int given = 0;
    for (int i = 0; i < 3; i++) {
        if (!cJSON_GetObjectItemCaseSensitive(node, amounts[i]))
            continue;
        given++;
        if ((s = json_required_number(rd, node, path, amounts[i], interval_of(fields[i]), values[i])))
            return s;
    }
    if (given != 1)
        return json_bad(rd, path, "give one of \"tau550\", \"lwp_gm2\" and \"visibility_m\"%s",
                        given ? ", not several" : "");
    if (out->lwp_gm2 > 0.0 && out->type->ice)
        return json_bad(rd, path, "\"%s\" is an ice cloud: give \"tau550\", not \"lwp_gm2\"", out->type->name);
    return FM_OK;
}

static fm_status load_layer(const char *name, const char *presets_dir, cloud_layer *out, fm_error *err)
{
    char path[1024];
    fm_status s = presets_find(name, presets_dir, "clouds", "clouds", "cloud", "", path, sizeof path, err);
    if (s)
        return s;
    json_reader rd = {path, "clouds", err};
    cJSON *root = json_reader_load(&rd, &s);
    if (!root)
        return s;
    s = cloud_layer_parse(&rd, root, "$", out);
    cJSON_Delete(root);
    return s;
}

fm_status cloud_params_validate(const fm_sky_params *p, fm_error *err)
{
    fm_status s;
    int listed = p->clouds && p->clouds[0];
    const char *fields[] = {"cloud_tau550", "cloud_lwp_gm2", "cloud_thickness_km", "cloud_base_km"};
    const double values[] = {p->cloud_tau550, p->cloud_lwp_gm2, p->cloud_thickness_km, p->cloud_base_km};
    const int given[] = {values[0] != 0.0, values[1] != 0.0, values[2] != 0.0,
                         values[3] != FM_CLOUD_BASE_FROM_FILE};
    for (int i = 0; i < 4; i++) {
        if (!given[i])
            continue;
        if (!listed)
            return fm_fail_parameter(err, fields[i], "sets the first cloud layer: give clouds (--cloud) too");
        if ((s = param_check(err, fields[i], values[i])))
            return s;
    }
    if (p->cloud_tau550 != 0.0 && p->cloud_lwp_gm2 != 0.0)
        return fm_fail_parameter(err, "cloud_lwp_gm2", "give cloud_tau550 or cloud_lwp_gm2, not both");
    if (p->fog_visibility_m != 0.0 && (s = param_check(err, "fog_visibility_m", p->fog_visibility_m)))
        return s;
    return FM_OK;
}

/* The next comma-separated name of *list (spaces around it dropped) into name; 0 at the end. */
static int next_name(const char **list, char *name, size_t size, fm_error *err, int *too_long)
{
    const char *c = *list;
    while (*c == ' ' || *c == ',')
        c++;
    if (!*c)
        return 0;
    const char *end = strchr(c, ',');
    size_t n = end ? (size_t)(end - c) : strlen(c);
    while (n > 0 && c[n - 1] == ' ')
        n--;
    *too_long = n >= size;
    if (*too_long)
        fm_fail_parameter(err, "clouds", "'%.40s...' is longer than %zu characters", c, size - 1);
    snprintf(name, size, "%.*s", (int)n, c);
    *list = end ? end + 1 : c + strlen(c);
    return 1;
}

/* tau550 from the layer's amount. */
static fm_status resolve_amount(cloud_layer *l, fm_error *err)
{
    fm_status s = FM_OK;
    if (l->lwp_gm2 > 0.0)
        s = cloud_tau_from_lwp(l->type, l->lwp_gm2, &l->tau550, err);
    else if (l->visibility_m > 0.0)
        l->tau550 = CLOUD_KOSCHMIEDER / l->visibility_m * l->thickness_m;
    if (s)
        return s;
    const fm_param_range *r = fm_param_range_of("cloud_tau550");
    if (!(l->tau550 <= r->max))
        return fm_fail_parameter(err, l->lwp_gm2 > 0.0 ? "cloud_lwp_gm2" : "fog_visibility_m",
                                 "the %s layer's optical depth at 550 nm would be %.3g, above %g", l->type->name,
                                 l->tau550, r->max);
    return FM_OK;
}

/* The "clouds" array of a custom atmosphere file (docs/atmosphere-file.md), appended to out. */
static fm_status layers_of_atmosphere_file(const char *path, cloud_layer *out, int *count, fm_error *err)
{
    json_reader rd = {path, "atmosphere_file", err};
    fm_status s;
    cJSON *root = json_reader_load(&rd, &s);
    if (!root)
        return s;
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "clouds"), *item;
    if (list && !(s = json_get_array(&rd, root, "$", "clouds", 1, FM_MAX_CLOUD_LAYERS, "cloud layers", &list))) {
        cJSON_ArrayForEach(item, list)
        {
            char path_in[JSON_PATH_CHARS];
            snprintf(path_in, sizeof path_in, "$.clouds[%d]", *count);
            if ((s = cloud_layer_parse(&rd, item, path_in, &out[*count])))
                break;
            (*count)++;
        }
    }
    cJSON_Delete(root);
    return s;
}

fm_status cloud_layers_from_params(const fm_sky_params *p, cloud_layer *out, int *count, fm_error *err)
{
    *count = 0;
    fm_status s = cloud_params_validate(p, err);
    if (s)
        return s;
    /* the atmosphere file's own layers first; the options' list after them */
    if (p->atmosphere_file && (s = layers_of_atmosphere_file(p->atmosphere_file, out, count, err)))
        return s;
    const int from_file = *count;
    const char *list = p->clouds ? p->clouds : "";
    char name[1024];
    int too_long = 0;
    while (next_name(&list, name, sizeof name, err, &too_long)) {
        if (too_long)
            return FM_ERR_INVALID_ARGUMENT;
        if (*count == FM_MAX_CLOUD_LAYERS)
            return fm_fail_parameter(err, "clouds", "more than %d cloud layers", FM_MAX_CLOUD_LAYERS);
        if ((s = load_layer(name, p->presets_dir, &out[*count], err)))
            return s;
        (*count)++;
    }
    if (*count > from_file) {
        cloud_layer *first = &out[from_file];
        if (p->cloud_base_km != FM_CLOUD_BASE_FROM_FILE)
            first->base_m = p->cloud_base_km * FM_KM;
        if (p->cloud_thickness_km > 0.0)
            first->thickness_m = p->cloud_thickness_km * FM_KM;
        if (p->cloud_tau550 > 0.0 || p->cloud_lwp_gm2 > 0.0) {
            if (p->cloud_lwp_gm2 > 0.0 && first->type->ice)
                return fm_fail_parameter(err, "cloud_lwp_gm2", "'%s' is an ice cloud: give its optical depth",
                                         first->type->name);
            first->tau550 = p->cloud_tau550;
            first->lwp_gm2 = p->cloud_lwp_gm2;
            first->visibility_m = 0.0;
        }
    }
    if (p->fog_visibility_m > 0.0) {
        int fog = 0;
        while (fog < *count && strcmp(out[fog].type->name, "fog") != 0)
            fog++;
        if (fog == *count) {
            if (*count == FM_MAX_CLOUD_LAYERS)
                return fm_fail_parameter(err, "fog_visibility_m", "more than %d cloud layers with the fog",
                                         FM_MAX_CLOUD_LAYERS);
            if ((s = load_layer("fog", p->presets_dir, &out[fog], err)))
                return s;
            (*count)++;
        }
        out[fog].tau550 = out[fog].lwp_gm2 = 0.0;
        out[fog].visibility_m = p->fog_visibility_m;
    }
    for (int i = 0; i < *count; i++)
        if ((s = resolve_amount(&out[i], err)))
            return s;
    return FM_OK;
}
