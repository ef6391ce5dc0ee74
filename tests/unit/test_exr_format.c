/* The EXR's pixel format: half-float output within half precision of the float output, the
 * half range refused (the sun disk), the lossless compression methods and DWAA (lossless for
 * float, lossy but close for half, every attribute kept), read back through OpenEXR. */
#define _GNU_SOURCE /* memmem */
#include "check.h"
#include "exr_read.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[256];
/* DWAA at level 45 on the 256 x 128 preview map, measured: RMS 0.20 %, worst pixel 1.3 % (float
 * and half alike); the bounds leave a factor of about 2.5 and catch a wrong channel order or scale. */
#define DWAA_RMS_BOUND 0.005
#define DWAA_WORST_BOUND 0.03

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/fm_test_exr_format_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static fm_status write_map(fm_image *img, const char *name, int half, fm_exr_compression c,
                           fm_error *err)
{
    char exr[300], json[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    snprintf(json, sizeof json, "%s/%s.json", dir, name);
    fm_output *out = NULL;
    assert_int_equal(fm_output_open(exr, json, &out, err), FM_OK);
    fm_status s = fm_output_set_format(out, half, c, err);
    if (!s)
        s = fm_output_commit(out, img, NULL, err);
    fm_output_close(out);
    return s;
}

static test_exr read_map(const char *name, exr_compression_t *compression, exr_pixel_type_t *type)
{
    char exr[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    exr_context_t ctxt = NULL;
    test_exr t = test_exr_read(exr, &ctxt);
    assert_int_equal(exr_get_compression(ctxt, 0, compression), EXR_ERR_SUCCESS);
    const exr_attr_chlist_t *ch = NULL;
    assert_int_equal(exr_get_channels(ctxt, 0, &ch), EXR_ERR_SUCCESS);
    *type = ch->entries[0].pixel_type;
    exr_finish(&ctxt);
    return t;
}

static void half_is_float_within_half_precision(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 64, FM_QUALITY_PREVIEW, 2, 1, 0, 0.25, 0);
    fm_error err = {0};
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    assert_int_equal(write_map(img, "float", 0, FM_EXR_ZIP, &err), FM_OK);
    assert_int_equal(write_map(img, "half", 1, FM_EXR_ZIP, &err), FM_OK);
    exr_compression_t c;
    exr_pixel_type_t type;
    test_exr f = read_map("float", &c, &type);
    assert_int_equal(type, EXR_PIXEL_FLOAT);
    test_exr h = read_map("half", &c, &type);
    assert_int_equal(type, EXR_PIXEL_HALF);
    assert_int_equal(c, EXR_COMPRESSION_ZIP);
    assert_int_equal(h.width, f.width);
    size_t n = (size_t)f.width * f.height * f.channels;
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        /* half has an 11-bit significand: round-to-nearest is within 2^-11 relative (normal
         * numbers, above 6.1e-5); below that the step is 2^-24 */
        double tol = fmax(fabs(f.pixels[i]) * 0x1p-11, 0x1p-24);
        double e = fabs(h.pixels[i] - f.pixels[i]);
        worst = fmax(worst, e / tol);
        if (e > tol)
            fail_msg("pixel value %zu: half %.8g vs float %.8g", i, h.pixels[i], f.pixels[i]);
    }
    assert_true(worst > 0.0); /* the half file really is rounded */
    test_exr_free(&f);
    test_exr_free(&h);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

static void half_refuses_the_sun_disk(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    /* at 256 pixels across the disk fills half a pixel: of order 10^5 in the map's units */
    fm_image *img = test_render(sky, 256, FM_QUALITY_PREVIEW, 2, 1, 0, 0.05, 1);
    fm_error err = {0};
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    assert_int_equal(write_map(img, "disk", 1, FM_EXR_ZIP, &err), FM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.parameter, "half");
    assert_non_null(strstr(err.message, "65504"));
    assert_non_null(strstr(err.message, "--no-sun-disk"));
    char exr[300];
    snprintf(exr, sizeof exr, "%s/disk.exr", dir);
    struct stat st;
    assert_true(stat(exr, &st) != 0); /* nothing written */
    /* the same map in float is fine */
    assert_int_equal(write_map(img, "disk", 0, FM_EXR_ZIP, &err), FM_OK);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

static void compression_methods(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 64, FM_QUALITY_PREVIEW, 2, 1, 0, 0.25, 0);
    fm_error err = {0};
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    const char *names[2] = {"zip", "piz"};
    const exr_compression_t expect[2] = {EXR_COMPRESSION_ZIP, EXR_COMPRESSION_PIZ};
    for (int k = 0; k < 2; k++) {
        if (write_map(img, names[k], 0, (fm_exr_compression)k, &err))
            fail_msg("%s: %s", names[k], err.message);
        exr_compression_t c;
        exr_pixel_type_t type;
        test_exr t = read_map(names[k], &c, &type);
        assert_int_equal(c, expect[k]);
        /* both methods are lossless */
        for (size_t i = 0; i < (size_t)t.width * t.height * 3; i++) {
            int x = (int)(i / 3), ch = t.names[i % 3][0] == 'R' ? 0 : t.names[i % 3][0] == 'G' ? 1 : 2;
            if (t.pixels[i] != img->pixels[(size_t)x * 3 + ch])
                fail_msg("%s: value %zu changed", names[k], i);
        }
        test_exr_free(&t);
    }
    assert_int_equal(write_map(img, "bad", 0, (fm_exr_compression)7, &err), FM_ERR_INVALID_ARGUMENT);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

static long file_size(const char *name)
{
    char exr[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    struct stat st;
    assert_int_equal(stat(exr, &st), 0);
    return (long)st.st_size;
}

/* The attributes that must survive the C++ re-encoding: chromaticities and a typed firmament.*
 * value (a double). */
static void check_attributes(const char *name, double sun_elevation_deg)
{
    char exr[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    exr_context_t ctxt = NULL;
    assert_int_equal(exr_start_read(&ctxt, exr, NULL), EXR_ERR_SUCCESS); /* the header only */
    exr_compression_t c;
    assert_int_equal(exr_get_compression(ctxt, 0, &c), EXR_ERR_SUCCESS);
    assert_int_equal(c, EXR_COMPRESSION_DWAA);
    exr_attr_chromaticities_t chroma;
    assert_int_equal(exr_attr_get_chromaticities(ctxt, 0, "chromaticities", &chroma), EXR_ERR_SUCCESS);
    assert_float_equal(chroma.red_x, 0.64, 1e-6);
    assert_float_equal(chroma.white_y, 0.329, 1e-3);
    double e = 0.0;
    assert_int_equal(exr_attr_get_double(ctxt, 0, "firmament.sun.elevation_deg", &e), EXR_ERR_SUCCESS);
    assert_float_equal(e, sun_elevation_deg, 1e-12);
    const char *projection = NULL;
    assert_int_equal(exr_attr_get_string(ctxt, 0, "firmament.image.projection", NULL, &projection), EXR_ERR_SUCCESS);
    assert_string_equal(projection, "equirectangular");
    exr_finish(&ctxt);
}

/* Pixels of a DWA file: OpenEXR's C library cannot decode DWA, fm_image_read_exr goes through its
 * C++ library (exr_recode.h). */
static fm_image *read_dwa(const char *name)
{
    char exr[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    fm_image *img = NULL;
    fm_error err = {0};
    if (fm_image_read_exr(exr, &img, &err))
        fail_msg("%s", err.message);
    return img;
}

static void dwaa(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 256, FM_QUALITY_PREVIEW, 2, 1, 0, 0.25, 0);
    fm_error err = {0};
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    assert_int_equal(write_map(img, "dwaa-float", 0, FM_EXR_DWAA, &err), FM_OK);
    assert_int_equal(write_map(img, "dwaa-half", 1, FM_EXR_DWAA, &err), FM_OK);
    assert_int_equal(write_map(img, "zip-half", 1, FM_EXR_ZIP, &err), FM_OK);
    /* 32-bit float channels are quantised through half precision too (DWA's colour channels) */
    fm_image *f = read_dwa("dwaa-float");
    assert_int_equal(f->width, img->width);
    assert_int_equal(f->channels, 3);
    size_t n = (size_t)f->width * f->height * 3;
    fm_image *h = read_dwa("dwaa-half");
    const fm_image *decoded[2] = {f, h};
    const char *label[2] = {"float", "half"};
    for (int k = 0; k < 2; k++) {
        double sum2 = 0.0, worst = 0.0;
        for (size_t i = 0; i < n; i++) {
            double ref = img->pixels[i];
            double rel = fabs(decoded[k]->pixels[i] - ref) / fmax(fabs(ref), 1e-6);
            sum2 += rel * rel;
            worst = fmax(worst, rel);
        }
        double rms = sqrt(sum2 / (double)n);
        print_message("dwaa %s: RMS %.3f %%, worst %.3f %%\n", label[k], 100 * rms, 100 * worst);
        assert_true(rms > 0.0); /* really lossy: the C++ encoder ran */
        assert_true(rms < DWAA_RMS_BOUND);
        assert_true(worst < DWAA_WORST_BOUND);
    }
    print_message("dwaa half: %ld bytes; zip half: %ld bytes\n", file_size("dwaa-half"), file_size("zip-half"));
    assert_true(file_size("dwaa-half") < file_size("zip-half"));
    /* the sun disk (beyond 65504) is refused, nothing written */
    fm_image *disk = test_render(sky, 256, FM_QUALITY_PREVIEW, 2, 1, 0, 0.05, 1);
    assert_int_equal(fm_image_to_rec709(disk, &err), FM_OK);
    assert_int_equal(write_map(disk, "dwaa-disk", 0, FM_EXR_DWAA, &err), FM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.parameter, "compression");
    assert_non_null(strstr(err.message, "65504"));
    char path[300];
    snprintf(path, sizeof path, "%s/dwaa-disk.exr", dir);
    struct stat st;
    assert_true(stat(path, &st) != 0);
    fm_image_destroy(disk);
    check_attributes("dwaa-float", 30.0);
    check_attributes("dwaa-half", 30.0);
    fm_image_destroy(f);
    fm_image_destroy(h);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

/* Overwrites the bytes `skip` bytes after the header's first `key` (key_size bytes, its NULs
 * included) in the map `name` with data. */
static void overwrite_after(const char *name, const char *key, size_t key_size, long skip, const void *data,
                            size_t size)
{
    char exr[300];
    snprintf(exr, sizeof exr, "%s/%s.exr", dir, name);
    FILE *f = fopen(exr, "r+b");
    assert_non_null(f);
    char head[4096];
    size_t n = fread(head, 1, sizeof head, f);
    char *at = memmem(head, n, key, key_size);
    assert_non_null(at);
    fseek(f, (long)(at - head) + (long)key_size + skip, SEEK_SET);
    assert_int_equal(fwrite(data, size, 1, f), 1);
    fclose(f);
}

static void claim_window(const char *name, int32_t width, int32_t height)
{
    static const char key[] = "dataWindow\0box2i";
    int32_t box[4] = {0, 0, width - 1, height - 1};
    overwrite_after(name, key, sizeof key, 4, box, sizeof box);
}

/* A preview map of the default sky at sun 30, `width` wide, in Rec.709. */
static fm_image *rec709_map(int width)
{
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, width, FM_QUALITY_PREVIEW, 2, 1, 0, 0.05, 0);
    fm_sky_destroy(sky);
    fm_error err = {0};
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    return img;
}

/* A header that claims far more pixels than its file can hold (a corrupt or hostile file) is
 * refused before anything is allocated for it, in a DWA file (read through the C++ library) as in
 * a ZIP one; a DWA map taller than one 256-line strip of the recoding reads back whole. */
static void corrupt_window_refused(void **state)
{
    fm_image *img = rec709_map(1200);
    fm_error err = {0};
    size_t n = (size_t)img->width * img->height * 3;
    if (write_map(img, "tall-dwaa", 1, FM_EXR_DWAA, &err))
        fail_msg("%s", err.message);
    fm_image *back = read_dwa("tall-dwaa");
    assert_int_equal(back->height, 600);
    double worst = 0.0;
    for (size_t i = 0; i < n; i++)
        worst = fmax(worst, fabs(back->pixels[i] - img->pixels[i]) / fmax(fabs(img->pixels[i]), 1e-6));
    assert_true(worst < DWAA_WORST_BOUND);
    fm_image_destroy(back);
    assert_int_equal(write_map(img, "claims-zip", 1, FM_EXR_ZIP, &err), FM_OK);
    fm_image_destroy(img);
    /* the ZIP file cannot hold 16384 x 12288 pixels: refused from its header; DWA can compress a
     * flat image that far, so its chunks are read strip by strip until the first corrupt one, in a
     * strip's memory, never the 1.2 GB the header claims */
    claim_window("claims-zip", 16384, 12288);
    claim_window("tall-dwaa", 16384, 12288);
    char exr[300];
    fm_image *none = NULL;
    snprintf(exr, sizeof exr, "%s/claims-zip.exr", dir);
    assert_int_equal(fm_image_read_exr(exr, &none, &err), FM_ERR_IO);
    print_message("zip: %s\n", err.message);
    assert_non_null(strstr(err.message, "bytes can hold"));
    struct rusage before, after;
    getrusage(RUSAGE_SELF, &before);
    snprintf(exr, sizeof exr, "%s/tall-dwaa.exr", dir);
    assert_int_equal(fm_image_read_exr(exr, &none, &err), FM_ERR_IO);
    getrusage(RUSAGE_SELF, &after);
    print_message("dwa: %s; peak memory +%ld MiB\n", err.message, (after.ru_maxrss - before.ru_maxrss) / 1024);
    assert_true(after.ru_maxrss - before.ru_maxrss < 256 * 1024); /* KiB */
    assert_null(none);
}

/* A DWA map whose string attribute claims 2 GB (a corrupt file the fuzzer found: the C++ library
 * that decodes DWA allocated what it claimed) is refused from its header, in no memory to speak of. */
static void corrupt_attribute_refused(void **state)
{
    fm_image *img = rec709_map(16);
    fm_error err = {0};
    assert_int_equal(write_map(img, "claims-attribute", 1, FM_EXR_DWAA, &err), FM_OK);
    fm_image_destroy(img);
    fm_image_destroy(read_dwa("claims-attribute"));
    static const char key[] = "firmament.version\0string";
    const int32_t claim = 0x7ff00000;
    overwrite_after("claims-attribute", key, sizeof key, 0, &claim, sizeof claim);
    char exr[300];
    snprintf(exr, sizeof exr, "%s/claims-attribute.exr", dir);
    struct rusage before, after;
    getrusage(RUSAGE_SELF, &before);
    fm_image *none = NULL;
    assert_int_equal(fm_image_read_exr(exr, &none, &err), FM_ERR_IO);
    getrusage(RUSAGE_SELF, &after);
    print_message("attribute: %s; peak memory +%ld MiB\n", err.message, (after.ru_maxrss - before.ru_maxrss) / 1024);
    assert_non_null(strstr(err.message, "claims more bytes than the file holds"));
    assert_true(after.ru_maxrss - before.ru_maxrss < 256 * 1024); /* KiB */
    assert_null(none);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(half_is_float_within_half_precision),
        cmocka_unit_test(half_refuses_the_sun_disk),
        cmocka_unit_test(compression_methods),
        cmocka_unit_test(dwaa),
        cmocka_unit_test(corrupt_window_refused),
        cmocka_unit_test(corrupt_attribute_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
