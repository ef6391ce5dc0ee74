#include "camera/footprint.h"

#include "base/units.h"

#include <math.h>

footprint_settings footprint_default_settings(int samples, double horizon)
{
    return (footprint_settings){
        .samples = samples,
        .horizon = horizon,
        .fine = 0.1 * FM_DEG,
        .band_below = 3.0 * FM_DEG,
        .band_above = 10.0 * FM_DEG,
        .max_samples = 64,
    };
}

/* Positions in slice coordinates: u across the slices, v along them; rows (slices of constant y)
 * or columns (constant x). */
typedef struct slicing {
    int rows;
} slicing;

static void position(slicing sl, double u, double v, double *x, double *y)
{
    *x = sl.rows ? v : u;
    *y = sl.rows ? u : v;
}

static double elevation_at(const camera *c, double x, double y)
{
    vec3 d;
    camera_direction(c, x, y, &d);
    return asin(clamp_cosine(d.z));
}

static double angle_between(vec3 a, vec3 b)
{
    return 2.0 * asin(fmin(1.0, 0.5 * v3_length(v3_sub(a, b))));
}

static int count_for(double angle, const footprint_settings *s, int near)
{
    int n = s->samples;
    if (near) {
        double need = ceil(angle / s->fine);
        if (need > n)
            n = need > s->max_samples ? s->max_samples : (int)need;
    }
    return n;
}

/* v in [lo, hi] where the elevation along the slice u crosses the horizon, if it does. */
static int horizon_crossing(const camera *c, slicing sl, double u, double lo, double hi, double horizon, double *v)
{
    double x, y;
    position(sl, u, lo, &x, &y);
    double a = elevation_at(c, x, y) - horizon;
    position(sl, u, hi, &x, &y);
    double b = elevation_at(c, x, y) - horizon;
    if ((a < 0.0) == (b < 0.0))
        return 0;
    for (int i = 0; i < 60 && hi - lo > 1e-12; i++) {
        double m = 0.5 * (lo + hi);
        position(sl, u, m, &x, &y);
        if ((elevation_at(c, x, y) - horizon < 0.0) == (a < 0.0))
            lo = m;
        else
            hi = m;
    }
    *v = 0.5 * (lo + hi);
    return 1;
}

int footprint_average(const camera *c, int px, int py, const footprint_settings *s, footprint_radiance f, void *ctx,
                      int channels, double *out)
{
    for (int k = 0; k < channels; k++)
        out[k] = 0.0;
    /* the corners: directions k = 2 j + i at (px + i, py + j) */
    vec3 corner[4];
    double z_min = INFINITY, z_max = -INFINITY;
    for (int k = 0; k < 4; k++) {
        camera_direction(c, px + (k & 1), py + (k >> 1), &corner[k]);
        z_min = fmin(z_min, corner[k].z);
        z_max = fmax(z_max, corner[k].z);
    }
    /* near the horizon?  (the corners bound the elevations of a pixel well enough for a band many
     * pixels wide) */
    int near = z_max > sin(fmax(-0.5 * FM_PI, s->horizon - s->band_below)) &&
               z_min < sin(fmin(0.5 * FM_PI, s->horizon + s->band_above));
    slicing sl = {0};
    int nu = s->samples, nv = s->samples;
    if (near) {
        /* slices cross the lines of equal elevation (the horizon, the fisheye's rim) rather than run
         * along them: where a slice grazes the boundary, the slices' sum converges slowly */
        double e[4];
        for (int k = 0; k < 4; k++)
            e[k] = asin(clamp_cosine(corner[k].z));
        sl.rows = fabs(e[1] + e[3] - e[0] - e[2]) > fabs(e[2] + e[3] - e[0] - e[1]);
        double across_x = 0.5 * (angle_between(corner[0], corner[1]) + angle_between(corner[2], corner[3]));
        double across_y = 0.5 * (angle_between(corner[0], corner[2]) + angle_between(corner[1], corner[3]));
        nu = count_for(sl.rows ? across_y : across_x, s, near);
        nv = count_for(sl.rows ? across_x : across_y, s, near);
    }
    double u0 = sl.rows ? py : px, v0 = sl.rows ? px : py;

    double acc[4] = {0, 0, 0, 0}, wsum = 0.0;
    float val[4];
    int evaluations = 0;
    for (int i = 0; i < nu; i++) {
        double u = u0 + (i + 0.5) / nu, lo, hi;
        if (!(sl.rows ? camera_row_span(c, u, v0, v0 + 1.0, &lo, &hi) : camera_column_span(c, u, v0, v0 + 1.0, &lo, &hi)))
            continue;
        double cuts[3] = {lo, hi, hi};
        int parts = 1;
        if (near && horizon_crossing(c, sl, u, lo, hi, s->horizon, &cuts[1]))
            parts = 2;
        for (int p = 0; p < parts; p++) {
            double a = cuts[p], b = cuts[p + 1];
            int n = (int)ceil(nv * (b - a)); /* the slice's share of nv */
            n = n < 1 ? 1 : n;
            for (int j = 0; j < n; j++) {
                double x, y;
                position(sl, u, a + (b - a) * (j + 0.5) / n, &x, &y);
                vec3 d;
                double w = camera_sample(c, x, y, &d) * (b - a) / n;
                if (!(w > 0.0))
                    continue;
                f(ctx, d, asin(clamp_cosine(d.z)), val);
                evaluations++;
                for (int k = 0; k < channels; k++)
                    acc[k] += w * val[k];
                wsum += w;
            }
        }
    }
    if (wsum > 0.0)
        for (int k = 0; k < channels; k++)
            out[k] = acc[k] / wsum;
    return evaluations;
}
