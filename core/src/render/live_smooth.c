#include "render/live_smooth.h"

#include "base/units.h"
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

/* The weights h[0..n) (summing to 1) that give the value at x = 0 of the weighted least-squares
 * polynomial of `degree` (0 to 2) through the values at x[0..n): live_quadratic_weights, a weighted
 * line or a weighted mean; 0 where they do not make one. */
static int poly_weights(const double *x, const double *w, int n, int degree, double *h)
{
    if (degree == 2)
        return live_quadratic_weights(x, w, n, h);
    double s0 = 0.0, s1 = 0.0, s2 = 0.0;
    int used = 0;
    for (int j = 0; j < n; j++) {
        used += w[j] > 0.0;
        s0 += w[j];
        s1 += w[j] * x[j];
        s2 += w[j] * x[j] * x[j];
    }
    const double det = s0 * s2 - s1 * s1;
    if (used <= degree || !(s0 > 0.0) || (degree == 1 && !(det > 1e-12 * s0 * s2)))
        return 0;
    for (int j = 0; j < n; j++)
        h[j] = degree == 0 ? w[j] / s0 : w[j] * (s2 - s1 * x[j]) / det;
    return 1;
}

/* One way to smooth across the nodes: a polynomial of `degree` in the sun elevation, weighted by a
 * Gaussian of width_deg. */
typedef struct deep_fit {
    int degree;
    double width_deg;
} deep_fit;

static const deep_fit DEEP_FITS[] = LIVE_SMOOTH_DEEP_FITS;
#define DEEP_FIT_COUNT ((int)(sizeof DEEP_FITS / sizeof DEEP_FITS[0]))

/* The weights h[0..n) that give node k's value from the nodes at[0..n) by fit f, without node `out`
 * (-1: with every node) and, unless `above_too`, without the nodes above deep twilight; 0 where they
 * do not make one. */
static int deep_weights(const fm_sky_live *live, const int *at, int n, int k, int out, deep_fit f, int above_too,
                        double *h)
{
    double x[64], w[64];
    if (n > 64)
        return 0;
    for (int j = 0; j < n; j++) {
        const double d = (live->nodes[at[j]].sun_elevation_deg - live->nodes[at[k]].sun_elevation_deg) / f.width_deg;
        const int in = j != out && (above_too || twilight_deep(live->nodes[at[j]].sun_elevation_deg));
        x[j] = d;
        w[j] = in ? exp(-0.5 * d * d) : 0.0;
    }
    return poly_weights(x, w, n, f.degree, h);
}

/* A cosine series over L points spanning 0..pi, both ends included (a DCT-I): the coefficients
 * a[m * stride] of the values v[c * stride], v[c] = sum_m a[m] cos(pi m c / (L - 1)), the cosines
 * orthogonal under the trapezoid rule's weights.  With the ends included it suits the table's
 * columns (relative azimuth 0 to pi) and its rows (u from 0 to 1). */
static double cosine_at(int m, int c, int L) { return cos(FM_PI * m * c / (L - 1)); }

static void cosine_series(const double *v, int L, int stride, double *a)
{
    for (int m = 0; m < L; m++) {
        double num = 0.0, den = 0.0;
        for (int c = 0; c < L; c++) {
            const double t = c == 0 || c == L - 1 ? 0.5 : 1.0, b = cosine_at(m, c, L);
            num += t * v[c * stride] * b;
            den += t * b * b;
        }
        a[m * stride] = num / den;
    }
}

/* The values v[0..L) of the coefficients a[m * stride]. */
static void cosine_sum(const double *a, int L, int stride, double *v)
{
    for (int c = 0; c < L; c++) {
        double sum = 0.0;
        for (int m = 0; m < L; m++)
            sum += a[m * stride] * cosine_at(m, c, L);
        v[c] = sum;
    }
}

/* One domain of the table (the sky's rows or the ground's) in the making: per node, the logarithms
 * of its luminance as a cosine series over the columns and then over the rows, coef[node][p][m]
 * (p: the rows' term, m: the azimuth's). */
typedef struct deep_domain {
    const int *at;
    int n, row0, rows, cols, C, lum;
    double *coef;
} deep_domain;

/* The terms choose their fit by classes: the level (p = m = 0), the two first-order terms, and the
 * rest together, each class with terms enough for its leave-one-out score to choose well. */
#define DEEP_CLASSES 3
#define DEEP_REST (DEEP_CLASSES - 1)
static int term_class(int p, int m) { return p + m < DEEP_REST ? p + m : DEEP_REST; }

/* Whether deep node k is the highest deep node with a node above deep twilight next in the fit: the
 * band's edge. */
static int at_band_edge(const fm_sky_live *live, const deep_domain *d, int k)
{
    return k + 1 < d->n && !twilight_deep(live->nodes[d->at[k + 1]].sun_elevation_deg);
}

/* Whether the nodes above deep twilight take part in node k's fit of the terms of `class` (-1: a
 * domain smoothed value by value).  The rest's fit is a wide mean or line, which the twilight nodes'
 * shape over the sky (another estimator's, off the deep nodes' curve) would pull at every deep node;
 * at the band's edge it keeps them, else it would end there and keep the edge's noise
 * (docs/decisions/2026-12-07-live-deep-variance.md). */
static int above_in_fit(const fm_sky_live *live, const deep_domain *d, int k, int class)
{
    return class != DEEP_REST || at_band_edge(live, d, k);
}

static float *ms_value(fm_sky_live *live, const deep_domain *d, int k, int r, int c)
{
    return &live->nodes[d->at[k]].ms.values[((size_t)(d->row0 + r) * d->cols + c) * d->C];
}

static double *coef_at(const deep_domain *d, double *base, int k, int p, int m)
{
    return &base[((size_t)k * d->rows + p) * d->cols + m];
}

/* What a leave-one-out score adds for inner node k predicted by the weights h: the squared errors. */
typedef void (*loo_errors_fn)(fm_sky_live *live, const deep_domain *d, int k, const double *h, int arg,
                              double *score);

/* The leave-one-out score of fit f: the errors of each inner deep node (a node with others on both
 * sides) predicted from the other nodes; arg is the class of terms (above_in_fit), or -1. */
static double loo_score(fm_sky_live *live, const deep_domain *d, deep_fit f, loo_errors_fn errors, int arg)
{
    double h[64], score = 0.0;
    for (int k = 1; k + 1 < d->n; k++) {
        if (!twilight_deep(live->nodes[d->at[k]].sun_elevation_deg))
            continue;
        if (!deep_weights(live, d->at, d->n, k, k, f, above_in_fit(live, d, k, arg), h))
            return INFINITY;
        errors(live, d, k, h, arg, &score);
    }
    return score;
}

/* The one of DEEP_FITS whose leave-one-out score is least. */
static deep_fit least_score_fit(fm_sky_live *live, const deep_domain *d, loo_errors_fn errors, int arg)
{
    deep_fit best = DEEP_FITS[0];
    double least = INFINITY;
    for (int c = 0; c < DEEP_FIT_COUNT; c++) {
        const double score = loo_score(live, d, DEEP_FITS[c], errors, arg);
        if (score < least) {
            least = score;
            best = DEEP_FITS[c];
        }
    }
    return best;
}

/* The errors of node k's terms of class `class`. */
static void term_errors(fm_sky_live *live, const deep_domain *d, int k, const double *h, int class, double *score)
{
    (void)live;
    for (int p = 0; p < d->rows; p++)
        for (int m = 0; m < d->cols; m++) {
            if (term_class(p, m) != class)
                continue;
            double z = -*coef_at(d, d->coef, k, p, m);
            for (int j = 0; j < d->n; j++)
                z += h[j] * *coef_at(d, d->coef, j, p, m);
            *score += z * z;
        }
}

/* Whether every value of the domain is positive at every node. */
static int domain_lit(fm_sky_live *live, const deep_domain *d)
{
    int lit = 1;
    for (int k = 0; k < d->n; k++)
        for (int r = 0; r < d->rows; r++)
            for (int c = 0; c < d->cols; c++)
                lit &= ms_value(live, d, k, r, c)[d->lum] > 0.0f;
    return lit;
}

/* Scales every channel of deep node k's value (r, c) so that its luminance's logarithm becomes l. */
static void set_log_luminance(fm_sky_live *live, const deep_domain *d, int k, int r, int c, double l)
{
    float *px = ms_value(live, d, k, r, c);
    const float ratio = (float)(exp(l) / px[d->lum]);
    for (int ch = 0; ch < d->C; ch++)
        px[ch] *= ratio;
}

/* The cosine series of every node's ln(v[ch] / v[over]) (over -1: ln v[ch]) into d->coef; `scratch`
 * rows cols doubles. */
static void domain_terms(fm_sky_live *live, deep_domain *d, int ch, int over, double *scratch)
{
    for (int k = 0; k < d->n; k++) {
        double *c = coef_at(d, d->coef, k, 0, 0);
        for (int r = 0; r < d->rows; r++)
            for (int col = 0; col < d->cols; col++) {
                const float *px = ms_value(live, d, k, r, col);
                scratch[r * d->cols + col] = log(px[ch]) - (over >= 0 ? log(px[over]) : 0.0);
            }
        for (int r = 0; r < d->rows; r++) /* over the columns, then over the rows */
            cosine_series(&scratch[r * d->cols], d->cols, 1, &c[r * d->cols]);
        for (int m = 0; m < d->cols; m++) {
            for (int r = 0; r < d->rows; r++)
                scratch[r * d->cols + m] = c[r * d->cols + m];
            cosine_series(&scratch[m], d->rows, d->cols, &c[m]);
        }
    }
}

/* Deep node k's terms of d->coef, those of the classes from `from` up each smoothed by its class's
 * fit, the others its own; back over the view directions into out (rows cols doubles). */
static void smoothed_node(fm_sky_live *live, const deep_domain *d, const deep_fit *fits, int from, int k, double *out)
{
    double h[64], l[64];
    for (int p = 0; p < d->rows; p++)
        for (int m = 0; m < d->cols; m++) {
            const int class = term_class(p, m);
            double z = 0.0;
            if (class < from || !deep_weights(live, d->at, d->n, k, -1, fits[class], above_in_fit(live, d, k, class), h))
                z = *coef_at(d, d->coef, k, p, m);
            else
                for (int j = 0; j < d->n; j++)
                    z += h[j] * *coef_at(d, d->coef, j, p, m);
            out[p * d->cols + m] = z;
        }
    for (int m = 0; m < d->cols; m++) { /* back over the rows, then over the columns */
        cosine_sum(&out[m], d->rows, d->cols, l);
        for (int r = 0; r < d->rows; r++)
            out[r * d->cols + m] = l[r];
    }
    for (int r = 0; r < d->rows; r++) {
        cosine_sum(&out[r * d->cols], d->cols, 1, l);
        memcpy(&out[r * d->cols], l, sizeof(double) * (size_t)d->cols);
    }
}

/* Whether every channel of every value of the domain is positive at every node. */
static int domain_coloured(fm_sky_live *live, const deep_domain *d)
{
    int lit = d->C == 3;
    for (int k = 0; k < d->n && lit; k++)
        for (int v = 0; v < d->rows * d->cols; v++)
            for (int ch = 0; ch < d->C; ch++)
                lit &= ms_value(live, d, k, v / d->cols, v % d->cols)[ch] > 0.0f;
    return lit;
}

/* A lit domain: per node the cosine series of ln Y, its first-order terms and the rest smoothed
 * across the nodes by their classes' fits, its level (the mean of ln Y over the domain, the least
 * noisy term) its own: the level falls by decades and bends, and a quadratic across the nodes put
 * -8, -10 and -15 percents off.  A mean of logarithms of noisy values lies half their relative
 * variance below the logarithm of their mean, so each node's logarithms are raised by half the mean
 * square of what the smoothing took off them.  The colour, ln X/Y and ln Z/Y, has its rest smoothed
 * by the rest's fit, its level and first-order terms each node's own
 * (docs/decisions/2026-12-07-live-smooth-bias.md).  work: 2 n rows cols doubles. */
static void smooth_lit_domain(fm_sky_live *live, deep_domain *d, double *work)
{
    const size_t per_node = (size_t)d->rows * (size_t)d->cols;
    double *smoothed = work + (size_t)d->n * per_node;
    d->coef = work;
    domain_terms(live, d, d->lum, -1, smoothed);
    deep_fit fits[DEEP_CLASSES];
    for (int class = 1; class < DEEP_CLASSES; class++)
        fits[class] = least_score_fit(live, d, term_errors, class);
    const int coloured = domain_coloured(live, d);
    for (int ch = 0; ch < d->C && coloured; ch++) {
        if (ch == d->lum)
            continue;
        domain_terms(live, d, ch, d->lum, smoothed);
        for (int k = 0; k < d->n; k++) {
            if (!twilight_deep(live->nodes[d->at[k]].sun_elevation_deg))
                continue;
            smoothed_node(live, d, fits, DEEP_REST, k, smoothed);
            for (size_t v = 0; v < per_node; v++) {
                float *px = ms_value(live, d, k, (int)(v / d->cols), (int)(v % d->cols));
                px[ch] = (float)exp(smoothed[v]) * px[d->lum];
            }
        }
    }
    domain_terms(live, d, d->lum, -1, smoothed);
    for (int k = 0; k < d->n; k++) {
        if (!twilight_deep(live->nodes[d->at[k]].sun_elevation_deg))
            continue;
        smoothed_node(live, d, fits, 1, k, smoothed);
        double taken = 0.0;
        for (size_t v = 0; v < per_node; v++) {
            const double z = smoothed[v] - log(ms_value(live, d, k, (int)(v / d->cols), (int)(v % d->cols))[d->lum]);
            taken += z * z / (double)per_node;
        }
        for (size_t v = 0; v < per_node; v++)
            set_log_luminance(live, d, k, (int)(v / d->cols), (int)(v % d->cols), smoothed[v] + 0.5 * taken);
    }
}

/* Whether value (r, c) of the domain is positive at every node. */
static int value_lit(fm_sky_live *live, const deep_domain *d, int r, int c)
{
    int lit = 1;
    for (int j = 0; j < d->n; j++)
        lit &= ms_value(live, d, j, r, c)[d->lum] > 0.0f;
    return lit;
}

/* The logarithm of the luminance of value (r, c) at node k from the nodes' weights h. */
static double weighted_log(fm_sky_live *live, const deep_domain *d, int r, int c, const double *h)
{
    double z = 0.0;
    for (int j = 0; j < d->n; j++)
        z += h[j] * log(ms_value(live, d, j, r, c)[d->lum]);
    return z;
}

/* The errors of node k's values lit at every node, each on its own. */
static void value_errors(fm_sky_live *live, const deep_domain *d, int k, const double *h, int unused, double *score)
{
    (void)unused;
    for (int r = 0; r < d->rows; r++)
        for (int c = 0; c < d->cols; c++)
            if (value_lit(live, d, r, c)) {
                const double z = weighted_log(live, d, r, c, h) - log(ms_value(live, d, k, r, c)[d->lum]);
                *score += z * z;
            }
}

/* A domain not lit at every node: each value lit at every node smoothed on its own, by the fit whose
 * leave-one-out score over those values is least; the others stay as they are. */
static void smooth_unlit_domain(fm_sky_live *live, const deep_domain *d)
{
    const deep_fit fit = least_score_fit(live, d, value_errors, -1);
    double h[64], z[64];
    for (int r = 0; r < d->rows; r++)
        for (int c = 0; c < d->cols; c++) {
            if (!value_lit(live, d, r, c))
                continue;
            for (int k = 0; k < d->n; k++) {
                const int deep = twilight_deep(live->nodes[d->at[k]].sun_elevation_deg);
                z[k] = deep && deep_weights(live, d->at, d->n, k, -1, fit, 1, h) ? weighted_log(live, d, r, c, h) : NAN;
            }
            for (int k = 0; k < d->n; k++) /* after every node: each from the nodes as they were */
                if (!isnan(z[k]))
                    set_log_luminance(live, d, k, r, c, z[k]);
        }
}

fm_status live_smooth_deep_twilight(fm_sky_live *live, const unsigned char *fresh)
{
    int *at = malloc(sizeof(int) * (size_t)live->count), n = 0;
    if (!at)
        return FM_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < live->count; i++)
        if (fresh[i] && (twilight_deep(live->nodes[i].sun_elevation_deg) ||
                         live->nodes[i].sun_elevation_deg <= LIVE_SMOOTH_DEEP_WITH_DEG))
            at[n++] = i;
    if (n < LIVE_SMOOTH_DEEP_MIN || n > 64) {
        free(at);
        return FM_OK;
    }
    const sky_grid *g = &live->nodes[at[0]].ms;
    const int most_rows = g->rows_sky > g->rows_ground ? g->rows_sky : g->rows_ground;
    const size_t work_doubles = 2 * (size_t)n * (size_t)most_rows * (size_t)g->cols;
    double *work = g->cols <= 64 && most_rows <= 64 ? malloc(sizeof(double) * work_doubles) : NULL;
    for (int domain = 0; domain < 2 && work; domain++) {
        deep_domain d = {.at = at,
                         .n = n,
                         .row0 = domain ? g->rows_sky : 0,
                         .rows = domain ? g->rows_ground : g->rows_sky,
                         .cols = g->cols,
                         .C = live->channels,
                         .lum = live->channels == 3 ? 1 : 0 /* CIE Y, or the one value */};
        if (domain_lit(live, &d))
            smooth_lit_domain(live, &d, work);
        else
            smooth_unlit_domain(live, &d);
    }
    const int failed = g->cols <= 64 && most_rows <= 64 && !work;
    free(at);
    free(work);
    return failed ? FM_ERR_OUT_OF_MEMORY : FM_OK;
}
