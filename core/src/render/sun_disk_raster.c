#include "render/sun_disk_raster.h"

#include "atmosphere/optical_depth.h"
#include "base/units.h"
#include "camera/equirect.h"
#include "render/channels.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

/* The sun disk, integrated over each pixel's footprint: a regular grid of points over the disk
 * (much finer than the pixels), each carrying its limb-darkened, attenuated share of the disk's
 * irradiance into the pixel that contains it, divided by that pixel's solid angle.  The disk's
 * energy in the map is thereby exact at any resolution, and a horizon cutting the disk is resolved
 * to a fraction of a percent.  Seen from the observer, the optical depth toward a point of the disk
 * depends only on its elevation: it is tabulated across the disk first. */
#define DISK_DEPTH_SAMPLES 257

/* Angular size (rad) of the camera's pixels around direction d: the smaller of the angles spanned by
 * one pixel across and down at d's position; 0 when the camera cannot place d. */
static double pixel_angle_at(const camera *cam, vec3 d)
{
    double x, y;
    if (!camera_project(cam, d, &x, &y))
        return 0.0;
    vec3 a, b, c, e;
    camera_direction(cam, x - 0.5, y, &a);
    camera_direction(cam, x + 0.5, y, &b);
    camera_direction(cam, x, y - 0.5, &c);
    camera_direction(cam, x, y + 0.5, &e);
    return fmin(v3_length(v3_sub(a, b)), v3_length(v3_sub(c, e)));
}

/* Pixel solid angles for the disk's points: direct-mapped by pixel index, since the disk covers few
 * pixels and the fisheye's are computed by quadrature. */
#define OMEGA_CACHE 4096

typedef struct omega_cache {
    int64_t pixel[OMEGA_CACHE];
    double inv_omega[OMEGA_CACHE];
} omega_cache;

static double inverse_pixel_solid_angle(const camera *cam, omega_cache *cache, int px, int py)
{
    if (cam->type == FM_CAMERA_EQUIRECT) /* the closed form */
        return 1.0 / equirect_pixel_solid_angle(cam->width, cam->height, py);
    int64_t index = (int64_t)py * cam->width + px;
    int slot = (int)(index % OMEGA_CACHE);
    if (cache->pixel[slot] != index) {
        cache->pixel[slot] = index;
        cache->inv_omega[slot] = 1.0 / camera_pixel_solid_angle(cam, px, py);
    }
    return cache->inv_omega[slot];
}

/* Points across the disk's diameter: 8 per pixel, within 256 to 2048; 0 when the sun is behind
 * the camera. */
static int disk_points(const fm_sky *sky, const camera *cam, int width)
{
    const double a = sky->sun.angular_radius;
    int n;
    if (cam->type == FM_CAMERA_EQUIRECT) {
        n = (int)ceil(2.0 * a / (2.0 * FM_PI / width) * 8.0);
    } else {
        double pixel = pixel_angle_at(cam, sky->sun_dir);
        if (!(pixel > 0.0))
            return 0;
        n = (int)fmin(4096.0, ceil(2.0 * a / pixel * 8.0));
    }
    return n < 256 ? 256 : (n > 2048 ? 2048 : n);
}

/* The disk's extent in cosines of the zenith angle, and the optical depth (every wavelength) at
 * DISK_DEPTH_SAMPLES cosines across it: depth[i * K + k], INFINITY where the ground blocks. */
typedef struct disk_span {
    double robs, mu_lo, mu_hi;
} disk_span;

static void disk_depths(const fm_sky *sky, disk_span *span, double *depth)
{
    const atmosphere *atm = &sky->atm;
    const int K = atm->grid.count;
    const double a = sky->sun.angular_radius;
    span->robs = v3_length(sky->observer);
    assert(span->robs >= atm->bottom_radius_m && span->robs < atm->top_radius_m);
    assert(fabs(v3_length(sky->sun_dir) - 1.0) < 1e-12);
    double e0 = asin(clamp_cosine(sky->sun_dir.z));
    span->mu_lo = sin(e0 - 1.01 * a);
    span->mu_hi = sin(fmin(e0 + 1.01 * a, 0.5 * FM_PI));
    double col[FM_MAX_SPECIES];
    for (int i = 0; i < DISK_DEPTH_SAMPLES; i++) {
        double mu = span->mu_lo + (span->mu_hi - span->mu_lo) * i / (DISK_DEPTH_SAMPLES - 1);
        int blocked = ray_hits_ground(atm, span->robs, mu);
        if (!blocked)
            column_quadrature(atm, span->robs, mu, ray_distance_to_top(atm, span->robs, mu), col);
        for (int k = 0; k < K; k++)
            depth[i * K + k] = blocked ? INFINITY : atmosphere_optical_depth(atm, col, k);
    }
}

/* Per depth sample and power of mu2, the channels of the disk's light (light[(i * SUN_LD_TERMS + p) *
 * C]): a point's light is the sum over the powers of mu2^p times the samples' (linear between
 * them), so each point costs a few multiplications instead of an exponential per wavelength.  The
 * limb darkening is a polynomial in mu2 (sun_disk.h), normalised per wavelength to sum to 1 over the
 * disk's n x n points: its sum is the coefficients times the sums of the powers of mu2. */
static void disk_light(const fm_sky *sky, int n, int C, const double *depth, float *light)
{
    const atmosphere *atm = &sky->atm;
    const sun_disk *sun = &sky->sun;
    const int K = atm->grid.count;
    double power_sum[SUN_LD_TERMS] = {0};
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i + 0.5) / n * 2.0 - 1.0, y = (j + 0.5) / n * 2.0 - 1.0, rr = x * x + y * y;
            if (rr >= 1.0)
                continue;
            double mu2 = sqrt(1.0 - rr), m = 1.0;
            for (int p = 0; p < SUN_LD_TERMS; p++, m *= mu2)
                power_sum[p] += m;
        }
    for (int i = 0; i < DISK_DEPTH_SAMPLES; i++)
        for (int p = 0; p < SUN_LD_TERMS; p++) {
            double L[FM_MAX_WAVELENGTHS];
            for (int k = 0; k < K; k++) {
                double norm = 0.0;
                for (int q = 0; q < SUN_LD_TERMS; q++)
                    norm += sun->ld[k][q] * power_sum[q];
                L[k] = atm->grid.solar_irradiance[k] * sun->ld[k][p] / norm * exp(-depth[i * K + k]);
            }
            render_channels(atm, C, L, &light[((size_t)i * SUN_LD_TERMS + p) * C]);
        }
}

/* Adds each of the disk's n x n points to the pixel that holds it, in img->sun_disk. */
static void disk_splat(const fm_sky *sky, const camera *cam, omega_cache *cache, int n, const disk_span *span,
                       const double *depth, const float *light, fm_image *img)
{
    const atmosphere *atm = &sky->atm;
    const int K = atm->grid.count, W = img->width, C = img->channels;
    const double a = sky->sun.angular_radius;
    frame f = frame_from_normal(sky->sun_dir);
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            double x = (i + 0.5) / n * 2.0 - 1.0, y = (j + 0.5) / n * 2.0 - 1.0, rr = x * x + y * y;
            if (rr >= 1.0)
                continue;
            vec3 d = v3_normalize(frame_to_world(&f, v3(tan(a) * x, tan(a) * y, 1.0)));
            assert(fabs(v3_length(d) - 1.0) < 1e-12);
            if (ray_hits_ground(atm, span->robs, d.z)) /* the observer's zenith is +Z */
                continue;
            int px, py;
            if (!camera_pixel(cam, d, &px, &py))
                continue;
            double fd = (d.z - span->mu_lo) / (span->mu_hi - span->mu_lo) * (DISK_DEPTH_SAMPLES - 1);
            int id = (int)fd;
            id = id < 0 ? 0 : (id > DISK_DEPTH_SAMPLES - 2 ? DISK_DEPTH_SAMPLES - 2 : id);
            double td = fd - id;
            /* next to the horizon one sample may be blocked: use the visible neighbour */
            if (isinf(depth[id * K]))
                td = 1.0;
            else if (isinf(depth[(id + 1) * K]))
                td = 0.0;
            const float *l0 = &light[(size_t)id * SUN_LD_TERMS * C], *l1 = l0 + SUN_LD_TERMS * C;
            double inv_omega = inverse_pixel_solid_angle(cam, cache, px, py), mu2 = sqrt(1.0 - rr);
            size_t idx = ((size_t)py * W + px) * C;
            for (int c = 0; c < C; c++) {
                double v = 0.0;
                for (int p = SUN_LD_TERMS - 1; p >= 0; p--)
                    v = v * mu2 + (1.0 - td) * l0[p * C + c] + td * l1[p * C + c];
                img->sun_disk[idx + c] += (float)(v * inv_omega);
            }
        }
}

fm_status sun_disk_rasterise(const fm_sky *sky, const camera *cam, fm_image *img)
{
    const int n = disk_points(sky, cam, img->width), C = img->channels;
    if (!n)
        return FM_OK; /* behind the camera */
    omega_cache *cache = cam->type != FM_CAMERA_EQUIRECT ? malloc(sizeof *cache) : NULL;
    double *depth = malloc(sizeof(double) * DISK_DEPTH_SAMPLES * (size_t)sky->atm.grid.count);
    float *light = malloc(sizeof(float) * DISK_DEPTH_SAMPLES * SUN_LD_TERMS * (size_t)C);
    if ((cam->type != FM_CAMERA_EQUIRECT && !cache) || !depth || !light) {
        free(light);
        free(depth);
        free(cache);
        return FM_ERR_OUT_OF_MEMORY;
    }
    for (int i = 0; cache && i < OMEGA_CACHE; i++)
        cache->pixel[i] = -1;
    disk_span span;
    disk_depths(sky, &span, depth);
    disk_light(sky, n, C, depth, light);
    disk_splat(sky, cam, cache, n, &span, depth, light, img);
    free(light);
    free(depth);
    free(cache);
    size_t total = (size_t)img->width * img->height * C;
    for (size_t i = 0; i < total; i++)
        img->pixels[i] += img->sun_disk[i];
    return FM_OK;
}
