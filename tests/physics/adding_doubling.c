/* Adding-doubling for one homogeneous plane-parallel layer over a Lambertian ground (see the header).
 *
 * Conventions (Hansen & Travis 1974).  A kernel K(mu, mu', dphi) = sum_m (2 - delta_m0) K_m cos(m dphi)
 * maps incident to outgoing radiance by L_out(mu) = 2 int_0^1 K_m(mu, mu') L_in,m(mu') mu' dmu' for each
 * mode; on the discrete points that integral is sum_j K[i][j] w[j] with w = 2 mu c (c: Gauss weights on
 * [0, 1]; 0 for the view and sun points).  E = exp(-tau / mu) is the direct transmission.  Doubling two
 * identical layers (R from above equals R from below for a homogeneous layer):
 *   Q = R w R,  S = Q (1 - w Q)^-1,  D = T + S E + S w T,  U = R E + R w D,
 *   R' = R + E U + T w U,  T' = E D + T E + T w D,  E' = E^2
 * (E on the right scales the incident direction's column, on the left the outgoing row). */
#include "adding_doubling.h"

#include "base/quadrature.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define AD_PI 3.14159265358979323846
#define TAU_START 1e-9 /* single scattering in the first layer: R + T = 1 to ~3e-7 at tau 10 */
#define MOMENT_PANELS 8000 /* panels in scattering angle for the Legendre moments (peaks to ~0.1 deg) */

double ad_phase_hg(double cos_theta, const void *ctx)
{
    double g = *(const double *)ctx, d = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * AD_PI * d * sqrt(d));
}

/* Gauss-Legendre nodes and weights on [0, 1]. */
static void gauss_01(int n, double *x, double *c)
{
    gauss_rule g;
    gauss_legendre(n, &g);
    for (int i = 0; i < n; i++) {
        x[i] = 0.5 * (1.0 + g.x[i]);
        c[i] = 0.5 * g.w[i];
    }
}

/* Legendre polynomials P_0..P_lmax at x. */
static void legendre(int lmax, double x, double *p)
{
    p[0] = 1.0;
    if (lmax > 0)
        p[1] = x;
    for (int l = 2; l <= lmax; l++)
        p[l] = ((2.0 * l - 1.0) * x * p[l - 1] - (l - 1.0) * p[l - 2]) / l;
}

/* chi_l = 1/2 int P(x) P_l(x) dx / (1/2 int P(x) dx), l = 0..lmax, by 4-point Gauss on panels
 * uniform in the scattering angle (so a forward peak is resolved); returns 1/2 int P(x) dx. */
static double moments(ad_phase_fn phase, const void *ctx, int lmax, double *chi)
{
    gauss_rule g4;
    gauss_legendre(4, &g4);
    double *pl = malloc(sizeof(double) * (size_t)(lmax + 1)), h = AD_PI / MOMENT_PANELS;
    memset(chi, 0, sizeof(double) * (size_t)(lmax + 1));
    for (int k = 0; k < MOMENT_PANELS; k++)
        for (int q = 0; q < 4; q++) {
            double th = h * (k + 0.5 * (1.0 + g4.x[q])), x = cos(th);
            double v = 0.5 * phase(x, ctx) * sin(th) * (0.5 * h * g4.w[q]); /* (1/2) p sin(theta) dtheta */
            legendre(lmax, x, pl);
            for (int l = 0; l <= lmax; l++)
                chi[l] += v * pl[l];
        }
    double chi0 = chi[0];
    for (int l = 0; l <= lmax; l++)
        chi[l] /= chi0;
    free(pl);
    return chi0;
}

/* The scaled phase function sum_l (2l + 1) chi_l P_l(x), normalised to 1 over 4 pi. */
static double phase_from_moments(const double *chi, int n, double x)
{
    double p0 = 1.0, p1 = x, sum = chi[0];
    if (n > 1)
        sum += 3.0 * chi[1] * x;
    for (int l = 2; l < n; l++) {
        double p2 = ((2.0 * l - 1.0) * x * p1 - (l - 1.0) * p0) / l;
        sum += (2.0 * l + 1.0) * chi[l] * p2;
        p0 = p1;
        p1 = p2;
    }
    return sum / (4.0 * AD_PI);
}

/* Normalised associated Legendre functions sqrt((l-m)!/(l+m)!) P_l^m(x), l = m..lmax (index l). */
static void assoc_legendre(int m, int lmax, double x, double *lam)
{
    double s = sqrt(fmax(0.0, 1.0 - x * x)), v = 1.0;
    for (int k = 1; k <= m; k++)
        v *= sqrt((2.0 * k - 1.0) / (2.0 * k)) * s;
    if (m > lmax)
        return;
    lam[m] = v;
    if (m + 1 <= lmax)
        lam[m + 1] = sqrt(2.0 * m + 1.0) * x * v;
    for (int l = m + 1; l < lmax; l++)
        lam[l + 1] = ((2.0 * l + 1.0) * x * lam[l] - sqrt((double)(l * l - m * m)) * lam[l - 1]) /
                     sqrt((double)((l + 1) * (l + 1) - m * m));
}

/* c = a diag(w) b over the first nq (weighted) indices; n x n row-major. */
static void mul_w(int n, int nq, const double *w, const double *a, const double *b, double *c)
{
    memset(c, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < n; i++)
        for (int k = 0; k < nq; k++) {
            double aik = a[i * n + k] * w[k];
            for (int j = 0; j < n; j++)
                c[i * n + j] += aik * b[k * n + j];
        }
}

/* Solves x a = q for x (n x n), overwriting q with x; a is destroyed.  Gauss with partial pivoting on
 * a^T x^T = q^T. */
static int solve_right(int n, double *a, double *q)
{
    /* transpose a in place */
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            double t = a[i * n + j];
            a[i * n + j] = a[j * n + i];
            a[j * n + i] = t;
        }
    int *piv = malloc(sizeof(int) * (size_t)n);
    if (!piv)
        return -1;
    for (int k = 0; k < n; k++) {
        int p = k;
        for (int i = k + 1; i < n; i++)
            if (fabs(a[i * n + k]) > fabs(a[p * n + k]))
                p = i;
        piv[k] = p;
        if (p != k)
            for (int j = 0; j < n; j++) {
                double t = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = t;
            }
        for (int i = k + 1; i < n; i++) {
            double f = a[i * n + k] /= a[k * n + k];
            for (int j = k + 1; j < n; j++)
                a[i * n + j] -= f * a[k * n + j];
        }
    }
    double *y = malloc(sizeof(double) * (size_t)n);
    for (int r = 0; r < n; r++) { /* row r of x is the solution for row r of q */
        for (int i = 0; i < n; i++)
            y[i] = q[r * n + i];
        for (int k = 0; k < n; k++) {
            double t = y[k];
            y[k] = y[piv[k]];
            y[piv[k]] = t;
            for (int i = k + 1; i < n; i++)
                y[i] -= a[i * n + k] * y[k];
        }
        for (int k = n - 1; k >= 0; k--) {
            for (int j = k + 1; j < n; j++)
                y[k] -= a[k * n + j] * y[j];
            y[k] /= a[k * n + k];
        }
        for (int i = 0; i < n; i++)
            q[r * n + i] = y[i];
    }
    free(y);
    free(piv);
    return 0;
}

typedef struct layer {
    int n, nq;
    const double *x, *w;
    double *r, *t, *e, *tmp[5];
} layer;

/* R and T of one azimuthal mode for the whole layer, from single scattering in tau0 and k doublings. */
static void layer_mode(layer *L, const double *pt, const double *pr, double ssa, double tau0, int k)
{
    int n = L->n, nq = L->nq;
    const double *x = L->x, *w = L->w;
    double *r = L->r, *t = L->t, *e = L->e;
    for (int i = 0; i < n; i++) {
        e[i] = exp(-tau0 / x[i]);
        for (int j = 0; j < n; j++) {
            double a = x[i], b = x[j], d = a - b;
            r[i * n + j] = 0.25 * ssa * pr[i * n + j] * -expm1(-tau0 * (a + b) / (a * b)) / (a + b);
            double tt = fabs(d) < 1e-14 ? tau0 / (a * b) : expm1(tau0 * d / (a * b)) / d;
            t[i * n + j] = 0.25 * ssa * pt[i * n + j] * exp(-tau0 / b) * tt;
        }
    }
    double *q = L->tmp[0], *s = L->tmp[1], *dd = L->tmp[2], *u = L->tmp[3], *a = L->tmp[4];
    for (int it = 0; it < k; it++) {
        mul_w(n, nq, w, r, r, q);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                a[i * n + j] = (i == j) - w[i] * q[i * n + j];
        memcpy(s, q, sizeof(double) * (size_t)(n * n));
        solve_right(n, a, s);
        mul_w(n, nq, w, s, t, dd); /* D = T + S E + S w T */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                dd[i * n + j] += t[i * n + j] + s[i * n + j] * e[j];
        mul_w(n, nq, w, r, dd, u); /* U = R E + R w D */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                u[i * n + j] += r[i * n + j] * e[j];
        mul_w(n, nq, w, t, u, a); /* R' = R + E U + T w U */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                r[i * n + j] += e[i] * u[i * n + j] + a[i * n + j];
        mul_w(n, nq, w, t, dd, a); /* T' = E D + T E + T w D */
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                t[i * n + j] = e[i] * dd[i * n + j] + t[i * n + j] * e[j] + a[i * n + j];
        for (int i = 0; i < n; i++)
            e[i] *= e[i];
    }
}

void ad_free(ad_solution *s)
{
    free(s->bottom);
    free(s->top);
    free(s->moments);
    free((double *)s->p.mu);
    memset(s, 0, sizeof *s);
}

int ad_solve(const ad_problem *p, ad_solution *s)
{
    memset(s, 0, sizeof *s);
    if (!(p->tau >= 0.0) || !(p->ssa >= 0.0 && p->ssa <= 1.0) || !(p->mu0 > 0.0 && p->mu0 <= 1.0) ||
        !(p->ground_albedo >= 0.0 && p->ground_albedo <= 1.0) || p->streams < 2 || p->streams > FM_GAUSS_MAX || p->n_mu < 0 || !p->phase)
        return -1;
    for (int k = 0; k < p->n_mu; k++)
        if (!(p->mu[k] > 0.0 && p->mu[k] <= 1.0))
            return -1;
    int nq = p->streams, M = 2 * nq, nv = p->n_mu, n = nq + nv + 1, sun = n - 1;
    s->p = *p;
    s->modes = M;
    double *mu = malloc(sizeof(double) * (size_t)(nv + 1));
    s->bottom = calloc((size_t)(nv * M + 1), sizeof(double));
    s->top = calloc((size_t)(nv * M + 1), sizeof(double));
    s->moments = calloc((size_t)(M + 1), sizeof(double));
    double *x = malloc(sizeof(double) * (size_t)n), *w = calloc((size_t)n, sizeof(double));
    double *lam = malloc(sizeof(double) * (size_t)(n * (M + 1)));
    double *pt = malloc(sizeof(double) * (size_t)(n * n)), *pr = malloc(sizeof(double) * (size_t)(n * n));
    layer L = {.n = n, .nq = nq, .x = x, .w = w};
    L.r = malloc(sizeof(double) * (size_t)(n * n));
    L.t = malloc(sizeof(double) * (size_t)(n * n));
    L.e = malloc(sizeof(double) * (size_t)n);
    int ok = mu && s->bottom && s->top && s->moments && x && w && lam && pt && pr && L.r && L.t && L.e;
    for (int i = 0; i < 5; i++)
        ok = ok && (L.tmp[i] = malloc(sizeof(double) * (size_t)(n * n)));
    if (!ok)
        goto fail;
    memcpy(mu, p->mu, sizeof(double) * (size_t)nv);
    s->p.mu = mu;

    double *c = malloc(sizeof(double) * (size_t)nq);
    gauss_01(nq, x, c);
    for (int i = 0; i < nq; i++)
        w[i] = 2.0 * x[i] * c[i];
    free(c);
    for (int k = 0; k < nv; k++)
        x[nq + k] = p->mu[k];
    x[sun] = p->mu0;

    /* moments, delta-M scaling */
    double *chi = s->moments;
    s->phase_scale = 1.0 / (4.0 * AD_PI * moments(p->phase, p->phase_ctx, M, chi));
    s->f = p->delta_m ? chi[M] : 0.0;
    for (int l = 0; l < M; l++)
        chi[l] = (chi[l] - s->f) / (1.0 - s->f);
    chi[M] = 0.0;
    s->tau_scaled = (1.0 - p->ssa * s->f) * p->tau;
    s->ssa_scaled = p->ssa * s->f < 1.0 ? p->ssa * (1.0 - s->f) / (1.0 - p->ssa * s->f) : 1.0;
    int doublings = 0;
    double tau0 = s->tau_scaled;
    while (tau0 > TAU_START) {
        tau0 *= 0.5;
        doublings++;
    }

    double A = p->ground_albedo, mu0 = p->mu0, t_sun = 0, r_sun = 0, sph = 0;
    double *rho = calloc((size_t)n, sizeof(double)), *tiso = calloc((size_t)n, sizeof(double));
    for (int m = 0; m < M; m++) {
        for (int i = 0; i < n; i++)
            assoc_legendre(m, M - 1, x[i], lam + i * (M + 1));
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double st = 0.0, sr = 0.0;
                for (int l = m; l < M; l++) {
                    double v = (2.0 * l + 1.0) * chi[l] * lam[i * (M + 1) + l] * lam[j * (M + 1) + l];
                    st += v;
                    sr += (l + m) % 2 ? -v : v;
                }
                pt[i * n + j] = st;
                pr[i * n + j] = sr;
            }
        layer_mode(&L, pt, pr, s->ssa_scaled, tau0, doublings);
        for (int k = 0; k < nv; k++) {
            s->bottom[k * M + m] = mu0 / AD_PI * L.t[(nq + k) * n + sun];
            s->top[k * M + m] = mu0 / AD_PI * L.r[(nq + k) * n + sun];
        }
        if (m == 0)
            for (int i = 0; i < n; i++) {
                for (int j = 0; j < nq; j++) {
                    rho[i] += L.r[i * n + j] * w[j];
                    tiso[i] += L.t[i * n + j] * w[j];
                }
                if (i < nq) {
                    t_sun += w[i] * L.t[i * n + sun];
                    r_sun += w[i] * L.r[i * n + sun];
                    sph += w[i] * rho[i];
                }
            }
    }
    /* the ground: E_down (per mu0 F0) includes the light the layer sends back down */
    double e_dn = (exp(-s->tau_scaled / mu0) + t_sun) / (1.0 - A * sph), lg = A * mu0 * e_dn / AD_PI;
    double up_from_ground = 0.0;
    for (int i = 0; i < nq; i++)
        up_from_ground += w[i] * (exp(-s->tau_scaled / x[i]) + tiso[i]);
    for (int k = 0; k < nv; k++) {
        s->bottom[k * M] += lg * rho[nq + k];
        s->top[k * M] += lg * (exp(-s->tau_scaled / x[nq + k]) + tiso[nq + k]);
    }
    s->flux_down_direct = exp(-p->tau / mu0);
    s->flux_down_diffuse = e_dn - s->flux_down_direct;
    s->flux_up_bottom = A * e_dn;
    s->flux_up_top = r_sun + A * e_dn * up_from_ground;
    free(rho);
    free(tiso);
    ok = 1;
    goto done;
fail:
    ok = 0;
done:
    free(x);
    free(w);
    free(lam);
    free(pt);
    free(pr);
    free(L.r);
    free(L.t);
    free(L.e);
    for (int i = 0; i < 5; i++)
        free(L.tmp[i]);
    if (!ok) {
        s->p.mu = mu;
        ad_free(s);
        return -1;
    }
    return 0;
}

/* Single-scattered radiance at the bottom (down) or the top (up), per unit F0, with optical depth
 * tau, albedo ssa and a phase function normalised to 1 over 4 pi at cos_theta. */
static double single_bottom(double tau, double ssa, double ph, double mu, double mu0)
{
    double d = mu - mu0;
    double f = fabs(d) < 1e-14 ? tau / (mu * mu0) : expm1(tau * d / (mu * mu0)) / d;
    return ssa * ph * mu0 * exp(-tau / mu0) * f;
}

static double single_top(double tau, double ssa, double ph, double mu, double mu0)
{
    return ssa * ph * mu0 / (mu + mu0) * -expm1(-tau * (mu + mu0) / (mu * mu0));
}

static double fourier(const double *c, int modes, double phi)
{
    double sum = c[0];
    for (int m = 1; m < modes; m++)
        sum += 2.0 * c[m] * cos(m * phi);
    return sum;
}

/* Nakajima & Tanaka's TMS correction: in the scaled medium (tau*, ssa*), the single-scattered radiance
 * with the true phase function over (1 - f) minus that with the truncated one.  Keeping tau* (not tau)
 * counts light scattered first within the truncated peak and then once more, which delta-M treats as
 * unscattered. */
static double tms(const ad_solution *s, int k, double phi, int bottom)
{
    if (!s->p.delta_m)
        return 0.0;
    double mu = s->p.mu[k], mu0 = s->p.mu0, sn = sqrt(fmax(0.0, 1.0 - mu * mu) * (1.0 - mu0 * mu0));
    double ct = (bottom ? mu * mu0 : -mu * mu0) + sn * cos(phi);
    double exact = s->phase_scale * s->p.phase(ct, s->p.phase_ctx);
    double scaled = phase_from_moments(s->moments, s->modes, ct);
    double ssa_exact = s->ssa_scaled / (1.0 - s->f), tau = s->tau_scaled;
    if (bottom)
        return single_bottom(tau, ssa_exact, exact, mu, mu0) - single_bottom(tau, s->ssa_scaled, scaled, mu, mu0);
    return single_top(tau, ssa_exact, exact, mu, mu0) - single_top(tau, s->ssa_scaled, scaled, mu, mu0);
}

double ad_radiance_bottom(const ad_solution *s, int k, double phi)
{
    return fourier(s->bottom + k * s->modes, s->modes, phi) + tms(s, k, phi, 1);
}

double ad_radiance_top(const ad_solution *s, int k, double phi)
{
    return fourier(s->top + k * s->modes, s->modes, phi) + tms(s, k, phi, 0);
}
