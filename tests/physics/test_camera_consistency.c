/* Every camera is a view of the same radiance.
 *
 *  - A pinhole or fisheye pixel equals the equirectangular map sampled in the same direction: both
 *    renders use the same seed and quality, hence the very same radiance tables (their nodes' random
 *    streams do not depend on the camera), so the differences are geometric: the pixel's footprint
 *    average (1-3 degree pixels) against a bilinear interpolation of the map (0.7 degree pixels), both
 *    second-order in the pixel size (0.1-0.5% measured), and the tables' noise seen differently: the
 *    multiple-scattering table's nodes (16 azimuths, rows 8 degrees apart up there) carry independent
 *    noise, and a pixel averages the interpolated noise over its footprint where the map's
 *    interpolation takes it at one point.  Near the zenith every column of a row looks almost the same
 *    way, so a point there meets the noise of single nodes while a pixel spans many: the comparison
 *    stops 10 degrees short of the zenith, and the tables get 4 times the final quality's paths (the
 *    worst difference halves with each 4 times, 1.3% -> 0.65% -> 0.3% at 70-77 degrees: noise).
 *    Away from the horizon (4 degrees) and the sun (15 degrees) they agree to 1% (worst 0.5-0.65%).
 *  - The fisheye's zenith pixels equal the map's top rows over a cap of the same solid angle, where
 *    both average over every azimuth (1%; measured 0.02%).
 *  - The sun disk carries the same energy (sum of disk pixels x pixel solid angle) through every
 *    camera, equal to the direct normal irradiance (0.5%).
 *  - Reference (per-pixel paths through the camera) and fast path agree within the reference's noise,
 *    across the pinhole's horizon and the fisheye's rim.
 *  - The fisheye's diffuse horizontal irradiance (sidecar) equals the map's (0.5%).
 *  - Same seed, 1 or 2 threads: the same bits, for both cameras and both estimators.
 *  - The files say which camera made them; only the equirectangular map claims envmap = latlong. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "exr_read.h"

#include "base/units.h"
#include "camera/camera.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static fm_camera pinhole_camera(double fov, double azimuth, double elevation, double aspect)
{
    fm_camera c = fm_render_params_default().camera;
    c.type = FM_CAMERA_PINHOLE;
    c.fov_deg = fov;
    c.look_azimuth_deg = azimuth;
    c.look_elevation_deg = elevation;
    c.aspect = aspect;
    return c;
}

static fm_camera fisheye_camera(fm_fisheye_projection projection)
{
    fm_camera c = fm_render_params_default().camera;
    c.type = FM_CAMERA_FISHEYE;
    c.fisheye_projection = projection;
    return c;
}

static fm_image *render(const fm_sky *sky, fm_camera cam, int width, fm_quality quality, int threads, uint64_t seed,
                        int samples, double scale, int disk)
{
    fm_render_params rp = fm_render_params_default();
    rp.camera = cam;
    rp.width = width;
    rp.quality = quality;
    rp.threads = threads;
    rp.seed = seed;
    rp.reference_samples = samples;
    rp.sample_scale = scale;
    rp.sun_disk = disk;
    fm_image *img = NULL;
    fm_error err;
    if (fm_render(sky, &rp, &img, &err) != FM_OK)
        fail_msg("fm_render: %s", err.message);
    return img;
}

static camera camera_of(const fm_image *img)
{
    camera c;
    fm_error err;
    if (camera_init(&c, &img->camera, img->width, &err) != FM_OK)
        fail_msg("camera_init: %s", err.message);
    assert_int_equal(c.height, img->height);
    return c;
}

/* The map's luminance toward d, interpolated bilinearly between pixel centres. */
static double map_y(const fm_image *map, vec3 d)
{
    const int W = map->width, H = map->height;
    double u = 0.25 + atan2(d.x, d.y) / (2.0 * FM_PI);
    double x = (u - floor(u)) * W - 0.5, y = (0.5 - asin(clamp_cosine(d.z)) / FM_PI) * H - 0.5;
    y = fmin(fmax(y, 0.0), H - 1.0);
    int x0 = (int)floor(x), y0 = (int)fmin(floor(y), H - 2.0);
    double fx = x - x0, fy = y - y0;
    int xa = (x0 % W + W) % W, xb = (x0 + 1) % W;
    return (1 - fy) * ((1 - fx) * test_pixel_y(map, xa, y0) + fx * test_pixel_y(map, xb, y0)) +
           fy * ((1 - fx) * test_pixel_y(map, xa, y0 + 1) + fx * test_pixel_y(map, xb, y0 + 1));
}

static double angle_deg(vec3 a, vec3 b)
{
    return acos(clamp_cosine(v3_dot(a, b))) / FM_DEG;
}

/* Pixels away from the horizon and the sun against the interpolated map: worst and RMS relative
 * difference of luminance. */
static void against_the_map(const fm_sky *sky, const fm_image *map, const fm_image *img, const char *what)
{
    camera c = camera_of(img);
    vec3 sun = sky->sun_dir;
    double worst = 0.0, sum2 = 0.0;
    long n = 0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            vec3 d;
            if (!camera_direction(&c, x + 0.5, y + 0.5, &d))
                continue;
            vec3 c00, c11, c01, c10; /* the pixel's corners: its half-diagonal is its reach */
            camera_direction(&c, x, y, &c00);
            camera_direction(&c, x + 1, y + 1, &c11);
            camera_direction(&c, x, y + 1, &c01);
            camera_direction(&c, x + 1, y, &c10);
            double reach = 0.5 * fmax(angle_deg(c00, c11), angle_deg(c01, c10));
            double e = asin(d.z) / FM_DEG;
            if (e < 4.0 + reach || e > 80.0 - reach || angle_deg(d, sun) < 15.0)
                continue;
            double rel = test_pixel_y(img, x, y) / map_y(map, d) - 1.0;
            worst = fmax(worst, fabs(rel));
            sum2 += rel * rel;
            n++;
        }
    print_message("%s: %ld pixels vs the equirect map: RMS %.3f%%, worst %.3f%%\n", what, n, 100.0 * sqrt(sum2 / n),
                  100.0 * worst);
    assert_true(n > 100);
    assert_true(worst < 0.01);
}

/* The sun 30 degrees up in the south-south-east; at one wavelength (550 nm) where a test needs many
 * paths, in colour elsewhere. */
static fm_sky *the_sky(double lambda_nm)
{
    fm_sky_params p = test_params(30.0, lambda_nm);
    p.sun_azimuth_deg = 160.0;
    return test_sky(&p);
}

static void views_of_the_same_radiance(void **state)
{
    fm_sky *sky = the_sky(550.0);
    const double scale = 4.0; /* 8192 paths per multiple-scattering node: see the header */
    fm_image *map = render(sky, fm_render_params_default().camera, 512, FM_QUALITY_FINAL, 0, 3, 0, scale, 0);
    struct {
        fm_camera cam;
        int width;
        const char *what;
    } views[] = {
        {pinhole_camera(60.0, 110.0, 12.0, 4.0 / 3.0), 64, "pinhole 60 deg toward azimuth 110, up 12"},
        {pinhole_camera(100.0, 300.0, 55.0, 1.0), 48, "pinhole 100 deg toward azimuth 300, up 55"},
        {fisheye_camera(FM_FISHEYE_EQUIDISTANT), 64, "fisheye, equidistant"},
        {fisheye_camera(FM_FISHEYE_EQUISOLID), 64, "fisheye, equisolid"},
    };
    for (int i = 0; i < 4; i++) {
        fm_image *img = render(sky, views[i].cam, views[i].width, FM_QUALITY_FINAL, 0, 3, 0, scale, 0);
        against_the_map(sky, map, img, views[i].what);
        if (views[i].cam.type == FM_CAMERA_FISHEYE) {
            /* the zenith: the 2 x 2 central pixels against the map's top rows over the same solid angle */
            camera c = camera_of(img);
            const int m = img->width / 2;
            double fish = 0.0, omega = 0.0;
            for (int y = m - 1; y <= m; y++)
                for (int x = m - 1; x <= m; x++) {
                    double o = camera_pixel_solid_angle(&c, x, y);
                    fish += o * test_pixel_y(img, x, y);
                    omega += o;
                }
            double cap = acos(1.0 - omega / (2.0 * FM_PI)) / FM_DEG;
            int rows = (int)lround(cap / (180.0 / map->height));
            double top = 0.0, top_omega = 0.0;
            for (int y = 0; y < rows; y++)
                for (int x = 0; x < map->width; x++) {
                    double o = 2.0 * FM_PI / map->width *
                               (cos(FM_PI * y / map->height) - cos(FM_PI * (y + 1) / map->height));
                    top += o * test_pixel_y(map, x, y);
                    top_omega += o;
                }
            print_message("zenith cap of %.2f deg: %d map rows\n", cap, rows);
            check_rel(fish / omega, top / top_omega, 0.01, "fisheye zenith vs the map's top rows");
            /* the hemisphere seen by a horizontal surface, as the sidecar reports it */
            double dh_fish[3], dh_map[3];
            assert_true(fm_image_diffuse_horizontal(img, dh_fish));
            assert_true(fm_image_diffuse_horizontal(map, dh_map));
            check_rel(dh_fish[0], dh_map[0], 0.005, "diffuse horizontal from the fisheye vs the map");
        } else {
            double dh[3] = {1, 1, 1};
            assert_false(fm_image_diffuse_horizontal(img, dh)); /* a pinhole does not see the hemisphere */
            assert_true(dh[0] == 0.0);
        }
        fm_image_destroy(img);
    }
    fm_image_destroy(map);
    fm_sky_destroy(sky);
}

/* Energy of the disk in an image: sum of the disk's luminance x pixel solid angle. */
static double disk_energy(const fm_image *img)
{
    camera c = camera_of(img);
    double e = 0.0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            double v = img->sun_disk[((size_t)y * img->width + x) * img->channels + (img->channels == 3 ? 1 : 0)];
            if (v != 0.0)
                e += v * camera_pixel_solid_angle(&c, x, y);
        }
    return e;
}

static void sun_disk_energy_in_every_camera(void **state)
{
    fm_sky *sky = the_sky(550.0);
    fm_sun_light light;
    fm_sky_sun_light(sky, &light);
    double direct = light.normal_irradiance[0]; /* spectral, at 550 nm */
    fm_image *map = render(sky, fm_render_params_default().camera, 512, FM_QUALITY_PREVIEW, 0, 1, 0, 0.05, 1);
    double reference = disk_energy(map);
    check_rel(reference, direct, 0.005, "equirect: disk energy vs the direct normal irradiance");
    struct {
        fm_camera cam;
        int width;
        const char *what;
    } views[] = {
        {fisheye_camera(FM_FISHEYE_EQUIDISTANT), 256, "fisheye equidistant"},
        {fisheye_camera(FM_FISHEYE_EQUISOLID), 128, "fisheye equisolid"},
        {pinhole_camera(10.0, 160.0, 30.0, 1.0), 64, "pinhole 10 deg at the sun (0.16 deg pixels)"},
        {pinhole_camera(1.0, 160.1, 29.95, 1.5), 64, "pinhole 1 deg near the sun (0.016 deg pixels)"},
        {pinhole_camera(120.0, 120.0, 5.0, 2.0), 96, "pinhole 120 deg, the sun off-centre"},
    };
    for (int i = 0; i < 5; i++) {
        fm_image *img = render(sky, views[i].cam, views[i].width, FM_QUALITY_PREVIEW, 0, 1, 0, 0.05, 1);
        double e = disk_energy(img);
        print_message("%s: disk energy %.6g (equirect %.6g, direct normal irradiance %.6g)\n", views[i].what, e,
                      reference, direct);
        check_rel(e, reference, 0.005, "disk energy vs the equirect map's");
        fm_image_destroy(img);
    }
    fm_image_destroy(map);
    fm_sky_destroy(sky);
}

/* The fast path against per-pixel paths through the camera (as in test_fast_vs_reference): mean z^2
 * below 1.6, the mean relative difference below 0.3% + 4 standard errors, no |z| beyond 5.5. */
static void reference_through_the_cameras(void **state)
{
    fm_sky *sky = the_sky(550.0);
    struct {
        fm_camera cam;
        int width;
        const char *what;
    } views[] = {
        {pinhole_camera(90.0, 100.0, 5.0, 4.0 / 3.0), 24, "pinhole across the horizon"},
        {fisheye_camera(FM_FISHEYE_EQUIDISTANT), 20, "fisheye"},
    };
    for (int i = 0; i < 2; i++) {
        fm_image *ref = render(sky, views[i].cam, views[i].width, FM_QUALITY_REFERENCE, 0, 11, 2048, 1.0, 0);
        fm_image *fast = render(sky, views[i].cam, views[i].width, FM_QUALITY_FINAL, 0, 12, 0, 1.0, 0);
        double z2 = 0.0, rel = 0.0, se2 = 0.0, worst = 0.0;
        long n = 0;
        for (size_t k = 0; k < (size_t)ref->width * ref->height; k++) {
            double se = ref->std_error[k];
            if (!(se > 0.0))
                continue;
            double z = (fast->pixels[k] - ref->pixels[k]) / se;
            z2 += z * z;
            rel += (fast->pixels[k] - ref->pixels[k]) / ref->pixels[k];
            se2 += (se / ref->pixels[k]) * (se / ref->pixels[k]);
            worst = fmax(worst, fabs(z));
            n++;
        }
        double bound = 3e-3 + 4.0 * sqrt(se2) / n;
        print_message("%s: %ld pixels, mean z^2 = %.3f, mean relative difference %+.3f%% (bound %.3f%%), worst |z| "
                      "%.2f\n",
                      views[i].what, n, z2 / n, 100.0 * rel / n, 100.0 * bound, worst);
        assert_true(n > 200);
        assert_true(z2 / n < 1.6);
        assert_true(fabs(rel / n) < bound);
        assert_true(worst < 5.5);
        fm_image_destroy(ref);
        fm_image_destroy(fast);
    }
    fm_sky_destroy(sky);
}

static int same_bits(const fm_image *a, const fm_image *b)
{
    size_t n = (size_t)a->width * a->height * a->channels;
    return a->width == b->width && a->height == b->height && memcmp(a->pixels, b->pixels, n * sizeof(float)) == 0 &&
           (!a->std_error || memcmp(a->std_error, b->std_error, n * sizeof(float)) == 0);
}

static void thread_count_does_not_change_the_bits(void **state)
{
    fm_sky *sky = the_sky(0.0);
    fm_camera cams[2] = {fisheye_camera(FM_FISHEYE_EQUISOLID), pinhole_camera(70.0, 150.0, 20.0, 1.5)};
    for (int i = 0; i < 2; i++)
        for (int q = 0; q < 2; q++) {
            fm_quality quality = q ? FM_QUALITY_REFERENCE : FM_QUALITY_PREVIEW;
            int width = q ? 12 : 48;
            fm_image *one = render(sky, cams[i], width, quality, 1, 5, 16, 0.25, 1);
            fm_image *two = render(sky, cams[i], width, quality, 2, 5, 16, 0.25, 1);
            fm_image *other = render(sky, cams[i], width, quality, 2, 6, 16, 0.25, 1);
            assert_true(same_bits(one, two));
            assert_false(same_bits(one, other)); /* another seed, other numbers */
            fm_image_destroy(one);
            fm_image_destroy(two);
            fm_image_destroy(other);
        }
    fm_sky_destroy(sky);
}

static const char *attribute_string(exr_context_t c, const char *name)
{
    static char text[64];
    const char *s = NULL;
    int32_t n = 0;
    if (exr_attr_get_string(c, 0, name, &n, &s) != EXR_ERR_SUCCESS)
        return "";
    snprintf(text, sizeof text, "%.*s", (int)n, s);
    return text;
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

static void camera_in_the_files(void **state)
{
    fm_sky *sky = the_sky(0.0);
    char dir[] = "/tmp/fm_test_camera_XXXXXX";
    assert_non_null(mkdtemp(dir));
    fm_camera cams[3] = {fm_render_params_default().camera, fisheye_camera(FM_FISHEYE_EQUISOLID),
                         pinhole_camera(50.0, 200.0, 10.0, 2.0)};
    const char *types[3] = {"equirect", "fisheye", "pinhole"};
    for (int i = 0; i < 3; i++) {
        fm_render_params rp = fm_render_params_default();
        rp.camera = cams[i];
        rp.width = 32;
        rp.quality = FM_QUALITY_PREVIEW;
        rp.sample_scale = 0.05;
        fm_image *img = NULL;
        fm_output *out = NULL;
        fm_error err;
        char exr[128], json[128];
        snprintf(exr, sizeof exr, "%s/%s.exr", dir, types[i]);
        snprintf(json, sizeof json, "%s/%s.json", dir, types[i]);
        assert_int_equal(fm_render(sky, &rp, &img, &err), FM_OK);
        assert_int_equal(fm_image_to_rec709(img, &err), FM_OK);
        assert_int_equal(fm_output_open(exr, json, &out, &err), FM_OK);
        assert_int_equal(fm_output_commit(out, img, NULL, &err), FM_OK);
        fm_output_close(out);

        exr_context_t c;
        test_exr e = test_exr_read(exr, &c);
        assert_int_equal(e.width, img->width);
        assert_int_equal(e.height, img->height);
        exr_envmap_t env;
        assert_int_equal(exr_attr_get_envmap(c, 0, "envmap", &env) == EXR_ERR_SUCCESS, i == 0);
        assert_string_equal(attribute_string(c, "firmament.camera.type"), types[i]);
        double v;
        if (i == 1)
            assert_string_equal(attribute_string(c, "firmament.camera.fisheye_projection"), "equisolid");
        if (i == 2) {
            assert_int_equal(exr_attr_get_double(c, 0, "firmament.camera.horizontal_fov_deg", &v), EXR_ERR_SUCCESS);
            check_abs(v, 50.0, 0.0, "fov attribute");
            assert_int_equal(exr_attr_get_double(c, 0, "firmament.camera.look_azimuth_deg", &v), EXR_ERR_SUCCESS);
            check_abs(v, 200.0, 0.0, "look azimuth attribute");
        }
        exr_finish(&c);
        test_exr_free(&e);

        cJSON *j = read_json(json);
        cJSON *camera_group = cJSON_GetObjectItemCaseSensitive(j, "camera");
        cJSON *sky_group = cJSON_GetObjectItemCaseSensitive(j, "sky");
        assert_string_equal(cJSON_GetObjectItemCaseSensitive(camera_group, "type")->valuestring, types[i]);
        /* a pinhole view does not hold the hemisphere: no diffuse horizontal from it */
        assert_int_equal(sky_group != NULL, i != 2);
        if (i == 2) {
            cJSON *look = cJSON_GetObjectItemCaseSensitive(camera_group, "look_direction");
            assert_int_equal(cJSON_GetArraySize(look), 3);
            check_abs(cJSON_GetArrayItem(look, 2)->valuedouble, sin(10.0 * FM_DEG), 1e-12, "look direction z");
            check_abs(cJSON_GetObjectItemCaseSensitive(camera_group, "vertical_fov_deg")->valuedouble,
                      2.0 * atan(tan(25.0 * FM_DEG) / 2.0) / FM_DEG, 1e-9, "vertical field of view");
        }
        cJSON_Delete(j);

        /* read back, the image knows its camera: comparing with itself, sun excluded, is exact */
        fm_image *back = NULL;
        assert_int_equal(fm_image_read_exr(exr, &back, &err), FM_OK);
        assert_int_equal(back->camera.type, cams[i].type);
        fm_comparison cmp;
        assert_int_equal(fm_image_compare(back, back, 2.0, &cmp, &err), FM_OK);
        assert_true(cmp.rms == 0.0 && cmp.pixels > 0);
        fm_image_destroy(back);
        fm_image_destroy(img);
        unlink(exr);
        unlink(json);
    }
    rmdir(dir);
    fm_sky_destroy(sky);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(views_of_the_same_radiance),
        cmocka_unit_test(sun_disk_energy_in_every_camera),
        cmocka_unit_test(reference_through_the_cameras),
        cmocka_unit_test(thread_count_does_not_change_the_bits),
        cmocka_unit_test(camera_in_the_files),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
