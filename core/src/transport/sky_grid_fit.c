#include "transport/sky_grid_fit.h"

#include "base/cholesky.h"
#include "base/units.h"
#include "base/vec.h"

#include <math.h>
#include <stdlib.h>

#define FIT_MAX 64 /* rows per domain, columns */
#define AUREOLE_TERMS 3
#define LAMBDAS 25      /* roughness penalties tried: 10^-4 .. 10^8 times the mean row weight */
#define BACKFIT_ROUNDS 3 /* rounds of choosing the smoothers around the aureole terms */

/* A cosine's choice: dropped, or smoothed with penalty index >= 0. */
#define DROPPED (-1)

/* exp(-gamma / width), gamma the angle from the sun: the multiple-scattering aureole of coarse
 * aerosols (desert dust at sun 30: 5 times its row's mean at the sun, half that one column away) */
static const double aureole_width_deg[AUREOLE_TERMS] = {3.0, 8.0, 20.0};

/* Rows whose fitted luminance falls below this share of their mean somewhere keep their nodes. */
#define ROW_RANGE 0.15

/* The sky's rows less than this far above the horizon are fitted as a band of their own, across the
 * azimuth only (sky_grid_fit.h). */
#define HORIZON_BAND_DEG 1.5

typedef double node_array[FIT_MAX][FIT_MAX]; /* [row][column] of one domain */
typedef double row_matrix[FIT_MAX][FIT_MAX]; /* [row][row] */

/* One domain's data and scratch space. */
typedef struct fit_work {
    int rows, cols;
    int band; /* the rows are a band below the pole (the horizon's): the cosines need not vanish at the last */
    double cs[FIT_MAX][FIT_MAX]; /* cos(m phi_j) */
    double t[FIT_MAX];           /* trapezoid weights of the columns */
    double norm[FIT_MAX];        /* sum_j t_j cos^2(m phi_j) */
    double omega[FIT_MAX];       /* row weights */
    node_array y, var, weight;   /* luminance, its variance, omega_r t_j */
    double coef_var[FIT_MAX][FIT_MAX]; /* [row][m]: the variance of a row's cosine coefficient */
    node_array aureole[AUREOLE_TERMS];
    row_matrix bank[2][LAMBDAS]; /* the penalised smoothers over the rows: [azimuthal][penalty] */
    int option[FIT_MAX];         /* per cosine: DROPPED or a penalty's index */
    node_array smooth, residual[AUREOLE_TERMS], z[AUREOLE_TERMS], fit, in, scratch; /* scratch */
} fit_work;

/* The trapezoid-rule mean of one row of node values over the relative azimuth. */
static double row_mean(const fit_work *w, const double *row)
{
    double sum = 0.0;
    for (int j = 0; j < w->cols; j++)
        sum += w->t[j] * row[j];
    return sum / w->norm[0];
}

/* The smoother over the rows for one penalty: f = B (B^T Omega B + lambda P)^-1 B^T Omega c, P the
 * sum of squared third differences over the rows (its null space the quadratics, so that a row's
 * curvature toward the horizon is not flattened), B = 1 or, for the azimuthal cosines, 1 - u
 * (they vanish at the pole, u = 1; not in a band of rows below it).  Fewer than 4 rows have no
 * third difference: each row then keeps its own coefficients.  S[r][q] = b_r X[r][q],
 * X = A^-1 diag(b omega).  0 if A is not positive definite. */
static int build_smoother(fit_work *w, int azimuthal, double lambda, row_matrix S)
{
    const int R = w->rows;
    double b[FIT_MAX], x[FIT_MAX], e[FIT_MAX];
    row_matrix A = {{0}};
    for (int r = 0; r < R; r++) {
        b[r] = azimuthal && !w->band ? 1.0 - (double)r / (R - 1) : 1.0;
        A[r][r] = b[r] * b[r] * w->omega[r];
    }
    for (int r = 0; r + 3 < R; r++) { /* (c_r - 3 c_r+1 + 3 c_r+2 - c_r+3)^2 */
        const double d[4] = {-1.0, 3.0, -3.0, 1.0};
        for (int k = 0; k < 4; k++)
            for (int l = 0; l < 4; l++)
                A[r + k][r + l] += lambda * d[k] * d[l];
    }
    if (!cholesky(R, FIT_MAX, &A[0][0]))
        return 0;
    for (int q = 0; q < R; q++) {
        for (int r = 0; r < R; r++)
            e[r] = r == q ? b[q] * w->omega[q] : 0.0;
        cholesky_solve(R, FIT_MAX, &A[0][0], e, x);
        for (int r = 0; r < R; r++)
            S[r][q] = b[r] * x[r];
    }
    return 1;
}

/* Every penalty's smoothers, the penalties scaled by the mean row weight so that their grid does
 * not depend on the radiance's units; 0 if one cannot be built. */
static int build_bank(fit_work *w)
{
    double mean_omega = 0.0;
    for (int r = 0; r < w->rows; r++)
        mean_omega += w->omega[r] / w->rows;
    for (int a = 0; a < 2; a++)
        for (int l = 0; l < LAMBDAS; l++)
            if (!build_smoother(w, a, mean_omega * pow(10.0, -4.0 + 0.5 * l), w->bank[a][l]))
                return 0;
    return 1;
}

/* The row coefficients of each cosine: coef[r][m] = sum_j t_j cos(m phi_j) in[r][j] / norm_m (the
 * weighted projection on the cosines, a DCT-I per row). */
static void cosine_coefficients(const fit_work *w, node_array in, double coef[FIT_MAX][FIT_MAX])
{
    for (int r = 0; r < w->rows; r++)
        for (int m = 0; m < w->cols; m++) {
            double sum = 0.0;
            for (int j = 0; j < w->cols; j++)
                sum += w->t[j] * w->cs[m][j] * in[r][j];
            coef[r][m] = sum / w->norm[m];
        }
}

/* The smoother of cosine m under option o, row-major with stride FIT_MAX; NULL for DROPPED. */
static const double *smoother_of(const fit_work *w, int m, int o)
{
    return o < 0 ? NULL : &w->bank[m > 0][o][0][0];
}

/* out[r][m] = sum_q S_m[r][q] in[q][m] (or S_m[q][r], transposed): each cosine's row coefficients
 * through its chosen smoother, 0 for a dropped cosine. */
static void smooth_coefficients(const fit_work *w, double in[FIT_MAX][FIT_MAX], double out[FIT_MAX][FIT_MAX],
                                int transposed)
{
    const int R = w->rows;
    for (int m = 0; m < w->cols; m++) {
        const double *S = smoother_of(w, m, w->option[m]);
        for (int r = 0; r < R; r++) {
            double v = 0.0;
            if (S)
                for (int q = 0; q < R; q++)
                    v += (transposed ? S[q * FIT_MAX + r] : S[r * FIT_MAX + q]) * in[q][m];
            out[r][m] = v;
        }
    }
}

/* out = S in: each cosine's row coefficients through its chosen smoother, summed back. */
static void smooth_nodes(const fit_work *w, node_array in, node_array out)
{
    const int R = w->rows, C = w->cols;
    double coef[FIT_MAX][FIT_MAX], f[FIT_MAX][FIT_MAX];
    cosine_coefficients(w, in, coef);
    smooth_coefficients(w, coef, f, 0);
    for (int r = 0; r < R; r++)
        for (int j = 0; j < C; j++) {
            double v = 0.0;
            for (int m = 0; m < C; m++)
                v += f[r][m] * w->cs[m][j];
            out[r][j] = v;
        }
}

/* out = S^T in, the transpose of smooth_nodes as a linear map of node arrays. */
static void smooth_nodes_transposed(const fit_work *w, node_array in, node_array out)
{
    const int R = w->rows, C = w->cols;
    double a[FIT_MAX][FIT_MAX], f[FIT_MAX][FIT_MAX];
    for (int r = 0; r < R; r++)
        for (int m = 0; m < C; m++) {
            double sum = 0.0;
            for (int j = 0; j < C; j++)
                sum += w->cs[m][j] * in[r][j];
            a[r][m] = sum;
        }
    smooth_coefficients(w, a, f, 1);
    for (int q = 0; q < R; q++)
        for (int j = 0; j < C; j++) {
            double v = 0.0;
            for (int m = 0; m < C; m++)
                v += w->t[j] * w->cs[m][j] / w->norm[m] * f[q][m];
            out[q][j] = v;
        }
}

/* The diagonal element of S for node (r, j). */
static double smooth_diagonal(const fit_work *w, int r, int j)
{
    double h = 0.0;
    for (int m = 0; m < w->cols; m++) {
        const double *S = smoother_of(w, m, w->option[m]);
        double s = S ? S[r * FIT_MAX + r] : 0.0;
        h += s * w->t[j] * w->cs[m][j] * w->cs[m][j] / w->norm[m];
    }
    return h;
}

/* Chooses the cosines kept, 0 .. M, and for each its penalty, of least SURE for the node values
 * `target` with the nodes' variances.  The cosines are orthogonal under the columns' weights, so
 * the risk is a sum over them: for a kept cosine sum_r omega_r norm_m ((f_r - c_r)^2 - v_r +
 * 2 S_rr v_r), for a dropped one sum_r omega_r norm_m (c_r^2 - v_r).  (A free choice of which
 * cosines to keep fits the noise of some high ones by chance.)  Returns the summed risk. */
static double choose_smoothers(fit_work *w, node_array target)
{
    const int R = w->rows, C = w->cols;
    double coef[FIT_MAX][FIT_MAX], kept[FIT_MAX], dropped[FIT_MAX];
    int best_of[FIT_MAX];
    cosine_coefficients(w, target, coef);
    for (int m = 0; m < C; m++) {
        dropped[m] = 0.0;
        for (int r = 0; r < R; r++)
            dropped[m] += w->omega[r] * w->norm[m] * (coef[r][m] * coef[r][m] - w->coef_var[r][m]);
        kept[m] = INFINITY;
        best_of[m] = 0;
        for (int l = 0; l < LAMBDAS; l++) {
            const double *S = smoother_of(w, m, l);
            double risk = 0.0;
            for (int r = 0; r < R; r++) {
                double f = 0.0;
                for (int q = 0; q < R; q++)
                    f += S[r * FIT_MAX + q] * coef[q][m];
                double e = f - coef[r][m];
                risk += w->omega[r] * w->norm[m] *
                        (e * e - w->coef_var[r][m] + 2.0 * S[r * FIT_MAX + r] * w->coef_var[r][m]);
            }
            if (risk < kept[m]) {
                kept[m] = risk;
                best_of[m] = l;
            }
        }
    }
    double best = INFINITY;
    int best_M = 0;
    for (int M = 0; M < C; M++) {
        double risk = 0.0;
        for (int m = 0; m < C; m++)
            risk += m <= M ? kept[m] : dropped[m];
        if (risk < best) {
            best = risk;
            best_M = M;
        }
    }
    for (int m = 0; m < C; m++)
        w->option[m] = m <= best_M ? best_of[m] : DROPPED;
    return best;
}

/* w->fit = the fit of node values `in`: the smoothers' S in alone, or with `terms` aureole terms X
 * as a partially linear model (Speckman): X~ = (I - S) X, beta from X~^T W X~ beta = X~^T W (I - S)
 * in, fit = S in + X~ beta.  With risk, also the fit's SURE for in = w->y:
 * sum_i W_i ((fit_i - y_i)^2 - var_i + 2 h_i var_i), h_i = S_ii + x~_i^T G^-1 [(I - S)^T W X~]_i.
 * Sets beta_out (if not NULL) to the terms' coefficients.  0 when the terms are not independent
 * of the smoothers. */
static int fit_nodes(fit_work *w, int terms, node_array in, double *risk, double *beta_out)
{
    const int R = w->rows, C = w->cols;
    smooth_nodes(w, in, w->smooth);
    row_matrix G = {{0}};
    double beta[AUREOLE_TERMS] = {0};
    if (terms) {
        for (int k = 0; k < terms; k++) {
            smooth_nodes(w, w->aureole[k], w->residual[k]);
            for (int r = 0; r < R; r++)
                for (int j = 0; j < C; j++)
                    w->residual[k][r][j] = w->aureole[k][r][j] - w->residual[k][r][j];
        }
        double b[AUREOLE_TERMS] = {0};
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C; j++)
                for (int k = 0; k < terms; k++) {
                    double wx = w->weight[r][j] * w->residual[k][r][j];
                    b[k] += wx * (in[r][j] - w->smooth[r][j]);
                    for (int l = 0; l <= k; l++)
                        G[k][l] += wx * w->residual[l][r][j];
                }
        if (!cholesky(terms, FIT_MAX, &G[0][0]))
            return 0;
        cholesky_solve(terms, FIT_MAX, &G[0][0], b, beta);
        if (risk)
            for (int k = 0; k < terms; k++) { /* z_k = (I - S)^T (W x~_k) */
                for (int r = 0; r < R; r++)
                    for (int j = 0; j < C; j++)
                        w->scratch[r][j] = w->weight[r][j] * w->residual[k][r][j];
                smooth_nodes_transposed(w, w->scratch, w->z[k]);
                for (int r = 0; r < R; r++)
                    for (int j = 0; j < C; j++)
                        w->z[k][r][j] = w->scratch[r][j] - w->z[k][r][j];
            }
    }
    if (beta_out)
        for (int k = 0; k < AUREOLE_TERMS; k++)
            beta_out[k] = beta[k];
    double sure = 0.0;
    for (int r = 0; r < R; r++)
        for (int j = 0; j < C; j++) {
            double v = w->smooth[r][j];
            for (int k = 0; k < terms; k++)
                v += beta[k] * w->residual[k][r][j];
            w->fit[r][j] = v;
            if (!risk)
                continue;
            double h = smooth_diagonal(w, r, j);
            if (terms) {
                double zi[AUREOLE_TERMS], g[AUREOLE_TERMS];
                for (int k = 0; k < terms; k++)
                    zi[k] = w->z[k][r][j];
                cholesky_solve(terms, FIT_MAX, &G[0][0], zi, g);
                for (int k = 0; k < terms; k++)
                    h += w->residual[k][r][j] * g[k];
            }
            double e = v - in[r][j];
            sure += w->weight[r][j] * (e * e - w->var[r][j] + 2.0 * h * w->var[r][j]);
        }
    if (risk)
        *risk = sure;
    return 1;
}

typedef struct model {
    int option[FIT_MAX]; /* per cosine */
    int terms;
    double risk;
} model;

static void keep_model(model *best, const fit_work *w, int terms, double risk)
{
    for (int m = 0; m < w->cols; m++)
        best->option[m] = w->option[m];
    best->terms = terms;
    best->risk = risk;
}

/* The model of least SURE: the smoothers chosen cosine by cosine, then with the aureole terms,
 * the smoothers chosen again for the nodes less the terms' part, a few rounds (backfitting).
 * Leaves w->option at the model's. */
static model choose(fit_work *w)
{
    model best;
    keep_model(&best, w, 0, choose_smoothers(w, w->y));
    for (int round = 0; round < BACKFIT_ROUNDS; round++) {
        double beta[AUREOLE_TERMS], risk;
        if (!fit_nodes(w, AUREOLE_TERMS, w->y, NULL, beta))
            break;
        for (int r = 0; r < w->rows; r++)
            for (int j = 0; j < w->cols; j++) {
                double v = w->y[r][j];
                for (int k = 0; k < AUREOLE_TERMS; k++)
                    v -= beta[k] * w->aureole[k][r][j];
                w->in[r][j] = v;
            }
        choose_smoothers(w, w->in);
        if (!fit_nodes(w, AUREOLE_TERMS, w->y, &risk, NULL))
            break;
        if (risk < best.risk)
            keep_model(&best, w, AUREOLE_TERMS, risk);
    }
    for (int m = 0; m < w->cols; m++)
        w->option[m] = best.option[m];
    return best;
}

/* Whether each row's fitted nodes (w->fit) are all at least ROW_RANGE of the row's mean: the rows
 * are weighted by their mean level, so a node far below it would carry the row's absolute error, a
 * large relative one (deep twilight: near the horizon away from the sun 0.1 of the mean or less,
 * down to negative values, against 0.75 by day, 0.38 at -4 and 0.23 at -10).  Returns how many
 * rows pass. */
static int rows_within_range(const fit_work *w, int *pass)
{
    int passing = 0;
    for (int r = 0; r < w->rows; r++) {
        double lowest = INFINITY;
        for (int j = 0; j < w->cols; j++)
            lowest = fmin(lowest, w->fit[r][j]);
        passing += pass[r] = lowest >= ROW_RANGE * row_mean(w, w->fit[r]);
    }
    return passing;
}

/* Chooses the fit of the w->rows rows of g from first_row for the values y (per node, with their
 * variances var; with shape, per node > 0, y divided by it): leaves the model in w->option, the fit
 * of y in w->fit, the rows within range in pass, and returns the choice (azimuth_modes -1: the
 * nodes stay raw). */
static sky_grid_fit_choice choose_domain(fit_work *w, const sky_grid *g, int first_row, double sun_elevation,
                                         const double *y, const double *var, const double *shape, int *pass)
{
    const int R = w->rows, C = w->cols;
    sky_grid_fit_choice ch = {-1, 0, 0.0, 0.0};
    const vec3 sun = direction_from_elevation_azimuth(sun_elevation, 0.0); /* relative azimuth 0 */
    double a0_max = 0.0, a0[FIT_MAX];
    for (int r = 0; r < R; r++) {
        for (int j = 0; j < C; j++) {
            int i = (first_row + r) * C + j;
            if (!isfinite(y[i]) || !isfinite(var[i]))
                return ch; /* no usable estimate */
            double s = shape ? shape[i] : 1.0;
            w->y[r][j] = y[i] / s;
            w->var[r][j] = var[i] / (s * s);
            double e, phi;
            sky_grid_node_angles(g, i, &e, &phi);
            double gamma = acos(clamp_cosine(v3_dot(direction_from_elevation_azimuth(e, phi), sun)));
            for (int k = 0; k < AUREOLE_TERMS; k++)
                w->aureole[k][r][j] = exp(-gamma / (aureole_width_deg[k] * FM_DEG));
        }
        a0[r] = row_mean(w, w->y[r]);
        a0_max = fmax(a0_max, fabs(a0[r]));
    }
    if (!(a0_max > 0.0))
        return ch; /* no light (the ground seen from the ground) */
    for (int r = 0; r < R; r++) {
        double level = fmax(fabs(a0[r]), 1e-3 * a0_max); /* relative error, bounded weights */
        w->omega[r] = 1.0 / (level * level);
        for (int j = 0; j < C; j++)
            w->weight[r][j] = w->omega[r] * w->t[j];
    }
    for (int r = 0; r < R; r++)
        for (int j = 0; j < C; j++)
            ch.risk_raw += w->weight[r][j] * w->var[r][j];
    ch.risk_fit = ch.risk_raw;
    for (int r = 0; r < R; r++) /* the variances of the cosines' row coefficients */
        for (int m = 0; m < C; m++) {
            double v = 0.0;
            for (int j = 0; j < C; j++) {
                double a = w->t[j] * w->cs[m][j] / w->norm[m];
                v += a * a * w->var[r][j];
            }
            w->coef_var[r][m] = v;
        }
    if (!build_bank(w))
        return ch;
    model best = choose(w);
    if (!(best.risk < ch.risk_raw) || !fit_nodes(w, best.terms, w->y, NULL, NULL) || !rows_within_range(w, pass))
        return ch;
    int highest = -1;
    for (int m = 0; m < C; m++)
        if (w->option[m] != DROPPED)
            highest = m;
    return (sky_grid_fit_choice){highest, best.terms, ch.risk_raw, best.risk};
}

/* Fits the w->rows rows of g from first_row; with shape (per node, > 0), the nodes divided by it and
 * the fit multiplied back. */
static void fit_domain(fit_work *w, sky_grid *g, int first_row, double sun_elevation, const double *y,
                       const double *var, const double *shape, sky_grid_fit_choice *ch)
{
    const int R = w->rows, C = w->cols, K = g->channels;
    int pass[FIT_MAX];
    *ch = choose_domain(w, g, first_row, sun_elevation, y, var, shape, pass);
    if (ch->azimuth_modes < 0)
        return;
    for (int k = 0; k < K; k++) {
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C; j++) {
                int i = (first_row + r) * C + j;
                w->in[r][j] = g->values[(size_t)i * K + k] / (shape ? shape[i] : 1.0);
            }
        fit_nodes(w, ch->aureole_terms, w->in, NULL, NULL);
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C && pass[r]; j++) {
                int i = (first_row + r) * C + j;
                g->values[(size_t)i * K + k] = (float)fmax(0.0, w->fit[r][j] * (shape ? shape[i] : 1.0));
            }
    }
}

/* The sky rows less than HORIZON_BAND_DEG above the horizon. */
static int horizon_rows(const sky_grid *g)
{
    int rows = 0;
    for (int r = 0; r < g->rows_sky; r++) {
        double e, phi;
        sky_grid_node_angles(g, r * g->cols, &e, &phi);
        if (e - g->horizon_elevation < HORIZON_BAND_DEG * FM_DEG)
            rows = r + 1;
    }
    return rows;
}

/* The first sky row above the horizon's band (horizon_rows), or -1 when a node's shape is not
 * positive. */
static int first_shaped_row(const sky_grid *g, const double *shape)
{
    for (int i = 0; i < g->rows_sky * g->cols; i++)
        if (!(shape[i] > 0.0 && isfinite(shape[i])))
            return -1;
    return horizon_rows(g);
}

/* The columns' cosines and trapezoid weights; NULL when out of memory. */
static fit_work *fit_work_new(int C)
{
    fit_work *w = malloc(sizeof *w);
    if (!w)
        return NULL;
    w->cols = C;
    w->band = 0;
    for (int j = 0; j < C; j++)
        w->t[j] = j == 0 || j == C - 1 ? 0.5 : 1.0;
    for (int m = 0; m < C; m++) {
        w->norm[m] = 0.0;
        for (int j = 0; j < C; j++) {
            w->cs[m][j] = cos(FM_PI * m * j / (C - 1));
            w->norm[m] += w->t[j] * w->cs[m][j] * w->cs[m][j];
        }
    }
    return w;
}

/* Whether the grid fits the fit's arrays. */
static int fits_arrays(const sky_grid *g)
{
    return g->cols >= 2 && g->cols <= FIT_MAX && g->rows_sky >= 3 && g->rows_sky <= FIT_MAX && g->rows_ground >= 3 &&
           g->rows_ground <= FIT_MAX;
}

fm_status sky_grid_fit(sky_grid *g, double sun_elevation, const double *y, const double *var_y,
                       const double *shape, sky_grid_fit_choice choice[2])
{
    const int C = g->cols;
    sky_grid_fit_choice own[2];
    sky_grid_fit_choice *ch = choice ? choice : own;
    ch[0] = ch[1] = (sky_grid_fit_choice){-1, 0, 0.0, 0.0};
    if (!fits_arrays(g))
        return FM_OK; /* beyond the fit's arrays: the raw nodes */
    fit_work *w = fit_work_new(C);
    if (!w)
        return FM_ERR_OUT_OF_MEMORY;
    const int R = g->rows_sky, first = shape ? first_shaped_row(g, shape) : -1;
    if (first > 0 && R - first >= 3) {
        /* the horizon's band on its own, then the rows above it, both through the shape */
        sky_grid_fit_choice band;
        w->band = 1;
        w->rows = first;
        fit_domain(w, g, 0, sun_elevation, y, var_y, shape, &band);
        w->band = 0;
        w->rows = R - first;
        fit_domain(w, g, first, sun_elevation, y, var_y, shape, &ch[0]);
    } else {
        w->rows = R;
        fit_domain(w, g, 0, sun_elevation, y, var_y, first == 0 ? shape : NULL, &ch[0]);
    }
    w->rows = g->rows_ground;
    fit_domain(w, g, g->rows_sky, sun_elevation, y, var_y, NULL, &ch[1]);
    free(w);
    return FM_OK;
}

/* The chromatic ratio c (0: X / Y, 1: Z / Y) of the rows [first_row, first_row + w->rows): Y times
 * its fit, where one is chosen. */
static void fit_ratio(fit_work *w, sky_grid *g, int first_row, double sun_elevation, const double *ratio,
                      const double *ratio_var, int c)
{
    int pass[FIT_MAX];
    if (choose_domain(w, g, first_row, sun_elevation, ratio, ratio_var, NULL, pass).azimuth_modes < 0)
        return;
    for (int r = 0; r < w->rows; r++)
        for (int j = 0; j < w->cols && pass[r]; j++) {
            float *v = &g->values[(size_t)((first_row + r) * w->cols + j) * 3];
            v[2 * c] = (float)fmax(0.0, w->fit[r][j] * v[1]);
        }
}

fm_status sky_grid_fit_chroma(sky_grid *g, double sun_elevation, const double *const ratio[2],
                              const double *const ratio_var[2])
{
    if (g->channels != 3 || !fits_arrays(g))
        return FM_OK;
    fit_work *w = fit_work_new(g->cols);
    if (!w)
        return FM_ERR_OUT_OF_MEMORY;
    const int horizon = horizon_rows(g);
    for (int c = 0; c < 2; c++) {
        /* the horizon's band on its own (it alone holds the sharp change of colour at the horizon,
         * which fitted through the rows above biased them), the sky above it, the ground */
        w->band = 1;
        w->rows = horizon;
        if (horizon > 0)
            fit_ratio(w, g, 0, sun_elevation, ratio[c], ratio_var[c], c);
        w->band = 0;
        w->rows = g->rows_sky - horizon;
        if (w->rows >= 3)
            fit_ratio(w, g, horizon, sun_elevation, ratio[c], ratio_var[c], c);
        w->rows = g->rows_ground;
        fit_ratio(w, g, g->rows_sky, sun_elevation, ratio[c], ratio_var[c], c);
    }
    free(w);
    return FM_OK;
}
