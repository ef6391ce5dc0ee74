/* fm_exr_attributes: an EXR's header as text, for `firmament info`: the standard attributes first,
 * then firmament.* (and any other), each group in alphabetical order. */
#include "base/status.h"
#include "image/image.h"

#include <openexr.h>
#include <stdio.h>
#include <string.h>

static const char *compression_name(uint8_t c)
{
    static const char *const names[] = {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"};
    return c < sizeof names / sizeof names[0] ? names[c] : "unknown";
}

static const char *pixel_type_name(exr_pixel_type_t t)
{
    return t == EXR_PIXEL_HALF ? "half" : (t == EXR_PIXEL_FLOAT ? "float" : "uint");
}

/* The attribute's value as text (truncated to size). */
static void value_text(const exr_attribute_t *a, char *out, size_t size)
{
    out[0] = '\0';
    switch (a->type) {
    case EXR_ATTR_INT:
        snprintf(out, size, "%d", a->i);
        break;
    case EXR_ATTR_FLOAT:
        snprintf(out, size, "%.9g", a->f);
        break;
    case EXR_ATTR_DOUBLE:
        snprintf(out, size, "%.17g", a->d);
        break;
    case EXR_ATTR_STRING:
        snprintf(out, size, "%.*s", a->string->length, a->string->str);
        break;
    case EXR_ATTR_V2F:
        snprintf(out, size, "(%.9g, %.9g)", a->v2f->x, a->v2f->y);
        break;
    case EXR_ATTR_V3F:
        snprintf(out, size, "(%.9g, %.9g, %.9g)", a->v3f->x, a->v3f->y, a->v3f->z);
        break;
    case EXR_ATTR_V3D:
        snprintf(out, size, "(%.17g, %.17g, %.17g)", a->v3d->x, a->v3d->y, a->v3d->z);
        break;
    case EXR_ATTR_BOX2I:
        snprintf(out, size, "(%d %d) - (%d %d)", a->box2i->min.x, a->box2i->min.y, a->box2i->max.x, a->box2i->max.y);
        break;
    case EXR_ATTR_CHROMATICITIES: {
        const exr_attr_chromaticities_t *c = a->chromaticities;
        snprintf(out, size, "red (%.6g, %.6g), green (%.6g, %.6g), blue (%.6g, %.6g), white (%.6g, %.6g)", c->red_x,
                 c->red_y, c->green_x, c->green_y, c->blue_x, c->blue_y, c->white_x, c->white_y);
        break;
    }
    case EXR_ATTR_COMPRESSION:
        snprintf(out, size, "%s", compression_name(a->uc));
        break;
    case EXR_ATTR_ENVMAP:
        snprintf(out, size, "%s", a->uc == EXR_ENVMAP_LATLONG ? "latlong" : "cube");
        break;
    case EXR_ATTR_LINEORDER:
        snprintf(out, size, "%s", a->uc == EXR_LINEORDER_INCREASING_Y ? "increasing y" : "other");
        break;
    case EXR_ATTR_CHLIST: {
        size_t used = 0;
        for (int i = 0; i < a->chlist->num_channels && used < size; i++) {
            const exr_attr_chlist_entry_t *e = &a->chlist->entries[i];
            int n = snprintf(out + used, size - used, "%s%s %s", i ? ", " : "", e->name.str,
                             pixel_type_name(e->pixel_type));
            used += n > 0 ? (size_t)n : 0;
        }
        break;
    }
    default:
        snprintf(out, size, "(%s value not shown)", a->type_name);
        break;
    }
}

/* OpenEXR's default handler prints; the library never does (the status says what failed). */
static void quiet(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
}

fm_status fm_exr_attributes(const char *path, fm_exr_attribute_fn fn, void *user, fm_error *err)
{
    exr_context_t ctxt = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet;
    fm_status regular = image_check_regular(path, err);
    if (regular)
        return regular;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    if (rv != EXR_ERR_SUCCESS)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cannot read '%s': %s", path, exr_get_default_error_message(rv));
    int32_t count = 0;
    if ((rv = exr_get_attribute_count(ctxt, 0, &count))) {
        exr_finish(&ctxt);
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cannot read '%s': %s", path, exr_get_default_error_message(rv));
    }
    char value[4096];
    for (int pass = 0; pass < 2; pass++) {
        for (int32_t i = 0; i < count; i++) {
            const exr_attribute_t *a = NULL;
            if (exr_get_attribute_by_index(ctxt, 0, EXR_ATTR_LIST_SORTED_ORDER, i, &a) || !a)
                continue;
            int ours = strncmp(a->name, "firmament", 9) == 0;
            if (ours != pass)
                continue;
            value_text(a, value, sizeof value);
            fn(user, a->name, a->type_name, value);
        }
    }
    exr_finish(&ctxt);
    return FM_OK;
}
