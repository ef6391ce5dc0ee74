#include "thick_media_cases.h"

#include "check.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

fm_sky *cloud_sky(const cloud *c, double altitude_m, char **path)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"planet_radius_km\": 1000000, \"top_altitude_km\": 3, \"ground_albedo\": %.17g, "
             "\"solar_irradiance\": 1, \"constituents\": [{\"name\": \"cloud\", \"profile\": {\"type\": "
             "\"tabulated\", \"altitudes_km\": [0, 0.95, 1.0, 2.0, 2.05, 3.0], \"values\": [0, 0, 1, 1, 0, 0]}, "
             "\"extinction\": %.17g, \"single_scattering_albedo\": %.17g, \"phase\": {\"type\": "
             "\"henyey-greenstein\", \"g\": %.17g}}]}",
             c->albedo, c->tau / 1050.0, c->ssa, c->g); /* 1000 m + two half ramps of 50 m */
    *path = test_write_temp("cloud", text);
    fm_sky_params p = fm_sky_params_default();
    p.atmosphere_file = *path;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = CLOUD_SUN_ELEVATION;
    p.observer_altitude_m = altitude_m;
    return test_sky(&p);
}

void drop_cloud_sky(fm_sky *sky, char *path)
{
    fm_sky_destroy(sky);
    unlink(path);
    free(path);
}

ad_solution cloud_reference(const cloud *c, int n_mu, const double *mu)
{
    ad_problem p = {.tau = c->tau, .ssa = c->ssa, .ground_albedo = c->albedo,
                    .mu0 = sin(CLOUD_SUN_ELEVATION * FM_DEG), .phase = ad_phase_hg, .phase_ctx = &c->g,
                    .streams = c->tau < 5.0 ? 32 : 16, .delta_m = 1, .n_mu = n_mu, .mu = mu};
    ad_solution s;
    if (ad_solve(&p, &s))
        fail_msg("ad_solve failed");
    return s;
}

double cloud_irradiance(const fm_sky *sky, double up, int N, uint64_t seed, double *se)
{
    path_context all = sky_path_context(sky, 1, 0);
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < N; i++) {
        rng r = rng_for(seed, 0, (uint64_t)i);
        double u1 = rng_uniform(&r), u2 = rng_uniform(&r), s = sqrt(u1), phi = 2.0 * FM_PI * u2;
        vec3 d = v3(s * cos(phi), s * sin(phi), up * sqrt(1.0 - u1));
        double L[FM_MAX_WAVELENGTHS] = {0};
        path_trace(&all, sky->observer, d, 0, &r, L);
        sum += L[0];
        sum2 += L[0] * L[0];
    }
    double mean = sum / N;
    *se = FM_PI * sqrt(fmax(0.0, sum2 / N - mean * mean) / N);
    return FM_PI * mean;
}
