#include "check.h"

#include <math.h>
#include <stdio.h>

void check_rel_impl(double actual, double expected, double rel_tol, const char *what, const char *file, int line)
{
    double err = fabs(actual - expected) / fabs(expected);
    if (!(err <= rel_tol)) {
        print_error("%s: got %.8g, expected %.8g (relative error %.3g > %.3g)\n", what, actual, expected, err,
                    rel_tol);
        _fail(file, line);
    } else
        print_message("%s: %.8g vs %.8g (rel %.2e, tol %.1e)\n", what, actual, expected, err, rel_tol);
}

void check_abs_impl(double actual, double expected, double abs_tol, const char *what, const char *file, int line)
{
    double err = fabs(actual - expected);
    if (!(err <= abs_tol)) {
        print_error("%s: got %.8g, expected %.8g (error %.3g > %.3g)\n", what, actual, expected, err, abs_tol);
        _fail(file, line);
    } else
        print_message("%s: %.8g vs %.8g (abs %.2e, tol %.1e)\n", what, actual, expected, err, abs_tol);
}

fm_sky *test_sky(const fm_sky_params *params)
{
    fm_sky *sky = NULL;
    fm_error err;
    if (fm_sky_create(params, &sky, &err) != FM_OK)
        fail_msg("fm_sky_create: %s", err.message);
    return sky;
}

fm_sky_params test_params(double sun_elevation_deg, double lambda_nm)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = sun_elevation_deg;
    p.wavelength_nm = lambda_nm;
    return p;
}

fm_image *test_render(const fm_sky *sky, int width, fm_quality quality, int threads, uint64_t seed, int samples,
                      double sample_scale, int with_disk)
{
    fm_render_params rp = fm_render_params_default();
    rp.width = width;
    rp.quality = quality;
    rp.threads = threads;
    rp.seed = seed;
    rp.reference_samples = samples;
    rp.sample_scale = sample_scale;
    rp.sun_disk = with_disk;
    fm_image *img = NULL;
    fm_error err;
    if (fm_render(sky, &rp, &img, &err) != FM_OK)
        fail_msg("fm_render: %s", err.message);
    return img;
}

double test_pixel_y(const fm_image *img, int x, int y)
{
    size_t i = ((size_t)y * img->width + x) * img->channels;
    return img->channels == 1 ? img->pixels[i] : img->pixels[i + 1];
}
