/* Adding-doubling for a plane-parallel column (see the header).
 *
 * Conventions (Hansen & Travis 1974).  A kernel K(mu, mu') of one Fourier mode maps incident to
 * outgoing radiance by L_out(mu) = 2 int_0^1 K(mu, mu') L_in(mu') mu' dmu'; on the discrete points that
 * integral is sum_j K[i][j] w[j], w = 2 mu c (c: Gauss weights on [0, 1]; 0 for the view and sun
 * points).  Rows run over every point (N Gauss nodes, the views, the sun last); columns over the
 * directions of incidence the beam's light can have (the N Gauss nodes, then the sun).  E = exp(-tau
 * / mu) is the direct transmission; E on the right scales the incident direction's column, on the
 * left the outgoing row.  Doubling two identical layers (R from above equals R from below):
 *   Q = R w R,  S = Q (1 - w Q)^-1,  D = T + S E + S w T,  U = R E + R w D,
 *   R' = R + E U + T w U,  T' = E D + T E + T w D,  E' = E^2.
 * Adding a homogeneous layer k under a column C (R*: C's reflection of light from below; only the
 * beam's diffuse transmission t = T_C[., sun] and R* are carried down):
 *   d = t + e_sun R* w R_k[., sun] + R* w R_k w d   (the downward light between them),
 *   t' = E_k d + T_k w d + T_k[., sun] e_sun,
 *   Q = R_k w R*,  S = Q (1 - w Q)^-1,  U = T_k + S E_k + S w T_k,  D = R* E_k + R* w U,
 *   R*' = R_k + E_k D + T_k w D,  E' = E_C E_k. */
#include "transport/plane_column.h"

#include "base/quadrature.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PC_PI 3.14159265358979323846
/* Doubling starts from single scattering in a sliver this thin: the second order it leaves out is
 * about tau_start times the layer's optical depth. */
#define PLANE_COLUMN_TAU_START 1e-6
#define MAX_STREAMS 32
#define MAX_VIEWS 512
#define MAX_POINTS (MAX_STREAMS + MAX_VIEWS + 1)

typedef struct work {
    int n, nq, nc, sun;              /* rows, Gauss nodes, columns; the sun's row */
    int fields;                      /* the diffuse fields carried at once (1 but for the response) */
    double *xs, *w;                  /* [n]: the rows' cosines and weights (0 past the Gauss nodes) */
    double *lam;                     /* [n][M]: normalised associated Legendre functions of the mode */
    double *pt, *pr;                 /* [n][nc]: the mode's phase kernels, transmission and reflection */
    double *r, *t, *e;               /* the layer: R, T [n][nc], E [n] */
    double *rs, *tc, *ec;            /* the column above: R* [n][nc], t [fields][n], E [n] */
    double *q, *s, *d, *u, *v;       /* scratch [n][nc] */
    double *a;                       /* [2][nc][nc] */
} work;

/* The column index's row: the Gauss nodes, then the sun. */
static inline int col_row(const work *W, int j)
{
    return j < W->nq ? j : W->sun;
}

/* Normalised associated Legendre functions sqrt((l-m)!/(l+m)!) P_l^m(x), l = m..lmax (index l). */
static void assoc_legendre(int m, int lmax, double x, double *lam)
{
    double s = sqrt(fmax(0.0, 1.0 - x * x)), v = 1.0;
    for (int k = 1; k <= m; k++)
        v *= sqrt((2.0 * k - 1.0) / (2.0 * k)) * s;
    lam[m] = v;
    if (m + 1 <= lmax)
        lam[m + 1] = sqrt(2.0 * m + 1.0) * x * v;
    for (int l = m + 1; l < lmax; l++)
        lam[l + 1] = ((2.0 * l + 1.0) * x * lam[l] - sqrt((double)(l * l - m * m)) * lam[l - 1]) /
                     sqrt((double)((l + 1) * (l + 1) - m * m));
}

/* c = a diag(w) b, summing over the Gauss nodes (b's first nq rows); all [n][nc]. */
static void mul_w(const work *W, const double *a, const double *b, double *c)
{
    const int n = W->n, nq = W->nq, nc = W->nc;
    memset(c, 0, sizeof(double) * (size_t)(n * nc));
    for (int i = 0; i < n; i++)
        for (int k = 0; k < nq; k++) {
            double aik = a[i * nc + k] * W->w[k];
            const double *bk = b + k * nc;
            double *ci = c + i * nc;
            for (int j = 0; j < nc; j++)
                ci[j] += aik * bk[j];
        }
}

/* S = Q (1 - w Q)^-1 over the columns: the matrix 1 - w Q is nc x nc (its sun row is the identity's:
 * w is 0 there), inverted once by Gauss-Jordan with partial pivoting, then S = Q times the inverse.
 * s may not alias q. */
static void resolvent(work *W, const double *q, double *s)
{
    const int n = W->n, nq = W->nq, nc = W->nc;
    double *a = W->a, *inv = W->a + nc * nc;
    for (int p = 0; p < nc; p++)
        for (int j = 0; j < nc; j++) {
            a[p * nc + j] = (p == j) - (p < nq ? W->w[p] * q[p * nc + j] : 0.0);
            inv[p * nc + j] = p == j;
        }
    for (int k = 0; k < nc; k++) {
        int p = k;
        for (int i = k + 1; i < nc; i++)
            if (fabs(a[i * nc + k]) > fabs(a[p * nc + k]))
                p = i;
        if (p != k)
            for (int j = 0; j < nc; j++) {
                double t = a[k * nc + j];
                a[k * nc + j] = a[p * nc + j];
                a[p * nc + j] = t;
                t = inv[k * nc + j];
                inv[k * nc + j] = inv[p * nc + j];
                inv[p * nc + j] = t;
            }
        const double d = 1.0 / a[k * nc + k];
        for (int j = 0; j < nc; j++) {
            a[k * nc + j] *= d;
            inv[k * nc + j] *= d;
        }
        for (int i = 0; i < nc; i++) {
            const double f = a[i * nc + k];
            if (i == k || f == 0.0)
                continue;
            for (int j = 0; j < nc; j++) {
                a[i * nc + j] -= f * a[k * nc + j];
                inv[i * nc + j] -= f * inv[k * nc + j];
            }
        }
    }
    memset(s, 0, sizeof(double) * (size_t)(n * nc));
    for (int i = 0; i < n; i++)
        for (int k = 0; k < nc; k++) {
            const double qik = q[i * nc + k];
            const double *row = inv + k * nc;
            double *si = s + i * nc;
            for (int j = 0; j < nc; j++)
                si[j] += qik * row[j];
        }
}

/* The mode's phase kernels for moments chi (terms l = m .. M-1). */
static void phase_kernels(work *W, const double *chi, int m, int M)
{
    for (int i = 0; i < W->n; i++)
        for (int j = 0; j < W->nc; j++) {
            const double *li = W->lam + i * M, *lj = W->lam + col_row(W, j) * M;
            double st = 0.0, sr = 0.0;
            for (int l = m; l < M; l++) {
                double v = (2.0 * l + 1.0) * chi[l] * li[l] * lj[l];
                st += v;
                sr += (l + m) % 2 ? -v : v;
            }
            W->pt[i * W->nc + j] = st;
            W->pr[i * W->nc + j] = sr;
        }
}

/* R, T and E of one homogeneous layer for the current phase kernels. */
static void layer_doubled(work *W, double tau, double ssa)
{
    const int n = W->n, nc = W->nc;
    int k = 0;
    double tau0 = tau;
    while (tau0 > PLANE_COLUMN_TAU_START) {
        tau0 *= 0.5;
        k++;
    }
    double *r = W->r, *t = W->t, *e = W->e, *q = W->q, *s = W->s, *dd = W->d, *u = W->u, *v = W->v;
    for (int i = 0; i < n; i++) {
        e[i] = exp(-tau0 / W->xs[i]);
        for (int j = 0; j < nc; j++) {
            double a = W->xs[i], b = W->xs[col_row(W, j)], d = a - b;
            r[i * nc + j] = 0.25 * ssa * W->pr[i * nc + j] * -expm1(-tau0 * (a + b) / (a * b)) / (a + b);
            double tt = fabs(d) < 1e-14 ? tau0 / (a * b) : expm1(tau0 * d / (a * b)) / d;
            t[i * nc + j] = 0.25 * ssa * W->pt[i * nc + j] * exp(-tau0 / b) * tt;
        }
    }
    for (int it = 0; it < k; it++) {
        mul_w(W, r, r, q);
        resolvent(W, q, s);
        mul_w(W, s, t, dd); /* D = T + S E + S w T */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < nc; j++)
                dd[i * nc + j] += t[i * nc + j] + s[i * nc + j] * e[col_row(W, j)];
        mul_w(W, r, dd, u); /* U = R E + R w D */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < nc; j++)
                u[i * nc + j] += r[i * nc + j] * e[col_row(W, j)];
        mul_w(W, t, u, v); /* R' = R + E U + T w U */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < nc; j++)
                r[i * nc + j] += e[i] * u[i * nc + j] + v[i * nc + j];
        mul_w(W, t, dd, v); /* T' = E D + T E + T w D */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < nc; j++)
                t[i * nc + j] = e[i] * dd[i * nc + j] + t[i * nc + j] * e[col_row(W, j)] + v[i * nc + j];
        for (int i = 0; i < n; i++)
            e[i] *= e[i];
    }
}

/* Solves (1 - B) y = y over the Gauss rows, B[i][k] = Q[i][k] w_k (nq x nq, overwritten in W->a). */
static void solve_gauss(work *W, const double *Q, double *y)
{
    const int nq = W->nq, nc = W->nc;
    double *a = W->a;
    for (int i = 0; i < nq; i++)
        for (int k = 0; k < nq; k++)
            a[i * nq + k] = (i == k) - Q[i * nc + k] * W->w[k];
    for (int k = 0; k < nq; k++) {
        int p = k;
        for (int i = k + 1; i < nq; i++)
            if (fabs(a[i * nq + k]) > fabs(a[p * nq + k]))
                p = i;
        if (p != k) {
            for (int j = 0; j < nq; j++) {
                double tmp = a[k * nq + j];
                a[k * nq + j] = a[p * nq + j];
                a[p * nq + j] = tmp;
            }
            double tmp = y[k];
            y[k] = y[p];
            y[p] = tmp;
        }
        for (int i = k + 1; i < nq; i++) {
            double f = a[i * nq + k] / a[k * nq + k];
            for (int j = k; j < nq; j++)
                a[i * nq + j] -= f * a[k * nq + j];
            y[i] -= f * y[k];
        }
    }
    for (int k = nq - 1; k >= 0; k--) {
        for (int j = k + 1; j < nq; j++)
            y[k] -= a[k * nq + j] * y[j];
        y[k] /= a[k * nq + k];
    }
}

/* The diffuse light at the boundary between the column above (rs, ec) and a reflector rb below it
 * (its reflection from above), q = R* w R_below, of one field whose diffuse transmission is tc:
 * downward d and, unless NULL, upward u (n each). */
static void boundary_light(work *W, const double *q, const double *rb, const double *tc, double *d, double *u)
{
    const int n = W->n, nq = W->nq, nc = W->nc;
    const double e_sun = W->ec[W->sun];
    for (int i = 0; i < nq; i++)
        d[i] = tc[i] + e_sun * q[i * nc + nq];
    solve_gauss(W, q, d);
    for (int i = nq; i < n; i++) {
        double sum = tc[i] + e_sun * q[i * nc + nq];
        for (int k = 0; k < nq; k++)
            sum += q[i * nc + k] * W->w[k] * d[k];
        d[i] = sum;
    }
    for (int i = 0; i < n && u; i++) {
        double sum = rb[i * nc + nq] * e_sun;
        for (int j = 0; j < nq; j++)
            sum += rb[i * nc + j] * W->w[j] * d[j];
        u[i] = sum;
    }
}

/* The light at the boundary (boundary_light) for each field (d and u: [fields][n]). */
static void level_light(work *W, const double *rb, double *d, double *u)
{
    mul_w(W, W->rs, rb, W->q); /* R* w R_below */
    for (int f = 0; f < W->fields; f++)
        boundary_light(W, W->q, rb, W->tc + (size_t)f * W->n, d + (size_t)f * W->n, u ? u + (size_t)f * W->n : NULL);
}

/* Adds the layer in (r, t, e) under the column in (rs, tc, ec). */
static void add_layer(work *W)
{
    const int n = W->n, nq = W->nq, nc = W->nc;
    double *q = W->q, *s = W->s, *uu = W->u, *dd = W->d, *v = W->v;
    const double e_sun = W->ec[W->sun];
    double dp[MAX_POINTS];
    mul_w(W, W->rs, W->r, q); /* R* w R_k */
    for (int f = 0; f < W->fields; f++) {
        double *tc = W->tc + (size_t)f * n;
        boundary_light(W, q, W->r, tc, dp, NULL);
        for (int i = 0; i < n; i++) {
            double sum = W->e[i] * dp[i] + W->t[i * nc + nq] * e_sun;
            for (int j = 0; j < nq; j++)
                sum += W->t[i * nc + j] * W->w[j] * dp[j];
            uu[i] = sum; /* t' (uu is free scratch until the reflection below) */
        }
        memcpy(tc, uu, sizeof(double) * (size_t)n);
    }
    /* the column's reflection of light from below */
    mul_w(W, W->r, W->rs, q); /* Q = R_k w R* */
    resolvent(W, q, s);
    mul_w(W, s, W->t, uu); /* U = T_k + S E_k + S w T_k */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            uu[i * nc + j] += W->t[i * nc + j] + s[i * nc + j] * W->e[col_row(W, j)];
    mul_w(W, W->rs, uu, dd); /* D = R* E_k + R* w U */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            dd[i * nc + j] += W->rs[i * nc + j] * W->e[col_row(W, j)];
    mul_w(W, W->t, dd, v); /* R*' = R_k + E_k D + T_k w D */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            W->rs[i * nc + j] = W->r[i * nc + j] + W->e[i] * dd[i * nc + j] + v[i * nc + j];
    for (int i = 0; i < n; i++)
        W->ec[i] *= W->e[i];
}

/* The layer in (r, t, e) laid over a reflector rb (its reflection from above): rb becomes the pair's. */
static void over_reflector(work *W, double *rb)
{
    const int n = W->n, nc = W->nc;
    double *q = W->q, *s = W->s, *dd = W->d, *u = W->u, *v = W->v;
    mul_w(W, W->r, rb, q); /* Q = R w R_below */
    resolvent(W, q, s);
    mul_w(W, s, W->t, dd); /* D = T + S E + S w T */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            dd[i * nc + j] += W->t[i * nc + j] + s[i * nc + j] * W->e[col_row(W, j)];
    mul_w(W, rb, dd, u); /* U = R_below E + R_below w D */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            u[i * nc + j] += rb[i * nc + j] * W->e[col_row(W, j)];
    mul_w(W, W->t, u, v); /* R' = R + E U + T w U */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < nc; j++)
            rb[i * nc + j] = W->r[i * nc + j] + W->e[i] * u[i * nc + j] + v[i * nc + j];
}

/* The layer's beam cosine in the sun's row and its Legendre functions, doubled, and its sun column
 * put per unit of the column's mu0 F0 (a layer's beam response is per unit of its own mu0 F0). */
static void layer_with_beam(work *W, const plane_column *c, const plane_layer *layer, int m, int M)
{
    const double mu = layer->mu0 > 0.0 ? layer->mu0 : c->mu0;
    if (W->xs[W->sun] != mu) {
        W->xs[W->sun] = mu;
        assoc_legendre(m, M - 1, mu, W->lam + W->sun * M);
    }
    phase_kernels(W, layer->chi, m, M);
    layer_doubled(W, layer->tau, layer->ssa);
    if (mu != c->mu0)
        for (int i = 0; i < W->n; i++) {
            W->r[i * W->nc + W->nq] *= mu / c->mu0;
            W->t[i * W->nc + W->nq] *= mu / c->mu0;
        }
}

static int column_valid(const plane_column *c)
{
    if (!c || c->streams < 2 || c->streams > MAX_STREAMS || c->layer_count < 1 ||
        c->layer_count > PLANE_COLUMN_MAX_LAYERS || !(c->mu0 > 0.0 && c->mu0 <= 1.0) ||
        !(c->ground_albedo >= 0.0 && c->ground_albedo <= 1.0) || c->n_mu < 0 || c->n_mu > MAX_VIEWS || (c->n_mu && !c->mu))
        return 0;
    for (int k = 0; k < c->n_mu; k++)
        if (!(c->mu[k] > 0.0 && c->mu[k] <= 1.0))
            return 0;
    for (int l = 0; l < c->layer_count; l++)
        if (!(c->layer[l].tau >= 0.0) || !(c->layer[l].ssa >= 0.0 && c->layer[l].ssa <= 1.0) || !c->layer[l].chi ||
            !(c->layer[l].mu0 >= 0.0 && c->layer[l].mu0 <= 1.0))
            return 0;
    return 1;
}

/* The work space of a column's solution (freed as the returned block), its nodes and view cosines
 * set: the Gauss nodes, the views and the sun; rb, d and u are matrices / vectors of it. */
static double *work_alloc(work *W, const plane_column *c, double **rb, double **d, double **u)
{
    *W = (work){.nq = c->streams, .nc = c->streams + 1, .fields = 1};
    const int nq = W->nq, nc = W->nc, M = 2 * nq, nv = c->n_mu, n = nq + nv + 1;
    W->n = n;
    W->sun = n - 1;
    const size_t nn = (size_t)n * (size_t)nc, nf = (size_t)n * (size_t)nq; /* room for nq fields */
    double *block = calloc((size_t)n * (4 + (size_t)M) + 3 * nf + nn * 11 + (size_t)(2 * nc * nc), sizeof(double));
    if (!block)
        return NULL;
    double *next = block;
    W->w = next, next += n;
    W->xs = next, next += n;
    W->lam = next, next += (size_t)n * (size_t)M;
    double **mats[] = {&W->pt, &W->pr, &W->r, &W->t, &W->rs, &W->q, &W->s, &W->d, &W->u, &W->v, rb};
    for (size_t i = 0; i < sizeof mats / sizeof mats[0]; i++)
        *mats[i] = next, next += nn;
    W->e = next, next += n;
    W->tc = next, next += nf;
    W->ec = next, next += n;
    *d = next, next += nf;
    *u = next, next += nf;
    W->a = next;
    gauss_rule g;
    gauss_legendre(nq, &g);
    for (int i = 0; i < nq; i++) {
        W->xs[i] = 0.5 * (1.0 + g.x[i]);
        W->w[i] = 2.0 * W->xs[i] * 0.5 * g.w[i];
    }
    for (int k = 0; k < nv; k++)
        W->xs[nq + k] = c->mu[k];
    W->xs[W->sun] = c->mu0;
    return block;
}

/* Fourier mode m of the light at the level (between layers level - 1 and level): the layers below
 * laid over the ground into rb, those above added from the top down, then down d and up u.  With
 * incident (W->fields vectors of n values: the mode of a diffuse field at the top on the Gauss rows,
 * 0 on the others) the beam is off and those fields are the light entering the top (d and u then
 * [fields][n]). */
static void level_mode(work *W, const plane_column *c, int level, int m, const double *incident, double *rb, double *d,
                       double *u)
{
    const int nq = W->nq, nc = W->nc, M = 2 * nq, n = W->n;
    const size_t nn = (size_t)n * (size_t)nc;
    W->xs[W->sun] = c->mu0; /* layer_with_beam changes it */
    for (int i = 0; i < n; i++)
        assoc_legendre(m, M - 1, W->xs[i], W->lam + i * M);
    /* below the level: the layers laid over the ground from the bottom up (the Lambertian
     * ground reflects the azimuthal mean only: its kernel is the albedo in mode 0) */
    const plane_layer *bottom = &c->layer[c->layer_count - 1];
    const double beam_on_ground = bottom->mu0 > 0.0 ? bottom->mu0 / c->mu0 : 1.0; /* per column mu0 F0 */
    for (size_t i = 0; i < nn; i++)
        rb[i] = m == 0 ? c->ground_albedo * ((int)(i % (size_t)nc) == nq ? beam_on_ground : 1.0) : 0.0;
    for (int l = c->layer_count - 1; l >= level; l--) {
        layer_with_beam(W, c, &c->layer[l], m, M);
        over_reflector(W, rb);
    }
    /* above it: the layers added from the top down (none: the beam alone) */
    memset(W->rs, 0, sizeof(double) * nn);
    memset(W->tc, 0, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; i++)
        W->ec[i] = 1.0;
    if (incident) { /* an empty column that lets the fields through, and no beam */
        memcpy(W->tc, incident, sizeof(double) * (size_t)n * (size_t)W->fields);
        W->ec[W->sun] = 0.0;
    }
    for (int l = 0; l < level; l++) {
        layer_with_beam(W, c, &c->layer[l], m, M);
        if (l == 0 && !incident) {
            memcpy(W->rs, W->r, sizeof(double) * nn);
            memcpy(W->ec, W->e, sizeof(double) * (size_t)n);
            for (int i = 0; i < n; i++)
                W->tc[i] = W->t[i * nc + nq];
        } else {
            add_layer(W);
        }
    }
    level_light(W, rb, d, u);
}

/* plane_column_level (incident NULL) and plane_column_diffuse_level. */
static fm_status column_level(const plane_column *c, int level, const double *incident, double *down, double *up,
                              double *flux_down)
{
    if (!column_valid(c) || level < 0 || level > c->layer_count)
        return FM_ERR_INVALID_ARGUMENT;
    work W;
    double *rb, *d, *u;
    double *block = work_alloc(&W, c, &rb, &d, &u);
    if (!block)
        return FM_ERR_OUT_OF_MEMORY;
    const int nq = W.nq, M = 2 * nq, nv = c->n_mu;
    const int modes = down || up ? M : 1; /* the flux alone is the azimuthal mean's */
    /* the beam's radiances are per unit F0 (d per mu0 F0 / pi), the field's in its own units */
    const double scale = incident ? 1.0 : c->mu0 / PC_PI;
    double in[MAX_POINTS] = {0};
    for (int m = 0; m < modes; m++) {
        int lit = !incident || m == 0;
        for (int j = 0; j < nq && incident; j++) {
            in[j] = incident[j * M + m];
            lit |= in[j] != 0.0;
        }
        if (lit)
            level_mode(&W, c, level, m, incident ? in : NULL, rb, d, u);
        else { /* the modes do not mix: one the field does not hold is dark (an isotropic field's m > 0) */
            memset(d, 0, sizeof(double) * (size_t)W.n);
            memset(u, 0, sizeof(double) * (size_t)W.n);
        }
        for (int k = 0; k < nv; k++) {
            if (down)
                down[k * M + m] = scale * d[nq + k];
            if (up)
                up[k * M + m] = scale * u[nq + k];
        }
        if (m == 0 && flux_down) {
            double flux = W.ec[W.sun];
            for (int i = 0; i < nq; i++)
                flux += W.w[i] * d[i];
            *flux_down = incident ? PC_PI * flux : flux;
        }
    }
    free(block);
    return FM_OK;
}

fm_status plane_column_level(const plane_column *c, int level, double *down, double *up, double *flux_down)
{
    return column_level(c, level, NULL, down, up, flux_down);
}

fm_status plane_column_diffuse_level(const plane_column *c, int level, const double *incident, double *down,
                                     double *up, double *flux_down)
{
    return incident ? column_level(c, level, incident, down, up, flux_down) : FM_ERR_INVALID_ARGUMENT;
}

fm_status plane_column_diffuse_response(const plane_column *c, int level, double *response)
{
    if (!column_valid(c) || level < 0 || level > c->layer_count)
        return FM_ERR_INVALID_ARGUMENT;
    work W;
    double *rb, *d, *u;
    double *block = work_alloc(&W, c, &rb, &d, &u);
    const int nq = W.nq, M = 2 * nq, nv = c->n_mu, n = W.n;
    double *unit = calloc((size_t)n * (size_t)nq, sizeof(double)); /* a unit field at each Gauss node */
    if (!block || !unit) {
        free(block);
        free(unit);
        return FM_ERR_OUT_OF_MEMORY;
    }
    for (int j = 0; j < nq; j++)
        unit[(size_t)j * n + j] = 1.0;
    W.fields = nq;
    for (int m = 0; m < M; m++) {
        level_mode(&W, c, level, m, unit, rb, d, NULL);
        for (int k = 0; k < nv; k++)
            for (int j = 0; j < nq; j++)
                response[((size_t)m * nv + k) * nq + j] = d[(size_t)j * n + nq + k];
    }
    free(unit);
    free(block);
    return FM_OK;
}

void plane_column_nodes(int streams, double *mu)
{
    gauss_rule g;
    gauss_legendre(streams, &g);
    for (int i = 0; i < streams; i++)
        mu[i] = 0.5 * (1.0 + g.x[i]);
}

fm_status plane_column_bottom(const plane_column *c, double *modes, double *flux_down)
{
    return plane_column_level(c, c ? c->layer_count : 0, modes, NULL, flux_down);
}
