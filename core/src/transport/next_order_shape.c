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

/* The azimuths' cosines and sines of the rings' points. */
static void ring_azimuths(double *cos_phi, double *sin_phi)
{
    for (int j = 0; j < AZIMUTHS; j++) {
        double phi = 2.0 * FM_PI * (j + 0.5) / AZIMUTHS;
        cos_phi[j] = cos(phi);
        sin_phi[j] = sin(phi);
    }
}

/* Ring i's polar angle's sine and cosine, and its points' solid angle. */
static void ring(int i, double *st, double *ct, double *omega)
{
    double v = (i + 0.5) / POLAR, theta = FM_PI * v * v;
    *st = sin(theta);
    *ct = cos(theta);
    *omega = *st * (2.0 * FM_PI * v / POLAR) * (2.0 * FM_PI / AZIMUTHS);
}

void next_order_sun_field(vec3 sun_dir, radiance_field F, void *ctx, double *field)
{
    double cos_phi[AZIMUTHS], sin_phi[AZIMUTHS], st, ct, omega;
    ring_azimuths(cos_phi, sin_phi);
    const frame f = frame_from_normal(sun_dir);
    for (int i = 0; i < POLAR; i++) {
        ring(i, &st, &ct, &omega);
        for (int j = 0; j < AZIMUTHS; j++)
            field[i * AZIMUTHS + j] = F(ctx, frame_to_world(&f, v3(st * cos_phi[j], st * sin_phi[j], ct)));
    }
}

/* The sphere's integral of f(d') = sum_c tau_c p_c(d . d') F(d') has two peaks: the phase functions'
 * forward peak about d and the field's aureole about the sun.  It is parted between them,
 * f = a_d f + a_s f with a_x = A_x / (A_d + A_s), A_x = 1 / (1 - d' . x + floor), and each part
 * integrated on polar rings crowded toward its own centre, where its only peak is. */
double next_order_shape_with(const atmosphere *atm, vec3 observer, vec3 d, vec3 sun_dir, int k, radiance_field F,
                             void *ctx, const double *sun_field)
{
    _Static_assert(POLAR * AZIMUTHS == NEXT_ORDER_SUN_POINTS, "the sun's rings' points");
    double tau[FM_MAX_SPECIES], cos_phi[AZIMUTHS], sin_phi[AZIMUTHS];
    scattering_paths(atm, observer, d, k, tau);
    ring_azimuths(cos_phi, sin_phi);
    const vec3 centres[2] = {d, sun_dir};
    double sum = 0.0;
    for (int centre = 0; centre < 2; centre++) {
        const frame f = frame_from_normal(centres[centre]);
        for (int i = 0; i < POLAR; i++) {
            double st, ct, omega;
            ring(i, &st, &ct, &omega);
            double p_ring = centre == 0 ? phase_sum(atm, tau, k, ct) : 0.0; /* about d: the same on the ring */
            for (int j = 0; j < AZIMUTHS; j++) {
                vec3 dp = frame_to_world(&f, v3(st * cos_phi[j], st * sin_phi[j], ct));
                double to_d = 1.0 / (1.0 - v3_dot(dp, d) + PARTITION_FLOOR);
                double to_sun = 1.0 / (1.0 - v3_dot(dp, sun_dir) + PARTITION_FLOOR);
                double share = (centre == 0 ? to_d : to_sun) / (to_d + to_sun);
                double p = centre == 0 ? p_ring : phase_sum(atm, tau, k, clamp_cosine(v3_dot(dp, d)));
                double field = centre == 1 && sun_field ? sun_field[i * AZIMUTHS + j] : F(ctx, dp);
                sum += omega * share * p * field;
            }
        }
    }
    return sum;
}

double next_order_shape(const atmosphere *atm, vec3 observer, vec3 d, vec3 sun_dir, int k, radiance_field F,
                        void *ctx)
{
    return next_order_shape_with(atm, observer, d, sun_dir, k, F, ctx, NULL);
}
