#include "aerosol/mie.h"

#include "base/units.h"

#include <math.h>
#include <stdlib.h>

int mie_term_count(double x)
{
    double c = cbrt(x);
    double n = x <= 8.0 ? x + 4.0 * c + 1.0 : x < 4200.0 ? x + 4.05 * c + 2.0 : x + 4.0 * c + 2.0;
    return (int)n + 1; /* one more than Wiscombe's count never hurts and covers tiny x */
}

int mie_coefficients(double x, double complex m, double complex *a, double complex *b)
{
    const int count = mie_term_count(x);
    /* Bohren & Huffman's formulas use m = n + ik: conjugate on the way in, and the coefficients on
     * the way out, so that a_n, b_n (and S1, S2) follow the n - ik convention of the header. */
    const double complex mb = conj(m);
    const double complex mx = mb * x;

    /* D_n(mx) = psi_n'(mx) / psi_n(mx), downward from far enough above both N and |mx| that the
     * start value 0 is forgotten: below n = |mx| the recurrence for a nearly real index no longer
     * damps errors, so start beyond the Airy transition region (width |mx|^(1/3)) where psi_n(mx)
     * falls off, by enough (8 widths) to damp the start error below 1e-16.  a[] holds D_n until
     * the upward pass below replaces it. */
    const int perfect = creal(m) == 0.0;
    double z = perfect ? 0.0 : cabs(mx);
    int start = (int)fmax((double)count, z + 8.0 * cbrt(z)) + 16;
    if (!perfect) {
        double complex d = 0.0;
        for (int n = start; n > count; n--)
            d = n / mx - 1.0 / (d + n / mx);
        a[count - 1] = d;
        for (int n = count; n > 1; n--) {
            d = n / mx - 1.0 / (d + n / mx);
            a[n - 2] = d;
        }
    }

    /* Riccati-Bessel psi_n(x) and chi_n(x) upward, xi_n = psi_n - i chi_n. */
    double psi_prev = cos(x), psi = sin(x);   /* psi_{-1}, psi_0 */
    double chi_prev = -sin(x), chi = cos(x);  /* chi_{-1}, chi_0 */
    for (int n = 1; n <= count; n++) {
        double f = (2.0 * n - 1.0) / x;
        double psi_n = f * psi - psi_prev;
        double chi_n = f * chi - chi_prev;
        double complex xi_n = psi_n - I * chi_n, xi_prev = psi - I * chi;
        double complex an, bn;
        if (perfect) { /* the limit |m| -> infinity of the formulas below */
            an = (n / x * psi_n - psi) / (n / x * xi_n - xi_prev);
            bn = psi_n / xi_n;
        } else {
            double complex dn = a[n - 1];
            double complex ta = dn / mb + n / x, tb = mb * dn + n / x;
            an = (ta * psi_n - psi) / (ta * xi_n - xi_prev);
            bn = (tb * psi_n - psi) / (tb * xi_n - xi_prev);
        }
        a[n - 1] = conj(an);
        b[n - 1] = conj(bn);
        psi_prev = psi;
        psi = psi_n;
        chi_prev = chi;
        chi = chi_n;
    }
    return count;
}

mie_result mie_efficiencies(double x, int count, const double complex *a, const double complex *b)
{
    double ext = 0.0, sca = 0.0, asym = 0.0;
    double complex back = 0.0;
    for (int n = 1; n <= count; n++) {
        double complex an = a[n - 1], bn = b[n - 1];
        double w = 2.0 * n + 1.0;
        ext += w * creal(an + bn);
        sca += w * (creal(an) * creal(an) + cimag(an) * cimag(an) + creal(bn) * creal(bn) + cimag(bn) * cimag(bn));
        asym += w / (n * (n + 1.0)) * creal(an * conj(bn));
        if (n < count)
            asym += n * (n + 2.0) / (n + 1.0) * creal(an * conj(a[n]) + bn * conj(b[n]));
        back += (n % 2 ? -w : w) * (an - bn);
    }
    mie_result r;
    double x2 = x * x;
    r.q_ext = 2.0 / x2 * ext;
    r.q_sca = 2.0 / x2 * sca;
    r.q_back = (creal(back) * creal(back) + cimag(back) * cimag(back)) / x2;
    r.g = r.q_sca > 0.0 ? 4.0 / x2 * asym / r.q_sca : 0.0;
    return r;
}

void mie_amplitudes(int count, const double complex *a, const double complex *b, int n_mu, const double *mu,
                    double complex *s1, double complex *s2)
{
    for (int j = 0; j < n_mu; j++) {
        double u = mu[j];
        double pi_prev = 0.0, pi = 1.0; /* pi_0, pi_1 */
        double complex t1 = 0.0, t2 = 0.0;
        for (int n = 1; n <= count; n++) {
            double tau = n * u * pi - (n + 1.0) * pi_prev;
            double c = (2.0 * n + 1.0) / (n * (n + 1.0));
            t1 += c * (a[n - 1] * pi + b[n - 1] * tau);
            t2 += c * (a[n - 1] * tau + b[n - 1] * pi);
            double pi_next = ((2.0 * n + 1.0) * u * pi - (n + 1.0) * pi_prev) / n;
            pi_prev = pi;
            pi = pi_next;
        }
        s1[j] = t1;
        s2[j] = t2;
    }
}

int mie_sphere(double x, double complex m, int n_mu, const double *mu, double complex *s1, double complex *s2,
               mie_result *out)
{
    if (!(x > 0.0 && x <= 1e5) || cimag(m) > 0.0 || (creal(m) == 0.0 && cimag(m) == 0.0))
        return -1;
    int cap = mie_term_count(x);
    double complex *a = malloc(2 * (size_t)cap * sizeof *a);
    if (!a)
        return -1;
    double complex *b = a + cap;
    int count = mie_coefficients(x, m, a, b);
    *out = mie_efficiencies(x, count, a, b);
    if (n_mu > 0)
        mie_amplitudes(count, a, b, n_mu, mu, s1, s2);
    free(a);
    return 0;
}

double mie_phase_function(double x, double q_sca, double complex s1, double complex s2)
{
    double i1 = creal(s1) * creal(s1) + cimag(s1) * cimag(s1);
    double i2 = creal(s2) * creal(s2) + cimag(s2) * cimag(s2);
    return (i1 + i2) / (2.0 * FM_PI * x * x * q_sca);
}
