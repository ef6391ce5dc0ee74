/* Spectral EXR (Fichet, Pacanowski & Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3),
 * 2021): channel names and units as the layout prescribes, and the spectra integrated here with the
 * CIE 1931 matching functions (trapezoid over the channels' wavelengths, independent of the
 * renderer's solar-weighted quadrature) give the RGB EXR of the same render within 0.5%. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"
#include "exr_read.h"

#include "colour/colour.h"
#include "spectrum/cie.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char dir[256], config_path[1024];

static int setup(void **state)
{
    snprintf(dir, sizeof dir, "/tmp/fm_test_spectral_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

static void spectral_exr_integrates_to_the_rgb_exr(void **state)
{
    fm_sky_params sp = test_params(20.0, 0.0);
    fm_sky *sky = test_sky(&sp);
    fm_render_params rp = fm_render_params_default();
    rp.width = 32;
    rp.quality = FM_QUALITY_PREVIEW;
    rp.sample_scale = 0.25;
    rp.threads = 2;
    rp.spectral = 1;
    fm_image *spectral = NULL, *img = NULL;
    fm_error err = {0};
    if (fm_render(sky, &rp, &spectral, &err))
        fail_msg("%s", err.message);
    assert_int_equal(spectral->content, FM_IMAGE_SPECTRAL_GRID);
    assert_int_equal(spectral->channels, 41);
    fm_colour_config *cfg = NULL;
    if (fm_colour_config_open(config_path, &cfg, &err) || fm_image_spectral_to_xyz(spectral, &img, &err) ||
        fm_image_to_colorspace(img, cfg, "Linear Rec.709", &err))
        fail_msg("%s", err.message);

    char rgb_path[300], json_path[300], spec_path[300];
    snprintf(rgb_path, sizeof rgb_path, "%s/sky.exr", dir);
    snprintf(json_path, sizeof json_path, "%s/sky.json", dir);
    snprintf(spec_path, sizeof spec_path, "%s/sky-spectral.exr", dir);
    fm_output *out = NULL;
    assert_int_equal(fm_output_open(rgb_path, json_path, &out, &err), FM_OK);
    if (fm_output_commit(out, img, NULL, &err) || fm_output_write_spectral(spec_path, spectral, img, NULL, &err))
        fail_msg("%s", err.message);
    fm_output_close(out);

    exr_context_t ctxt = NULL;
    test_exr s = test_exr_read(spec_path, &ctxt);
    test_exr r = test_exr_read(rgb_path, NULL);
    /* the header of the layout */
    int32_t len = 0;
    const char *units = NULL;
    assert_int_equal(exr_attr_get_string(ctxt, 0, "emissiveUnits", &len, &units), EXR_ERR_SUCCESS);
    assert_string_equal(units, "W.m^-2.sr^-1.nm^-1");
    exr_finish(&ctxt);
    assert_int_equal(s.channels, 41);
    double lambda[48];
    for (int k = 0; k < s.channels; k++) {
        int whole = 0, frac = -1;
        char tail[8] = "";
        assert_int_equal(sscanf(s.names[k], "S0.%d,%6d%7s", &whole, &frac, tail), 3);
        assert_string_equal(tail, "nm");
        lambda[k] = whole + frac * 1e-6;
    }
    assert_string_equal(s.names[17], "S0.550,000000nm");
    for (int k = 1; k < s.channels; k++)
        check_abs(lambda[k] - lambda[k - 1], 10.0, 1e-9, "10 nm steps");

    /* integrate every pixel's spectrum with the CMFs (trapezoid) and compare in Rec.709 */
    int ri[3];
    for (int c = 0; c < 3; c++)
        ri[c] = r.names[c][0] == 'R' ? 0 : (r.names[c][0] == 'G' ? 1 : 2);
    double worst = 0.0;
    for (int i = 0; i < s.width * s.height; i++) {
        double xyz[3] = {0, 0, 0}, rgb[3], cmf[3];
        for (int k = 0; k < s.channels; k++) {
            double w = (k == 0 || k == s.channels - 1) ? 5.0 : 10.0;
            cie_xyz_at(lambda[k], cmf);
            for (int c = 0; c < 3; c++)
                xyz[c] += w * s.pixels[(size_t)i * s.channels + k] * cmf[c];
        }
        colour_xyz_to_rec709(xyz, rgb);
        double scale = fmax(fabs(rgb[0]), fmax(fabs(rgb[1]), fabs(rgb[2])));
        for (int c = 0; c < 3; c++) {
            double got = 0.0;
            for (int j = 0; j < 3; j++)
                if (ri[j] == c)
                    got = r.pixels[(size_t)i * 3 + j];
            double e = fabs(got - rgb[c]) / scale;
            worst = fmax(worst, e);
            if (e > 5e-3)
                fail_msg("pixel %d channel %d: RGB EXR %.6g, integrated spectrum %.6g", i, c, got, rgb[c]);
        }
    }
    print_message("largest difference, relative to the pixel's largest channel: %.3g%%\n", 100.0 * worst);
    test_exr_free(&s);
    test_exr_free(&r);
    fm_colour_config_close(cfg);
    fm_image_destroy(img);
    fm_image_destroy(spectral);
    fm_sky_destroy(sky);
}

int main(void)
{
    snprintf(config_path, sizeof config_path, "%s/presets/ocio/config.ocio", FM_SOURCE_DIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(spectral_exr_integrates_to_the_rgb_exr),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
