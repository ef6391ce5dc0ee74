/* fm_image: allocation, colour conversion and the hemispherical integral used by the sidecar. */
#include "base/status.h"
#include "base/units.h"
#include "camera/camera.h"
#include "colour/colour.h"
#include "image/image.h"
#include "spectrum/spectral_grid.h"

#include <math.h>
#include <stdlib.h>

fm_image *image_create(int width, int height, int channels, fm_image_content content, int with_disk, int with_error)
{
    fm_image *img = calloc(1, sizeof *img);
    if (!img)
        return NULL;
    size_t n = (size_t)width * (size_t)height * (size_t)channels;
    img->width = width;
    img->height = height;
    img->channels = channels;
    img->content = content;
    img->pixels = calloc(n, sizeof(float));
    img->sun_disk = with_disk ? calloc(n, sizeof(float)) : NULL;
    img->std_error = with_error ? calloc(n, sizeof(float)) : NULL;
    if (!img->pixels || (with_disk && !img->sun_disk) || (with_error && !img->std_error)) {
        fm_image_destroy(img);
        return NULL;
    }
    return img;
}

_Static_assert(FM_IMAGE_MAX_WAVELENGTHS == FM_MAX_WAVELENGTHS, "a spectral map holds every grid wavelength");

void image_set_wavelengths(fm_image *img, int n, const double *lambda_nm, const double *xyz_weight)
{
    img->wavelengths = n;
    for (int k = 0; k < n; k++) {
        img->lambda_nm[k] = lambda_nm[k];
        for (int c = 0; c < 3; c++)
            img->xyz_weight[k][c] = xyz_weight[3 * k + c];
    }
}

static void integrate_plane(const fm_image *s, const float *in, float *out, size_t pixels)
{
    const int K = s->wavelengths;
    for (size_t i = 0; i < pixels; i++) {
        double xyz[3] = {0.0, 0.0, 0.0};
        for (int k = 0; k < K; k++)
            for (int c = 0; c < 3; c++)
                xyz[c] += in[i * K + k] * s->xyz_weight[k][c];
        for (int c = 0; c < 3; c++)
            out[3 * i + c] = (float)xyz[c];
    }
}

fm_status fm_image_spectral_to_xyz(const fm_image *s, fm_image **out, fm_error *err)
{
    *out = NULL;
    if (s->content != FM_IMAGE_SPECTRAL_GRID || s->channels != s->wavelengths)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "not a spectral map");
    fm_image *x = image_create(s->width, s->height, 3, FM_IMAGE_XYZ, s->sun_disk != NULL, 0);
    if (!x)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for a %d x %d image", s->width, s->height);
    size_t n = (size_t)s->width * (size_t)s->height;
    integrate_plane(s, s->pixels, x->pixels, n);
    if (s->sun_disk)
        integrate_plane(s, s->sun_disk, x->sun_disk, n);
    for (int c = 0; c < 3; c++)
        x->sun_direction[c] = s->sun_direction[c];
    x->paths_per_node = s->paths_per_node;
    x->record = s->record;
    *out = x;
    return FM_OK;
}

void fm_image_destroy(fm_image *image)
{
    if (!image)
        return;
    free(image->pixels);
    free(image->sun_disk);
    free(image->std_error);
    free(image);
}

void fm_image_remove_sun_disk(fm_image *image)
{
    if (!image->sun_disk)
        return;
    size_t n = (size_t)image->width * (size_t)image->height * (size_t)image->channels;
    for (size_t i = 0; i < n; i++)
        image->pixels[i] -= image->sun_disk[i];
    free(image->sun_disk);
    image->sun_disk = NULL;
}

static void convert_buffer(float *buf, size_t pixels)
{
    for (size_t i = 0; i < pixels; i++) {
        double xyz[3] = {buf[3 * i], buf[3 * i + 1], buf[3 * i + 2]}, rgb[3];
        colour_xyz_to_rec709(xyz, rgb);
        for (int c = 0; c < 3; c++)
            buf[3 * i + c] = (float)rgb[c];
    }
}

fm_status fm_image_to_rec709(fm_image *image, fm_error *err)
{
    if (image->content == FM_IMAGE_RGB_REC709)
        return FM_OK;
    if (image->content != FM_IMAGE_XYZ)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "a monochromatic image has no colour to convert");
    size_t n = (size_t)image->width * (size_t)image->height;
    convert_buffer(image->pixels, n);
    if (image->sun_disk)
        convert_buffer(image->sun_disk, n);
    /* The standard error of a linear combination is not a linear combination of standard errors;
     * it stays in XYZ, as documented for fm_image. */
    image->content = FM_IMAGE_RGB_REC709;
    return FM_OK;
}

/* The fisheye: each pixel's integral of cos(theta) dOmega over its part inside the circle, by
 * Green's theorem (fisheye.h), with radiance constant over the pixel. */
static void fisheye_diffuse_horizontal(const fm_image *image, const camera *cam, double out[3])
{
    const int W = image->width, H = image->height, C = image->channels;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double weight = fisheye_pixel_integral(&cam->fish, x, y, 1);
            size_t i = ((size_t)y * W + x) * C;
            for (int c = 0; c < C && c < 3; c++)
                out[c] += weight * (image->pixels[i + c] - (image->sun_disk ? image->sun_disk[i + c] : 0.0f));
        }
}

int fm_image_diffuse_horizontal(const fm_image *image, double out[3])
{
    const int W = image->width, H = image->height, C = image->channels;
    out[0] = out[1] = out[2] = 0.0;
    if (image->camera.type == FM_CAMERA_FISHEYE) {
        camera cam;
        if (camera_init(&cam, &image->camera, W, NULL) || cam.height != H)
            return 0;
        fisheye_diffuse_horizontal(image, &cam, out);
        return 1;
    }
    if (image->camera.type != FM_CAMERA_EQUIRECT)
        return 0; /* a pinhole view does not hold the hemisphere */
    for (int y = 0; y < H; y++) {
        /* the part of the row above the horizontal plane; with radiance constant over a pixel, its
         * cos(zenith)-weighted solid angle is (2 pi / W) * (sin^2 top - sin^2 bottom) / 2 */
        double top = FM_PI * (0.5 - (double)y / H), bottom = fmax(0.0, FM_PI * (0.5 - (double)(y + 1) / H));
        if (top <= 0.0)
            break;
        double weight = FM_PI / W * (sin(top) * sin(top) - sin(bottom) * sin(bottom));
        for (int x = 0; x < W; x++) {
            size_t i = ((size_t)y * W + x) * C;
            for (int c = 0; c < C && c < 3; c++)
                out[c] += weight * (image->pixels[i + c] - (image->sun_disk ? image->sun_disk[i + c] : 0.0f));
        }
    }
    return 1;
}

void image_colour_to_xyz(const fm_image *img, const double v[3], double xyz[3])
{
    if (img->content == FM_IMAGE_XYZ) {
        xyz[0] = v[0], xyz[1] = v[1], xyz[2] = v[2];
    } else if (img->content == FM_IMAGE_RGB) {
        colour_matrix_apply(&img->rgb_to_xyz[0][0], v, xyz);
    } else {
        colour_rec709_to_xyz(v, xyz);
    }
}
