#include "transport/next_order_shape.h"

#include "base/units.h"
#include "phase/phase.h"
#include "transport/free_flight.h"

#include <math.h>

#define RAY_STEPS 64 /* midpoints along the view ray, crowded toward the observer (t = t_end u^2) */
#define POLAR 48     /* rings about each centre of the sphere's quadrature, crowded toward it
                      * (theta = pi v^2) */
#define AZIMUTHS 24  /* points per ring */
/* 1 - cos of the angle (0.8 degrees) within which the partition of the sphere (below) no longer
 * sharpens: both peaks are narrower than the table's nodes are apart */
#define PARTITION_FLOOR 1e-4

/* tau[c]: the scattering path of every species along the view ray, at wavelength k. */
static void scattering_paths(const atmosphere *atm, vec3 observer, vec3 d, int k, double *tau)
{
    ray_segment seg;
    ray_segment_init(&seg, atm, observer, d);
    double n[FM_MAX_SPECIES], sigma_s[FM_MAX_WAVELENGTHS], sigma_t[FM_MAX_WAVELENGTHS], depth = 0.0;
    for (int c = 0; c < atm->scattering_count; c++)
        tau[c] = 0.0;
    for (int j = 0; j < RAY_STEPS; j++) {
        double u0 = (double)j / RAY_STEPS, u1 = (double)(j + 1) / RAY_STEPS, um = 0.5 * (u0 + u1);
        double t = seg.t_end * um * um, dt = seg.t_end * (u1 * u1 - u0 * u0);
        atmosphere_densities(atm, ray_segment_radius(&seg, t), n);
        atmosphere_coefficients_from_densities(atm, n, sigma_s, sigma_t);
        double T = exp(-(depth + 0.5 * sigma_t[k] * dt));
        for (int c = 0; c < atm->scattering_count; c++)
            tau[c] += T * atm->species[c].sigma_s[k] * n[c] * dt;
        depth += sigma_t[k] * dt;
    }
}

/* sum_c tau_c p_c(mu) */
static double phase_sum(const atmosphere *atm, const double *tau, int k, double mu)
{
    double p = 0.0;
    for (int c = 0; c < atm->scattering_count; c++)
        if (tau[c] > 0.0)
            p += tau[c] * phase_evaluate(&atm->species[c].phase, k, mu);
    return p;
}

/* The sphere's integral of f(d') = sum_c tau_c p_c(d . d') F(d') has two peaks: the phase functions'
 * forward peak about d and the field's aureole about the sun.  It is parted between them,
 * f = a_d f + a_s f with a_x = A_x / (A_d + A_s), A_x = 1 / (1 - d' . x + floor), and each part
 * integrated on polar rings crowded toward its own centre, where its only peak is. */
double next_order_shape(const atmosphere *atm, vec3 observer, vec3 d, vec3 sun_dir, int k, radiance_field F,
                        void *ctx)
{
    double tau[FM_MAX_SPECIES], cos_phi[AZIMUTHS], sin_phi[AZIMUTHS];
    scattering_paths(atm, observer, d, k, tau);
    for (int j = 0; j < AZIMUTHS; j++) {
        double phi = 2.0 * FM_PI * (j + 0.5) / AZIMUTHS;
        cos_phi[j] = cos(phi);
        sin_phi[j] = sin(phi);
    }
    const vec3 centres[2] = {d, sun_dir};
    double sum = 0.0;
    for (int centre = 0; centre < 2; centre++) {
        const frame f = frame_from_normal(centres[centre]);
        for (int i = 0; i < POLAR; i++) {
            double v = (i + 0.5) / POLAR, theta = FM_PI * v * v, st = sin(theta), ct = cos(theta);
            double ring = st * (2.0 * FM_PI * v / POLAR) * (2.0 * FM_PI / AZIMUTHS); /* d omega */
            double p_ring = centre == 0 ? phase_sum(atm, tau, k, ct) : 0.0; /* about d: the same on the ring */
            for (int j = 0; j < AZIMUTHS; j++) {
                vec3 dp = frame_to_world(&f, v3(st * cos_phi[j], st * sin_phi[j], ct));
                double to_d = 1.0 / (1.0 - v3_dot(dp, d) + PARTITION_FLOOR);
                double to_sun = 1.0 / (1.0 - v3_dot(dp, sun_dir) + PARTITION_FLOOR);
                double share = (centre == 0 ? to_d : to_sun) / (to_d + to_sun);
                double p = centre == 0 ? p_ring : phase_sum(atm, tau, k, clamp_cosine(v3_dot(dp, d)));
                sum += ring * share * p * F(ctx, dp);
            }
        }
    }
    return sum;
}
