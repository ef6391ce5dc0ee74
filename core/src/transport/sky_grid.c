#include "transport/sky_grid.h"

#include "base/quadrature.h"
#include "base/units.h"
#include "base/vec.h"

#include <math.h>
#include <stdlib.h>

/* Nodes sit this far (rad) inside their domain, so the horizon rows look just above the horizon
 * (grazing, reaching space) and just below it (reaching the ground), never exactly along it. */
#define HORIZON_GAP 1e-7

fm_status sky_grid_init(sky_grid *g, double horizon_elevation, int rows_sky, int rows_ground, int cols,
                        int channels, int logarithmic)
{
    g->horizon_elevation = horizon_elevation;
    g->logarithmic = logarithmic;
    g->rows_sky = rows_sky;
    g->rows_ground = rows_ground;
    g->cols = cols;
    g->channels = channels;
    g->values = calloc((size_t)sky_grid_nodes(g) * (size_t)channels, sizeof(float));
    return g->values ? FM_OK : FM_ERR_OUT_OF_MEMORY;
}

void sky_grid_set(sky_grid *g, int index, int c, float v)
{
    g->values[(size_t)index * g->channels + c] = g->logarithmic ? logf(fmaxf(v, FM_GRID_FLOOR)) : v;
}

void sky_grid_free(sky_grid *g)
{
    free(g->values);
    g->values = NULL;
}

static double sky_span(const sky_grid *g) { return 0.5 * FM_PI - g->horizon_elevation - HORIZON_GAP; }
static double ground_span(const sky_grid *g) { return 0.5 * FM_PI + g->horizon_elevation - HORIZON_GAP; }

void sky_grid_node_angles(const sky_grid *g, int index, double *elevation, double *rel_azimuth)
{
    int row = index / g->cols, col = index % g->cols;
    *rel_azimuth = FM_PI * col / (g->cols - 1);
    if (row < g->rows_sky) {
        double u = (double)row / (g->rows_sky - 1);
        *elevation = g->horizon_elevation + HORIZON_GAP + sky_span(g) * u * u;
    } else {
        double u = (double)(row - g->rows_sky) / (g->rows_ground - 1);
        *elevation = g->horizon_elevation - HORIZON_GAP - ground_span(g) * u * u;
    }
}

/* Over each interval between two rows the interpolant is linear in u (weights 1 - t and t of its
 * rows) and the elevation e = e_h + span u^2, so the integrand  sin e cos e de = sin e cos e 2 span
 * u du  is smooth: 8 Gauss-Legendre points per interval.  Over the azimuth the interpolant's hats
 * integrate to one column spacing (half at the ends, phi = 0 and pi), doubled for the mirrored half. */
/* Row r's share of the integral: its hat over the intervals on either side. */
static double row_irradiance_share(const sky_grid *g, int r)
{
    const gauss_rule *gl = gauss_legendre_cached(8);
    const double span = sky_span(g), du = 1.0 / (g->rows_sky - 1);
    double share = 0.0;
    for (int i = r - 1; i <= r; i++) { /* interval i lies between rows i and i + 1 */
        if (i < 0 || i + 1 >= g->rows_sky)
            continue;
        for (int j = 0; j < gl->n; j++) {
            double t = 0.5 * (gl->x[j] + 1.0), u = (i + t) * du;
            double e = g->horizon_elevation + HORIZON_GAP + span * u * u;
            double hat = i == r ? 1.0 - t : t;
            share += hat * sin(e) * cos(e) * 2.0 * span * u * 0.5 * gl->w[j] * du;
        }
    }
    return share;
}

void sky_grid_irradiance_weights(const sky_grid *g, double *w)
{
    const int C = g->cols;
    const double dphi = FM_PI / (C - 1);
    for (int r = 0; r < g->rows_sky; r++) {
        double share = row_irradiance_share(g, r);
        for (int c = 0; c < C; c++)
            w[r * C + c] = share * 2.0 * dphi * (c == 0 || c == C - 1 ? 0.5 : 1.0);
    }
}

/* The bilinear cell of (elevation, relative azimuth): the offset of its first value (row r0, column c0)
 * in g->values and the weights tr, tc of its next row and column. */
static size_t cell_of(const sky_grid *g, double elevation, double rel_azimuth, double *tr, double *tc)
{
    double u;
    int first, rows;
    if (elevation > g->horizon_elevation) {
        u = safe_sqrt((elevation - g->horizon_elevation - HORIZON_GAP) / sky_span(g));
        first = 0;
        rows = g->rows_sky;
    } else {
        u = safe_sqrt((g->horizon_elevation - HORIZON_GAP - elevation) / ground_span(g));
        first = g->rows_sky;
        rows = g->rows_ground;
    }
    double fr = clamp_between(u, 0.0, 1.0) * (rows - 1);
    int r0 = (int)fr;
    if (r0 > rows - 2)
        r0 = rows - 2;
    *tr = fr - r0;
    double fc = clamp_between(rel_azimuth / FM_PI, 0.0, 1.0) * (g->cols - 1);
    int c0 = (int)fc;
    if (c0 > g->cols - 2)
        c0 = g->cols - 2;
    *tc = fc - c0;
    return ((size_t)(first + r0) * g->cols + c0) * g->channels;
}

/* Channel c of the cell at v00 (cell_of), interpolated. */
static double interpolate(const sky_grid *g, const float *v00, double tr, double tc, int c)
{
    const size_t C = (size_t)g->channels, next_row = (size_t)g->cols * C;
    double v = (1 - tr) * ((1 - tc) * v00[c] + tc * v00[C + c]) + tr * ((1 - tc) * v00[next_row + c] +
                                                                          tc * v00[next_row + C + c]);
    return g->logarithmic ? exp(v) : v;
}

void sky_grid_lookup(const sky_grid *g, double elevation, double rel_azimuth, float *out)
{
    double tr, tc;
    const float *v00 = &g->values[cell_of(g, elevation, rel_azimuth, &tr, &tc)];
    for (int c = 0; c < g->channels; c++)
        out[c] = (float)interpolate(g, v00, tr, tc, c);
}

double sky_grid_lookup_channel(const sky_grid *g, double elevation, double rel_azimuth, int c)
{
    double tr, tc;
    const float *v00 = &g->values[cell_of(g, elevation, rel_azimuth, &tr, &tc)];
    return (float)interpolate(g, v00, tr, tc, c);
}

void sky_grid_average_poles(sky_grid *g)
{
    const int pole_rows[2] = {g->rows_sky - 1, g->rows_sky + g->rows_ground - 1};
    for (int p = 0; p < 2; p++)
        for (int c = 0; c < g->channels; c++) {
            float *row = &g->values[(size_t)pole_rows[p] * g->cols * g->channels];
            double sum = 0.0;
            for (int j = 0; j < g->cols; j++)
                sum += row[j * g->channels + c];
            for (int j = 0; j < g->cols; j++)
                row[j * g->channels + c] = (float)(sum / g->cols);
        }
}
