/* fm_output: the EXR, its sidecar and the files published with them (preview, spectral map, a
 * second output's pair) reach their final names together, complete, or not at all.  Each is written
 * to a temporary file beside its destination (same directory, so the rename is atomic) and renamed
 * only after all are complete; a rename that fails puts back the files replaced before it.  The
 * renames are made holding a lock on ".<map>.lock" beside the map, so that two renders into one map
 * publish one after the other. */
#define _POSIX_C_SOURCE 200809L /* PATH_MAX */
#include "base/platform.h"
#include "base/stale_temps.h"
#include "base/status.h"
#include "base/text.h"
#include "image/image.h"
#include "image/exr_recode.h"
#include "image/image_exr.h"
#include "image/image_hdr.h"
#include "image/sidecar.h"

#include <cjson/cJSON.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A file written to tmp, to be renamed over path. */
typedef struct staged_file {
    char *path, *tmp; /* tmp NULL once renamed or removed */
} staged_file;

/* the map, its sidecar, and the preview and spectral map published with them */
enum { FILE_EXR, FILE_JSON, MAX_FILES = 4 };

struct fm_output {
    staged_file files[MAX_FILES];
    int count;  /* files reserved */
    int staged; /* the map and sidecar are written into their temporaries */
    int half;
    fm_exr_compression compression;
    char *job;    /* fm_output_set_job's JSON object, or NULL */
    int radiance; /* the map as a Radiance picture, not an EXR */
};

fm_status fm_output_set_radiance(fm_output *o, fm_error *err)
{
    if (o->half)
        return fm_fail_parameter(err, "format", "hdr: a Radiance picture has no half floats");
    o->radiance = 1;
    return FM_OK;
}

fm_status fm_output_set_format(fm_output *o, int half, fm_exr_compression compression, fm_error *err)
{
    if (compression != FM_EXR_ZIP && compression != FM_EXR_PIZ && compression != FM_EXR_DWAA)
        return fm_fail_parameter(err, "compression", "unknown compression %d", (int)compression);
    o->half = half;
    o->compression = compression;
    return FM_OK;
}

fm_status fm_output_set_job(fm_output *o, const char *json_object, fm_error *err)
{
    cJSON *job = json_object ? cJSON_Parse(json_object) : NULL;
    int ok = cJSON_IsObject(job);
    cJSON_Delete(job);
    if (!ok)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the sidecar's job is not a JSON object");
    free(o->job);
    if (!(o->job = text_copy(json_object)))
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    return FM_OK;
}

/* How many of the pixels' values are NaN or infinite: a map never holds one. */
static size_t non_finite_values(const fm_image *img)
{
    size_t n = (size_t)img->width * img->height * img->channels, bad = 0;
    for (size_t i = 0; i < n; i++)
        bad += !isfinite(img->pixels[i]);
    return bad;
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

/* Where a file written to path goes: a symbolic link's target (written through, the link kept, as
 * shells and most tools do), else path; malloc'd, NULL when out of memory. */
static char *destination(const char *path)
{
    char *target = platform_link_target(path);
    return target ? target : text_copy(path);
}

/* Creates "<dir>/.<name>.XXXXXX" (name cut to TEMP_NAME_PART bytes) and returns its path (malloc'd),
 * or NULL with err filled. */
char *image_reserve_temp(const char *path, fm_error *err)
{
    if (!path[0]) {
        fm_fail(err, FM_ERR_IO, "an output path is empty");
        return NULL;
    }
    platform_kind kind = platform_path_kind(path);
    if (kind == PLATFORM_DIRECTORY) {
        fm_fail(err, FM_ERR_IO, "cannot write '%s': it is a directory", path);
        return NULL;
    }
    /* the rename would replace a device, FIFO or socket (run as root: /dev/null) by a regular file */
    if (kind == PLATFORM_OTHER) {
        fm_fail(err, FM_ERR_IO, "cannot write '%s': it is not a regular file", path);
        return NULL;
    }
    char *dest = destination(path);
    if (!dest) {
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    const char *slash = platform_last_separator(dest);
    size_t dir_len = slash ? (size_t)(slash - dest + 1) : 0;
    /* the final name too, not only the temporary's shortened one: else the rename fails after the
     * render, and for a pair, after its first file replaced the old one */
    char *tmp = NULL;
    size_t name_len = strlen(dest + dir_len), n = strlen(dest) + 16;
    if (strlen(dest) >= PLATFORM_PATH_MAX)
        fm_fail(err, FM_ERR_IO, "cannot write '%s': the path is %zu bytes, longer than the %d a path may have",
                dest, strlen(dest), PLATFORM_PATH_MAX - 1);
    else if (name_len > PLATFORM_NAME_MAX)
        fm_fail(err, FM_ERR_IO, "cannot write '%s': the file name is %zu bytes, longer than the %d a name may have",
                dest, name_len, PLATFORM_NAME_MAX);
    else if (!(tmp = malloc(n)))
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    if (tmp) {
        int part = name_len > TEMP_NAME_PART ? TEMP_NAME_PART : (int)name_len;
        snprintf(tmp, n, "%.*s.%.*s.XXXXXX", (int)dir_len, dest, part, dest + dir_len);
        if (platform_create_unique(tmp) != 0) {
            fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
            free(tmp);
            tmp = NULL;
        }
    }
    free(dest);
    return tmp;
}

/* The writers name the file they write, the hidden temporary: an error names the output instead. */
static void name_output(fm_error *err, const char *tmp, const char *path)
{
    char *at = err ? strstr(err->message, tmp) : NULL;
    if (!at)
        return;
    char rest[sizeof err->message];
    snprintf(rest, sizeof rest, "%s", at + strlen(tmp));
    snprintf(at, sizeof err->message - (size_t)(at - err->message), "%s%s", path, rest);
}

fm_status image_finish_temp(char *tmp, const char *path, fm_status s, fm_error *err)
{
    char *dest = s ? NULL : destination(path);
    if (!s && !dest)
        s = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    if (!s && platform_rename_replace(tmp, dest) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, strerror(errno));
    free(dest);
    if (s)
        platform_remove(tmp);
    free(tmp);
    return s;
}

fm_status fm_output_check_path(const char *path, fm_error *err)
{
    if (!path)
        return fm_fail(err, FM_ERR_IO, "an output path is missing");
    char *tmp = image_reserve_temp(path, err);
    if (!tmp)
        return err ? err->status : FM_ERR_IO;
    platform_remove(tmp);
    free(tmp);
    return FM_OK;
}

/* A temporary left by a killed run (SIGKILL, a crash) is removed by a later run to the same output
 * once it is a day old: a live run's temporaries are younger (renders take minutes to hours). */
#define STALE_TEMP_S 86400.0

/* Adds path to o's files with a temporary reserved beside it; returns its index, or -1 with err. */
static int reserve_file(fm_output *o, const char *path, fm_error *err)
{
    if (o->count == MAX_FILES) {
        fm_fail(err, FM_ERR_INVALID_ARGUMENT, "too many files in one output");
        return -1;
    }
    staged_file *f = &o->files[o->count];
    if (!(f->path = text_copy(path))) {
        fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
        return -1;
    }
    if (!(f->tmp = image_reserve_temp(path, err))) {
        free(f->path);
        f->path = NULL;
        return -1;
    }
    stale_temps_remove(f->tmp, 0, 0, STALE_TEMP_S);
    return o->count++;
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
    if (reserve_file(o, exr_path, err) != FILE_EXR || reserve_file(o, json_path, err) != FILE_JSON) {
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
    if (!s && recode_exr(staging, path, RECODE_DWAA, FM_DWAA_LEVEL, msg, sizeof msg) != 0)
        s = fm_fail(err, FM_ERR_IO, "cannot write '%s' with DWAA compression: %s", path, msg);
    platform_remove(staging);
    free(staging);
    return s;
}

/* What the files report is the image's render record: an image that no render made has none. */
static fm_status check_record(const fm_image *image, fm_error *err)
{
    return image->record.rendered
               ? FM_OK
               : fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the map has no render record (it was not made by fm_render)");
}

fm_status fm_output_stage(fm_output *o, const fm_image *image, const atomic_int *cancel, fm_error *err)
{
    if (o->staged || !o->files[FILE_EXR].tmp)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "output already written");
    size_t bad = non_finite_values(image);
    if (bad)
        return fm_fail(err, FM_ERR_INTERNAL, "the render produced %zu values that are not finite (NaN or infinity): "
                                             "nothing was written",
                       bad);
    fm_status s = check_record(image, err);
    if (s)
        return s;
    /* 65504 is the largest finite half; rounding to it starts at 65520.  DWA quantises colour
     * channels through half precision even when they are stored as 32-bit float. */
    if (!o->radiance && (o->half || o->compression == FM_EXR_DWAA)) {
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
    const char *exr_tmp = o->files[FILE_EXR].tmp, *exr_path = o->files[FILE_EXR].path;
    metadata meta;
    metadata_collect(&meta, image, exr_path);
    const int threads = image->record.threads;
    s = o->radiance ? image_write_hdr(exr_tmp, image, &meta, cancel, err)
        : o->compression == FM_EXR_DWAA
            ? write_dwaa(exr_tmp, image, &meta, o->half, threads, cancel, err)
            : image_write_exr(exr_tmp, image, &meta, o->half, o->compression, threads, cancel, err);
    if (s)
        name_output(err, exr_tmp, exr_path);
    if (!s && (s = sidecar_write(o->files[FILE_JSON].tmp, &meta, o->job, err)))
        name_output(err, o->files[FILE_JSON].tmp, o->files[FILE_JSON].path);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled before the files were complete");
    if (!s)
        o->staged = 1;
    return s; /* after a failure the temporary files are removed by fm_output_close */
}

/* The spectral map into file (path: the name it will have, for its metadata). */
static fm_status write_spectral_file(const char *file, const char *path, const fm_image *spectral,
                                     const fm_image *colour, const atomic_int *cancel, fm_error *err)
{
    if (spectral->content != FM_IMAGE_SPECTRAL_GRID)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "not a spectral map");
    fm_status s = check_record(colour, err);
    if (s)
        return s;
    size_t bad = non_finite_values(spectral);
    if (bad)
        return fm_fail(err, FM_ERR_INTERNAL, "the spectral map holds %zu values that are not finite: nothing was "
                                             "written", bad);
    metadata meta;
    metadata_collect(&meta, colour, path);
    s = image_write_exr(file, spectral, &meta, 0, FM_EXR_ZIP, colour->record.threads, cancel, err);
    if (!s && cancel && atomic_load(cancel))
        s = fm_fail(err, FM_ERR_CANCELLED, "cancelled while writing '%s'", path);
    return s;
}

fm_status fm_output_stage_spectral(fm_output *o, const char *path, const fm_image *spectral, const fm_image *colour,
                                   const atomic_int *cancel, fm_error *err)
{
    int i = reserve_file(o, path, err);
    if (i < 0)
        return err ? err->status : FM_ERR_IO;
    return write_spectral_file(o->files[i].tmp, path, spectral, colour, cancel, err);
}

fm_status fm_output_stage_preview(fm_output *o, const char *path, const fm_image *image, const fm_colour_config *cfg,
                                  double exposure_ev, fm_error *err)
{
    int i = reserve_file(o, path, err);
    if (i < 0)
        return err ? err->status : FM_ERR_IO;
    return image_write_preview_file(image, cfg, o->files[i].tmp, path, exposure_ev, err);
}

/* A hard link to path's current file under a new hidden name beside it (malloc'd), to put it back
 * if a later rename fails; NULL when there is no file at path or the file system has no links
 * (then that one old file cannot be restored). */
static char *keep_old(const char *path)
{
    if (platform_path_kind(path) == PLATFORM_MISSING)
        return NULL;
    char *backup = image_reserve_temp(path, NULL);
    if (backup && (platform_remove(backup) != 0 || platform_link(path, backup) != 0)) {
        platform_remove(backup);
        free(backup);
        backup = NULL;
    }
    return backup;
}

/* Renames the n files in order; on a failure, undoes the renames made (old files put back, new ones
 * removed) and fails naming the file. */
static fm_status publish_files(staged_file *const *files, int n, fm_error *err)
{
    char *backup[2 * MAX_FILES] = {0}, *dest[2 * MAX_FILES] = {0};
    int done = 0, e = 0;
    for (int i = 0; i < n; i++)
        if (!(dest[i] = destination(files[i]->path))) {
            while (i > 0)
                free(dest[--i]);
            return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory; nothing was written");
        }
    for (; done < n; done++) {
        backup[done] = keep_old(dest[done]);
        if (platform_rename_replace(files[done]->tmp, dest[done]) != 0) {
            e = errno;
            break;
        }
    }
    if (done < n) {
        if (backup[done])
            platform_remove(backup[done]);
        free(backup[done]);
        for (int i = done - 1; i >= 0; i--) {
            if (backup[i])
                platform_rename_replace(backup[i], dest[i]);
            else
                platform_remove(dest[i]);
            free(backup[i]);
            /* the new file is gone: nothing left for fm_output_close to remove */
            free(files[i]->tmp);
            files[i]->tmp = NULL;
        }
        for (int i = 0; i < n; i++)
            free(dest[i]);
        return fm_fail(err, FM_ERR_IO, "cannot write '%s': %s; nothing was written", files[done]->path, strerror(e));
    }
    for (int i = 0; i < n; i++) {
        if (backup[i])
            platform_remove(backup[i]);
        free(backup[i]);
        free(files[i]->tmp);
        files[i]->tmp = NULL;
        free(dest[i]);
    }
    return FM_OK;
}

/* "<dir>/.<name>.lock" beside path (name cut as a temporary's), malloc'd; NULL when out of memory. */
static char *lock_name(const char *path)
{
    const char *slash = platform_last_separator(path);
    size_t dir_len = slash ? (size_t)(slash - path + 1) : 0, name_len = strlen(path + dir_len);
    int part = name_len > TEMP_NAME_PART ? TEMP_NAME_PART : (int)name_len;
    size_t n = strlen(path) + 8;
    char *name = malloc(n);
    if (name)
        snprintf(name, n, "%.*s.%.*s.lock", (int)dir_len, path, part, path + dir_len);
    return name;
}

fm_status fm_output_publish(fm_output *const *outputs, int n, fm_error *err)
{
    staged_file *files[2 * MAX_FILES];
    int count = 0;
    for (int k = 0; k < n; k++) {
        if (!outputs[k]->staged || !outputs[k]->files[FILE_EXR].tmp)
            return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "output not written, or already published");
        if (count + outputs[k]->count > 2 * MAX_FILES)
            return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "too many outputs published together");
        /* the extras first, the map's sidecar last: a reader that sees the sidecar sees its map */
        for (int i = FILE_JSON + 1; i < outputs[k]->count; i++)
            files[count++] = &outputs[k]->files[i];
        files[count++] = &outputs[k]->files[FILE_EXR];
        files[count++] = &outputs[k]->files[FILE_JSON];
    }
    /* a concurrent render to the same map publishes before or after this one, never between its
     * renames: else its map could stand beside this one's sidecar */
    char *name = lock_name(outputs[0]->files[FILE_EXR].path);
    platform_lock *lock = name ? platform_lock_file(name) : NULL;
    fm_status s = lock ? publish_files(files, count, err)
                       : fm_fail(err, FM_ERR_IO, "cannot lock '%s' to write '%s': %s; nothing was written",
                                 name ? name : "", outputs[0]->files[FILE_EXR].path, strerror(errno));
    platform_unlock(lock);
    free(name);
    return s;
}

fm_status fm_output_commit(fm_output *o, const fm_image *image, const atomic_int *cancel, fm_error *err)
{
    fm_status s = fm_output_stage(o, image, cancel, err);
    return s ? s : fm_output_publish(&o, 1, err);
}

void fm_output_close(fm_output *o)
{
    if (!o)
        return;
    for (int i = 0; i < o->count; i++) {
        if (o->files[i].tmp)
            platform_remove(o->files[i].tmp);
        free(o->files[i].tmp);
        free(o->files[i].path);
    }
    free(o->job);
    free(o);
}

fm_status fm_output_write_spectral(const char *path, const fm_image *spectral, const fm_image *colour,
                                   const atomic_int *cancel, fm_error *err)
{
    char *tmp = image_reserve_temp(path, err);
    if (!tmp)
        return err ? err->status : FM_ERR_IO;
    return image_finish_temp(tmp, path, write_spectral_file(tmp, path, spectral, colour, cancel, err), err);
}
