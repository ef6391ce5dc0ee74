/* The live sky (firmament.h, "The live sky"): its key, its maps against fm_render at the same sun,
 * and its file (saved, loaded, and refused when it is another atmosphere's, truncated or corrupt). */
#include "check.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static fm_sky_live *live_for(const fm_sky_params *p)
{
    fm_sky_live *live = NULL;
    fm_error err;
    if (fm_sky_live_create(p, NULL, &live, &err) != FM_OK)
        fail_msg("fm_sky_live_create: %s", err.message);
    return live;
}

static fm_image *live_map(const fm_sky_live *live, double elevation, double azimuth, int width, fm_quality q)
{
    fm_render_params rp = fm_render_params_default();
    rp.width = width;
    rp.quality = q;
    rp.threads = 2;
    fm_image *img = NULL;
    fm_error err;
    if (fm_sky_live_render(live, elevation, azimuth, &rp, &img, &err) != FM_OK)
        fail_msg("fm_sky_live_render: %s", err.message);
    return img;
}

static void key_is_the_atmosphere_not_the_sun(void **state)
{
    fm_sky_params a = test_params(10.0, 0.0), b = a;
    char ka[33], kb[33];
    fm_sky_live_key(&a, ka);
    assert_int_equal(strlen(ka), 32);
    assert_int_equal(strspn(ka, "0123456789abcdef"), 32);
    b.sun_elevation_deg = -7.0;
    b.sun_azimuth_deg = 33.0;
    b.threads = 1;
    fm_sky_live_key(&b, kb);
    assert_string_equal(ka, kb);
    /* a time of day moves the sun only; the date and place make the ozone profile */
    b.year = 2024, b.month = 6, b.day = 21, b.latitude_deg = 48.0, b.hour = 9;
    fm_sky_live_key(&b, kb);
    assert_string_not_equal(ka, kb);
    char kc[33];
    b.hour = 17;
    fm_sky_live_key(&b, kc);
    assert_string_equal(kb, kc);
    const fm_sky_params changed[] = {
        {.ground_albedo = 0.5}, {.turbidity = 2.0}, {.observer_altitude_m = 100.0}, {.ozone_column_du = 250.0},
        {.earth_sun_distance_au = 1.01}, {.humidity_percent = 80.0}, {.aod550 = 0.3}, {.wavelength_nm = 550.0}};
    for (size_t i = 0; i < sizeof changed / sizeof changed[0]; i++) {
        fm_sky_params c = a;
        const fm_sky_params *d = &changed[i];
        if (d->ground_albedo != 0.0) c.ground_albedo = d->ground_albedo;
        if (d->turbidity != 0.0) c.turbidity = d->turbidity;
        if (d->observer_altitude_m != 0.0) c.observer_altitude_m = d->observer_altitude_m;
        if (d->ozone_column_du != 0.0) c.ozone_column_du = d->ozone_column_du;
        if (d->earth_sun_distance_au != 0.0) c.earth_sun_distance_au = d->earth_sun_distance_au;
        if (d->humidity_percent != 0.0) c.humidity_percent = d->humidity_percent;
        if (d->aod550 != 0.0) c.aod550 = d->aod550;
        if (d->wavelength_nm != 0.0) c.wavelength_nm = d->wavelength_nm;
        fm_sky_live_key(&c, kc);
        assert_string_not_equal(ka, kc);
    }
    b = a;
    b.biome = "rural";
    fm_sky_live_key(&b, kc);
    assert_string_not_equal(ka, kc);
}

static void bad_sun_is_refused(void **state)
{
    fm_sky_params p = test_params(10.0, 550.0);
    fm_sky_live *live = live_for(&p);
    fm_render_params rp = fm_render_params_default();
    rp.width = 16;
    fm_image *img = (fm_image *)1;
    fm_error err;
    assert_int_equal(fm_sky_live_render(live, 91.0, 0.0, &rp, &img, &err), FM_ERR_INVALID_ARGUMENT);
    assert_string_equal(err.parameter, "sun_elevation_deg");
    assert_null(img);
    fm_sky_live_destroy(live);
}

/* The live map at a sun against fm_render of a sky with that sun: the same layout, sun and record. */
static void map_matches_fm_render(void **state)
{
    fm_sky_params p = test_params(10.0, 0.0);
    fm_sky_live *live = live_for(&p);
    p.sun_elevation_deg = 12.0;
    p.sun_azimuth_deg = 40.0;
    fm_sky *sky = test_sky(&p);
    fm_image *want = test_render(sky, 32, FM_QUALITY_PREVIEW, 2, 0, 0, 1.0, 1);
    fm_image *got = live_map(live, 12.0, 40.0, 32, FM_QUALITY_PREVIEW);
    assert_int_equal(got->width, want->width);
    assert_int_equal(got->height, want->height);
    assert_int_equal(got->content, want->content);
    for (int i = 0; i < 3; i++)
        check_abs(got->sun_direction[i], want->sun_direction[i], 1e-12, "sun direction");
    check_abs(got->record.sky.sun_azimuth_deg, 40.0, 0.0, "recorded azimuth");
    fm_comparison c;
    fm_error err;
    assert_int_equal(fm_image_compare(got, want, 1.0, &c, &err), FM_OK);
    check_abs(c.rms, 0.0, 1e-6, "luminance rms");
    fm_image_destroy(got);
    fm_image_destroy(want);
    fm_sky_destroy(sky);
    fm_sky_live_destroy(live);
}

/* A file beside the test's temporary folder; the caller frees it. */
static char *temp_path(const char *name)
{
    char *path = malloc(512);
    snprintf(path, 512, "/tmp/fm_live_%ld_%s", (long)getpid(), name);
    return path;
}

static void rewrite(const char *path, long keep, long flip)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    char *buf = malloc(1 << 26);
    long n = (long)fread(buf, 1, 1 << 26, f);
    fclose(f);
    if (flip >= 0 && flip < n)
        buf[flip] ^= 0x10;
    f = fopen(path, "wb");
    fwrite(buf, 1, (size_t)(keep >= 0 && keep < n ? keep : n), f);
    fclose(f);
    free(buf);
}

static long file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fclose(f);
    return n;
}

static void expect_refused(const fm_sky_params *p, const char *path, fm_status want, const char *why)
{
    fm_sky_live *live = (fm_sky_live *)1;
    fm_error err;
    fm_status s = fm_sky_live_load(p, path, &live, &err);
    if (s != want || !strstr(err.message, why))
        fail_msg("loading %s: status %d '%s', expected %d '...%s...'", path, s, s ? err.message : "", want, why);
    assert_null(live);
}

static void file_round_trip_and_refusals(void **state)
{
    fm_sky_params p = test_params(10.0, 550.0);
    fm_sky_live *live = live_for(&p);
    char *path = temp_path("sky.live");
    fm_error err;
    assert_int_equal(fm_sky_live_save(live, path, &err), FM_OK);
    fm_sky_live *back = NULL;
    if (fm_sky_live_load(&p, path, &back, &err))
        fail_msg("load: %s", err.message);
    fm_image *a = live_map(live, 12.0, 40.0, 32, FM_QUALITY_PREVIEW), *b = live_map(back, 12.0, 40.0, 32, FM_QUALITY_PREVIEW);
    assert_memory_equal(a->pixels, b->pixels, sizeof(float) * 32 * 16 * a->channels);
    fm_image_destroy(a);
    fm_image_destroy(b);
    fm_sky_live_destroy(back);

    fm_sky_params other = p;
    other.ground_albedo = 0.3;
    expect_refused(&other, path, FM_ERR_INVALID_ARGUMENT, "another atmosphere");
    long n = file_size(path);
    rewrite(path, -1, n - 1); /* the last byte of the tables, or of the header */
    expect_refused(&p, path, FM_ERR_INVALID_ARGUMENT, "corrupt");
    assert_int_equal(fm_sky_live_save(live, path, &err), FM_OK);
    rewrite(path, n / 2, -1);
    expect_refused(&p, path, FM_ERR_INVALID_ARGUMENT, n / 2 < 64 ? "not a live sky" : "truncated");
    assert_int_equal(fm_sky_live_save(live, path, &err), FM_OK);
    rewrite(path, -1, 3);
    expect_refused(&p, path, FM_ERR_INVALID_ARGUMENT, "not a live sky");
    unlink(path);
    expect_refused(&p, path, FM_ERR_IO, "cannot read");

    /* an unwritable place: an error, nothing left */
    char *bad = temp_path("missing/sky.live");
    assert_int_equal(fm_sky_live_save(live, bad, &err), FM_ERR_IO);
    assert_non_null(strstr(err.message, bad));
    assert_int_equal(access(bad, F_OK), -1);
    free(bad);
    free(path);
    fm_sky_live_destroy(live);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(key_is_the_atmosphere_not_the_sun),
        cmocka_unit_test(bad_sun_is_refused),
        cmocka_unit_test(map_matches_fm_render),
        cmocka_unit_test(file_round_trip_and_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
