/* fm_output: the EXR and its sidecar reach their final names together, complete, or not at all.
 * Both are written to temporary files beside their destinations (same directory, so rename() is
 * atomic) and renamed only after both are complete. */
#define _POSIX_C_SOURCE 200809L
#include "base/status.h"
#include "image/image.h"
#include "image/exr_recode.h"
#include "image/image_exr.h"
#include "image/sidecar.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

struct fm_output {
    char *exr_path, *json_path;
    char *exr_tmp, *json_tmp; /* NULL once renamed or removed */
    int half;
    fm_exr_compression compression;
};

fm_status fm_output_set_format(fm_output *o, int half, fm_exr_compression compression, fm_error *err)
{
    if (compression != FM_EXR_ZIP && compression != FM_EXR_PIZ && compression != FM_EXR_DWAA)
        return fm_fail_parameter(err, "compression", "unknown compression %d", (int)compression);
    o->half = half;
    o->compression = compression;
    return FM_OK;
}

/* The largest magnitude of the pixels, for the half-float range check (NaN counts as too large). */
static double largest_value(const fm_image *img)
{
    size_t n = (size_t)img->width * img->height * img->channels;
    double m = 0.0;
    for (size_t i = 0; i < n; i++) {
        double v = fabs((double)img->pixels[i]);
        if (!(v <= m))
            m = v != v ? INFINITY : v;
    }
    return m;
}

/* The temporary file's name holds at most this much of the output's: "." + it + ".XXXXXX" stays
 * within the 255 bytes of a file name, so an output named up to that length is written too. */
#define TEMP_NAME_PART 240

/* Creates "<dir>/.<name>.XXXXXX" (name cut to TEMP_NAME_PART bytes) and returns its path (malloc'd),
 * or NULL with err filled. */
char *image_reserve_temp(const char *path, fm_error *err)
{
    struct stat st;
    if (!path[0]) {
        fm_fail(err, FM_ERR_IO, "an output path is empty");
        return NULL;
    }
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        fm_fail(err, FM_ERR_IO, "cannot write '%s': it is a directory", path);
        return NULL;
    }
    /* rename() would replace a device, FIFO or socket (run as root: /dev/null) by a regular file */
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        fm_fail(err, FM_ERR_IO, "cannot write '%s': it is not a regular file", path);
        return NULL;
    }
    const char *slash = strrchr(path, '/');
    size_t dir_len = slash ? (size_t)(slash - path + 1) : 0;
    size_t n = strlen(path) + 16;
    char *tmp = malloc(n);
    if (!tmp) {
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    size_t name_len = strlen(path + dir_len);
    int part = name_len > TEMP_NAME_PART ? TEMP_NAME_PART : (int)name_len;
    snprintf(tmp, n, "%.*s.%.*s.XXXXXX", (int)dir_len, path, part, path + dir_len);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
        free(tmp);
        return NULL;
    }
    /* mkstemp creates 0600; give the file the usual permissions for a new file */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    close(fd);
    return tmp;
}

fm_status fm_output_check_path(const char *path, fm_error *err)
{
    if (!path)
        return fm_fail(err, FM_ERR_IO, "an output path is missing");
    char *tmp = image_reserve_temp(path, err);
    if (!tmp)
        return err ? err->status : FM_ERR_IO;
    unlink(tmp);
    free(tmp);
    return FM_OK;
}

static char *copy_string(const char *s)
{
    size_t n = strlen(s) + 1;
    char *c = malloc(n);
    if (c)
        memcpy(c, s, n);
    return c;
}

fm_status fm_output_open(const char *exr_path, const char *json_path, fm_output **out, fm_error *err)
{
    *out = NULL;
    if (!exr_path || !exr_path[0])
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the output path is empty");
    if (!json_path || !json_path[0])
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the sidecar path is empty");
    if (strcmp(exr_path, json_path) == 0)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the image and its sidecar would both be '%s'", exr_path);
    fm_output *o = calloc(1, sizeof *o);
    if (!o)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    o->exr_path = copy_string(exr_path);
    o->json_path = copy_string(json_path);
    if (!o->exr_path || !o->json_path) {
        fm_output_close(o);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if (!(o->exr_tmp = image_reserve_temp(exr_path, err)) || !(o->json_tmp = image_reserve_temp(json_path, err))) {
        fm_output_close(o);
        return err ? err->status : FM_ERR_IO;
    }
    *out = o;
    return FM_OK;
}

/* DWAA: OpenEXR's C library writes the map losslessly to a staging file beside the destination, its
 * C++ library re-encodes that as DWAA into path (exr_recode.h); the staging file is always removed. */
#define FM_DWAA_LEVEL 45.0f
static fm_status write_dwaa(const char *path, const fm_image *image, const metadata *meta, int half, int threads,
                            const atomic_int *cancel, fm_error *err)
{
    char *staging = image_reserve_temp(path, err);
    if (!staging)
        return err ? err->status : FM_ERR_IO;
    fm_status s = image_write_exr(staging, image, meta, half, FM_EXR_ZIP, threads, cancel, err);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled while writing '%s'", path);
    char msg[256];
    if (!s && exr_recode(staging, path, EXR_RECODE_DWAA, FM_DWAA_LEVEL, msg, sizeof msg) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s' with DWAA compression: %s", path, msg);
    unlink(staging);
    free(staging);
    return s;
}

fm_status fm_output_commit(fm_output *o, const fm_sky *sky, const fm_render_params *params, const fm_image *image,
                           const atomic_int *cancel, fm_error *err)
{
    if (!o->exr_tmp || !o->json_tmp)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "output already committed");
    /* 65504 is the largest finite half; rounding to it starts at 65520.  DWA quantises colour
     * channels through half precision even when they are stored as 32-bit float. */
    if (o->half || o->compression == FM_EXR_DWAA) {
        double m = largest_value(image);
        if (m >= 65504.0 && o->half)
            return fm_fail_parameter(err, "half", "the map holds values up to %.4g (the sun disk), beyond the "
                                                  "half-float range 65504; leave the sun disk out (--no-sun-disk) "
                                                  "or write 32-bit float",
                                     m);
        if (m >= 65504.0)
            return fm_fail_parameter(err, "compression", "dwaa: the map holds values up to %.4g (the sun disk), "
                                                         "beyond the half-float range 65504 that DWA quantises "
                                                         "through; leave the sun disk out (--no-sun-disk) or use "
                                                         "zip or piz",
                                     m);
    }
    metadata meta;
    metadata_collect(&meta, sky, params, image, o->exr_path);
    fm_status s = o->compression == FM_EXR_DWAA
                      ? write_dwaa(o->exr_tmp, image, &meta, o->half, params->threads, cancel, err)
                      : image_write_exr(o->exr_tmp, image, &meta, o->half, o->compression, params->threads, cancel,
                                        err);
    if (!s)
        s = sidecar_write(o->json_tmp, &meta, err);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled before the files were complete");
    if (s)
        return s; /* the temporary files are removed by fm_output_close */
    /* Past this point nothing checks for cancellation: both renames happen. */
    if (rename(o->exr_tmp, o->exr_path) != 0)
        return fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", o->exr_path, strerror(errno));
    free(o->exr_tmp);
    o->exr_tmp = NULL;
    if (rename(o->json_tmp, o->json_path) != 0)
        return fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", o->json_path, strerror(errno));
    free(o->json_tmp);
    o->json_tmp = NULL;
    return FM_OK;
}

void fm_output_close(fm_output *o)
{
    if (!o)
        return;
    if (o->exr_tmp)
        unlink(o->exr_tmp);
    if (o->json_tmp)
        unlink(o->json_tmp);
    free(o->exr_tmp);
    free(o->json_tmp);
    free(o->exr_path);
    free(o->json_path);
    free(o);
}

fm_status fm_output_write_spectral(const char *path, const fm_sky *sky, const fm_render_params *params,
                                   const fm_image *spectral, const fm_image *colour, const atomic_int *cancel,
                                   fm_error *err)
{
    if (spectral->content != FM_IMAGE_SPECTRAL_GRID)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "not a spectral map");
    char *tmp = image_reserve_temp(path, err);
    if (!tmp)
        return err ? err->status : FM_ERR_IO;
    metadata meta;
    metadata_collect(&meta, sky, params, colour, path);
    fm_status s = image_write_exr(tmp, spectral, &meta, 0, FM_EXR_ZIP, params->threads, cancel, err);
    if (!s && rename(tmp, path) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    if (s)
        unlink(tmp);
    free(tmp);
    return s;
}
