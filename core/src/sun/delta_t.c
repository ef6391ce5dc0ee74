#include "sun/delta_t.h"

/* p[0] + p[1] t + ... + p[n-1] t^(n-1) */
static double poly(double t, const double *p, int n)
{
    double v = 0.0;
    for (int i = n - 1; i >= 0; i--)
        v = v * t + p[i];
    return v;
}

static double long_term_parabola(double y)
{
    double u = (y - 1820.0) / 100.0;
    return -20.0 + 32.0 * u * u;
}

double delta_t_estimate_s(int year, int month)
{
    double y = year + (month - 0.5) / 12.0;
    if (y < -500.0 || y >= 2150.0)
        return long_term_parabola(y);
    if (y < 500.0) {
        static const double p[] = {10583.6, -1014.41, 33.78311, -5.952053, -0.1798452, 0.022174192, 0.0090316521};
        return poly(y / 100.0, p, 7);
    }
    if (y < 1600.0) {
        static const double p[] = {1574.2, -556.01, 71.23472, 0.319781, -0.8503463, -0.005050998, 0.0083572073};
        return poly((y - 1000.0) / 100.0, p, 7);
    }
    if (y < 1700.0) {
        static const double p[] = {120.0, -0.9808, -0.01532, 1.0 / 7129.0};
        return poly(y - 1600.0, p, 4);
    }
    if (y < 1800.0) {
        static const double p[] = {8.83, 0.1603, -0.0059285, 0.00013336, -1.0 / 1174000.0};
        return poly(y - 1700.0, p, 5);
    }
    if (y < 1860.0) {
        static const double p[] = {13.72, -0.332447, 0.0068612, 0.0041116, -0.00037436, 0.0000121272, -0.0000001699,
                                   0.000000000875};
        return poly(y - 1800.0, p, 8);
    }
    if (y < 1900.0) {
        static const double p[] = {7.62, 0.5737, -0.251754, 0.01680668, -0.0004473624, 1.0 / 233174.0};
        return poly(y - 1860.0, p, 6);
    }
    if (y < 1920.0) {
        static const double p[] = {-2.79, 1.494119, -0.0598939, 0.0061966, -0.000197};
        return poly(y - 1900.0, p, 5);
    }
    if (y < 1941.0) {
        static const double p[] = {21.20, 0.84493, -0.076100, 0.0020936};
        return poly(y - 1920.0, p, 4);
    }
    if (y < 1961.0) {
        static const double p[] = {29.07, 0.407, -1.0 / 233.0, 1.0 / 2547.0};
        return poly(y - 1950.0, p, 4);
    }
    if (y < 1986.0) {
        static const double p[] = {45.45, 1.067, -1.0 / 260.0, -1.0 / 718.0};
        return poly(y - 1975.0, p, 4);
    }
    if (y < 2005.0) {
        static const double p[] = {63.86, 0.3345, -0.060374, 0.0017275, 0.000651814, 0.00002373599};
        return poly(y - 2000.0, p, 6);
    }
    if (y < 2050.0) {
        static const double p[] = {62.92, 0.32217, 0.005589};
        return poly(y - 2000.0, p, 3);
    }
    /* 2050-2150: the parabola, shifted to meet the 2005-2050 polynomial in 2050 */
    return long_term_parabola(y) - 0.5628 * (2150.0 - y);
}
