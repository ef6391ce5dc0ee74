#include "transport/sky_grid_fit.h"

#include "base/units.h"
#include "base/vec.h"

#include <math.h>
#include <stdlib.h>

#define FIT_MAX 64        /* rows per domain, columns */
#define FIT_MAX_DEGREE 14 /* highest Chebyshev degree tried (and at most rows - 2) */
#define AUREOLE_TERMS 3
#define SMALL (FIT_MAX_DEGREE + 1) /* the largest normal equations solved */

/* exp(-gamma / width), gamma the angle from the sun: the multiple-scattering aureole of coarse
 * aerosols (desert dust at sun 30: 5 times its row's mean at the sun, half that one column away) */
static const double aureole_width_deg[AUREOLE_TERMS] = {3.0, 8.0, 20.0};

/* Rows whose fitted luminance falls below this share of their mean somewhere keep their nodes. */
#define ROW_RANGE 0.15

typedef double node_array[FIT_MAX][FIT_MAX]; /* [row][column] of one domain */

/* One domain's data and scratch space. */
typedef struct fit_work {
    int rows, cols;
    double cs[FIT_MAX][FIT_MAX]; /* cos(m phi_j) */
    double t[FIT_MAX];           /* trapezoid weights of the columns */
    double norm[FIT_MAX];        /* sum_j t_j cos^2(m phi_j) */
    double omega[FIT_MAX];       /* row weights */
    node_array y, var, weight;   /* luminance, its variance, omega_r t_j */
    node_array aureole[AUREOLE_TERMS];
    double hat[2][FIT_MAX][FIT_MAX]; /* [azimuthal][row][row] of the current degree */
    node_array smooth, residual[AUREOLE_TERMS], fit, in; /* scratch */
} fit_work;

/* T_d(2u - 1), times 1 - u for the azimuthal terms (they vanish at the pole, u = 1). */
static double row_basis(int d, int azimuthal, double u)
{
    double x = 2.0 * u - 1.0, t0 = 1.0, t1 = x, t = d == 0 ? 1.0 : x;
    for (int k = 2; k <= d; k++) {
        t = 2.0 * x * t1 - t0;
        t0 = t1;
        t1 = t;
    }
    return azimuthal ? t * (1.0 - u) : t;
}

/* In-place Cholesky factor (lower triangle) of the n x n matrix a; 0 if not positive definite. */
static int cholesky(int n, double a[SMALL][SMALL])
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            double sum = a[i][j];
            for (int k = 0; k < j; k++)
                sum -= a[i][k] * a[j][k];
            if (i == j) {
                if (!(sum > 0.0))
                    return 0;
                a[i][i] = sqrt(sum);
            } else {
                a[i][j] = sum / a[j][j];
            }
        }
    return 1;
}

/* z = L^-1 b for the factor L of cholesky. */
static void forward_solve(int n, double L[SMALL][SMALL], const double *b, double *z)
{
    for (int i = 0; i < n; i++) {
        double sum = b[i];
        for (int k = 0; k < i; k++)
            sum -= L[i][k] * z[k];
        z[i] = sum / L[i][i];
    }
}

/* x = L^-T z for the factor L of cholesky. */
static void back_solve(int n, double L[SMALL][SMALL], const double *z, double *x)
{
    for (int i = n - 1; i >= 0; i--) {
        double sum = z[i];
        for (int k = i + 1; k < n; k++)
            sum -= L[k][i] * x[k];
        x[i] = sum / L[i][i];
    }
}

/* The trapezoid-rule mean of one row of node values over the relative azimuth. */
static double row_mean(const fit_work *w, const double *row)
{
    double sum = 0.0;
    for (int j = 0; j < w->cols; j++)
        sum += w->t[j] * row[j];
    return sum / w->norm[0];
}

/* The weighted least-squares hat matrix H = U (U^T W U)^-1 U^T W over the rows for degree D into
 * w->hat[azimuthal]; 0 if U^T W U is not positive definite. */
static int build_hat(fit_work *w, int D, int azimuthal)
{
    const int R = w->rows, P = D + 1;
    double U[FIT_MAX][SMALL], L[SMALL][SMALL], Z[FIT_MAX][SMALL]; /* Z row r: L^-1 u_r */
    for (int r = 0; r < R; r++)
        for (int p = 0; p < P; p++)
            U[r][p] = row_basis(p, azimuthal, (double)r / (R - 1));
    for (int i = 0; i < P; i++)
        for (int j = 0; j <= i; j++) {
            L[i][j] = 0.0;
            for (int r = 0; r < R; r++)
                L[i][j] += w->omega[r] * U[r][i] * U[r][j];
        }
    if (!cholesky(P, L))
        return 0;
    for (int r = 0; r < R; r++)
        forward_solve(P, L, U[r], Z[r]);
    for (int r = 0; r < R; r++)
        for (int q = 0; q < R; q++) {
            double sum = 0.0;
            for (int i = 0; i < P; i++)
                sum += Z[r][i] * Z[q][i];
            w->hat[azimuthal][r][q] = sum * w->omega[q];
        }
    return 1;
}

/* out = S in: the separable fit (cosines 0..M, the current degree) of node values in, which is the
 * weighted projection on that basis, row by row a DCT-I, then per cosine the hat over the rows. */
static void project(const fit_work *w, int M, node_array in, node_array out)
{
    const int R = w->rows, C = w->cols;
    double coef[FIT_MAX][FIT_MAX]; /* [row][m] */
    for (int r = 0; r < R; r++)
        for (int m = 0; m <= M; m++) {
            double sum = 0.0;
            for (int j = 0; j < C; j++)
                sum += w->t[j] * w->cs[m][j] * in[r][j];
            coef[r][m] = sum / w->norm[m];
        }
    for (int r = 0; r < R; r++) {
        double fit[FIT_MAX];
        for (int m = 0; m <= M; m++) {
            fit[m] = 0.0;
            for (int q = 0; q < R; q++)
                fit[m] += w->hat[m > 0][r][q] * coef[q][m];
        }
        for (int j = 0; j < C; j++) {
            double v = 0.0;
            for (int m = 0; m <= M; m++)
                v += fit[m] * w->cs[m][j];
            out[r][j] = v;
        }
    }
}

/* w->fit = the weighted least-squares fit of node values `in` on the separable basis (cosines
 * 0..M, the current degree) and `terms` aureole terms: S in + X~ beta, with X~ = X - S X the terms'
 * part the separable basis misses and beta from X~^T W X~ beta = X~^T W in.  With risk, also the
 * fit's SURE for in = w->y: sum_i W_i ((fit_i - y_i)^2 - var_i + 2 h_i var_i), h_i the fit's
 * derivative by y_i.  0 when the terms are not independent of the basis. */
static int fit_nodes(fit_work *w, int M, int terms, node_array in, double *risk)
{
    const int R = w->rows, C = w->cols;
    project(w, M, in, w->smooth);
    double G[SMALL][SMALL], beta[AUREOLE_TERMS] = {0}, z[AUREOLE_TERMS];
    if (terms) {
        for (int k = 0; k < terms; k++) {
            project(w, M, w->aureole[k], w->residual[k]);
            for (int r = 0; r < R; r++)
                for (int j = 0; j < C; j++)
                    w->residual[k][r][j] = w->aureole[k][r][j] - w->residual[k][r][j];
        }
        double b[AUREOLE_TERMS];
        for (int k = 0; k < terms; k++) {
            b[k] = 0.0;
            for (int l = 0; l <= k; l++)
                G[k][l] = 0.0;
            for (int r = 0; r < R; r++)
                for (int j = 0; j < C; j++) {
                    double wx = w->weight[r][j] * w->residual[k][r][j];
                    b[k] += wx * in[r][j];
                    for (int l = 0; l <= k; l++)
                        G[k][l] += wx * w->residual[l][r][j];
                }
        }
        if (!cholesky(terms, G))
            return 0;
        forward_solve(terms, G, b, z);
        back_solve(terms, G, z, beta);
    }
    double sure = 0.0;
    for (int r = 0; r < R; r++)
        for (int j = 0; j < C; j++) {
            double v = w->smooth[r][j];
            for (int k = 0; k < terms; k++)
                v += beta[k] * w->residual[k][r][j];
            w->fit[r][j] = v;
            if (!risk)
                continue;
            double h = 0.0, x[AUREOLE_TERMS], g[AUREOLE_TERMS];
            for (int m = 0; m <= M; m++)
                h += w->hat[m > 0][r][r] * w->t[j] * w->cs[m][j] * w->cs[m][j] / w->norm[m];
            if (terms) {
                for (int k = 0; k < terms; k++)
                    x[k] = w->residual[k][r][j];
                forward_solve(terms, G, x, g);
                for (int k = 0; k < terms; k++)
                    h += w->weight[r][j] * g[k] * g[k];
            }
            double e = v - in[r][j];
            sure += w->weight[r][j] * (e * e - w->var[r][j] + 2.0 * h * w->var[r][j]);
        }
    if (risk)
        *risk = sure;
    return 1;
}

typedef struct model {
    int modes, degree, terms; /* modes -1: the raw nodes */
    double risk;
} model;

/* The model of least SURE among the raw nodes (whose risk is risk_raw) and every separable basis,
 * with and without the aureole terms. */
static model choose(fit_work *w, double risk_raw)
{
    const int R = w->rows, C = w->cols;
    model best = {-1, -1, 0, risk_raw};
    const int max_degree = R - 2 < FIT_MAX_DEGREE ? R - 2 : FIT_MAX_DEGREE;
    for (int D = 0; D <= max_degree; D++) {
        if (!build_hat(w, D, 0) || !build_hat(w, D, 1))
            continue;
        for (int M = 0; M < C; M++)
            for (int terms = 0; terms <= AUREOLE_TERMS; terms += AUREOLE_TERMS) {
                double risk;
                if (fit_nodes(w, M, terms, w->y, &risk) && risk < best.risk)
                    best = (model){M, D, terms, risk};
            }
    }
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

static void fit_domain(fit_work *w, sky_grid *g, int first_row, double sun_elevation, const double *y,
                       const double *var, sky_grid_fit_choice *ch)
{
    const int R = w->rows, C = w->cols, K = g->channels;
    *ch = (sky_grid_fit_choice){-1, -1, 0, 0.0, 0.0};
    const vec3 sun = direction_from_elevation_azimuth(sun_elevation, 0.0); /* relative azimuth 0 */
    double a0_max = 0.0, a0[FIT_MAX];
    for (int r = 0; r < R; r++) {
        for (int j = 0; j < C; j++) {
            int i = (first_row + r) * C + j;
            if (!isfinite(y[i]) || !isfinite(var[i]))
                return; /* no usable estimate */
            w->y[r][j] = y[i];
            w->var[r][j] = var[i];
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
        return; /* no light (the ground seen from the ground) */
    for (int r = 0; r < R; r++) {
        double level = fmax(fabs(a0[r]), 1e-3 * a0_max); /* relative error, bounded weights */
        w->omega[r] = 1.0 / (level * level);
        for (int j = 0; j < C; j++)
            w->weight[r][j] = w->omega[r] * w->t[j];
    }
    for (int r = 0; r < R; r++)
        for (int j = 0; j < C; j++)
            ch->risk_raw += w->weight[r][j] * w->var[r][j];
    ch->risk_fit = ch->risk_raw;
    model best = choose(w, ch->risk_raw);
    if (best.modes < 0 || !build_hat(w, best.degree, 0) || !build_hat(w, best.degree, 1) ||
        !fit_nodes(w, best.modes, best.terms, w->y, NULL))
        return;
    int pass[FIT_MAX];
    if (!rows_within_range(w, pass))
        return;
    *ch = (sky_grid_fit_choice){best.modes, best.degree, best.terms, ch->risk_raw, best.risk};
    for (int k = 0; k < K; k++) {
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C; j++)
                w->in[r][j] = g->values[((size_t)(first_row + r) * C + j) * K + k];
        fit_nodes(w, best.modes, best.terms, w->in, NULL);
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C && pass[r]; j++)
                g->values[((size_t)(first_row + r) * C + j) * K + k] = (float)fmax(0.0, w->fit[r][j]);
    }
}

fm_status sky_grid_fit(sky_grid *g, double sun_elevation, const double *y, const double *var_y,
                       sky_grid_fit_choice choice[2])
{
    const int C = g->cols;
    sky_grid_fit_choice own[2];
    sky_grid_fit_choice *ch = choice ? choice : own;
    ch[0] = ch[1] = (sky_grid_fit_choice){-1, -1, 0, 0.0, 0.0};
    if (C < 2 || C > FIT_MAX || g->rows_sky < 3 || g->rows_sky > FIT_MAX || g->rows_ground < 3 ||
        g->rows_ground > FIT_MAX)
        return FM_OK; /* beyond the fit's arrays: the raw nodes */
    fit_work *w = malloc(sizeof *w);
    if (!w)
        return FM_ERR_OUT_OF_MEMORY;
    w->cols = C;
    for (int j = 0; j < C; j++)
        w->t[j] = j == 0 || j == C - 1 ? 0.5 : 1.0;
    for (int m = 0; m < C; m++) {
        w->norm[m] = 0.0;
        for (int j = 0; j < C; j++) {
            w->cs[m][j] = cos(FM_PI * m * j / (C - 1));
            w->norm[m] += w->t[j] * w->cs[m][j] * w->cs[m][j];
        }
    }
    w->rows = g->rows_sky;
    fit_domain(w, g, 0, sun_elevation, y, var_y, &ch[0]);
    w->rows = g->rows_ground;
    fit_domain(w, g, g->rows_sky, sun_elevation, y, var_y, &ch[1]);
    free(w);
    return FM_OK;
}
