#include "aerosol/biome.h"

#include "base/json_file.h"
#include "base/platform.h"
#include "base/status.h"
#include "base/units.h"
#include "presets.h"

#include <stdio.h>
#include <string.h>

const char *const biome_component_codes[] = {"inso", "waso", "soot", "ssam", "sscm", "minm",
                                             "miam", "micm", "mitr", "suso", NULL};

/* Layers may reach the stratosphere but not beyond the model atmosphere. */
#define BIOME_TOP_M (50.0 * FM_KM)


static int known_component(const char *code)
{
    for (int i = 0; biome_component_codes[i]; i++)
        if (strcmp(code, biome_component_codes[i]) == 0)
            return 1;
    return 0;
}

static const char *const component_list = "inso, waso, soot, ssam, sscm, minm, miam, micm, mitr, suso";

/* {"waso": 7000, ...}: OPAC components and their number densities (particles per cm^3). */
static fm_status parse_densities(const json_reader *rd, const cJSON *densities, const char *path, biome_layer *layer)
{
    fm_status s;
    if ((s = json_require_object(rd, densities, path)))
        return s;
    const cJSON *c;
    cJSON_ArrayForEach(c, densities)
    {
        if (!known_component(c->string))
            return json_bad(rd, path, "unknown OPAC component \"%s\" (known: %s)", c->string, component_list);
    }
    if ((s = json_check_keys(rd, densities, path, biome_component_codes))) /* repeated components */
        return s;
    const json_interval density_cm3 = {0.0, 1e7, 0, 0};
    layer->component_count = 0;
    cJSON_ArrayForEach(c, densities)
    {
        char pc[JSON_PATH_CHARS];
        json_child_path(pc, path, ".%s", c->string);
        if (layer->component_count == BIOME_MAX_COMPONENTS)
            return json_bad(rd, path, "more than %d components in one layer", BIOME_MAX_COMPONENTS);
        biome_component *bc = &layer->component[layer->component_count];
        if ((s = json_get_number(rd, c, pc, density_cm3, &bc->density_m3)))
            return s;
        snprintf(bc->code, sizeof bc->code, "%s", c->string);
        bc->density_m3 *= 1e6; /* per cm^3 to per m^3 */
        layer->component_count++;
    }
    return FM_OK;
}

/* two steps of the 50 m grid that atmosphere/profile.h samples profiles on: a thinner layer would
 * lose its optical depth between the samples */
#define MIN_LAYER_M 100.0

static fm_status parse_layer(const json_reader *rd, const cJSON *item, const char *path, biome_layer *layer)
{
    static const char *const keys[] = {"name", "bottom_km", "top_km", "scale_height_km", "humidity_percent",
                                       "number_density_cm3", "note", NULL};
    const json_interval altitude_km = {0.0, BIOME_TOP_M / FM_KM, 0, 0}, scale_height_km = {0.1, 1000.0, 0, 0},
                        humidity = {0.0, 99.0, 0, 0};
    fm_status s;
    const char *name;
    if ((s = json_require_object(rd, item, path)) || (s = json_check_keys(rd, item, path, keys)) ||
        (s = json_get_string(rd, item, path, "name", 1, &name)))
        return s;
    snprintf(layer->name, sizeof layer->name, "%s", name);
    double bottom_km, top_km, scale_km, rh;
    if ((s = json_required_number(rd, item, path, "bottom_km", altitude_km, &bottom_km)) ||
        (s = json_required_number(rd, item, path, "top_km", altitude_km, &top_km)) ||
        (s = json_optional_number(rd, item, path, "scale_height_km", scale_height_km, 0.0, &scale_km)) ||
        (s = json_optional_number(rd, item, path, "humidity_percent", humidity, -1.0, &rh)))
        return s;
    if (!(top_km - bottom_km >= MIN_LAYER_M / FM_KM)) {
        char p[JSON_PATH_CHARS];
        json_child_path(p, path, ".top_km");
        if (!(top_km > bottom_km))
            return json_bad(rd, p, "must be above bottom_km (%g), not %g", bottom_km, top_km);
        return json_bad(rd, p, "must be at least %g km above bottom_km (%g) (a thinner layer falls between the "
                               "altitude grid's 50 m steps), not %.15g",
                        MIN_LAYER_M / FM_KM, bottom_km, top_km);
    }
    layer->bottom_m = bottom_km * FM_KM;
    layer->top_m = top_km * FM_KM;
    layer->scale_height_m = scale_km * FM_KM; /* 0: constant through the layer */
    layer->humidity_percent = rh;             /* -1: the ambient humidity */

    const cJSON *densities = cJSON_GetObjectItemCaseSensitive(item, "number_density_cm3");
    if (!densities)
        return json_bad(rd, path, "missing \"number_density_cm3\"");
    char pd[JSON_PATH_CHARS];
    json_child_path(pd, path, ".number_density_cm3");
    return parse_densities(rd, densities, pd, layer);
}

static fm_status parse_biome(const json_reader *rd, const cJSON *root, biome *out)
{
    static const char *const keys[] = {"name", "description", "opac_mixture", "humidity_percent", "sources",
                                       "layers", "note", NULL};
    const json_interval humidity = {0.0, 99.0, 0, 0};
    fm_status s;
    const char *name;
    const cJSON *layers;
    if ((s = json_require_object(rd, root, "$")) || (s = json_check_keys(rd, root, "$", keys)) ||
        (s = json_get_string(rd, root, "$", "name", 1, &name)))
        return s;
    snprintf(out->name, sizeof out->name, "%s", name);
    if ((s = json_required_number(rd, root, "$", "humidity_percent", humidity, &out->humidity_percent)) ||
        (s = json_get_array(rd, root, "$", "layers", 1, BIOME_MAX_LAYERS, "layers", &layers)))
        return s;
    out->layer_count = 0;
    const cJSON *item;
    cJSON_ArrayForEach(item, layers)
    {
        char p[JSON_PATH_CHARS];
        snprintf(p, sizeof p, "$.layers[%d]", out->layer_count);
        biome_layer *layer = &out->layer[out->layer_count];
        if ((s = parse_layer(rd, item, p, layer)))
            return s;
        if (out->layer_count > 0 && layer->bottom_m < out->layer[out->layer_count - 1].top_m) {
            char pb[JSON_PATH_CHARS];
            json_child_path(pb, p, ".bottom_km");
            return json_bad(rd, pb, "overlaps the layer below (layers go upward without overlap)");
        }
        out->layer_count++;
    }
    return FM_OK;
}

fm_status biome_load(const char *name_or_path, const char *presets_dir, biome *out, fm_error *err)
{
    memset(out, 0, sizeof *out);
    char path[1024];
    fm_status found = presets_find(name_or_path, presets_dir, "biomes", "biome", "biome", "none, ", path, sizeof path,
                                   err);
    if (found)
        return found;
    json_reader rd = {path, "biome", err};
    fm_status s;
    cJSON *root = json_reader_load(&rd, &s);
    if (!root)
        return s;
    s = parse_biome(&rd, root, out);
    cJSON_Delete(root);
    return s;
}
