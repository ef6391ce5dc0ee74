#define _DEFAULT_SOURCE /* mkstemps */
#include "check.h"

#include "atmosphere/optical_depth.h"
#include "base/rng.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
    p.biome = "none"; /* molecules and ozone: the closed forms of the core tests know no aerosols */
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

double test_view_ray_integral(const fm_sky *sky, vec3 d, int steps, ray_integrand f, void *ctx,
                              double *end_transmittance, int *hits_ground)
{
    const atmosphere *a = &sky->atm;
    vec3 o = sky->observer;
    int ground;
    double t_end = ray_distance_to_boundary(a, v3_length(o), v3_dot(o, d) / v3_length(o), &ground);
    double sum = 0.0, tau = 0.0, t_prev = 0.0;
    vec3 x_prev = o;
    for (int i = 0; i <= steps; i++) {
        double u = (double)i / steps, t = t_end * u * u, dt_du = 2.0 * t_end * u;
        vec3 x = v3_madd(o, d, t);
        if (i > 0) { /* view optical depth, exact on each step */
            double col[FM_MAX_SPECIES], r = v3_length(x_prev);
            column_exact(a, r, v3_dot(x_prev, d) / r, t - t_prev, col);
            tau += atmosphere_optical_depth(a, col, 0);
        }
        double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        if (dt_du > 0.0)
            sum += w * dt_du * exp(-tau) * f(ctx, x);
        t_prev = t;
        x_prev = x;
    }
    if (end_transmittance)
        *end_transmittance = exp(-tau);
    if (hits_ground)
        *hits_ground = ground;
    return sum / (3.0 * steps);
}

double test_path_radiance(const path_context *ctx, vec3 origin, vec3 dir, int N, uint64_t seed, uint64_t item,
                          double *se)
{
    double sum = 0.0, sum2 = 0.0;
    for (int j = 0; j < N; j++) {
        rng r = rng_for(seed, item, (uint64_t)j);
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(ctx, origin, dir, 0, &r, L);
        sum += L[0];
        sum2 += L[0] * L[0];
    }
    double mean = sum / N;
    if (se)
        *se = sqrt(fmax(0.0, sum2 / N - mean * mean) / N);
    return mean;
}

double test_molecular_scattering(const fm_sky *sky, vec3 x)
{
    const species *mol = &sky->atm.species[0];
    return mol->sigma_s[0] * profile_density(&mol->profile, v3_length(x) - sky->atm.bottom_radius_m);
}

char *test_write_temp(const char *stem, const char *text)
{
    char *path = malloc(96);
    assert_non_null(path);
    snprintf(path, 96, "/tmp/fm_%.40s_XXXXXX.json", stem);
    int fd = mkstemps(path, 5);
    assert_true(fd >= 0);
    size_t n = strlen(text);
    assert_true(write(fd, text, n) == (ssize_t)n);
    close(fd);
    return path;
}

void test_check_input_error(const char *what, fm_status status, const fm_error *err, const char *field,
                            const char *file, const char *expected)
{
    char start[512];
    snprintf(start, sizeof start, "%s: %s%s", field, file, expected);
    print_message("%-40s %s\n", what, err->message);
    if (status != FM_ERR_INVALID_ARGUMENT || strcmp(err->parameter, field) != 0 ||
        strncmp(err->message, start, strlen(start)) != 0)
        fail_msg("%s: status %d, message\n  %s\nexpected it to start with\n  %s", what, (int)status, err->message,
                 start);
}
