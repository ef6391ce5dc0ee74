#include "seed_noise.h"

#include "base/units.h"
#include "colour/colour.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* linear Rec.709 of pixel i */
static void pixel_rec709(const fm_image *m, size_t i, double rgb[3])
{
    const float *p = &m->pixels[i * (size_t)m->channels];
    double v[3] = {p[0], p[1], p[2]}, xyz[3];
    image_colour_to_xyz(m, v, xyz);
    colour_xyz_to_rec709(xyz, rgb);
}

static int usable(const fm_image *a, const fm_image *b)
{
    if (a->width != b->width || a->height != b->height || a->channels != 3 || b->channels != 3 ||
        a->camera.type != FM_CAMERA_EQUIRECT || b->camera.type != FM_CAMERA_EQUIRECT ||
        a->content == FM_IMAGE_SPECTRAL_GRID || b->content == FM_IMAGE_SPECTRAL_GRID) {
        fprintf(stderr, "sky-bench: the maps must be equirect colour maps of one size\n");
        return 0;
    }
    return 1;
}

/* solid-angle weight of row y of an equirect map (top row at the zenith) */
static double row_weight(int y, int height) { return cos(FM_PI * (0.5 - (y + 0.5) / height)); }

static double lab_f(double t)
{
    const double d = 6.0 / 29.0;
    return t > d * d * d ? cbrt(t) : t / (3.0 * d * d) + 4.0 / 29.0;
}

/* CIELAB of a display-referred linear Rec.709 colour, clipped to [0, 1], against the white
 * (XYZ of Rec.709 1, 1, 1: D65) */
static void display_lab(const double rgb[3], const double white[3], double lab[3])
{
    double c[3], xyz[3];
    for (int i = 0; i < 3; i++)
        c[i] = rgb[i] < 0.0 ? 0.0 : (rgb[i] > 1.0 ? 1.0 : rgb[i]);
    colour_rec709_to_xyz(c, xyz);
    double fx = lab_f(xyz[0] / white[0]), fy = lab_f(xyz[1] / white[1]), fz = lab_f(xyz[2] / white[2]);
    lab[0] = 116.0 * fy - 16.0;
    lab[1] = 500.0 * (fx - fy);
    lab[2] = 200.0 * (fy - fz);
}

static double degrees_of(double y, double x)
{
    double h = atan2(y, x) / FM_DEG;
    return h < 0.0 ? h + 360.0 : h;
}

double seed_noise_ciede2000(const double l1[3], const double l2[3])
{
    const double p25 = pow(25.0, 7.0);
    double c1 = hypot(l1[1], l1[2]), c2 = hypot(l2[1], l2[2]), cm = 0.5 * (c1 + c2);
    double g = 0.5 * (1.0 - sqrt(pow(cm, 7.0) / (pow(cm, 7.0) + p25)));
    double a1 = (1.0 + g) * l1[1], a2 = (1.0 + g) * l2[1];
    double cp1 = hypot(a1, l1[2]), cp2 = hypot(a2, l2[2]);
    double hp1 = degrees_of(l1[2], a1), hp2 = degrees_of(l2[2], a2);
    double dl = l2[0] - l1[0], dc = cp2 - cp1, dh = 0.0;
    int chromatic = cp1 * cp2 != 0.0;
    if (chromatic) {
        dh = hp2 - hp1;
        dh = dh > 180.0 ? dh - 360.0 : (dh < -180.0 ? dh + 360.0 : dh);
    }
    double dH = 2.0 * sqrt(cp1 * cp2) * sin(0.5 * dh * FM_DEG);
    double lm = 0.5 * (l1[0] + l2[0]), cpm = 0.5 * (cp1 + cp2), hm = hp1 + hp2;
    if (chromatic && fabs(hp1 - hp2) > 180.0)
        hm = hm < 360.0 ? 0.5 * (hm + 360.0) : 0.5 * (hm - 360.0);
    else if (chromatic)
        hm *= 0.5;
    double t = 1.0 - 0.17 * cos((hm - 30.0) * FM_DEG) + 0.24 * cos(2.0 * hm * FM_DEG) +
               0.32 * cos((3.0 * hm + 6.0) * FM_DEG) - 0.20 * cos((4.0 * hm - 63.0) * FM_DEG);
    double dtheta = 30.0 * exp(-pow((hm - 275.0) / 25.0, 2.0));
    double rc = 2.0 * sqrt(pow(cpm, 7.0) / (pow(cpm, 7.0) + p25));
    double sl = 1.0 + 0.015 * (lm - 50.0) * (lm - 50.0) / sqrt(20.0 + (lm - 50.0) * (lm - 50.0));
    double sc = 1.0 + 0.045 * cpm, sh = 1.0 + 0.015 * cpm * t, rt = -sin(2.0 * dtheta * FM_DEG) * rc;
    double x = dl / sl, y = dc / sc, z = dH / sh;
    return sqrt(x * x + y * y + z * z + rt * y * z);
}

static double log_ratio(double x, double y) { return x > 0.0 && y > 0.0 ? log(x / y) : 0.0; }

/* CIE Y of a linear Rec.709 colour */
static double luminance(const double rgb[3])
{
    const double *y = fm_rec709_to_xyz[1];
    return y[0] * rgb[0] + y[1] * rgb[1] + y[2] * rgb[2];
}

static int ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int seed_noise_measure(const fm_image *a, const fm_image *b, double exposure_ev, seed_noise *out)
{
    if (!usable(a, b))
        return 1;
    const int W = a->width, H = a->height / 2;
    double *de = malloc(sizeof(double) * (size_t)W * H), *prev = malloc(sizeof(double) * (size_t)W);
    if (!de || !prev) {
        free(de);
        free(prev);
        fprintf(stderr, "sky-bench: out of memory\n");
        return 1;
    }
    const double scale = exp2(exposure_ev), one[3] = {1.0, 1.0, 1.0};
    double white[3];
    colour_rec709_to_xyz(one, white);
    double sw = 0.0, sy = 0.0, srg = 0.0, sbg = 0.0, sgrain = 0.0, sgw = 0.0;
    for (int y = 0; y < H; y++) {
        double w = row_weight(y, a->height);
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double ca[3], cb[3], la[3], lb[3], da[3], db[3];
            pixel_rec709(a, i, ca);
            pixel_rec709(b, i, cb);
            double dy = log_ratio(luminance(ca), luminance(cb));
            double drg = log_ratio(ca[0], ca[1]) - log_ratio(cb[0], cb[1]);
            double dbg = log_ratio(ca[2], ca[1]) - log_ratio(cb[2], cb[1]);
            sy += w * dy * dy;
            srg += w * drg * drg;
            sbg += w * dbg * dbg;
            sw += w;
            if (x > 0) {
                sgrain += w * (dy - prev[x - 1]) * (dy - prev[x - 1]);
                sgw += w;
            }
            prev[x] = dy;
            for (int c = 0; c < 3; c++) {
                da[c] = scale * ca[c];
                db[c] = scale * cb[c];
            }
            display_lab(da, white, la);
            display_lab(db, white, lb);
            de[i] = seed_noise_ciede2000(la, lb);
        }
    }
    double mean = 0.0;
    size_t n = (size_t)W * H;
    for (size_t i = 0; i < n; i++)
        mean += de[i] / (double)n;
    qsort(de, n, sizeof de[0], ascending);
    *out = (seed_noise){.luminance = sqrt(sy / sw / 2.0),
                        .red_green = sqrt(srg / sw / 2.0),
                        .blue_green = sqrt(sbg / sw / 2.0),
                        .grain = sqrt(sgrain / sgw) / 2.0,
                        .de_mean = mean,
                        .de_p99 = de[(size_t)floor(0.99 * (double)(n - 1))]};
    free(de);
    free(prev);
    return 0;
}

int seed_flicker(const fm_image *a1, const fm_image *b1, const fm_image *a2, const fm_image *b2, double *flicker)
{
    if (!usable(a1, b1) || !usable(a1, a2) || !usable(a1, b2))
        return 1;
    const int W = a1->width, H = a1->height / 2;
    double sw = 0.0, s = 0.0;
    for (int y = 0; y < H; y++) {
        double w = row_weight(y, a1->height);
        for (int x = 0; x < W; x++) {
            size_t i = (size_t)y * W + x;
            double c[4][3];
            pixel_rec709(a1, i, c[0]);
            pixel_rec709(b1, i, c[1]);
            pixel_rec709(a2, i, c[2]);
            pixel_rec709(b2, i, c[3]);
            double d = log_ratio(luminance(c[1]), luminance(c[0])) - log_ratio(luminance(c[3]), luminance(c[2]));
            s += w * d * d;
            sw += w;
        }
    }
    *flicker = sqrt(s / sw / 2.0);
    return 0;
}
