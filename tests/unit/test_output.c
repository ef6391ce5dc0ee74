/* Output files: the EXR's channels and attributes as OpenEXR reads them back, the JSON sidecar,
 * and the all-or-nothing commit (temporary files, rename, cancellation). */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "exr_read.h"

#include "base/units.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256];

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/fm_test_output_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static int count_files(void)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while ((e = readdir(d)))
        n += e->d_name[0] != '.' || (e->d_name[1] != '\0' && strcmp(e->d_name, "..") != 0);
    closedir(d);
    return n;
}

static cJSON *read_json(const char *path)
{
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    static char buf[1 << 16];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    cJSON *j = cJSON_Parse(buf);
    assert_non_null(j);
    return j;
}

static double json_number(cJSON *root, const char *group, const char *key)
{
    cJSON *g = cJSON_GetObjectItemCaseSensitive(root, group);
    cJSON *v = g ? cJSON_GetObjectItemCaseSensitive(g, key) : NULL;
    if (!cJSON_IsNumber(v))
        fail_msg("sidecar has no number %s.%s", group, key);
    return v->valuedouble;
}

static void commit_files(fm_image *img, const char *exr, const char *json, const atomic_int *cancel,
                  fm_status expect)
{
    fm_output *out = NULL;
    fm_error err;
    assert_int_equal(fm_output_open(exr, json, &out, &err), FM_OK);
    fm_status s = fm_output_commit(out, img, cancel, &err);
    if (s != expect)
        fail_msg("commit returned %d (%s), expected %d", s, err.message, expect);
    fm_output_close(out);
}

/* The files report the sky as it was when the map was rendered (its render record), not as it is
 * at the commit: the sky is moved and then destroyed before the map is written, and the sidecar
 * still holds the rendered sun and its direct light (fm_sky_sun_light of a sky with those
 * parameters).  A map whose disk was taken out reports none; an image that no render made has no
 * record to write and is refused. */
static void files_report_the_render_not_the_sky(void **state)
{
    fm_sky_params p = test_params(20.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_sun_light light;
    fm_sky_sun_light(sky, &light);
    fm_image *img = test_render(sky, 16, FM_QUALITY_PREVIEW, 0, 1, 0, 0.25, 1);
    fm_error err;
    assert_int_equal(fm_sky_set_sun(sky, 45.0, 90.0, &err), FM_OK);
    fm_sky_destroy(sky);
    fm_image_remove_sun_disk(img);
    assert_null(img->sun_disk);
    char exr[300], json[300];
    snprintf(exr, sizeof exr, "%s/record.exr", dir);
    snprintf(json, sizeof json, "%s/record.json", dir);
    commit_files(img, exr, json, NULL, FM_OK);
    cJSON *j = read_json(json);
    check_abs(json_number(j, "sun", "elevation_deg"), 20.0, 0.0, "the rendered sun's elevation");
    double lux = FM_LUMINOUS_EFFICACY * light.normal_irradiance[1];
    check_rel(json_number(j, "sun", "direct_normal_illuminance_lux"), lux, 1e-12, "the rendered sun's light");
    assert_true(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "image"),
                                                               "contains_sun_disk")));
    cJSON_Delete(j);
    unlink(exr);
    unlink(json);

    fm_image blank = *img;
    blank.record.rendered = 0;
    fm_output *out = NULL;
    assert_int_equal(fm_output_open(exr, json, &out, &err), FM_OK);
    assert_int_equal(fm_output_commit(out, &blank, NULL, &err), FM_ERR_INVALID_ARGUMENT);
    fm_output_close(out);
    assert_int_equal(access(exr, F_OK), -1);
    fm_image_destroy(img);
}

static void colour_exr_attributes_and_sidecar(void **state)
{
    fm_sky_params p = test_params(30.0, 0.0);
    p.sun_azimuth_deg = 135.0;
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 32, FM_QUALITY_PREVIEW, 0, 1, 0, 0.25, 1);
    fm_error err;
    assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
    char exr[300], json[300];
    snprintf(exr, sizeof exr, "%s/sky.exr", dir);
    snprintf(json, sizeof json, "%s/sky.json", dir);
    commit_files(img, exr, json, NULL, FM_OK);
    assert_int_equal(count_files(), 2); /* no temporary file left */

    exr_context_t c;
    test_exr e = test_exr_read(exr, &c);
    assert_int_equal(e.width, 32);
    assert_int_equal(e.height, 16);
    assert_int_equal(e.channels, 3);
    /* pixels survive the round trip bit for bit (32-bit float) */
    for (int y = 0; y < 16; y++)
        for (int x = 0; x < 32; x++)
            for (int ch = 0; ch < 3; ch++) {
                int off = e.names[ch][0] == 'R' ? 0 : (e.names[ch][0] == 'G' ? 1 : 2);
                assert_true(e.pixels[(y * 32 + x) * 3 + ch] == img->pixels[(y * 32 + x) * 3 + off]);
            }
    exr_attr_chromaticities_t chroma;
    assert_int_equal(exr_attr_get_chromaticities(c, 0, "chromaticities", &chroma), EXR_ERR_SUCCESS);
    check_abs(chroma.red_x, 0.64, 1e-6, "red x");
    check_abs(chroma.green_y, 0.60, 1e-6, "green y");
    check_abs(chroma.blue_x, 0.15, 1e-6, "blue x");
    check_abs(chroma.white_x, 0.3127, 1e-6, "white x");
    check_abs(chroma.white_y, 0.3290, 1e-6, "white y");
    exr_envmap_t env;
    assert_int_equal(exr_attr_get_envmap(c, 0, "envmap", &env), EXR_ERR_SUCCESS);
    assert_int_equal(env, EXR_ENVMAP_LATLONG);
    float white;
    assert_int_equal(exr_attr_get_float(c, 0, "whiteLuminance", &white), EXR_ERR_SUCCESS);
    check_abs(white, 683.0, 1e-3, "whiteLuminance");
    double v;
    assert_int_equal(exr_attr_get_double(c, 0, "firmament.parameters.sun_azimuth_deg", &v), EXR_ERR_SUCCESS);
    check_abs(v, 135.0, 0.0, "sun azimuth attribute");
    assert_int_equal(exr_attr_get_double(c, 0, "firmament.sun.direct_normal_illuminance_lux", &v), EXR_ERR_SUCCESS);
    double exr_lux = v;
    exr_attr_v3d_t dir3;
    assert_int_equal(exr_attr_get_v3d(c, 0, "firmament.sun.direction", &dir3), EXR_ERR_SUCCESS);
    exr_finish(&c);
    test_exr_free(&e);

    cJSON *j = read_json(json);
    check_abs(json_number(j, "sun", "elevation_deg"), 30.0, 0.0, "sidecar elevation");
    check_abs(json_number(j, "sun", "azimuth_deg"), 135.0, 0.0, "sidecar azimuth");
    check_abs(json_number(j, "sun", "direct_normal_illuminance_lux"), exr_lux, 1e-9 * exr_lux, "lux in both files");
    /* the direction vector in map axes: azimuth 135 = south-east, elevation 30 */
    cJSON *d = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "sun"), "direction");
    assert_int_equal(cJSON_GetArraySize(d), 3);
    double dx = cJSON_GetArrayItem(d, 0)->valuedouble, dy = cJSON_GetArrayItem(d, 1)->valuedouble,
           dz = cJSON_GetArrayItem(d, 2)->valuedouble;
    check_abs(dx, cos(30 * FM_DEG) * sin(135 * FM_DEG), 1e-12, "direction x (east)");
    check_abs(dy, cos(30 * FM_DEG) * cos(135 * FM_DEG), 1e-12, "direction y (north)");
    check_abs(dz, 0.5, 1e-12, "direction z (up)");
    check_abs(dir3.x, dx, 1e-12, "EXR direction attribute");
    /* RGB irradiance has the luminance that the lux figure states */
    cJSON *rgb = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(j, "sun"), "direct_normal_irradiance_rgb");
    double y = 0.2126729 * cJSON_GetArrayItem(rgb, 0)->valuedouble + 0.7151522 * cJSON_GetArrayItem(rgb, 1)->valuedouble +
               0.0721750 * cJSON_GetArrayItem(rgb, 2)->valuedouble;
    check_rel(683.0 * y, exr_lux, 1e-9, "RGB irradiance vs lux");
    double diffuse = json_number(j, "sky", "diffuse_horizontal_illuminance_lux");
    double global = json_number(j, "sky", "global_horizontal_illuminance_lux");
    double direct_h = json_number(j, "sun", "direct_horizontal_illuminance_lux");
    check_rel(global, diffuse + direct_h, 1e-12, "global = diffuse + direct horizontal");
    check_rel(direct_h, 0.5 * exr_lux, 2e-3, "direct horizontal = normal x sin(30 deg)");
    cJSON *image = cJSON_GetObjectItemCaseSensitive(j, "image");
    assert_true(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(image, "contains_sun_disk")));
    cJSON_Delete(j);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

/* A small rendered sky and the paths <dir>/<name>.exr and .json. */
static fm_image *small_sky(double lambda, const char *name, fm_sky **sky, char exr[300], char json[300])
{
    fm_sky_params p = test_params(30.0, lambda);
    *sky = test_sky(&p);
    snprintf(exr, 300, "%s/%s.exr", dir, name);
    snprintf(json, 300, "%s/%s.json", dir, name);
    return test_render(*sky, 16, FM_QUALITY_PREVIEW, 0, 1, 0, 0.25, 0);
}

static void monochromatic_exr_has_one_channel(void **state)
{
    fm_sky *sky;
    char exr[300], json[300];
    fm_image *img = small_sky(550.0, "mono", &sky, exr, json);
    commit_files(img, exr, json, NULL, FM_OK);
    exr_context_t c;
    test_exr e = test_exr_read(exr, &c);
    assert_int_equal(e.channels, 1);
    assert_string_equal(e.names[0], "Y");
    double lambda;
    assert_int_equal(exr_attr_get_double(c, 0, "firmament.parameters.wavelength_nm", &lambda), EXR_ERR_SUCCESS);
    check_abs(lambda, 550.0, 0.0, "wavelength attribute");
    exr_attr_chromaticities_t chroma;
    assert_int_not_equal(exr_attr_get_chromaticities(c, 0, "chromaticities", &chroma), EXR_ERR_SUCCESS);
    exr_finish(&c);
    test_exr_free(&e);
    cJSON *j = read_json(json);
    assert_true(json_number(j, "sun", "direct_normal_spectral_irradiance") > 1.0);
    cJSON_Delete(j);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

static void cancelled_commit_leaves_existing_files_alone(void **state)
{
    fm_sky *sky;
    char exr[300], json[300];
    fm_image *img = small_sky(0.0, "keep", &sky, exr, json);
    FILE *f = fopen(exr, "w");
    fputs("old image", f);
    fclose(f);
    f = fopen(json, "w");
    fputs("old sidecar", f);
    fclose(f);
    int before = count_files();
    atomic_int cancel;
    atomic_init(&cancel, 1);
    commit_files(img, exr, json, &cancel, FM_ERR_CANCELLED);
    assert_int_equal(count_files(), before); /* temporary files removed */
    char buf[32] = {0};
    f = fopen(exr, "r");
    assert_non_null(fgets(buf, sizeof buf, f));
    fclose(f);
    assert_string_equal(buf, "old image");
    /* an uncancelled commit replaces both */
    commit_files(img, exr, json, NULL, FM_OK);
    test_exr e = test_exr_read(exr, NULL);
    assert_int_equal(e.width, 16);
    test_exr_free(&e);
    assert_int_equal(count_files(), before);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

/* A map holding values that are not finite is refused before anything is written, by a message
 * that names them (not the half-float range, which a NaN or infinity would also fail), and the
 * files already at the paths stay as they were. */
static void non_finite_maps_are_refused(void **state)
{
    fm_sky *sky;
    char exr[300], json[300];
    fm_image *img = small_sky(0.0, "nan", &sky, exr, json);
    for (int i = 0; i < 2; i++) {
        FILE *f = fopen(i ? json : exr, "w");
        fputs("old", f);
        fclose(f);
    }
    const int before = count_files();
    img->pixels[5] = NAN;
    img->pixels[(size_t)img->width * img->height * img->channels - 1] = INFINITY;
    for (int half = 0; half < 2; half++) {
        fm_output *out = NULL;
        fm_error err;
        assert_int_equal(fm_output_open(exr, json, &out, &err), FM_OK);
        assert_int_equal(fm_output_set_format(out, half, FM_EXR_PIZ, &err), FM_OK);
        assert_int_equal(fm_output_commit(out, img, NULL, &err), FM_ERR_INTERNAL);
        fm_output_close(out);
        assert_non_null(strstr(err.message, "2 values that are not finite"));
        assert_int_equal(count_files(), before);
        for (int i = 0; i < 2; i++) {
            char buf[8] = {0};
            FILE *f = fopen(i ? json : exr, "r");
            assert_non_null(fgets(buf, sizeof buf, f));
            fclose(f);
            assert_string_equal(buf, "old");
        }
    }
    fm_image_destroy(img);
    fm_sky_destroy(sky);
}

static void unwritable_paths_are_refused_up_front(void **state)
{
    fm_output *out = NULL;
    fm_error err;
    assert_int_equal(fm_output_open("/nonexistent-dir/x.exr", "/nonexistent-dir/x.json", &out, &err), FM_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/x.exr"));
    assert_int_equal(fm_output_open(dir, "/tmp/x.json", &out, &err), FM_ERR_IO);
    assert_non_null(strstr(err.message, "directory"));
    assert_int_equal(fm_output_open("a.exr", "a.exr", &out, &err), FM_ERR_INVALID_ARGUMENT);
    assert_null(out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(colour_exr_attributes_and_sidecar),
        cmocka_unit_test(files_report_the_render_not_the_sky),
        cmocka_unit_test(monochromatic_exr_has_one_channel),
        cmocka_unit_test(cancelled_commit_leaves_existing_files_alone),
        cmocka_unit_test(non_finite_maps_are_refused),
        cmocka_unit_test(unwritable_paths_are_refused_up_front),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
