#include "image/image_exr.h"

#include "base/status.h"
#include "base/threads.h"
#include "base/units.h"
#include "colour/colour.h"

#include <openexr.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
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

/* One chunk's bytes as they go into the file. */
typedef struct encoded_chunk {
    exr_chunk_info_t info;
    void *data;
    uint64_t bytes;
} encoded_chunk;

typedef struct encode_job {
    exr_context_t ctxt;
    int part;
    const fm_image *img;
    int chunks, threads;
    encoded_chunk *chunk;
    exr_encode_pipeline_t *pipe; /* one per thread */
    int *started;
    atomic_int failed; /* the first OpenEXR error */
} encode_job;

/* The pipeline's last step: keep the compressed bytes instead of writing them (the thread that
 * owns the file writes every chunk in order). */
static exr_result_t keep_chunk(exr_encode_pipeline_t *pipe)
{
    encoded_chunk *c = pipe->encoding_user_data;
    c->data = malloc(pipe->compressed_bytes ? pipe->compressed_bytes : 1);
    if (!c->data)
        return EXR_ERR_OUT_OF_MEMORY;
    memcpy(c->data, pipe->compressed_buffer, pipe->compressed_bytes);
    c->bytes = pipe->compressed_bytes;
    return EXR_ERR_SUCCESS;
}

static void encode_chunks(void *ctx, int64_t begin, int64_t end, int thread)
{
    encode_job *job = ctx;
    const fm_image *img = job->img;
    const int W = img->width, C = img->channels;
    exr_encode_pipeline_t *pipe = &job->pipe[thread];
    for (int64_t i = begin; i < end && atomic_load(&job->failed) == EXR_ERR_SUCCESS; i++) {
        encoded_chunk *c = &job->chunk[i];
        exr_result_t rv = job->started[thread] ? exr_encoding_update(job->ctxt, job->part, &c->info, pipe)
                                               : exr_encoding_initialize(job->ctxt, job->part, &c->info, pipe);
        for (int ch = 0; !rv && ch < pipe->channel_count; ch++) {
            exr_coding_channel_info_t *info = &pipe->channels[ch];
            info->user_bytes_per_element = 4;
            info->user_data_type = EXR_PIXEL_FLOAT;
            info->user_pixel_stride = C * (int32_t)sizeof(float);
            info->user_line_stride = W * C * (int32_t)sizeof(float);
            info->encode_from_ptr = (const uint8_t *)&img->pixels[((size_t)c->info.start_y * W) * C +
                                                                  channel_offset(img, info->channel_name)];
        }
        if (!rv && !job->started[thread]) {
            rv = exr_encoding_choose_default_routines(job->ctxt, job->part, pipe);
            job->started[thread] = !rv;
        }
        if (!rv) {
            pipe->yield_until_ready_fn = NULL;
            pipe->write_fn = keep_chunk;
            pipe->encoding_user_data = c;
            rv = exr_encoding_run(job->ctxt, job->part, pipe);
        }
        if (rv) {
            int none = EXR_ERR_SUCCESS;
            atomic_compare_exchange_strong(&job->failed, &none, rv);
        }
    }
}

/* zlib level of ZIP chunks: 1 (fastest) instead of the library's 6.  A 4096 x 2048 RGB float
 * map: 41.2 MB instead of 40.0 MB (+3%), and about 0.3 s less of a 2.5-3 s render on two cores
 * (zlib had been a tenth of the urban sunset's final 4096 x 2048 render's CPU). */
#define ZIP_LEVEL 1

fm_status image_write_exr(const char *path, const fm_image *img, const metadata *meta, int half,
                          fm_exr_compression compression, int threads, const atomic_int *cancel, fm_error *err)
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
        (rv = exr_initialize_required_attr_simple(ctxt, part, W, H, method)) ||
        (method == EXR_COMPRESSION_ZIP && (rv = exr_set_zip_compression_level(ctxt, part, ZIP_LEVEL))))
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
    /* Chunks are packed and compressed on all threads, each into its own buffer, and written to the
     * file in order by this thread (zlib was a third of a 4096 x 2048 render's time). */
    encode_job job = {.ctxt = ctxt, .part = part, .img = img, .chunks = (H + lines - 1) / lines};
    job.threads = parallel_thread_count(threads);
    job.chunk = calloc((size_t)job.chunks, sizeof *job.chunk);
    job.pipe = calloc((size_t)job.threads, sizeof *job.pipe);
    job.started = calloc((size_t)job.threads, sizeof *job.started);
    if (!job.chunk || !job.pipe || !job.started) {
        status = fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory writing '%s'", path);
    } else {
        atomic_init(&job.failed, EXR_ERR_SUCCESS);
        for (int i = 0; i < job.chunks && !rv; i++)
            rv = exr_write_scanline_chunk_info(ctxt, part, i * lines, &job.chunk[i].info);
        fm_status run = rv ? FM_OK : parallel_for(job.threads, job.chunks, 1, encode_chunks, &job, cancel, NULL);
        if (!rv)
            rv = atomic_load(&job.failed);
        if (run == FM_ERR_CANCELLED || (cancel && atomic_load(cancel)))
            status = fm_fail(err, FM_ERR_CANCELLED, "cancelled while writing '%s'", path);
        else if (run)
            status = fm_fail(err, run, "cannot write '%s': %s", path, fm_status_name(run));
        for (int i = 0; i < job.chunks && status == FM_OK && !rv; i++)
            rv = exr_write_scanline_chunk(ctxt, part, job.chunk[i].info.start_y, job.chunk[i].data,
                                          job.chunk[i].bytes);
        for (int t = 0; t < job.threads; t++)
            if (job.started[t])
                exr_encoding_destroy(ctxt, &job.pipe[t]);
    }
    if (job.chunk)
        for (int i = 0; i < job.chunks; i++)
            free(job.chunk[i].data);
    free(job.chunk);
    free(job.pipe);
    free(job.started);
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
