/* Test helpers on top of cmocka: tolerance checks that print the numbers when they fail, and
 * shortcuts for building skies and rendering small maps. */
#ifndef FM_TEST_CHECK_H
#define FM_TEST_CHECK_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "firmament/firmament.h"
#include "sky.h"
#include "transport/path.h"

/* |actual - expected| <= rel_tol * |expected| */
#define check_rel(actual, expected, rel_tol, what) \
    check_rel_impl((actual), (expected), (rel_tol), (what), __FILE__, __LINE__)
/* |actual - expected| <= abs_tol */
#define check_abs(actual, expected, abs_tol, what) \
    check_abs_impl((actual), (expected), (abs_tol), (what), __FILE__, __LINE__)

void check_rel_impl(double actual, double expected, double rel_tol, const char *what, const char *file, int line);
void check_abs_impl(double actual, double expected, double abs_tol, const char *what, const char *file, int line);

/* A sky from parameters; fails the test on error. */
fm_sky *test_sky(const fm_sky_params *params);

/* Default sky parameters without aerosols (biome "none"), the sun at the given elevation,
 * monochromatic if lambda_nm > 0. */
fm_sky_params test_params(double sun_elevation_deg, double lambda_nm);

/* Renders a map (fails the test on error). */
fm_image *test_render(const fm_sky *sky, int width, fm_quality quality, int threads, uint64_t seed, int samples,
                      double sample_scale, int with_disk);

/* Independent quadrature along the view ray from the sky's observer in direction d (first grid
 * wavelength): integral_0^t_end T(0, t) f(x_t) dt by Simpson's rule in u with t = t_end u^2 (nodes
 * crowd near the observer, where the air is densest), T from the exact column of each step.
 * *end_transmittance receives T(0, t_end); *hits_ground whether the ray ends on the ground. */
typedef double (*ray_integrand)(void *ctx, vec3 x);
double test_view_ray_integral(const fm_sky *sky, vec3 d, int steps, ray_integrand f, void *ctx,
                              double *end_transmittance, int *hits_ground);

/* Molecular scattering coefficient (m^-1) at point x for the first grid wavelength. */
double test_molecular_scattering(const fm_sky *sky, vec3 x);

/* Mean of N path-traced radiance estimates (first grid wavelength, hero 0) from origin along dir,
 * with random streams (seed, item, 0..N-1); *se receives the standard error of the mean. */
double test_path_radiance(const path_context *ctx, vec3 origin, vec3 dir, int N, uint64_t seed, uint64_t item,
                          double *se);

/* Writes text to a new file /tmp/fm_<stem>_XXXXXX.json; returns its path (unlink and free it). */
char *test_write_temp(const char *stem, const char *text);

/* Fails the test unless loading `file` was refused as bad input of `field` with a message that starts
 * "FIELD: FILE" followed by `expected` (": $.layers[0]: ..."); `what` names the case. */
void test_check_input_error(const char *what, fm_status status, const fm_error *err, const char *field,
                            const char *file, const char *expected);

/* CIE Y of pixel (x, y) of an XYZ image, or the value of a monochromatic one. */
double test_pixel_y(const fm_image *img, int x, int y);

#endif
