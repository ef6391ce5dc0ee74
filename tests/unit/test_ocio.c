/* Colour management through OpenColorIO: firmament's config and the C interface around OCIO.
 * Expected values are computed here independently of the config: RGB -> XYZ matrices from the
 * published chromaticities (BT.709, AP1, D65, ACES white) and the Bradford transform, and the
 * published Rec.709 -> ACEScg (Bradford) matrix. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include "colour/colour.h"
#include "image/image.h"
#include "spectrum/cie.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* CIE standard illuminant D65, relative spectral power at 5 nm from 380 to 780 nm (ISO/CIE 11664-2,
 * Table B.1; every 5th value of the 1 nm table). */
static const double d65_5nm[] = {
    49.9755, 52.3118, 54.6482, 68.7015, 82.7549, 87.1204, 91.486,  92.4589, 93.4318, 90.057,  86.6823,
    95.7736, 104.865, 110.936, 117.008, 117.41,  117.812, 116.336, 114.861, 115.392, 115.923, 112.367,
    108.811, 109.082, 109.354, 108.578, 107.802, 106.296, 104.79,  106.239, 107.689, 106.047, 104.405,
    104.225, 104.046, 102.023, 100.0,   98.1671, 96.3342, 96.0611, 95.788,  92.2368, 88.6856, 89.3459,
    90.0062, 89.8026, 89.5991, 88.6489, 87.6987, 85.4936, 83.2886, 83.4939, 83.6992, 81.863,  80.0268,
    80.1207, 80.2146, 81.2462, 82.2778, 80.281,  78.2842, 74.0027, 69.7213, 70.6652, 71.6091, 72.979,
    74.349,  67.9765, 61.604,  65.7448, 69.8856, 72.4863, 75.087,  69.3398, 63.5927, 55.0054, 46.4182,
    56.6118, 66.8054, 65.0941, 63.3828};

/* Linear Rec.709 -> ACEScg with Bradford adaptation D65 -> ACES white, as published (e.g. the
 * colour-science package's RGB_to_RGB(sRGB, ACEScg, 'Bradford'), 7 digits). */
static double rec709_to_acescg_published[3][3] = {
    {0.6130974, 0.3395231, 0.0473795},
    {0.0701937, 0.9163539, 0.0134524},
    {0.0206156, 0.1095698, 0.8698151},
};

static void inverse(double m[3][3], double inv[3][3])
{
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]) / det;
        }
}

static void multiply(double a[3][3], double b[3][3], double out[3][3])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
}

static void apply(double m[3][3], const double in[3], double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[i][0] * in[0] + m[i][1] * in[1] + m[i][2] * in[2];
}

static void xy_to_xyz(double x, double y, double out[3])
{
    out[0] = x / y, out[1] = 1.0, out[2] = (1.0 - x - y) / y;
}

/* RGB -> XYZ from primaries (x, y) R, G, B and the white, scaled so that RGB = 1 is the white. */
static void primaries_matrix(const double p[6], const double w[2], double m[3][3])
{
    double cols[3][3], pm[3][3], inv[3][3], white[3], s[3];
    for (int c = 0; c < 3; c++)
        xy_to_xyz(p[2 * c], p[2 * c + 1], cols[c]);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            pm[r][c] = cols[c][r];
    xy_to_xyz(w[0], w[1], white);
    inverse(pm, inv);
    apply(inv, white, s);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            m[r][c] = pm[r][c] * s[c];
}

static const double rec709_primaries[6] = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06};
static const double ap1_primaries[6] = {0.713, 0.293, 0.165, 0.830, 0.128, 0.044};
static const double d65[2] = {0.3127, 0.3290}, aces_white[2] = {0.32168, 0.33767};

/* ACEScg -> XYZ (D65 adopted white): Bradford from the ACES white to D65 after the AP1 matrix. */
static void acescg_to_xyz(double m[3][3])
{
    static double bradford[3][3] = {
        {0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}};
    double src[3], dst[3], cs[3], cd[3], scale[3][3] = {{0}}, binv[3][3], t[3][3], adapt[3][3], ap1[3][3];
    xy_to_xyz(aces_white[0], aces_white[1], src);
    xy_to_xyz(d65[0], d65[1], dst);
    apply(bradford, src, cs);
    apply(bradford, dst, cd);
    for (int i = 0; i < 3; i++)
        scale[i][i] = cd[i] / cs[i];
    inverse(bradford, binv);
    multiply(scale, bradford, t);
    multiply(binv, t, adapt);
    primaries_matrix(ap1_primaries, aces_white, ap1);
    multiply(adapt, ap1, m);
}

static char config_path[1024];

static fm_colour_config *open_config(void)
{
    fm_colour_config *cfg = NULL;
    fm_error err = {0};
    fm_status s = fm_colour_config_open(config_path, &cfg, &err);
    if (s)
        fail_msg("cannot open %s: %s", config_path, err.message);
    return cfg;
}

static void d65_xyz(double xyz[3])
{
    double lambda[81];
    for (int i = 0; i < 81; i++)
        lambda[i] = 380.0 + 5.0 * i;
    cie_spectrum_to_xyz(lambda, d65_5nm, 81, xyz); /* relative: Y is about 10567 */
}

static void d65_gives_white_in_rec709_and_acescg(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    double xyz[3];
    d65_xyz(xyz);
    double y = xyz[1];

    double m709[3][3], inv709[3][3], expect709[3];
    primaries_matrix(rec709_primaries, d65, m709);
    inverse(m709, inv709);
    apply(inv709, xyz, expect709);
    float px[3] = {(float)xyz[0], (float)xyz[1], (float)xyz[2]};
    assert_int_equal(fm_colour_convert(cfg, "CIE XYZ D65", "Linear Rec.709", px, 1, &err), FM_OK);
    for (int c = 0; c < 3; c++) {
        check_rel(px[c], expect709[c], 1e-4, "Rec.709 of D65 against the primaries matrix");
        /* D65 is Rec.709's white: R = G = B = Y, to the precision of the 5 nm table's chromaticity */
        check_rel(px[c], y, 2e-3, "Rec.709 of D65 is (1, 1, 1) Y");
    }

    double expect_cg[3];
    apply(rec709_to_acescg_published, expect709, expect_cg);
    float cg[3] = {(float)xyz[0], (float)xyz[1], (float)xyz[2]};
    assert_int_equal(fm_colour_convert(cfg, "CIE XYZ D65", "ACEScg", cg, 1, &err), FM_OK);
    for (int c = 0; c < 3; c++) {
        check_rel(cg[c], expect_cg[c], 1e-4, "ACEScg of D65 against the published Rec.709 -> ACEScg matrix");
        /* Bradford keeps the adopted white neutral */
        check_rel(cg[c], y, 2e-3, "ACEScg of D65 is (1, 1, 1) Y");
    }
    fm_colour_config_close(cfg);
}

/* Linear Rec.709 -> Linear Rec.2020 (both D65, no adaptation) as published in ITU-R BT.2087-0
 * (4 digits): the config's Rec.2020 matrix against an independent source. */
static void rec709_to_rec2020_as_published(void **state)
{
    static const double m[3][3] = {{0.6274, 0.3293, 0.0433}, {0.0691, 0.9195, 0.0114}, {0.0164, 0.0880, 0.8956}};
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    for (int c = 0; c < 3; c++) {
        float v[3] = {c == 0, c == 1, c == 2};
        assert_int_equal(fm_colour_convert(cfg, "Linear Rec.709", "Linear Rec.2020", v, 1, &err), FM_OK);
        for (int r = 0; r < 3; r++)
            assert_true(fabs(v[r] - m[r][c]) < 1.5e-4);
    }
    fm_colour_config_close(cfg);
}

static void rec709_acescg_round_trip(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    enum { N = 64 };
    float v[3 * N], orig[3 * N];
    unsigned u = 12345u;
    for (int i = 0; i < 3 * N; i++) {
        u = u * 1664525u + 1013904223u;
        orig[i] = v[i] = (float)(u >> 8) / (float)(1u << 24) * 10.0f;
    }
    assert_int_equal(fm_colour_convert(cfg, "Linear Rec.709", "ACEScg", v, N, &err), FM_OK);
    assert_int_equal(fm_colour_convert(cfg, "ACEScg", "lin_rec709", v, N, &err), FM_OK);
    for (int i = 0; i < 3 * N; i++)
        check_rel(v[i], orig[i], 1e-5, "Rec.709 -> ACEScg -> Rec.709");
    fm_colour_config_close(cfg);
}

/* An 8 x 4 XYZ image of assorted colours. */
static fm_image *xyz_image(void)
{
    fm_image *img = image_create(8, 4, 3, FM_IMAGE_XYZ, 0, 0);
    assert_non_null(img);
    for (int i = 0; i < 32; i++) {
        img->pixels[3 * i] = 0.05f + 0.03f * (float)i;
        img->pixels[3 * i + 1] = 0.1f + 0.02f * (float)(i % 7);
        img->pixels[3 * i + 2] = 0.02f + 0.05f * (float)(i % 5);
    }
    return img;
}

static void luminance_is_preserved(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    double m709[3][3], mcg[3][3], ident[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    primaries_matrix(rec709_primaries, d65, m709);
    acescg_to_xyz(mcg);
    const char *names[3] = {"Linear Rec.709", "ACEScg", "CIE XYZ E"};
    double(*luma[3])[3] = {m709, mcg, ident};
    for (int k = 0; k < 3; k++) {
        fm_image *ref = xyz_image(), *img = xyz_image();
        if (fm_image_to_colorspace(img, cfg, names[k], &err))
            fail_msg("%s", err.message);
        assert_int_equal(img->content, FM_IMAGE_RGB);
        assert_string_equal(img->colorspace, names[k]);
        for (int i = 0; i < 32; i++) {
            const float *p = &img->pixels[3 * i];
            double y = luma[k][1][0] * p[0] + luma[k][1][1] * p[1] + luma[k][1][2] * p[2];
            check_rel(y, ref->pixels[3 * i + 1], 1e-4, names[k]);
        }
        fm_image_destroy(ref);
        fm_image_destroy(img);
    }
    fm_colour_config_close(cfg);
}

static void chromaticities_follow_the_space(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    static const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
    static const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
    static const float xyz[8] = {1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 1.0f / 3.0f, 1.0f / 3.0f};
    const char *names[3] = {"lin_rec709", "ACEScg", "CIE XYZ D65"};
    const float *expect[3] = {rec709, ap1, xyz};
    for (int k = 0; k < 3; k++) {
        fm_image *img = xyz_image();
        if (fm_image_to_colorspace(img, cfg, names[k], &err))
            fail_msg("%s", err.message);
        for (int i = 0; i < 8; i++) {
            /* ACEScg's chromaticities are those of AP1 only up to the Bradford step back to D65:
             * the white is D65 then, the primaries move a little */
            double tol = k == 1 ? 2e-2 : 1e-5;
            check_abs(img->chromaticities[i], expect[k][i], tol, names[k]);
        }
        /* the chromaticities give back the space's matrix (how `compare` reads such a file) */
        double m[3][3];
        assert_true(colour_matrix_from_chromaticities(img->chromaticities, m));
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                check_abs(m[r][c], img->rgb_to_xyz[r][c], 2e-6, "matrix from the chromaticities");
        fm_image_destroy(img);
    }
    fm_colour_config_close(cfg);
}

static void unknown_space_lists_the_names(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_error err = {0};
    fm_image *img = xyz_image();
    assert_int_equal(fm_image_to_colorspace(img, cfg, "Rec.2020 please", &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "Rec.2020 please"));
    assert_non_null(strstr(err.message, "\"Linear Rec.709\""));
    assert_non_null(strstr(err.message, "\"ACEScg\""));
    assert_non_null(strstr(err.message, "\"ACES2065-1\""));
    assert_int_equal(img->content, FM_IMAGE_XYZ); /* untouched */
    /* a display encoding is not a place for radiance */
    assert_int_equal(fm_colour_config_check(cfg, "sRGB", &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "not scene-linear"));
    assert_int_equal(fm_colour_config_check(cfg, "lin_rec709", &err), FM_OK);
    fm_image_destroy(img);
    fm_colour_config_close(cfg);
}

static void broken_ocio_is_one_clear_line(void **state)
{
    char path[] = "/tmp/fm_test_ocio_XXXXXX";
    int fd = mkstemp(path);
    assert_true(fd >= 0);
    const char junk[] = "ocio_profile_version: 2\ncolorspaces: [this is not a colour space\n";
    assert_true(write(fd, junk, sizeof junk - 1) == (ssize_t)(sizeof junk - 1));
    close(fd);
    setenv("OCIO", path, 1);
    fm_colour_config *cfg = NULL;
    fm_error err = {0};
    assert_int_equal(fm_colour_config_open(NULL, &cfg, &err), FM_ERR_INVALID_ARGUMENT);
    assert_null(cfg);
    assert_non_null(strstr(err.message, path));
    assert_null(strchr(err.message, '\n'));
    setenv("OCIO", "/nonexistent/config.ocio", 1);
    assert_int_equal(fm_colour_config_open(NULL, &cfg, &err), FM_ERR_INVALID_ARGUMENT);
    assert_non_null(strstr(err.message, "/nonexistent/config.ocio"));
    unsetenv("OCIO");
    unlink(path);
}

static void default_config_is_firmaments(void **state)
{
    unsetenv("OCIO");
    fm_colour_config *cfg = NULL;
    fm_error err = {0};
    if (fm_colour_config_open(NULL, &cfg, &err))
        fail_msg("%s", err.message);
    const char *p = fm_colour_config_path(cfg);
    const char *tail = "ocio/config.ocio";
    assert_true(strlen(p) > strlen(tail) && strcmp(p + strlen(p) - strlen(tail), tail) == 0);
    assert_int_equal(fm_colour_config_count(cfg), 8);
    fm_colour_config_close(cfg);
}

int main(void)
{
    snprintf(config_path, sizeof config_path, "%s/presets/ocio/config.ocio", FM_SOURCE_DIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(d65_gives_white_in_rec709_and_acescg),
        cmocka_unit_test(rec709_acescg_round_trip),
        cmocka_unit_test(rec709_to_rec2020_as_published),
        cmocka_unit_test(luminance_is_preserved),
        cmocka_unit_test(chromaticities_follow_the_space),
        cmocka_unit_test(unknown_space_lists_the_names),
        cmocka_unit_test(broken_ocio_is_one_clear_line),
        cmocka_unit_test(default_config_is_firmaments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
