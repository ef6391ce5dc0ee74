/* Map comparison metrics (firmament.h: fm_image_compare). */
#include "firmament/firmament.h"

#include "base/status.h"
#include "base/units.h"
#include "camera/camera.h"
#include "image/image.h"

#include <math.h>
#include <stdlib.h>

static void pixel_xyz(const fm_image *img, size_t i, double xyz[3])
{
    const float *p = &img->pixels[i * img->channels];
    if (img->channels == 1) {
        xyz[0] = xyz[2] = 0.0;
        xyz[1] = p[0];
    } else {
        double v[3] = {p[0], p[1], p[2]};
        image_colour_to_xyz(img, v, xyz);
    }
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

fm_status fm_image_compare(const fm_image *a, const fm_image *b, double exclude_deg, fm_comparison *out,
                           fm_error *err)
{
    const double *around = b->sun_direction;
    if (exclude_deg > 0.0 && around[0] == 0.0 && around[1] == 0.0 && around[2] == 0.0)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the reference map does not say where the sun is");
    if (a->width != b->width || a->height != b->height || a->channels != b->channels)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the images differ in size or channels (%dx%dx%d vs %dx%dx%d)",
                       a->width, a->height, a->channels, b->width, b->height, b->channels);
    const int W = a->width, H = a->height;
    /* a NaN or infinity would make every statistic NaN (or the max disagree with the RMS) */
    for (int which = 0; which < 2; which++) {
        const fm_image *m = which ? b : a;
        size_t values = (size_t)W * H * m->channels, bad = 0;
        for (size_t i = 0; i < values; i++)
            bad += !isfinite(m->pixels[i]);
        if (bad)
            return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the %s holds %zu values that are not finite (NaN or "
                                                         "infinity)",
                           which ? "reference" : "image", bad);
    }
    double *errs = malloc(sizeof(double) * (size_t)W * H);
    if (!errs)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    double cos_exclude = exclude_deg > 0.0 ? cos(exclude_deg * FM_DEG) : 2.0;
    camera cam; /* the reference's: where its pixels look */
    if (cos_exclude <= 1.0 && (camera_init(&cam, &b->camera, W, NULL) != FM_OK || cam.height != H)) {
        free(errs);
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the reference's camera does not fit its %d x %d pixels", W, H);
    }
    /* the compared pixels (lit in the reference, away from the sun) and the reference's mean */
    size_t *kept = malloc(sizeof(size_t) * (size_t)W * H);
    if (!kept) {
        free(errs);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    }
    long n = 0;
    double mean_ref = 0.0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            if (cos_exclude <= 1.0) {
                vec3 d;
                camera_direction(&cam, x + 0.5, y + 0.5, &d);
                if (d.x * around[0] + d.y * around[1] + d.z * around[2] > cos_exclude)
                    continue;
            }
            size_t i = (size_t)y * W + x;
            double xb[3];
            pixel_xyz(b, i, xb);
            if (xb[1] > 0.0) {
                kept[n++] = i;
                mean_ref += xb[1];
            }
        }
    /* Relative error means nothing on black pixels (an unlit ground of albedo 0 is 0 up to rounding,
     * 1e-20 in one map and 1e-13 in the other): below 1e-6 of the mean, errors are relative to that
     * floor, so black matches black and light where the reference is black still counts. */
    const double black = n ? 1e-6 * mean_ref / n : 0.0;
    double sum = 0.0, sum2 = 0.0, chroma = 0.0, worst = 0.0;
    for (long j = 0; j < n; j++) {
        double xa[3], xb[3];
        pixel_xyz(a, kept[j], xa);
        pixel_xyz(b, kept[j], xb);
        double e = (xa[1] - xb[1]) / fmax(xb[1], black);
        errs[j] = fabs(e);
        sum += e;
        sum2 += e * e;
        worst = fmax(worst, fabs(e));
        if (a->channels == 3 && xb[1] > black) {
            double sa = xa[0] + xa[1] + xa[2], sb = xb[0] + xb[1] + xb[2];
            if (sa > 0.0 && sb > 0.0)
                chroma += hypot(xa[0] / sa - xb[0] / sb, xa[1] / sa - xb[1] / sb);
        }
    }
    free(kept);
    if (n == 0) {
        free(errs);
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "no pixel to compare");
    }
    qsort(errs, (size_t)n, sizeof *errs, cmp_double);
    out->pixels = n;
    out->rms = sqrt(sum2 / n);
    out->mean = sum / n;
    out->max = worst;
    out->p99 = errs[(size_t)fmin((double)n - 1.0, floor(0.99 * (double)n))];
    out->chromaticity = chroma / n;
    free(errs);
    return FM_OK;
}
