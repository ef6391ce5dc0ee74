/* A biome ("bioclimatic aerosol environment"): a mixture of OPAC aerosol components in vertical
 * layers, read from a JSON definition (presets/biomes/NAME.json; schema in presets/biomes/README.md).
 * Each layer holds components at number densities given at the layer's bottom, decaying upward
 * with the layer's scale height (or constant), between the layer's bottom and top. */
#ifndef FM_AEROSOL_BIOME_H
#define FM_AEROSOL_BIOME_H

#include "firmament/firmament.h"

#define BIOME_MAX_LAYERS 6
#define BIOME_MAX_COMPONENTS 8

typedef struct biome_component {
    char code[8];      /* OPAC component code, e.g. "waso" */
    double density_m3; /* number density at the layer's bottom, particles m^-3 */
} biome_component;

typedef struct biome_layer {
    char name[48];
    double bottom_m, top_m;  /* altitudes above the ground */
    double scale_height_m;   /* 0: constant density through the layer */
    double humidity_percent; /* fixed humidity of this layer, or < 0: the biome's (ambient) humidity */
    int component_count;
    biome_component component[BIOME_MAX_COMPONENTS];
} biome_layer;

typedef struct biome {
    char name[64];
    double humidity_percent; /* default ambient relative humidity */
    int layer_count;
    biome_layer layer[BIOME_MAX_LAYERS];
} biome;

/* Loads a biome by name (from PRESETS/biomes/NAME.json, PRESETS = presets_dir or, where NULL, the
 * one presets_locate finds) or from a path (anything containing a '/' or ending in ".json").  An unknown name fails listing the known ones. */
fm_status biome_load(const char *name_or_path, const char *presets_dir, biome *out, fm_error *err);

/* The OPAC component codes a biome may use (NULL-terminated). */
extern const char *const biome_component_codes[];

#endif
