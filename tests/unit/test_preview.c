/* Previews: 8-bit sRGB PNGs through the OpenColorIO display "sRGB" / view "Standard", read back
 * with libpng.  The mid-grey check is the sRGB encoding (IEC 61966-2-1) of 0.18:
 * 1.055 * 0.18^(1/2.4) - 0.055 = 0.4614, code 255 * 0.4614 = 117.7 -> 118. */
#define _POSIX_C_SOURCE 200809L
#include "check.h"

#include "image/image.h"

#include <math.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

typedef struct png_image_data {
    int width, height;
    unsigned char *rgb;
} png_image_data;

/* Reads an 8-bit RGB PNG; fails the test on anything else. */
static png_image_data read_png(const char *path)
{
    png_image_data d = {0};
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    unsigned char sig[8];
    assert_int_equal(fread(sig, 1, 8, fp), 8);
    assert_int_equal(png_sig_cmp(sig, 0, 8), 0);
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    assert_non_null(png);
    assert_non_null(info);
    if (setjmp(png_jmpbuf(png)))
        fail_msg("libpng could not read %s", path);
    png_init_io(png, fp);
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    assert_int_equal(png_get_bit_depth(png, info), 8);
    assert_int_equal(png_get_color_type(png, info), PNG_COLOR_TYPE_RGB);
    d.width = (int)png_get_image_width(png, info);
    d.height = (int)png_get_image_height(png, info);
    d.rgb = malloc((size_t)d.width * d.height * 3);
    assert_non_null(d.rgb);
    for (int y = 0; y < d.height; y++)
        png_read_row(png, d.rgb + (size_t)y * d.width * 3, NULL);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    return d;
}

static char config_path[1024];

static fm_colour_config *open_config(void)
{
    fm_colour_config *cfg = NULL;
    fm_error err = {0};
    if (fm_colour_config_open(config_path, &cfg, &err))
        fail_msg("%s", err.message);
    return cfg;
}

/* A W x H Linear Rec.709 image of grey luminance L (R = G = B = L: Y = L for the D65 white). */
static fm_image *grey_image(const fm_colour_config *cfg, int w, int h, double lum)
{
    fm_image *img = image_create(w, h, 3, FM_IMAGE_XYZ, 0, 0);
    assert_non_null(img);
    for (size_t i = 0; i < (size_t)w * h; i++) {
        /* XYZ of D65 with Y = L */
        img->pixels[3 * i] = (float)(lum * 0.3127 / 0.3290);
        img->pixels[3 * i + 1] = (float)lum;
        img->pixels[3 * i + 2] = (float)(lum * (1.0 - 0.3127 - 0.3290) / 0.3290);
    }
    fm_error err = {0};
    if (fm_image_to_colorspace(img, cfg, "Linear Rec.709", &err))
        fail_msg("%s", err.message);
    return img;
}

static void temp_png(char *path, size_t size)
{
    snprintf(path, size, "/tmp/fm_test_preview_%ld.png", (long)getpid());
}

static void mid_grey_maps_to_code_118(void **state)
{
    fm_colour_config *cfg = open_config();
    const double lum = 37.5; /* of the order of a clear sky's Y in the map's units */
    fm_image *img = grey_image(cfg, 16, 8, lum);
    double ev = log2(0.18 / lum);
    /* automatic exposure of a uniform sky: its log-average is L, so the same EV */
    check_abs(fm_image_auto_exposure(img), ev, 1e-5, "automatic exposure of a uniform grey");
    char path[128];
    temp_png(path, sizeof path);
    fm_error err = {0};
    if (fm_image_write_preview(img, cfg, path, ev, &err))
        fail_msg("%s", err.message);
    png_image_data d = read_png(path);
    assert_int_equal(d.width, 16);
    assert_int_equal(d.height, 8);
    for (int i = 0; i < d.width * d.height * 3; i++)
        check_abs(d.rgb[i], 118.0, 1.0, "sRGB code of 18% grey");
    free(d.rgb);
    /* one stop more: 0.36 encodes to 1.055 * 0.36^(1/2.4) - 0.055 = 0.6342, code 161.7 */
    if (fm_image_write_preview(img, cfg, path, ev + 1.0, &err))
        fail_msg("%s", err.message);
    d = read_png(path);
    for (int i = 0; i < d.width * d.height * 3; i++)
        check_abs(d.rgb[i], 161.7, 1.0, "sRGB code of 36% grey");
    free(d.rgb);
    unlink(path);
    fm_image_destroy(img);
    fm_colour_config_close(cfg);
}

static void preview_of_a_render(void **state)
{
    fm_colour_config *cfg = open_config();
    fm_sky_params p = test_params(30.0, 0.0);
    fm_sky *sky = test_sky(&p);
    fm_image *img = test_render(sky, 32, FM_QUALITY_PREVIEW, 2, 1, 0, 1.0, 1);
    fm_error err = {0};
    if (fm_image_to_colorspace(img, cfg, "ACEScg", &err))
        fail_msg("%s", err.message);
    double ev = fm_image_auto_exposure(img);
    assert_true(isfinite(ev));
    char path[128];
    temp_png(path, sizeof path);
    if (fm_image_write_preview(img, cfg, path, ev, &err))
        fail_msg("%s", err.message);
    png_image_data d = read_png(path);
    assert_int_equal(d.width, 32);
    assert_int_equal(d.height, 16);
    /* the clear sky above the horizon is blue: B > R at the zenith row's middle */
    const unsigned char *z = d.rgb + (size_t)(d.width / 2) * 3;
    assert_true(z[2] > z[0]);
    free(d.rgb);
    unlink(path);
    /* a directory is not a file: refused, nothing written */
    assert_int_equal(fm_image_write_preview(img, cfg, "/tmp", ev, &err), FM_ERR_IO);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
    fm_colour_config_close(cfg);
}

int main(void)
{
    snprintf(config_path, sizeof config_path, "%s/presets/ocio/config.ocio", FM_SOURCE_DIR);
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mid_grey_maps_to_code_118),
        cmocka_unit_test(preview_of_a_render),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
