#include "phase/phase_rayleigh.h"

double phase_rayleigh_sample(double u, double gamma)
{
    /* CDF in x = cos_theta: F(x) = (a (x + 1) + b (x^3 + 1) / 3) / (2 a + 2 b / 3), a = 1 + 3 gamma,
     * b = 1 - gamma.  Solve b x^3 / 3 + a x = c with c = F_total (2u - 1) / 2 (odd in x):
     * a depressed cubic x^3 + P x = Q with P = 3a/b > 0, which has one real root (Cardano). */
    double a = 1.0 + 3.0 * gamma, b = 1.0 - gamma;
    double q_total = 2.0 * a + 2.0 * b / 3.0;
    double c = (2.0 * u - 1.0) * 0.5 * q_total;
    double P = 3.0 * a / b, Q = 3.0 * c / b;
    double D = sqrt(Q * Q / 4.0 + P * P * P / 27.0);
    double x = cbrt(Q / 2.0 + D) + cbrt(Q / 2.0 - D);
    return x < -1.0 ? -1.0 : (x > 1.0 ? 1.0 : x);
}
