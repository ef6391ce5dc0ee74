#include "render/live_smooth.h"

#include "transport/twilight.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int live_quadratic_weights(const double *x, const double *w, int n, double *h)
{
    double m[3][3] = {{0}};
    int used = 0;
    for (int j = 0; j < n; j++) {
        const double b[3] = {1.0, x[j], x[j] * x[j]};
        used += w[j] > 0.0;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                m[r][c] += w[j] * b[r] * b[c];
    }
    /* the first row of the inverse of the (symmetric) normal matrix, by cofactors */
    const double c0 = m[1][1] * m[2][2] - m[1][2] * m[2][1], c1 = m[1][2] * m[2][0] - m[1][0] * m[2][2],
                 c2 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
    const double det = m[0][0] * c0 + m[0][1] * c1 + m[0][2] * c2;
    if (used < 3 || !(fabs(det) > 1e-12 * fabs(m[0][0] * m[1][1] * m[2][2])))
        return 0;
    for (int j = 0; j < n; j++)
        h[j] = w[j] * (c0 + c1 * x[j] + c2 * x[j] * x[j]) / det;
    return 1;
}

/* The weights of node i's window lo..hi: tricube in the index distance (a node LIVE_SMOOTH_HALF + 1
 * away would weigh 0), the quadratic in the index: the grid is dense where the sky changes fast, so
 * by index its logarithm changes at a like pace everywhere and a window's odd terms cancel. */
static int node_weights(int i, int lo, int hi, double *h)
{
    double x[2 * LIVE_SMOOTH_HALF + 1], w[2 * LIVE_SMOOTH_HALF + 1];
    for (int j = lo; j <= hi; j++) {
        double d = fabs((double)(j - i)) / (LIVE_SMOOTH_HALF + 1.0), u = 1.0 - d * d * d;
        x[j - lo] = j - i;
        w[j - lo] = u * u * u;
    }
    return live_quadratic_weights(x, w, hi - lo + 1, h);
}

static int takes_part(const fm_sky_live *live, const unsigned char *fresh, int i, double from_deg)
{
    return i >= 0 && i < live->count && fresh[i] && live->nodes[i].sun_elevation_deg >= from_deg;
}

fm_status live_smooth_day(fm_sky_live *live, const unsigned char *fresh, double from_deg)
{
    const size_t values = (size_t)sky_grid_nodes(&live->nodes[0].ms) * (size_t)live->channels;
    float *raw = malloc(sizeof(float) * values * (size_t)live->count);
    if (!raw)
        return FM_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < live->count; i++)
        if (fresh[i])
            memcpy(&raw[i * values], live->nodes[i].ms.values, sizeof(float) * values);
    for (int i = 0; i < live->count; i++) {
        if (!takes_part(live, fresh, i, from_deg))
            continue;
        int lo = i, hi = i;
        while (lo > i - LIVE_SMOOTH_HALF && takes_part(live, fresh, lo - 1, from_deg))
            lo--;
        while (hi < i + LIVE_SMOOTH_HALF && takes_part(live, fresh, hi + 1, from_deg))
            hi++;
        double h[2 * LIVE_SMOOTH_HALF + 1];
        if (!node_weights(i, lo, hi, h))
            continue;
        float *out = live->nodes[i].ms.values;
        for (size_t v = 0; v < values; v++) {
            double sum = 0.0;
            int j = lo;
            for (; j <= hi && raw[j * values + v] > 0.0f; j++)
                sum += h[j - lo] * log(raw[j * values + v]);
            if (j > hi)
                out[v] = (float)exp(sum);
        }
    }
    free(raw);
    return FM_OK;
}

/* The weights h[0..n) that give node k's value from the nodes at[0..n): the least-squares quadratic in
 * the sun elevation, weighted by a Gaussian of width_deg, without node `out` (-1: with every node);
 * 0 where they do not make one. */
static int deep_weights(const fm_sky_live *live, const int *at, int n, int k, int out, double width_deg, double *x,
                        double *w, double *h)
{
    for (int j = 0; j < n; j++) {
        const double d = (live->nodes[at[j]].sun_elevation_deg - live->nodes[at[k]].sun_elevation_deg) / width_deg;
        x[j] = d;
        w[j] = j == out ? 0.0 : exp(-0.5 * d * d);
    }
    return live_quadratic_weights(x, w, n, h);
}

static int value_lit(const fm_sky_live *live, const int *at, int n, size_t i)
{
    int lit = 1;
    for (int j = 0; j < n; j++)
        lit &= live->nodes[at[j]].ms.values[i] > 0.0f;
    return lit;
}

/* The leave-one-out score of a width: the squared error of each inner deep node's logarithms (a
 * node with others on both sides) predicted from the other nodes, summed over the lit values. */
static double deep_width_score(const fm_sky_live *live, const int *at, int n, double width_deg, double *x,
                               double *w, double *h)
{
    const int C = live->channels, lum = C == 3 ? 1 : 0;
    const size_t values = (size_t)sky_grid_nodes(&live->nodes[at[0]].ms);
    double score = 0.0;
    for (int k = 1; k + 1 < n; k++) {
        if (!twilight_deep(live->nodes[at[k]].sun_elevation_deg))
            continue;
        if (!deep_weights(live, at, n, k, k, width_deg, x, w, h))
            return INFINITY;
        for (size_t v = 0; v < values; v++) {
            if (!value_lit(live, at, n, v * C + lum))
                continue;
            double z = -log(live->nodes[at[k]].ms.values[v * C + lum]);
            for (int j = 0; j < n; j++)
                z += h[j] * log(live->nodes[at[j]].ms.values[v * C + lum]);
            score += z * z;
        }
    }
    return score;
}

fm_status live_smooth_deep_twilight(fm_sky_live *live, const unsigned char *fresh)
{
    int *at = malloc(sizeof(int) * (size_t)live->count), n = 0;
    double *x = malloc(sizeof(double) * 4 * (size_t)live->count);
    if (!at || !x) {
        free(at);
        free(x);
        return FM_ERR_OUT_OF_MEMORY;
    }
    double *w = x + live->count, *h = w + live->count, *ratio = h + live->count;
    for (int i = 0; i < live->count; i++)
        if (fresh[i] && (twilight_deep(live->nodes[i].sun_elevation_deg) ||
                         live->nodes[i].sun_elevation_deg <= LIVE_SMOOTH_DEEP_WITH_DEG))
            at[n++] = i;
    const int C = live->channels, lum = C == 3 ? 1 : 0; /* CIE Y, or the one value */
    const size_t values = n >= LIVE_SMOOTH_DEEP_MIN ? (size_t)sky_grid_nodes(&live->nodes[at[0]].ms) : 0;
    const double widths[] = LIVE_SMOOTH_DEEP_WIDTHS;
    double width = widths[0], best = INFINITY;
    for (size_t c = 0; c < sizeof widths / sizeof widths[0] && values; c++) {
        double score = deep_width_score(live, at, n, widths[c], x, w, h);
        if (score < best) {
            best = score;
            width = widths[c];
        }
    }
    for (size_t v = 0; v < values; v++) {
        const int lit = value_lit(live, at, n, v * C + lum);
        for (int k = 0; k < n && lit; k++) {
            ratio[k] = 1.0; /* the nodes above deep twilight take part as they are */
            if (!twilight_deep(live->nodes[at[k]].sun_elevation_deg) ||
                !deep_weights(live, at, n, k, -1, width, x, w, h))
                continue;
            double z = 0.0;
            for (int j = 0; j < n; j++)
                z += h[j] * log(live->nodes[at[j]].ms.values[v * C + lum]);
            ratio[k] = exp(z) / live->nodes[at[k]].ms.values[v * C + lum];
        }
        for (int k = 0; k < n && lit; k++) /* after every ratio: each from the nodes as they were */
            for (int c = 0; c < C && twilight_deep(live->nodes[at[k]].sun_elevation_deg); c++)
                live->nodes[at[k]].ms.values[v * C + c] *= (float)ratio[k];
    }
    free(at);
    free(x);
    return FM_OK;
}
