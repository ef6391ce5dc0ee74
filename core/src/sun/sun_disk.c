#include "sun/sun_disk.h"

#include "base/quadrature.h"
#include "base/units.h"
#include "data/tables.h"

#include <math.h>

void sun_limb_darkening_coefficients(double lambda_nm, double a[SUN_LD_TERMS])
{
    const int n = FM_LIMB_DARKENING_COUNT;
    const double (*t)[8] = fm_limb_darkening_neckel_labs;
    if (lambda_nm <= t[0][0]) {
        for (int m = 0; m < SUN_LD_TERMS; m++)
            a[m] = t[0][1 + m];
        return;
    }
    if (lambda_nm >= t[n - 1][0]) {
        for (int m = 0; m < SUN_LD_TERMS; m++)
            a[m] = t[n - 1][1 + m];
        return;
    }
    int i = 0;
    while (i < n - 2 && t[i + 1][0] <= lambda_nm)
        i++;
    double f = (lambda_nm - t[i][0]) / (t[i + 1][0] - t[i][0]);
    for (int m = 0; m < SUN_LD_TERMS; m++)
        a[m] = t[i][1 + m] * (1.0 - f) + t[i + 1][1 + m] * f;
}

/* integral of cos^n over [-pi/2, pi/2] and of (1 - t^2)^(m/2) over [-1, 1] */
static double cos_power_integral(int n) { return sqrt(FM_PI) * tgamma(0.5 * (n + 1)) / tgamma(0.5 * n + 1.0); }
static double chord_factor(int m) { return sqrt(FM_PI) * tgamma(0.5 * m + 1.0) / tgamma(0.5 * m + 1.5); }

/* Gauss-Legendre in phi over [lo, pi/2] with FM_SUN_CHORD_POINTS nodes */
static void chord_rule(const sun_disk *sun, int wavelengths, double lo, sun_chord_rule *rule)
{
    double rho = sun->angular_radius;
    double hi = 0.5 * FM_PI;
    if (hi - lo <= 0.0) {
        rule->n = 0;
        return;
    }
    const gauss_rule *g = gauss_legendre_cached(FM_SUN_CHORD_POINTS);
    double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
    rule->n = g->n;
    for (int j = 0; j < g->n; j++) {
        double phi = mid + half * g->x[j];
        double c = cos(phi);
        rule->delta[j] = rho * sin(phi);
        for (int k = 0; k < wavelengths; k++) {
            double chord = 0.0, cp = c * c; /* cos^(m+2) */
            for (int m = 0; m < SUN_LD_TERMS; m++) {
                chord += sun->ld[k][m] * sun->chord_b[m] * cp;
                cp *= c;
            }
            rule->weight[j][k] = half * g->w[j] * chord / sun->chord_norm[k];
        }
    }
}

void sun_disk_init(sun_disk *sun, const spectral_grid *grid, double earth_sun_distance_au)
{
    double d = earth_sun_distance_au * FM_ASTRONOMICAL_UNIT_M;
    sun->angular_radius = asin(FM_SUN_RADIUS_M / d);
    sun->solid_angle = 2.0 * FM_PI * (1.0 - cos(sun->angular_radius));
    for (int m = 0; m < SUN_LD_TERMS; m++)
        sun->chord_b[m] = chord_factor(m);
    for (int k = 0; k < grid->count; k++) {
        double *a = sun->ld[k];
        sun_limb_darkening_coefficients(grid->lambda_nm[k], a);
        /* normalise so I(centre) = 1 exactly (the published rows sum to 1 within rounding) */
        double s = a[0] + a[1] + a[2] + a[3] + a[4] + a[5];
        for (int m = 0; m < SUN_LD_TERMS; m++)
            a[m] /= s;
        double mean = 0.0, norm = 0.0;
        for (int m = 0; m < SUN_LD_TERMS; m++) {
            mean += 2.0 * a[m] / (m + 2);
            norm += a[m] * sun->chord_b[m] * cos_power_integral(m + 2);
        }
        sun->ld_mean[k] = mean;
        sun->chord_norm[k] = norm;
    }
    /* The coarse rule: nodes -a, 0, a with a^2 = M4 / M2 (moments of the limb-darkened chord
     * weight in delta) at the grid's middle wavelength, and weights per wavelength that integrate
     * 1 and delta^2 exactly there: exact for cubic transmittance, and for the quartic at the
     * middle wavelength. */
    chord_rule(sun, grid->count, -0.5 * FM_PI, &sun->full);
    const sun_chord_rule *fine = &sun->full;
    double m2[FM_MAX_WAVELENGTHS], m4 = 0.0;
    const int mid = grid->count / 2;
    for (int k = 0; k < grid->count; k++) {
        m2[k] = 0.0;
        for (int j = 0; j < fine->n; j++) {
            double d2 = fine->delta[j] * fine->delta[j];
            m2[k] += fine->weight[j][k] * d2;
            if (k == mid)
                m4 += fine->weight[j][k] * d2 * d2;
        }
    }
    double a2 = m4 / m2[mid];
    sun->coarse.n = FM_SUN_COARSE_CHORD_POINTS;
    sun->coarse.delta[0] = -sqrt(a2);
    sun->coarse.delta[1] = 0.0;
    sun->coarse.delta[2] = sqrt(a2);
    for (int k = 0; k < grid->count; k++) {
        double w = 0.5 * m2[k] / a2;
        sun->coarse.weight[0][k] = sun->coarse.weight[2][k] = w;
        sun->coarse.weight[1][k] = 1.0 - 2.0 * w;
    }
}

void sun_chord_rule_above(const sun_disk *sun, int wavelengths, double delta_min, sun_chord_rule *rule)
{
    double rho = sun->angular_radius;
    double lo = delta_min <= -rho ? -0.5 * FM_PI : (delta_min >= rho ? 0.5 * FM_PI : asin(delta_min / rho));
    chord_rule(sun, wavelengths, lo, rule);
}
