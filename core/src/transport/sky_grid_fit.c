#include "transport/sky_grid_fit.h"

#include "base/units.h"

#include <math.h>
#include <stdlib.h>

#define FIT_MAX 64        /* rows per domain, columns */
#define FIT_MAX_DEGREE 14 /* highest Chebyshev degree tried (and at most rows - 2) */

/* One domain's data and scratch space. */
typedef struct fit_work {
    int rows, cols;
    double cs[FIT_MAX][FIT_MAX]; /* cos(m phi_j) */
    double t[FIT_MAX];           /* trapezoid weights of the columns */
    double norm[FIT_MAX];        /* sum_j t_j cos^2(m phi_j) */
    double a[FIT_MAX][FIT_MAX];  /* [row][m]: the luminance's cosine coefficients */
    double s[FIT_MAX][FIT_MAX];  /* [row][m]: their variances */
    double omega[FIT_MAX];       /* row weights */
    double hat[2][FIT_MAX][FIT_MAX]; /* [pole factor][row][row] of the current degree */
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

/* The weighted least-squares hat matrix H = U (U^T W U)^-1 U^T W over the rows for degree D into
 * w->hat[azimuthal]; 0 if U^T W U is not positive definite. */
static int build_hat(fit_work *w, int D, int azimuthal)
{
    const int R = w->rows, P = D + 1;
    double U[FIT_MAX][FIT_MAX_DEGREE + 1], L[FIT_MAX_DEGREE + 1][FIT_MAX_DEGREE + 1] = {{0}};
    for (int r = 0; r < R; r++)
        for (int p = 0; p < P; p++)
            U[r][p] = row_basis(p, azimuthal, (double)r / (R - 1));
    for (int i = 0; i < P; i++) /* Cholesky of U^T W U */
        for (int j = 0; j <= i; j++) {
            double sum = 0.0;
            for (int r = 0; r < R; r++)
                sum += w->omega[r] * U[r][i] * U[r][j];
            for (int k = 0; k < j; k++)
                sum -= L[i][k] * L[j][k];
            if (i == j) {
                if (!(sum > 0.0))
                    return 0;
                L[i][i] = sqrt(sum);
            } else {
                L[i][j] = sum / L[j][j];
            }
        }
    double Z[FIT_MAX_DEGREE + 1][FIT_MAX]; /* L^-1 U^T */
    for (int r = 0; r < R; r++)
        for (int i = 0; i < P; i++) {
            double sum = U[r][i];
            for (int k = 0; k < i; k++)
                sum -= L[i][k] * Z[k][r];
            Z[i][r] = sum / L[i][i];
        }
    for (int r = 0; r < R; r++)
        for (int q = 0; q < R; q++) {
            double sum = 0.0;
            for (int i = 0; i < P; i++)
                sum += Z[i][r] * Z[i][q];
            w->hat[azimuthal][r][q] = sum * w->omega[q];
        }
    return 1;
}

/* SURE of cosine m smoothed by the current hat: norm_m sum_r omega_r ((fit - a)^2 - s + 2 H_rr s),
 * the expected weighted squared error against the truth, bias and noise together. */
static double risk_smoothed(const fit_work *w, int m)
{
    const double(*H)[FIT_MAX] = w->hat[m > 0];
    double risk = 0.0;
    for (int r = 0; r < w->rows; r++) {
        double fit = 0.0;
        for (int q = 0; q < w->rows; q++)
            fit += H[r][q] * w->a[q][m];
        double e = fit - w->a[r][m];
        risk += w->omega[r] * (e * e - w->s[r][m] + 2.0 * H[r][r] * w->s[r][m]);
    }
    return w->norm[m] * risk;
}

/* Chooses M and D for the domain of w (a and s filled) by the least SURE; M = -1 keeps the raw
 * nodes (their risk: their variance). */
static void choose(fit_work *w, sky_grid_fit_choice *ch)
{
    const int R = w->rows, C = w->cols;
    double drop[FIT_MAX]; /* SURE of leaving cosine m out: norm_m sum_r omega_r (a^2 - s) */
    ch->azimuth_modes = ch->degree = -1;
    ch->risk_raw = 0.0;
    for (int m = 0; m < C; m++) {
        drop[m] = 0.0;
        for (int r = 0; r < R; r++) {
            drop[m] += w->omega[r] * (w->a[r][m] * w->a[r][m] - w->s[r][m]);
            ch->risk_raw += w->norm[m] * w->omega[r] * w->s[r][m];
        }
        drop[m] *= w->norm[m];
    }
    ch->risk_fit = ch->risk_raw;
    const int max_degree = R - 2 < FIT_MAX_DEGREE ? R - 2 : FIT_MAX_DEGREE;
    for (int D = 0; D <= max_degree; D++) {
        if (!build_hat(w, D, 0) || !build_hat(w, D, 1))
            continue;
        double risk = 0.0;
        for (int m = 0; m < C; m++)
            risk += drop[m];
        for (int M = 0; M < C; M++) { /* cosines 0..M smoothed, the rest left out */
            risk += risk_smoothed(w, M) - drop[M];
            if (risk < ch->risk_fit) {
                ch->risk_fit = risk;
                ch->azimuth_modes = M;
                ch->degree = D;
            }
        }
    }
}

/* Cosine coefficients of one row of values (stride apart) into out[m], m < C. */
static void row_cosines(const fit_work *w, const float *v, int stride, double *out)
{
    for (int m = 0; m < w->cols; m++) {
        double sum = 0.0;
        for (int j = 0; j < w->cols; j++)
            sum += w->t[j] * w->cs[m][j] * v[j * stride];
        out[m] = sum / w->norm[m];
    }
}

/* The rows are weighted by their mean level, so a node far below its row's mean gets the row's
 * absolute error, a large relative one.  Deep twilight has such rows (sun -14 and -18: the fitted
 * luminance away from the sun 0.1 of the row's mean or less, down to negative values, against 0.75
 * by day, 0.38 at -4 and 0.23 at -10); there the raw nodes stay.  True if every fitted node of the
 * luminance is at least ROW_RANGE of its row's fitted mean. */
#define ROW_RANGE 0.15

static int within_row_range(const fit_work *w, int M)
{
    for (int r = 0; r < w->rows; r++) {
        double fit[FIT_MAX], v[FIT_MAX], mean = 0.0, lowest = INFINITY;
        for (int m = 0; m <= M; m++) {
            fit[m] = 0.0;
            for (int q = 0; q < w->rows; q++)
                fit[m] += w->hat[m > 0][r][q] * w->a[q][m];
        }
        for (int j = 0; j < w->cols; j++) {
            v[j] = 0.0;
            for (int m = 0; m <= M; m++)
                v[j] += fit[m] * w->cs[m][j];
            mean += w->t[j] * v[j] / w->norm[0];
            lowest = fmin(lowest, v[j]);
        }
        if (!(lowest >= ROW_RANGE * mean))
            return 0;
    }
    return 1;
}

static void fit_domain(fit_work *w, sky_grid *g, int first_row, const double *y, const double *var,
                       sky_grid_fit_choice *ch)
{
    const int R = w->rows, C = w->cols, K = g->channels;
    double a0_max = 0.0;
    int finite = 1;
    for (int r = 0; r < R; r++)
        for (int m = 0; m < C; m++) {
            double sum = 0.0, sum_s = 0.0;
            for (int j = 0; j < C; j++) {
                int i = (first_row + r) * C + j;
                double c = w->t[j] * w->cs[m][j] / w->norm[m];
                sum += c * y[i];
                sum_s += c * c * var[i];
                finite &= isfinite(y[i]) && isfinite(var[i]);
            }
            w->a[r][m] = sum;
            w->s[r][m] = sum_s;
            if (m == 0)
                a0_max = fmax(a0_max, fabs(sum));
        }
    *ch = (sky_grid_fit_choice){-1, -1, 0.0, 0.0};
    if (!finite || !(a0_max > 0.0))
        return; /* no light (the ground seen from the ground) or no usable estimate */
    for (int r = 0; r < R; r++) {
        double level = fmax(fabs(w->a[r][0]), 1e-3 * a0_max); /* relative error, bounded weights */
        w->omega[r] = 1.0 / (level * level);
    }
    choose(w, ch);
    if (ch->azimuth_modes < 0 || !build_hat(w, ch->degree, 0) || !build_hat(w, ch->degree, 1) ||
        !within_row_range(w, ch->azimuth_modes)) {
        *ch = (sky_grid_fit_choice){-1, -1, ch->risk_raw, ch->risk_raw};
        return;
    }
    const int M = ch->azimuth_modes;
    for (int k = 0; k < K; k++) {
        double coef[FIT_MAX][FIT_MAX];
        for (int r = 0; r < R; r++)
            row_cosines(w, &g->values[(size_t)(first_row + r) * C * K + k], K, coef[r]);
        for (int r = 0; r < R; r++)
            for (int j = 0; j < C; j++) {
                double v = 0.0;
                for (int m = 0; m <= M; m++) {
                    double fit = 0.0;
                    for (int q = 0; q < R; q++)
                        fit += w->hat[m > 0][r][q] * coef[q][m];
                    v += fit * w->cs[m][j];
                }
                g->values[((size_t)(first_row + r) * C + j) * K + k] = (float)fmax(0.0, v);
            }
    }
}

fm_status sky_grid_fit(sky_grid *g, const double *y, const double *var_y, sky_grid_fit_choice choice[2])
{
    const int C = g->cols;
    sky_grid_fit_choice own[2];
    sky_grid_fit_choice *ch = choice ? choice : own;
    ch[0] = ch[1] = (sky_grid_fit_choice){-1, -1, 0.0, 0.0};
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
    fit_domain(w, g, 0, y, var_y, &ch[0]);
    w->rows = g->rows_ground;
    fit_domain(w, g, g->rows_sky, y, var_y, &ch[1]);
    free(w);
    return FM_OK;
}
