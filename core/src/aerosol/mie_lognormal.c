#include "aerosol/mie_lognormal.h"

#include "aerosol/mie.h"
#include "base/units.h"

#include <math.h>
#include <stdlib.h>

mie_lognormal_quadrature mie_lognormal_default_quadrature(void)
{
    return (mie_lognormal_quadrature){.step_ln_r = 0.02, .step_x = 1.0};
}

double lognormal_density(const lognormal_size *size, double r_um)
{
    double s = log(size->sigma), t = log(r_um / size->r_mod_um) / s;
    return exp(-0.5 * t * t) / (sqrt(2.0 * FM_PI) * s);
}

/* The quadrature variable u(v) with v = x / h, for a = 1 / step_ln_r:
 * u = integral of sqrt(a^2 + v^2) dv / v = sqrt(a^2 + v^2) - a ln((a + sqrt(a^2 + v^2)) / v). */
static double u_of_v(double a, double v)
{
    double s = sqrt(a * a + v * v);
    return s - a * log((a + s) / v);
}

/* Inverse of u_of_v by Newton's method (u is increasing and concave in ln v). */
static double v_of_u(double a, double u, double v)
{
    for (int it = 0; it < 100; it++) {
        double f = u_of_v(a, v) - u, dfdlnv = sqrt(a * a + v * v);
        double step = f / dfdlnv;
        v *= exp(-step);
        if (fabs(step) < 1e-15)
            break;
    }
    return v;
}

/* Adds w * (|S1|^2 + |S2|^2) at every mu to acc for the coefficients a, b, using
 * |S1|^2 + |S2|^2 = (|S1 + S2|^2 + |S1 - S2|^2) / 2 with S1 +- S2 = sum c_n (a_n +- b_n)(pi_n +- tau_n).
 * The angles go in blocks held in vector registers (GCC/Clang vector extensions) through the
 * whole recurrence over n; this is the table generator's hot loop.  On x86-64 a second copy
 * built for AVX2 + FMA (4 doubles a register) is chosen at run time where the CPU has them. */
#define MIE_INTENSITY_KERNEL(name, block, attr)                                                          \
    attr static void name(int count, const double *cpq, int n_mu, const double *mu, double w, double *acc) \
    {                                                                                                   \
        typedef double vec __attribute__((vector_size(block * sizeof(double))));                        \
        for (int j0 = 0; j0 < n_mu; j0 += block) {                                                      \
            vec u, pi_prev, pi, pr, pim, mr, mi;                                                        \
            for (int l = 0; l < block; l++)                                                             \
                u[l] = mu[j0 + l < n_mu ? j0 + l : n_mu - 1];                                           \
            pi_prev = u * 0.0;                                                                          \
            pi = pi_prev + 1.0;                                                                         \
            pr = pim = mr = mi = pi_prev;                                                               \
            for (int n = 1; n <= count; n++) {                                                          \
                const double *c = cpq + 8 * (n - 1);                                                    \
                vec tau = c[4] * u * pi - c[5] * pi_prev;                                               \
                vec sp = pi + tau, sm = pi - tau;                                                       \
                pr += c[0] * sp;                                                                        \
                pim += c[1] * sp;                                                                       \
                mr += c[2] * sm;                                                                        \
                mi += c[3] * sm;                                                                        \
                vec next = c[6] * u * pi - c[7] * pi_prev;                                              \
                pi_prev = pi;                                                                           \
                pi = next;                                                                              \
            }                                                                                           \
            vec in = 0.5 * (pr * pr + pim * pim + mr * mr + mi * mi);                                   \
            for (int l = 0; l < block && j0 + l < n_mu; l++)                                            \
                acc[j0 + l] += w * in[l];                                                               \
        }                                                                                               \
    }

MIE_INTENSITY_KERNEL(add_intensity_generic, 2, )
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
MIE_INTENSITY_KERNEL(add_intensity_avx2, 4, __attribute__((target("avx2,fma"))))
#endif

static void add_intensity(int count, const double *cpq, int n_mu, const double *mu, double w, double *acc)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) {
        add_intensity_avx2(count, cpq, n_mu, mu, w, acc);
        return;
    }
#endif
    add_intensity_generic(count, cpq, n_mu, mu, w, acc);
}

/* The per-term constants add_intensity reads, 8 doubles per n. */
static void intensity_constants(int count, const double complex *a, const double complex *b, double *cpq)
{
    for (int n = 1; n <= count; n++) {
        double c = (2.0 * n + 1.0) / (n * (n + 1.0));
        double complex p = c * (a[n - 1] + b[n - 1]), q = c * (a[n - 1] - b[n - 1]);
        double *o = cpq + 8 * (n - 1);
        o[0] = creal(p);
        o[1] = cimag(p);
        o[2] = creal(q);
        o[3] = cimag(q);
        o[4] = n;
        o[5] = n + 1.0;
        o[6] = (2.0 * n + 1.0) / n;
        o[7] = (n + 1.0) / n;
    }
}

/* The quadrature of the file's header over [r_min, r_top] for any density dN/dln r. */
static int mie_integrate(double (*density)(const void *ctx, double r_um), const void *ctx, double r_min_um,
                         double r_top_um, double lambda_um, double complex m, const mie_lognormal_quadrature *quad,
                         int n_mu, const double *mu, double *phase, mie_lognormal_result *out)
{
    if (!(r_min_um > 0.0 && r_top_um > r_min_um && lambda_um > 0.0) || cimag(m) > 0.0 || n_mu < 0)
        return -1;
    mie_lognormal_quadrature q = quad ? *quad : mie_lognormal_default_quadrature();
    const double k = 2.0 * FM_PI / lambda_um; /* um^-1 */
    const double a_inv = 1.0 / q.step_ln_r;
    const double v_min = k * r_min_um / q.step_x, v_max = k * r_top_um / q.step_x;
    const double u_min = u_of_v(a_inv, v_min), u_max = u_of_v(a_inv, v_max);
    const int intervals = (int)ceil(u_max - u_min);
    const double du = (u_max - u_min) / intervals;

    int cap = mie_term_count(k * r_top_um);
    double complex *coef = malloc(2 * (size_t)cap * sizeof *coef);
    double *work = malloc((8 * (size_t)cap + (size_t)n_mu) * sizeof *work);
    if (!coef || !work) {
        free(coef);
        free(work);
        return -1;
    }
    double *acc = work + 8 * (size_t)cap;
    for (int j = 0; j < n_mu; j++)
        acc[j] = 0.0;

    double ext = 0.0, sca = 0.0, gsca = 0.0; /* um^2 per particle */
    double v = v_min;
    for (int i = 0; i <= intervals; i++) {
        v = i == 0 ? v_min : i == intervals ? v_max : v_of_u(a_inv, u_min + i * du, v);
        double x = v * q.step_x, r = x / k;
        /* trapezoid weight in u times dln r / du times the number density per ln r */
        double w = (i == 0 || i == intervals ? 0.5 : 1.0) * du / sqrt(a_inv * a_inv + v * v) *
                   density(ctx, r);
        int count = mie_coefficients(x, m, coef, coef + cap);
        mie_result e = mie_efficiencies(x, count, coef, coef + cap);
        double area = FM_PI * r * r;
        ext += w * area * e.q_ext;
        sca += w * area * e.q_sca;
        gsca += w * area * e.q_sca * e.g;
        /* differential scattering cross section (|S1|^2 + |S2|^2) / (2 k^2) */
        if (n_mu > 0) {
            intensity_constants(count, coef, coef + cap, work);
            add_intensity(count, work, n_mu, mu, w / (2.0 * k * k), acc);
        }
    }
    out->ext_m2 = ext * 1e-12;
    out->sca_m2 = sca * 1e-12;
    out->g = sca > 0.0 ? gsca / sca : 0.0;
    out->radii = intervals + 1;
    for (int j = 0; j < n_mu; j++)
        phase[j] = sca > 0.0 ? acc[j] / sca : 0.0;
    free(coef);
    free(work);
    return 0;
}

static double lognormal_density_ctx(const void *ctx, double r_um)
{
    return lognormal_density(ctx, r_um);
}

int mie_lognormal(const lognormal_size *size, double lambda_um, double complex m,
                  const mie_lognormal_quadrature *quad, int n_mu, const double *mu, double *phase,
                  mie_lognormal_result *out)
{
    if (!(size->r_mod_um > 0.0 && size->sigma > 1.0 && size->r_min_um > 0.0 && size->r_max_um > size->r_min_um))
        return -1;
    /* Beyond 5 standard deviations above the mode of r^4 dN/dln r (the weight of the forward
     * peak at 0 degrees, the most size-sensitive quantity) the distribution adds below 3e-7 to anything. */
    const double ls = log(size->sigma);
    const double r_top = fmin(size->r_max_um, size->r_mod_um * exp(4.0 * ls * ls + 5.0 * ls));
    return mie_integrate(lognormal_density_ctx, size, size->r_min_um, r_top, lambda_um, m, quad, n_mu, mu, phase,
                         out);
}

/* ---- modified gamma ------------------------------------------------------------------------- */

static double gamma_shape(const modified_gamma_size *s, double r_um)
{
    /* r dn/dr in logarithms, for the ln r density: (alpha + 1) ln r - B r^gamma */
    return (s->alpha + 1.0) * log(r_um) - s->b * pow(r_um, s->gamma);
}

/* ln r of the peak of r^(alpha + 1 + extra) exp(-B r^gamma): d/dln r = 0 at B gamma r^gamma = alpha + 1 + extra */
static double gamma_peak_um(const modified_gamma_size *s, double extra)
{
    return pow((s->alpha + 1.0 + extra) / (s->b * s->gamma), 1.0 / s->gamma);
}

typedef struct gamma_ctx {
    const modified_gamma_size *size;
    double log_norm; /* ln of the number of the truncated distribution, relative to exp(peak) */
    double shift;    /* gamma_shape at its peak */
} gamma_ctx;

static double gamma_density_ctx(const void *ctx, double r_um)
{
    const gamma_ctx *g = ctx;
    return exp(gamma_shape(g->size, r_um) - g->shift - g->log_norm);
}

/* Moments integral of r^p dN/dln r over [r_min, r_max] of the unnormalised shape (times exp(-shift)),
 * by the trapezoid rule in ln r (the integrand is smooth and negligible at both ends). */
static double gamma_moment(const modified_gamma_size *s, double shift, double p)
{
    const int n = 20000;
    double a = log(s->r_min_um), b = log(s->r_max_um), h = (b - a) / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double lr = a + i * h;
        sum += (i == 0 || i == n ? 0.5 : 1.0) * exp(gamma_shape(s, exp(lr)) - shift + p * lr);
    }
    return sum * h;
}

static int gamma_valid(const modified_gamma_size *s)
{
    return s->alpha > -1.0 && s->b > 0.0 && s->gamma > 0.0 && s->r_min_um > 0.0 && s->r_max_um > s->r_min_um;
}

double modified_gamma_effective_radius_um(const modified_gamma_size *size)
{
    if (!gamma_valid(size))
        return 0.0;
    double shift = gamma_shape(size, gamma_peak_um(size, 0.0));
    return gamma_moment(size, shift, 3.0) / gamma_moment(size, shift, 2.0);
}

double modified_gamma_mean_volume_um3(const modified_gamma_size *size)
{
    if (!gamma_valid(size))
        return 0.0;
    double shift = gamma_shape(size, gamma_peak_um(size, 0.0));
    return 4.0 / 3.0 * FM_PI * gamma_moment(size, shift, 3.0) / gamma_moment(size, shift, 0.0);
}

int mie_modified_gamma(const modified_gamma_size *size, double lambda_um, double complex m,
                       const mie_lognormal_quadrature *quad, int n_mu, const double *mu, double *phase,
                       mie_lognormal_result *out)
{
    if (!gamma_valid(size))
        return -1;
    gamma_ctx g = {size, 0.0, gamma_shape(size, gamma_peak_um(size, 0.0))};
    g.log_norm = log(gamma_moment(size, g.shift, 0.0));
    /* The forward peak weighs r^4 dN/dln r: beyond where that falls below 1e-9 of its peak the
     * distribution adds nothing measurable (the same margin as the log-normal's). */
    double peak4 = gamma_peak_um(size, 2.0), top4 = (size->alpha + 3.0) * log(peak4) - size->b * pow(peak4, size->gamma);
    double r_top = peak4;
    while (r_top < size->r_max_um &&
           (size->alpha + 3.0) * log(r_top) - size->b * pow(r_top, size->gamma) > top4 - 9.0 * log(10.0))
        r_top *= 1.01;
    r_top = fmin(r_top, size->r_max_um);
    return mie_integrate(gamma_density_ctx, &g, size->r_min_um, r_top, lambda_um, m, quad, n_mu, mu, phase, out);
}
