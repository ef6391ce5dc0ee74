#include "image/image_hdr.h"

#include "base/platform.h"
#include "base/status.h"
#include "base/units.h"
#include "colour/colour.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One pixel as RGBE: the largest component's exponent shared, 8-bit mantissas (Ward, "Real Pixels",
 * Graphics Gems II, 1991). */
static void rgbe(const float *rgb, unsigned char *out)
{
    float v = fmaxf(rgb[0], fmaxf(rgb[1], rgb[2]));
    if (!(v >= 1e-32f)) { /* also NaN and negatives: black */
        memset(out, 0, 4);
        return;
    }
    int e;
    float scale = frexpf(v, &e) * 256.0f / v;
    for (int c = 0; c < 3; c++)
        out[c] = (unsigned char)(rgb[c] > 0.0f ? rgb[c] * scale : 0.0f);
    out[3] = (unsigned char)(e + 128);
}

static void write_header(FILE *f, const fm_image *img, const metadata *meta)
{
    const float *c = img->content == FM_IMAGE_RGB ? img->chromaticities : fm_rec709_chromaticities;
    fprintf(f, "#?RADIANCE\n");
    fprintf(f, "# firmament sky map: values are CIE-weighted radiance in W m^-2 sr^-1 as in the EXR, with "
               "luminance = %g x Y cd/m^2;\n", FM_LUMINOUS_EFFICACY);
    fprintf(f, "# Radiance takes luminance = %g x Y: multiply by %g/%g = %.5f for Radiance's watts (rtrace, rpict)\n",
            FM_RADIANCE_EFFICACY, FM_LUMINOUS_EFFICACY, FM_RADIANCE_EFFICACY,
            FM_LUMINOUS_EFFICACY / FM_RADIANCE_EFFICACY);
    for (int i = 0; i < meta->count; i++) {
        const meta_entry *e = &meta->e[i];
        fprintf(f, "# firmament%s%s.%s: ", e->group[0] ? "." : "", e->group, e->key);
        if (e->type == META_STRING)
            fprintf(f, "%s\n", e->s);
        else if (e->type == META_VEC3)
            fprintf(f, "%.9g %.9g %.9g\n", e->v[0], e->v[1], e->v[2]);
        else
            fprintf(f, "%.9g\n", e->v[0]);
    }
    fprintf(f, "SOFTWARE=firmament %s\n", FIRMAMENT_VERSION);
    fprintf(f, "FORMAT=32-bit_rle_rgbe\n");
    fprintf(f, "EXPOSURE=1\n");
    if (img->channels == 3)
        fprintf(f, "PRIMARIES=%.4f %.4f %.4f %.4f %.4f %.4f %.4f %.4f\n", c[0], c[1], c[2], c[3], c[4], c[5], c[6],
                c[7]);
    fprintf(f, "\n-Y %d +X %d\n", img->height, img->width);
}

fm_status image_write_hdr(const char *path, const fm_image *img, const metadata *meta, const atomic_int *cancel,
                          fm_error *err)
{
    if (img->channels != 3 && img->channels != 1)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "a Radiance picture holds a colour or one-channel map");
    if (img->content == FM_IMAGE_RGB && img->chromaticities[0] == 1.0f && img->chromaticities[1] == 0.0f)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT,
                       "'%s': a Radiance RGBE picture needs an RGB colour space, not %s", path, img->colorspace);
    FILE *f = platform_fopen(path, "wb");
    if (!f)
        return fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    write_header(f, img, meta);
    size_t w = (size_t)img->width;
    unsigned char *row = malloc(4 * w);
    int ok = row != NULL;
    for (int y = 0; y < img->height && ok; y++) {
        if (cancel && atomic_load(cancel))
            break;
        for (size_t x = 0; x < w; x++) {
            const float *p = img->pixels + ((size_t)y * w + x) * (size_t)img->channels;
            float grey[3] = {p[0], p[0], p[0]};
            rgbe(img->channels == 3 ? p : grey, row + 4 * x);
        }
        ok = fwrite(row, 4, w, f) == w;
    }
    free(row);
    ok = fclose(f) == 0 && ok;
    if (cancel && atomic_load(cancel))
        return fm_fail(err, FM_ERR_CANCELLED, "cancelled while writing '%s'", path);
    return ok ? FM_OK : fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno ? errno : EIO));
}
