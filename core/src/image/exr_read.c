/* Reading EXRs back (firmament.h: fm_image_read_exr), used by `firmament compare`. */
#include "base/platform.h"
#include "base/status.h"
#include "image/image.h"

#include "colour/colour.h"
#include "image/exr_attributes.h"
#include "image/exr_recode.h"

#include <errno.h>
#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* 2^28: a 16384 x 16384 map; a side of at most 2^16 bounds one scanline's buffers */
#define MAX_READ_PIXELS ((int64_t)1 << 28)

static _Thread_local char read_message[256];

static void capture(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    strncpy(read_message, msg ? msg : "", sizeof read_message - 1);
}

static int attribute_is(exr_context_t c, const char *name, const char *value)
{
    const char *str = NULL;
    int32_t length = 0;
    return exr_attr_get_string(c, 0, name, &length, &str) == EXR_ERR_SUCCESS && str &&
           (size_t)length == strlen(value) && strncmp(str, value, (size_t)length) == 0;
}

/* The camera from firmament's attributes (metadata.c); equirect when there are none. */
static void read_camera(exr_context_t c, fm_image *img)
{
    fm_camera *cam = &img->camera;
    double v;
    if (attribute_is(c, "firmament.camera.type", "fisheye")) {
        cam->type = FM_CAMERA_FISHEYE;
        cam->fisheye_projection = attribute_is(c, "firmament.camera.fisheye_projection", "equisolid")
                                      ? FM_FISHEYE_EQUISOLID
                                      : FM_FISHEYE_EQUIDISTANT;
    } else if (attribute_is(c, "firmament.camera.type", "pinhole")) {
        cam->type = FM_CAMERA_PINHOLE;
        cam->aspect = (double)img->width / img->height;
        if (exr_attr_get_double(c, 0, "firmament.camera.horizontal_fov_deg", &v) == EXR_ERR_SUCCESS)
            cam->fov_deg = v;
        if (exr_attr_get_double(c, 0, "firmament.camera.look_azimuth_deg", &v) == EXR_ERR_SUCCESS)
            cam->look_azimuth_deg = v;
        if (exr_attr_get_double(c, 0, "firmament.camera.look_elevation_deg", &v) == EXR_ERR_SUCCESS)
            cam->look_elevation_deg = v;
    }
}

static fm_status read_exr(const char *path, fm_image **out, fm_error *err);
static fm_status read_opened(exr_context_t c, const char *path, fm_image **out, fm_error *err);

/* The most a codec expands its stored bytes: deflate (ZIP, ZIPS) about 1032:1, times 4/3 for
 * PXR24's 24-bit floats; PIZ's Huffman run codes about 400:1; RLE 64:1; B44A about 11:1; DWA keeps
 * one DCT coefficient of 64 in a flat block before deflating it. */
static double max_expansion(exr_compression_t method)
{
    switch (method) {
    case EXR_COMPRESSION_NONE: return 1.0;
    case EXR_COMPRESSION_RLE: return 64.0;
    case EXR_COMPRESSION_B44:
    case EXR_COMPRESSION_B44A: return 16.0;
    case EXR_COMPRESSION_DWAA:
    case EXR_COMPRESSION_DWAB: return 64.0 * 2048.0;
    default: return 2048.0;
    }
}

/* What a header claims, checked before anything is allocated for it: a scanline image of at most
 * MAX_READ_PIXELS and four channels, whose decoded size its file could hold after compression
 * (a corrupt header of a few bytes can ask for gigabytes). */
static fm_status check_header(exr_context_t c, const char *path, int64_t file_bytes, fm_error *err)
{
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *cl;
    exr_compression_t method;
    if (exr_get_storage(c, 0, &storage) || storage != EXR_STORAGE_SCANLINE || exr_get_data_window(c, 0, &dw) ||
        exr_get_channels(c, 0, &cl) || exr_get_compression(c, 0, &method))
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': not a scanline image", path);
    int64_t W = (int64_t)dw.max.x - dw.min.x + 1, H = (int64_t)dw.max.y - dw.min.y + 1;
    if (W < 1 || H < 1 || W > EXR_MAX_SIDE || H > EXR_MAX_SIDE || W * H > MAX_READ_PIXELS)
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': its data window is %lld x %lld pixels (at most %lld a side "
                       "and %lld in all are read)", path, (long long)W, (long long)H, (long long)EXR_MAX_SIDE,
                       (long long)MAX_READ_PIXELS);
    if (cl->num_channels > EXR_MAX_CHANNELS)
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': expected R, G, B or Y channels, found %d channels", path,
                       cl->num_channels);
    double decoded = 0.0;
    for (int i = 0; i < cl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &cl->entries[i];
        int xs = e->x_sampling > 0 ? e->x_sampling : 1, ys = e->y_sampling > 0 ? e->y_sampling : 1;
        decoded += (double)(W / xs) * (double)(H / ys) * (e->pixel_type == EXR_PIXEL_HALF ? 2.0 : 4.0);
    }
    if (decoded > (double)file_bytes * max_expansion(method))
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': its header claims %lld x %lld pixels, more than its %lld "
                       "bytes can hold", path, (long long)W, (long long)H, (long long)file_bytes);
    return FM_OK;
}

/* Opens an EXR for reading, its header checked (check_header); on failure nothing stays open. */
static fm_status open_exr(const char *path, exr_context_t *c, fm_error *err)
{
    read_message[0] = '\0';
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = capture;
    *c = NULL;
    struct stat st;
    fm_status s = exr_start_read(c, path, &init) != EXR_ERR_SUCCESS
                      ? fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path,
                                read_message[0] ? read_message : "not an EXR")
                  : stat(path, &st) != 0 ? fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, strerror(errno))
                                         : check_header(*c, path, (int64_t)st.st_size, err);
    if (s)
        exr_finish(c);
    return s;
}

fm_status image_check_regular(const char *path, fm_error *err)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "cannot read '%s': not a regular file", path);
    return FM_OK;
}

/* DWA files (firmament's --compression dwaa, or other tools') are re-encoded losslessly as ZIP in
 * a private temporary file first: OpenEXR 3.1's C library cannot decode DWA; any other is read as
 * opened. */
fm_status fm_image_read_exr(const char *path, fm_image **out, fm_error *err)
{
    *out = NULL;
    fm_status regular = image_check_regular(path, err);
    if (regular)
        return regular;
    exr_context_t c = NULL;
    fm_status s = open_exr(path, &c, err);
    if (s)
        return s;
    exr_compression_t method = EXR_COMPRESSION_NONE;
    exr_get_compression(c, 0, &method);
    if (method != EXR_COMPRESSION_DWAA && method != EXR_COMPRESSION_DWAB)
        return read_opened(c, path, out, err);
    exr_finish(&c);
    struct stat st;
    if (stat(path, &st) != 0 || !exr_attributes_fit(path, (int64_t)st.st_size))
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': an attribute of its header claims more bytes than the file "
                       "holds", path);
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s/firmament-read-XXXXXX", platform_temp_dir());
    if (platform_create_unique(tmp) != 0)
        return fm_fail(err, FM_ERR_IO, "cannot read '%s': no temporary file for decoding DWA (%s)", path,
                       strerror(errno));
    char msg[256];
    s = recode_exr(path, tmp, RECODE_ZIP, 0.0f, msg, sizeof msg) != 0
                      ? fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, msg)
                      : read_exr(tmp, out, err);
    platform_remove(tmp);
    return s;
}

/* Where each of the file's channels goes in a pixel (offsets[i], -1: not read) and how many
 * channels a pixel has: R, G and B together (3), or Y alone (1); 0 for anything else (a file with B
 * only is not a colour image with R = G = 0). */
static int channel_offsets(const exr_attr_chlist_t *cl, int offsets[4])
{
    unsigned found = 0;
    for (int i = 0; i < cl->num_channels; i++) {
        const char *n = cl->entries[i].name.str;
        const char *names = "RGBY";
        offsets[i] = -1;
        for (int k = 0; k < 4; k++)
            if (n[0] == names[k] && n[1] == '\0' && !(found & (1u << k))) {
                found |= 1u << k;
                offsets[i] = k == 3 ? 0 : k;
            }
    }
    return found == 7u ? 3 : found == 8u ? 1 : 0;
}

/* An RGB file in another colour space (firmament's --colorspace): its matrix to XYZ from its
 * chromaticities, so that comparisons are of luminance. */
static void read_colour_space(exr_context_t c, fm_image *img)
{
    exr_attr_chromaticities_t chroma;
    if (img->channels != 3 || exr_attr_get_chromaticities(c, 0, "chromaticities", &chroma) != EXR_ERR_SUCCESS)
        return;
    const float v[8] = {chroma.red_x,  chroma.red_y,  chroma.green_x, chroma.green_y,
                         chroma.blue_x, chroma.blue_y, chroma.white_x, chroma.white_y};
    double diff = 0.0;
    for (int i = 0; i < 8; i++)
        diff = fmax(diff, fabs(v[i] - fm_rec709_chromaticities[i]));
    if (diff > 1e-5 && colour_matrix_from_chromaticities(v, img->rgb_to_xyz)) {
        img->content = FM_IMAGE_RGB;
        memcpy(img->chromaticities, v, sizeof v);
        int32_t len = 0;
        const char *name = NULL;
        if (exr_attr_get_string(c, 0, "firmament.image.colorspace", &len, &name) != EXR_ERR_SUCCESS || !name)
            name = "from the file's chromaticities";
        snprintf(img->colorspace, sizeof img->colorspace, "%s", name);
    }
}

/* Decodes every chunk into img's float pixels, each channel at its offset. */
static fm_status decode_chunks(exr_context_t c, const char *path, const exr_attr_box2i_t *window,
                               const exr_attr_chlist_t *cl, const int offsets[4], int lines, fm_image *img,
                               fm_error *err)
{
    const exr_attr_box2i_t dw = *window;
    const int W = img->width, H = img->height, C = img->channels;
    fm_status s = FM_OK;
    exr_decode_pipeline_t d = EXR_DECODE_PIPELINE_INITIALIZER;
    int initialised = 0, routines = 0;
    for (int y = 0; y < H && !s; y += lines) {
        exr_chunk_info_t ci;
        if (exr_read_scanline_chunk_info(c, 0, dw.min.y + y, &ci) ||
            (initialised ? exr_decoding_update(c, 0, &ci, &d) : exr_decoding_initialize(c, 0, &ci, &d))) {
            s = fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, read_message);
            break;
        }
        initialised = 1;
        for (int k = 0; k < d.channel_count; k++) {
            exr_coding_channel_info_t *ch = &d.channels[k];
            int off = -1;
            for (int i = 0; i < cl->num_channels; i++)
                if (!strcmp(cl->entries[i].name.str, ch->channel_name))
                    off = offsets[i];
            ch->decode_to_ptr = off < 0 ? NULL : (uint8_t *)&img->pixels[((size_t)(ci.start_y - dw.min.y) * W) * C + off];
            ch->user_pixel_stride = C * 4;
            ch->user_line_stride = W * C * 4;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (!routines) {
            if (exr_decoding_choose_default_routines(c, 0, &d)) {
                s = fm_fail(err, FM_ERR_IO, "cannot read '%s': unsupported layout", path);
                break;
            }
            routines = 1;
        }
        if (exr_decoding_run(c, 0, &d))
            s = fm_fail(err, FM_ERR_IO, "cannot read '%s': %s", path, read_message);
    }
    if (initialised)
        exr_decoding_destroy(c, &d);
    return s;
}

static fm_status read_exr(const char *path, fm_image **out, fm_error *err)
{
    exr_context_t c = NULL;
    fm_status s = open_exr(path, &c, err);
    return s ? s : read_opened(c, path, out, err);
}

/* The image of the EXR opened as c (open_exr), which it closes. */
static fm_status read_opened(exr_context_t c, const char *path, fm_image **out, fm_error *err)
{
    fm_status s = FM_OK;
    fm_image *img = NULL;
    exr_attr_box2i_t dw;
    const exr_attr_chlist_t *cl;
    int32_t lines = 1;
    if (exr_get_data_window(c, 0, &dw) || exr_get_channels(c, 0, &cl) || exr_get_scanlines_per_chunk(c, 0, &lines)) {
        s = fm_fail(err, FM_ERR_IO, "cannot read '%s': not a scanline image", path);
        goto done;
    }
    int offsets[4];
    const int C = channel_offsets(cl, offsets);
    if (!C) {
        s = fm_fail(err, FM_ERR_IO, "cannot read '%s': expected channels R, G and B, or Y alone", path);
        goto done;
    }
    /* the window is bounded by check_header */
    img = image_create(dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1, C,
                       C == 3 ? FM_IMAGE_RGB_REC709 : FM_IMAGE_SPECTRAL_RADIANCE, 0, 0);
    if (!img) {
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory reading '%s'", path);
        goto done;
    }
    read_colour_space(c, img);
    exr_attr_v3d_t sun;
    if (exr_attr_get_v3d(c, 0, "firmament.sun.direction", &sun) == EXR_ERR_SUCCESS) {
        img->sun_direction[0] = sun.x;
        img->sun_direction[1] = sun.y;
        img->sun_direction[2] = sun.z;
    }
    read_camera(c, img);
    s = decode_chunks(c, path, &dw, cl, offsets, lines, img, err);
done:
    exr_finish(&c);
    if (s) {
        fm_image_destroy(img);
        return s;
    }
    *out = img;
    return FM_OK;
}
