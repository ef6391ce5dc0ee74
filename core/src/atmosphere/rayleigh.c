#include "atmosphere/rayleigh.h"

#include "base/units.h"

#include <math.h>

double rayleigh_cross_section_m2(double lambda_nm)
{
    double l = lambda_nm * 1e-3; /* micrometres */
    double a, b, c, d;
    if (l <= 0.5) {
        a = 3.01577e-28, b = 3.55212, c = 1.35579, d = 0.11563;
    } else {
        a = 4.01061e-28, b = 3.99668, c = 1.10298e-3, d = 2.71393e-2;
    }
    return a * pow(l, -(b + c * l + d / l)) * FM_CM2;
}

double rayleigh_king_factor(double lambda_nm)
{
    double l2 = 1.0 / ((lambda_nm * 1e-3) * (lambda_nm * 1e-3)); /* micrometres^-2 */
    double f_n2 = 1.034 + 3.17e-4 * l2;
    double f_o2 = 1.096 + 1.385e-3 * l2 + 1.448e-4 * l2 * l2;
    double f_ar = 1.00, f_co2 = 1.15;
    return (78.084 * f_n2 + 20.946 * f_o2 + 0.934 * f_ar + 0.036 * f_co2) / (78.084 + 20.946 + 0.934 + 0.036);
}

double rayleigh_depolarization_ratio(double lambda_nm)
{
    double f = rayleigh_king_factor(lambda_nm);
    return 6.0 * (f - 1.0) / (3.0 + 7.0 * f);
}

double rayleigh_gamma(double lambda_nm)
{
    double rho = rayleigh_depolarization_ratio(lambda_nm);
    return rho / (2.0 - rho);
}
