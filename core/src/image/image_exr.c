#include "image/image_exr.h"

#include "base/status.h"
#include "base/units.h"
#include "colour/colour.h"

#include <openexr.h>
#include <stdio.h>
#include <string.h>

/* OpenEXR reports details through a callback, called with the context locked (so the callback
 * cannot query the context); keep the last message per thread for our own one-line error. */
typedef struct exr_messages {
    char last[256];
} exr_messages;

static _Thread_local exr_messages thread_messages;

static void capture_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    snprintf(thread_messages.last, sizeof thread_messages.last, "%s", msg ? msg : "");
}

static fm_status exr_failure(fm_error *err, const char *path, const char *step, exr_result_t rv,
                             const exr_messages *msgs)
{
    return fm_fail(err, FM_ERR_IO, "cannot write '%s': %s (%s)", path, msgs->last[0] ? msgs->last : step,
                   exr_get_default_error_message(rv));
}

static exr_result_t write_attributes(exr_context_t ctxt, const fm_image *img, const metadata *meta)
{
    /* only the equirectangular map is a latlong environment map */
    exr_result_t rv = EXR_ERR_SUCCESS;
    if (img->camera.type == FM_CAMERA_EQUIRECT)
        rv = exr_attr_set_envmap(ctxt, 0, "envmap", EXR_ENVMAP_LATLONG);
    if (rv == EXR_ERR_SUCCESS && img->content == FM_IMAGE_SPECTRAL_GRID) {
        /* Fichet, Pacanowski & Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021 */
        rv = exr_attr_set_string(ctxt, 0, "spectralLayoutVersion", "1.0");
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_attr_set_string(ctxt, 0, "emissiveUnits", "W.m^-2.sr^-1.nm^-1");
    }
    if (rv == EXR_ERR_SUCCESS && (img->content == FM_IMAGE_RGB_REC709 || img->content == FM_IMAGE_RGB)) {
        const float *c = img->content == FM_IMAGE_RGB ? img->chromaticities : fm_rec709_chromaticities;
        exr_attr_chromaticities_t chroma = {c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]};
        rv = exr_attr_set_chromaticities(ctxt, 0, "chromaticities", &chroma);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_attr_set_float(ctxt, 0, "whiteLuminance", (float)FM_LUMINOUS_EFFICACY);
    }
    char name[128];
    for (int i = 0; i < meta->count && rv == EXR_ERR_SUCCESS; i++) {
        const meta_entry *e = &meta->e[i];
        snprintf(name, sizeof name, "firmament%s%s.%s", e->group[0] ? "." : "", e->group, e->key);
        switch (e->type) {
        case META_DOUBLE:
            rv = exr_attr_set_double(ctxt, 0, name, e->v[0]);
            break;
        case META_INT:
            rv = exr_attr_set_int(ctxt, 0, name, (int32_t)e->v[0]);
            break;
        case META_STRING:
            rv = exr_attr_set_string(ctxt, 0, name, e->s);
            break;
        case META_VEC3: {
            exr_attr_v3d_t v = {.x = e->v[0], .y = e->v[1], .z = e->v[2]};
            rv = exr_attr_set_v3d(ctxt, 0, name, &v);
            break;
        }
        }
    }
    return rv;
}

/* The EXR name of channel c: Y, R G B, or for spectral maps the emissive channel of the spectral
 * layout, "S0.<wavelength>nm" with six decimals and a comma as decimal separator. */
static void channel_name(const fm_image *img, int c, char *name, size_t size)
{
    if (img->content == FM_IMAGE_SPECTRAL_GRID) {
        snprintf(name, size, "S0.%.6fnm", img->lambda_nm[c]);
        char *dot = strchr(name + 3, '.');
        if (dot)
            *dot = ',';
    } else {
        snprintf(name, size, "%s", img->channels == 1 ? "Y" : (c == 0 ? "R" : (c == 1 ? "G" : "B")));
    }
}

/* Offset of an EXR channel name within our interleaved pixel. */
static int channel_offset(const fm_image *img, const char *name)
{
    char own[32];
    for (int c = 0; c < img->channels; c++) {
        channel_name(img, c, own, sizeof own);
        if (strcmp(own, name) == 0)
            return c;
    }
    return 0;
}

fm_status image_write_exr(const char *path, const fm_image *img, const metadata *meta, int half,
                          fm_exr_compression compression, const atomic_int *cancel, fm_error *err)
{
    const exr_compression_t method = compression == FM_EXR_PIZ ? EXR_COMPRESSION_PIZ : EXR_COMPRESSION_ZIP;
    exr_messages *msgs_ptr = &thread_messages;
    msgs_ptr->last[0] = '\0';
    const exr_messages *msgs_view = msgs_ptr;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = capture_error;
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS)
        return exr_failure(err, path, "cannot create the file", rv, msgs_view);

    fm_status status = FM_OK;
    int part = 0;
    const int W = img->width, H = img->height, C = img->channels;
    /* attribute names such as firmament.sun.direct_normal_illuminance_lux exceed 31 characters */
    if ((rv = exr_set_longname_support(ctxt, 1)) ||
        (rv = exr_add_part(ctxt, "", EXR_STORAGE_SCANLINE, &part)) ||
        (rv = exr_initialize_required_attr_simple(ctxt, part, W, H, method)))
        goto fail;
    for (int c = 0; c < C; c++) {
        char name[32];
        channel_name(img, c, name, sizeof name);
        if ((rv = exr_add_channel(ctxt, part, name, half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR,
                                  1, 1)))
            goto fail;
    }
    if ((rv = write_attributes(ctxt, img, meta)) || (rv = exr_write_header(ctxt)))
        goto fail;

    int32_t lines = 1;
    if ((rv = exr_get_scanlines_per_chunk(ctxt, part, &lines)))
        goto fail;
    exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < H; y += lines) {
        if (cancel && atomic_load(cancel)) {
            status = fm_fail(err, FM_ERR_CANCELLED, "cancelled while writing '%s'", path);
            break;
        }
        exr_chunk_info_t cinfo;
        if ((rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo)))
            break;
        rv = started ? exr_encoding_update(ctxt, part, &cinfo, &encoder)
                     : exr_encoding_initialize(ctxt, part, &cinfo, &encoder);
        if (rv)
            break;
        for (int c = 0; c < encoder.channel_count; c++) {
            exr_coding_channel_info_t *ch = &encoder.channels[c];
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_pixel_stride = C * (int32_t)sizeof(float);
            ch->user_line_stride = W * C * (int32_t)sizeof(float);
            ch->encode_from_ptr = (const uint8_t *)&img->pixels[((size_t)cinfo.start_y * W) * C +
                                                                channel_offset(img, ch->channel_name)];
        }
        if (!started) {
            if ((rv = exr_encoding_choose_default_routines(ctxt, part, &encoder)))
                break;
            started = 1;
        }
        if ((rv = exr_encoding_run(ctxt, part, &encoder)))
            break;
    }
    if (started)
        exr_encoding_destroy(ctxt, &encoder);
    if (status == FM_OK && rv != EXR_ERR_SUCCESS)
        status = exr_failure(err, path, "cannot write pixels", rv, msgs_view);
    rv = exr_finish(&ctxt);
    if (status == FM_OK && rv != EXR_ERR_SUCCESS)
        status = exr_failure(err, path, "cannot finish the file", rv, msgs_view);
    return status;
fail:
    exr_finish(&ctxt);
    return exr_failure(err, path, "cannot write the header", rv, msgs_view);
}
