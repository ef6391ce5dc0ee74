#include "transport/sky_guide.h"

#include "base/units.h"
#include "transport/sun_frame.h"

#include <math.h>

/* and their distances toward the sun (degrees of arc) */
const double sky_guide_offset_deg[SKY_GUIDE_MAX_OFFSETS] = {0.0, 2.0, 4.0, 6.0, 9.0, 12.0};


/* Index i with a[i] <= u < a[i + 1] among n bins (a ascending). */
static int find_bin(const double *a, int n, double u)
{
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi + 1) / 2;
        if (a[mid] <= u)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* The level for the vertex x: the offset whose local sun is nearest x's among those with a usable
 * level, then the usable level of that offset nearest x's radius (sky_guide_build guarantees one). */
static const sky_guide_level *level_for(const sky_guide *g, vec3 x, vec3 sun_dir)
{
    double r = v3_length(x);
    int offset = 0;
    if (g->offsets > 1) {
        double beta = (asin(clamp_cosine(v3_dot(x, sun_dir) / r)) - g->sun0) / FM_DEG, gap = INFINITY;
        for (int i = 0; i < g->levels; i++)
            if (g->level[i].usable && fabs(sky_guide_offset_deg[g->level[i].offset] - beta) < gap) {
                gap = fabs(sky_guide_offset_deg[g->level[i].offset] - beta);
                offset = g->level[i].offset;
            }
    }
    int best = -1;
    for (int i = 0; i < g->levels; i++)
        if (g->level[i].usable && g->level[i].offset == offset &&
            (best < 0 || fabs(g->level[i].radius - r) < fabs(g->level[best].radius - r)))
            best = i;
    return &g->level[best];
}

/* The elevation (rad) of the horizon of a vertex at radius r, as the level's sky is laid over it
 * (sky_guide.h: lined up with the level's, unless align_horizons is 0). */
static double vertex_horizon(const sky_guide *g, const sky_guide_level *l, double r)
{
    return g->align_horizons ? -acos(fmin(1.0, g->bottom_radius / r)) : l->horizon;
}

/* The slope d(e_level) / de of the map from the elevations of a vertex whose horizon is at eh to the
 * level's, linear between the horizons and the zenith (above) or the nadir. */
static double level_slope(const sky_guide_level *l, double eh, int above)
{
    return above ? (0.5 * FM_PI - l->horizon) / (0.5 * FM_PI - eh) : (0.5 * FM_PI + l->horizon) / (0.5 * FM_PI + eh);
}

vec3 sky_guide_sample(const sky_guide *g, vec3 x, vec3 sun_dir, double u1, double u2, double u3)
{
    const sky_guide_level *l = level_for(g, x, sun_dir);
    int i = find_bin(l->cdf_row, SKY_GUIDE_ROWS, u1);
    while (i > 0 && !(l->cdf_row[i + 1] > l->cdf_row[i]))
        i--; /* never an empty row */
    int c = find_bin(l->cdf_col[i], SKY_GUIDE_COLS, u2);
    while (c > 0 && !(l->cdf_col[i][c + 1] > l->cdf_col[i][c]))
        c--;
    double v = (u2 - l->cdf_col[i][c]) / (l->cdf_col[i][c + 1] - l->cdf_col[i][c]);
    double sin_level = l->edge_sin[i] + (l->edge_sin[i + 1] - l->edge_sin[i]) * u3;
    double phi = 2.0 * FM_PI * (c + clamp_between(v, 0.0, 1.0)) / SKY_GUIDE_COLS;
    double e_level = asin(clamp_cosine(sin_level)), eh = vertex_horizon(g, l, v3_length(x));
    double slope = level_slope(l, eh, e_level >= l->horizon);
    double e = clamp_between(eh + (e_level - l->horizon) / slope, -0.5 * FM_PI, 0.5 * FM_PI);
    sun_frame f = sun_frame_at(x, sun_dir);
    return sun_frame_direction(&f, sin(e), phi);
}

double sky_guide_pdf(const sky_guide *g, vec3 x, vec3 sun_dir, vec3 d)
{
    const sky_guide_level *l = level_for(g, x, sun_dir);
    sun_frame f = sun_frame_at(x, sun_dir);
    double e = asin(clamp_cosine(v3_dot(d, f.up))), eh = vertex_horizon(g, l, v3_length(x));
    double phi = atan2(v3_dot(d, f.side), v3_dot(d, f.sun_h));
    if (phi < 0.0)
        phi += 2.0 * FM_PI;
    double slope = level_slope(l, eh, e >= eh);
    double e_level = l->horizon + (e - eh) * slope;
    /* per steradian of the vertex's sky: d(sin e_level) / d(sin e) */
    double cos_e = cos(e), jacobian = cos_e > 1e-9 ? cos(e_level) * slope / cos_e : slope * slope;
    int i = find_bin(l->edge_sin, SKY_GUIDE_ROWS, sin(e_level));
    int c = (int)(phi / (2.0 * FM_PI) * SKY_GUIDE_COLS);
    c = c < 0 ? 0 : (c >= SKY_GUIDE_COLS ? SKY_GUIDE_COLS - 1 : c);
    return l->pdf[i][c] * jacobian;
}
