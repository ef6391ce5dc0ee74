#include "transport/sky_grid_refine.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

/* The cubic through p0..p3 (at -1, 0, 1, 2) at t in [0, 1] (Catmull-Rom), kept within the four
 * values' range. */
static double cubic(double p0, double p1, double p2, double p3, double t)
{
    double v = p1 + 0.5 * t * (p2 - p0 + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)));
    double lo = fmin(fmin(p0, p1), fmin(p2, p3)), hi = fmax(fmax(p0, p1), fmax(p2, p3));
    return v < lo ? lo : (v > hi ? hi : v);
}

/* Column c's value of a row (channel ch), mirrored at the azimuths 0 and pi. */
static double column(const float *row, int cols, int channels, int c, int ch)
{
    if (c < 0)
        c = -c;
    if (c > cols - 1)
        c = 2 * (cols - 1) - c;
    return row[(size_t)c * channels + ch];
}

/* One coarse domain's rows `first` .. `first + rows - 1`, each refined across the azimuth into
 * tmp's rows (rows x fine cols). */
static void refine_columns(const sky_grid *g, int first, int rows, int factor, int fine_cols, double *tmp)
{
    for (int r = 0; r < rows; r++) {
        const float *row = &g->values[(size_t)(first + r) * g->cols * g->channels];
        for (int fc = 0; fc < fine_cols; fc++) {
            int c = fc / factor < g->cols - 1 ? fc / factor : g->cols - 2;
            double t = (double)(fc - c * factor) / factor;
            for (int ch = 0; ch < g->channels; ch++)
                tmp[((size_t)r * fine_cols + fc) * g->channels + ch] =
                    cubic(column(row, g->cols, g->channels, c - 1, ch), column(row, g->cols, g->channels, c, ch),
                          column(row, g->cols, g->channels, c + 1, ch), column(row, g->cols, g->channels, c + 2, ch), t);
        }
    }
}

/* Row r of a domain refined across the azimuth (tmp, rows x fine_cols), at fine column fc: past the
 * pole (r = rows) the row before it at the opposite azimuth, below the horizon row (r = -1) the
 * straight line through rows 0 and 1. */
static double row_value(const double *tmp, int rows, int fine_cols, int channels, int r, int fc, int ch)
{
    if (r < 0)
        return 2.0 * tmp[(size_t)fc * channels + ch] - tmp[((size_t)fine_cols + fc) * channels + ch];
    if (r > rows - 1) {
        r = 2 * (rows - 1) - r;
        fc = fine_cols - 1 - fc;
    }
    return tmp[((size_t)r * fine_cols + fc) * channels + ch];
}

/* One domain: coarse rows `first`..; fine rows from `fine_first`. */
static void refine_domain(const sky_grid *g, int first, int rows, int factor, sky_grid *fine, int fine_first,
                          double *tmp)
{
    const int fine_cols = fine->cols, fine_rows = (rows - 1) * factor + 1, C = g->channels;
    refine_columns(g, first, rows, factor, fine_cols, tmp);
    for (int fr = 0; fr < fine_rows; fr++) {
        int r = fr / factor < rows - 1 ? fr / factor : rows - 2;
        double t = (double)(fr - r * factor) / factor;
        for (int fc = 0; fc < fine_cols; fc++)
            for (int ch = 0; ch < C; ch++)
                fine->values[((size_t)(fine_first + fr) * fine_cols + fc) * C + ch] = (float)cubic(
                    row_value(tmp, rows, fine_cols, C, r - 1, fc, ch), row_value(tmp, rows, fine_cols, C, r, fc, ch),
                    row_value(tmp, rows, fine_cols, C, r + 1, fc, ch), row_value(tmp, rows, fine_cols, C, r + 2, fc, ch), t);
    }
}

fm_status sky_grid_refine(const sky_grid *coarse, int factor, sky_grid *fine)
{
    assert(!coarse->logarithmic && factor >= 1 && coarse->rows_sky >= 2 && coarse->rows_ground >= 2 && coarse->cols >= 2);
    const int rows_sky = (coarse->rows_sky - 1) * factor + 1, rows_ground = (coarse->rows_ground - 1) * factor + 1;
    const int cols = (coarse->cols - 1) * factor + 1;
    if (sky_grid_init(fine, coarse->horizon_elevation, rows_sky, rows_ground, cols, coarse->channels, 0))
        return FM_ERR_OUT_OF_MEMORY;
    const int most_rows = coarse->rows_sky > coarse->rows_ground ? coarse->rows_sky : coarse->rows_ground;
    double *tmp = malloc(sizeof(double) * (size_t)most_rows * (size_t)cols * (size_t)coarse->channels);
    if (!tmp) {
        sky_grid_free(fine);
        return FM_ERR_OUT_OF_MEMORY;
    }
    refine_domain(coarse, 0, coarse->rows_sky, factor, fine, 0, tmp);
    refine_domain(coarse, coarse->rows_sky, coarse->rows_ground, factor, fine, rows_sky, tmp);
    free(tmp);
    return FM_OK;
}
