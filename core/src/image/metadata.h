/* The numbers that describe a rendered map, gathered once and written both as typed EXR header
 * attributes (image_exr.c) and into the JSON sidecar (sidecar.c). */
#ifndef FM_IMAGE_METADATA_H
#define FM_IMAGE_METADATA_H

#include "firmament/firmament.h"

#define FM_META_MAX 144

typedef enum meta_type { META_DOUBLE, META_INT, META_STRING, META_VEC3 } meta_type;

typedef struct meta_entry {
    const char *group; /* "parameters", "image", "atmosphere", "sun", "sky" or "solar_position" */
    const char *key;
    meta_type type;
    double v[3];
    const char *s;
} meta_entry;

typedef struct metadata {
    int count;
    meta_entry e[FM_META_MAX];
    char seed_text[24];
    char out_name[256];
    char date_text[16];
    fm_composition composition;
    /* the sun from the date and time */
    char time_text[16], offset_text[8], sunrise_text[16], noon_text[16], sunset_text[16], from_time_text[64];
} metadata;

/* Gathers what the image's render record holds and what the image itself gives (its diffuse
 * horizontal illuminance). */
void metadata_collect(metadata *m, const fm_image *img, const char *exr_path);

#endif
