/* Previews: display-referred 8-bit sRGB PNGs of a radiance map, through the OpenColorIO config's
 * "sRGB" display and "Standard" view after an exposure scale, written with libpng. */
#define _POSIX_C_SOURCE 200809L
#include "base/platform.h"
#include "base/status.h"
#include "base/units.h"
#include "camera/camera.h"
#include "image/image.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Luminance (Y, the image's scale) of pixel i without the sun disk. */
static double sky_luminance(const fm_image *img, size_t i)
{
    double v[3];
    for (int c = 0; c < 3; c++)
        v[c] = img->pixels[3 * i + c] - (img->sun_disk ? img->sun_disk[3 * i + c] : 0.0f);
    double xyz[3];
    image_colour_to_xyz(img, v, xyz);
    return xyz[1];
}

double fm_image_auto_exposure(const fm_image *img)
{
    if (img->channels != 3)
        return 0.0;
    camera cam;
    if (camera_init(&cam, &img->camera, img->width, NULL) != FM_OK)
        return 0.0;
    /* Each pixel whose centre looks above the horizontal weighs by its solid angle (any camera);
     * the luminance floor keeps a black pixel from sending the log to -infinity. */
    const double floor_y = 1e-9;
    double sum_w = 0.0, sum_log = 0.0;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++) {
            vec3 d;
            if (!camera_direction(&cam, x + 0.5, y + 0.5, &d) || !(d.z > 0.0))
                continue;
            double w = camera_pixel_solid_angle(&cam, x, y);
            double yl = sky_luminance(img, (size_t)y * img->width + x);
            sum_log += w * log(fmax(yl, floor_y));
            sum_w += w;
        }
    if (sum_w <= 0.0)
        return 0.0;
    return log2(0.18) - sum_log / sum_w / log(2.0);
}

typedef struct png_failure {
    char message[200];
} png_failure;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_failure *f = png_get_error_ptr(png);
    snprintf(f->message, sizeof f->message, "%s", msg);
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* the library never prints */
}

/* Writes 8-bit RGB rows to path; returns 0, else fills f. */
static int write_png(const char *path, const uint8_t *rgb, int width, int height, png_failure *f)
{
    FILE *fp = platform_fopen(path, "wb");
    if (!fp) {
        snprintf(f->message, sizeof f->message, "%s", strerror(errno));
        return 1;
    }
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, f, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info) {
        snprintf(f->message, sizeof f->message, "out of memory");
        png_destroy_write_struct(&png, &info);
        fclose(fp);
        return 1;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        fclose(fp);
        return 1;
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = 0; y < height; y++)
        png_write_row(png, (png_const_bytep)(rgb + (size_t)y * width * 3));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    if (fclose(fp) != 0) {
        snprintf(f->message, sizeof f->message, "%s", strerror(errno));
        return 1;
    }
    return 0;
}

fm_status image_write_preview_file(const fm_image *img, const fm_colour_config *cfg, const char *file,
                                   const char *path, double exposure_ev, fm_error *err)
{
    if (img->channels != 3 || img->content == FM_IMAGE_SPECTRAL_RADIANCE)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "a preview needs a colour image, not a monochromatic one");
    if (!isfinite(exposure_ev) || fabs(exposure_ev) > 100.0)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "exposure %g EV is out of range [-100, 100]", exposure_ev);
    const size_t n = (size_t)img->width * (size_t)img->height;
    float *buf = malloc(3 * n * sizeof *buf);
    uint8_t *bytes = malloc(3 * n);
    if (!buf || !bytes) {
        free(buf);
        free(bytes);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the preview");
    }
    const float scale = (float)exp2(exposure_ev);
    for (size_t i = 0; i < 3 * n; i++)
        buf[i] = img->pixels[i] * scale;
    /* the source space: the image's own, or Rec.709 by its fixed matrix, or the rendered XYZ */
    const char *src = img->content == FM_IMAGE_RGB ? img->colorspace
                      : img->content == FM_IMAGE_RGB_REC709 ? "Linear Rec.709"
                                                             : NULL;
    fm_status s = fm_colour_display(cfg, src, "sRGB", "Standard", buf, n, err);
    if (!s) {
        for (size_t i = 0; i < 3 * n; i++) {
            float v = buf[i] != buf[i] ? 0.0f : fminf(fmaxf(buf[i], 0.0f), 1.0f); /* NaN -> 0 */
            bytes[i] = (uint8_t)lrintf(v * 255.0f);
        }
        png_failure f = {{0}};
        if (write_png(file, bytes, img->width, img->height, &f))
            s = fm_fail(err, FM_ERR_IO, "cannot write '%s': %s", path, f.message);
    }
    free(buf);
    free(bytes);
    return s;
}

fm_status fm_image_write_preview(const fm_image *img, const fm_colour_config *cfg, const char *path,
                                 double exposure_ev, fm_error *err)
{
    char *tmp = image_reserve_temp(path, err);
    if (!tmp)
        return err ? err->status : FM_ERR_IO;
    return image_finish_temp(tmp, path, image_write_preview_file(img, cfg, tmp, path, exposure_ev, err), err);
}
