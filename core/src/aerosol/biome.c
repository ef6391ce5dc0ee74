#include "aerosol/biome.h"

#include "base/json_file.h"
#include "base/status.h"
#include "base/units.h"

#include <dirent.h>
#include <stdio.h>
#include <string.h>

const char *const biome_component_codes[] = {"inso", "waso", "soot", "ssam", "sscm", "minm",
                                             "miam", "micm", "mitr", "suso", NULL};

/* Layers may reach the stratosphere but not beyond the model atmosphere. */
#define BIOME_TOP_M (50.0 * FM_KM)

static int is_path(const char *s)
{
    size_t n = strlen(s);
    return strchr(s, '/') != NULL || (n > 5 && strcmp(s + n - 5, ".json") == 0);
}

/* "background, desert-dust, ..." from the directory listing, sorted. */
static void known_names(const char *dir, char *out, size_t size)
{
    char names[32][64];
    int count = 0;
    DIR *d = opendir(dir);
    struct dirent *e;
    while (d && (e = readdir(d)) != NULL && count < 32) {
        size_t n = strlen(e->d_name);
        if (n > 5 && n < 64 && strcmp(e->d_name + n - 5, ".json") == 0) {
            snprintf(names[count], sizeof names[count], "%.*s", (int)(n - 5), e->d_name);
            count++;
        }
    }
    if (d)
        closedir(d);
    for (int i = 1; i < count; i++) /* insertion sort: a handful of names */
        for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
            char t[64];
            memcpy(t, names[j], sizeof t);
            memcpy(names[j], names[j - 1], sizeof t);
            memcpy(names[j - 1], t, sizeof t);
        }
    out[0] = '\0';
    size_t used = 0;
    for (int i = 0; i < count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? ", " : "", names[i]);
    if (count == 0)
        snprintf(out, size, "no biome files found in %.400s", dir);
}

static int known_component(const char *code)
{
    for (int i = 0; biome_component_codes[i]; i++)
        if (strcmp(code, biome_component_codes[i]) == 0)
            return 1;
    return 0;
}

static fm_status parse_layer(const cJSON *item, const char *file, const json_path *path, biome_layer *layer,
                             fm_error *err)
{
    static const char *const keys[] = {"name", "bottom_km", "top_km", "scale_height_km", "humidity_percent",
                                       "number_density_cm3", "note", NULL};
    fm_status s;
    if (!cJSON_IsObject(item))
        return json_fail(err, file, path, "must be an object");
    if ((s = json_only_keys(item, keys, file, path, err)))
        return s;
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(item, "name");
    if (!cJSON_IsString(name)) {
        json_path p = json_path_key(path, "name");
        return json_fail(err, file, &p, "missing (a string)");
    }
    snprintf(layer->name, sizeof layer->name, "%s", name->valuestring);
    double bottom_km, top_km, scale_km, rh;
    if ((s = json_number(item, "bottom_km", 0.0, BIOME_TOP_M / FM_KM, 0, 0.0, &bottom_km, file, path, err)) ||
        (s = json_number(item, "top_km", 0.0, BIOME_TOP_M / FM_KM, 0, 0.0, &top_km, file, path, err)) ||
        (s = json_number(item, "scale_height_km", 0.1, 1000.0, 1, 0.0, &scale_km, file, path, err)) ||
        (s = json_number(item, "humidity_percent", 0.0, 99.0, 1, -1.0, &rh, file, path, err)))
        return s;
    if (!(top_km > bottom_km)) {
        json_path p = json_path_key(path, "top_km");
        return json_fail(err, file, &p, "must be above bottom_km (%g)", bottom_km);
    }
    layer->bottom_m = bottom_km * FM_KM;
    layer->top_m = top_km * FM_KM;
    layer->scale_height_m = scale_km * FM_KM;
    layer->humidity_percent = rh;

    json_path pd = json_path_key(path, "number_density_cm3");
    const cJSON *densities = cJSON_GetObjectItemCaseSensitive(item, "number_density_cm3");
    if (!cJSON_IsObject(densities))
        return json_fail(err, file, &pd, "missing (an object of component: particles per cm^3)");
    const cJSON *c;
    layer->component_count = 0;
    cJSON_ArrayForEach(c, densities)
    {
        json_path pc = json_path_key(&pd, c->string);
        if (!known_component(c->string))
            return json_fail(err, file, &pc, "unknown OPAC component (known: inso, waso, soot, ssam, sscm, "
                                             "minm, miam, micm, mitr, suso)");
        if (!cJSON_IsNumber(c) || !(c->valuedouble >= 0.0) || c->valuedouble > 1e7)
            return json_fail(err, file, &pc, "must be a number of particles per cm^3 in [0, 1e7]");
        if (layer->component_count == BIOME_MAX_COMPONENTS)
            return json_fail(err, file, &pc, "more than %d components in one layer", BIOME_MAX_COMPONENTS);
        biome_component *bc = &layer->component[layer->component_count++];
        snprintf(bc->code, sizeof bc->code, "%s", c->string);
        bc->density_m3 = c->valuedouble * 1e6;
    }
    return FM_OK;
}

static fm_status parse_biome(const cJSON *root, const char *file, biome *out, fm_error *err)
{
    static const char *const keys[] = {"name", "description", "opac_mixture", "humidity_percent", "sources",
                                       "layers", "note", NULL};
    json_path root_path = json_path_root();
    fm_status s;
    if (!cJSON_IsObject(root))
        return json_fail(err, file, &root_path, "must be an object");
    if ((s = json_only_keys(root, keys, file, &root_path, err)))
        return s;
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(root, "name");
    if (!cJSON_IsString(name)) {
        json_path p = json_path_key(&root_path, "name");
        return json_fail(err, file, &p, "missing (a string)");
    }
    snprintf(out->name, sizeof out->name, "%s", name->valuestring);
    if ((s = json_number(root, "humidity_percent", 0.0, 99.0, 0, 0.0, &out->humidity_percent, file, &root_path, err)))
        return s;

    json_path pl = json_path_key(&root_path, "layers");
    const cJSON *layers = cJSON_GetObjectItemCaseSensitive(root, "layers");
    if (!cJSON_IsArray(layers) || cJSON_GetArraySize(layers) < 1)
        return json_fail(err, file, &pl, "missing (an array of at least one layer)");
    if (cJSON_GetArraySize(layers) > BIOME_MAX_LAYERS)
        return json_fail(err, file, &pl, "more than %d layers", BIOME_MAX_LAYERS);
    out->layer_count = 0;
    const cJSON *item;
    cJSON_ArrayForEach(item, layers)
    {
        json_path p = json_path_index(&pl, out->layer_count);
        biome_layer *layer = &out->layer[out->layer_count];
        if ((s = parse_layer(item, file, &p, layer, err)))
            return s;
        if (out->layer_count > 0 && layer->bottom_m < out->layer[out->layer_count - 1].top_m) {
            json_path pb = json_path_key(&p, "bottom_km");
            return json_fail(err, file, &pb, "overlaps the layer below (layers go upward without overlap)");
        }
        out->layer_count++;
    }
    return FM_OK;
}

fm_status biome_load(const char *name_or_path, const char *presets_dir, biome *out, fm_error *err)
{
    memset(out, 0, sizeof *out);
    char path[1024];
    if (is_path(name_or_path)) {
        snprintf(path, sizeof path, "%s", name_or_path);
    } else {
        char dir[900];
        snprintf(dir, sizeof dir, "%s/biomes", presets_dir);
        int valid = name_or_path[0] != '\0';
        for (const char *c = name_or_path; *c; c++)
            valid = valid && ((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_');
        snprintf(path, sizeof path, "%s/%s.json", dir, name_or_path);
        FILE *f = valid ? fopen(path, "r") : NULL;
        if (!f) {
            char names[600];
            known_names(dir, names, sizeof names);
            return fm_fail_parameter(err, "biome", "unknown biome '%s' (known: none, %s)", name_or_path, names);
        }
        fclose(f);
    }
    cJSON *root = json_file_read(path, err);
    if (!root)
        return err ? err->status : FM_ERR_INVALID_ARGUMENT;
    fm_status s = parse_biome(root, path, out, err);
    cJSON_Delete(root);
    return s;
}
