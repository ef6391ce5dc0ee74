#include "aerosol/ice_halo.h"

#include "base/units.h"

#include <math.h>
#include <pthread.h>

#define BINS 1800  /* 0.1-degree bins of the scattering angle */
#define GRID_MU 3600
#define GRID_PHI 1800

static double density[BINS]; /* sr^-1 over each bin */
static double mean_cos;
static pthread_once_t once = PTHREAD_ONCE_INIT;

double ice_halo_minimum_deviation(double n)
{
    return 2.0 * asin(n * 0.5) - FM_PI / 3.0;
}

/* Unpolarised Fresnel transmittance for cosines of incidence ci and transmission ct, index ratio
 * eta = n_incident / n_transmitted. */
static double fresnel_t(double ci, double ct, double eta)
{
    double rs = (eta * ci - ct) / (eta * ci + ct), rp = (eta * ct - ci) / (eta * ct + ci);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

/* Refracts unit d at a surface of unit normal nrm (against d) with index ratio eta; 0 when the
 * surface reflects it totally, else 1 with out, the cosine of transmission in *ct. */
static int refract(const double d[3], const double nrm[3], double eta, double out[3], double *ci, double *ct)
{
    *ci = -(d[0] * nrm[0] + d[1] * nrm[1] + d[2] * nrm[2]);
    double s2 = eta * eta * (1.0 - *ci * *ci);
    if (s2 >= 1.0)
        return 0;
    *ct = sqrt(1.0 - s2);
    for (int i = 0; i < 3; i++)
        out[i] = eta * d[i] + (eta * *ci - *ct) * nrm[i];
    return 1;
}

static void build(void)
{
    /* the prism's edge along z; the outward normals of its faces 120 degrees apart (faces 1 and 3 of
     * the hexagon, whose planes meet at 60 degrees) */
    const double n1[3] = {cos(210.0 * FM_DEG), sin(210.0 * FM_DEG), 0.0};
    const double in2[3] = {-cos(330.0 * FM_DEG), -sin(330.0 * FM_DEG), 0.0}; /* face 2's inward normal */
    const double n = ICE_REFRACTIVE_INDEX;
    double weight[BINS] = {0}, total = 0.0, cos_sum = 0.0;
    for (int a = 0; a < GRID_MU; a++) {
        double mu = -1.0 + 2.0 * (a + 0.5) / GRID_MU, s = sqrt(1.0 - mu * mu);
        for (int b = 0; b < GRID_PHI; b++) {
            double phi = 2.0 * FM_PI * (b + 0.5) / GRID_PHI, d[3] = {s * cos(phi), s * sin(phi), mu}, t[3], o[3];
            double ci1, ct1, ci2, ct2;
            if (d[0] * n1[0] + d[1] * n1[1] >= 0.0 || !refract(d, n1, 1.0 / n, t, &ci1, &ct1))
                continue; /* not entering face 1 */
            if (t[0] * in2[0] + t[1] * in2[1] >= 0.0 || !refract(t, in2, n, o, &ci2, &ct2))
                continue; /* not heading for face 2, or reflected totally there */
            double w = ci1 * fresnel_t(ci1, ct1, 1.0 / n) * fresnel_t(ci2, ct2, n);
            double c = d[0] * o[0] + d[1] * o[1] + d[2] * o[2];
            int bin = (int)(acos(fmax(-1.0, fmin(1.0, c))) / FM_PI * BINS);
            weight[bin < BINS ? bin : BINS - 1] += w;
            total += w;
            cos_sum += w * c;
        }
    }
    for (int j = 0; j < BINS; j++) {
        double solid = 2.0 * FM_PI * (cos(FM_PI * j / BINS) - cos(FM_PI * (j + 1) / BINS));
        density[j] = weight[j] / total / solid;
    }
    mean_cos = cos_sum / total;
}

double ice_halo_phase(double cos_theta)
{
    pthread_once(&once, build);
    int j = (int)(acos(fmax(-1.0, fmin(1.0, cos_theta))) / FM_PI * BINS);
    return density[j < BINS ? j : BINS - 1];
}

double ice_halo_asymmetry(void)
{
    pthread_once(&once, build);
    return mean_cos;
}
