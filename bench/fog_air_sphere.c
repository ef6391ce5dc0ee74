/* fog-air-sphere SUN_DEG ALBEDO PATHS [ATMOSPHERE_FILE [SEED]]: the diffuse irradiance on the ground
 * of a clear sky (550 nm; the built-in atmosphere or the file's; ground albedo ALBEDO unless the file
 * gives one) from the fog column's air (render/fog_column.h: its layers, moments, delta-M and
 * pseudo-spherical beam as fog_sums.c solves them, a 1 m "fog" of air at the bottom) against the
 * plain path tracer's (PATHS cosine-weighted directions; 0: none), and the same column with the
 * downward radiance at its Gauss nodes read at the sphere's slant (fog_sphere_sky_cosines' mapping).
 * The column is plane-parallel in its diffuse light: on a planet of 6360 km it is 1.7-2.2 % brighter
 * than the paths, on one of 10^6 km within 0.1 %; the fog's sky, lit mostly by that light at a low
 * sun, is bright by as much times its share (issue 48; docs/decisions/2026-12-08-fog-air-sphere.md).
 * Not a test. */
#include "check.h"

#include "thick_media_cases.h"

#include "atmosphere/sun_irradiance.h"
#include "base/quadrature.h"
#include "render/fog_column.h"
#include "sky.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The downward flux at the column's bottom (per mu0 F0) and, in Ep and Es, the Gauss sum of its
 * diffuse irradiance (per F0) from the nodes' radiance as it is and read at the sphere's slant. */
static double column_flux(const fog_column *fc, const fm_sky *sky, const plane_layer *pl, double *Ep, double *Es)
{
    const atmosphere *atm = &sky->atm;
    const int NQ = FOG_STREAMS, M = FOG_MOMENTS, k = 0;
    double mu[2 * FOG_STREAMS], modes[2 * FOG_STREAMS * FOG_MOMENTS], flux, Tv[FM_MAX_WAVELENGTHS],
        Tm[FM_MAX_WAVELENGTHS];
    plane_column_nodes(NQ, mu);
    const double r = atm->bottom_radius_m + 1.0;
    sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, 1.0, Tv);
    for (int j = 0; j < NQ; j++) {
        sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, r, mu[j], Tm);
        mu[NQ + j] = Tm[k] > 0.0 && log(Tm[k]) < log(Tv[k]) ? fmax(log(Tv[k]) / log(Tm[k]), 1e-3) : mu[j];
    }
    plane_column col = {.streams = NQ, .layer_count = fc->layers, .layer = pl, .ground_albedo = atm->ground_albedo[k],
                        .mu0 = sky->sun_dir.z, .n_mu = 2 * NQ, .mu = mu};
    if (plane_column_level(&col, fc->layers, modes, NULL, &flux))
        exit(1);
    const gauss_rule *g = gauss_legendre_cached(NQ);
    *Ep = *Es = 0.0;
    for (int j = 0; j < NQ; j++) {
        *Ep += FM_PI * g->w[j] * mu[j] * modes[j * M];
        *Es += FM_PI * g->w[j] * mu[j] * modes[(NQ + j) * M];
    }
    return flux;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: fog-air-sphere SUN_DEG ALBEDO PATHS [ATMOSPHERE_FILE [SEED]]\n");
        return 2;
    }
    fm_sky_params p = fm_sky_params_default();
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = atof(argv[1]);
    p.sun_azimuth_deg = 180.0;
    p.ground_albedo = atof(argv[2]);
    p.atmosphere_file = argc > 4 && argv[4][0] ? argv[4] : NULL;
    const int N = atoi(argv[3]);
    const uint64_t seed = argc > 5 ? (uint64_t)atoll(argv[5]) : 5;
    fm_sky *sky = test_sky(&p);
    const atmosphere *atm = &sky->atm;
    fog_column *fc = calloc(1, sizeof *fc);
    if (!fc)
        return 1;
    fog_column_layers(fc, sky, 0.0, 1.0, atm->top_radius_m - atm->bottom_radius_m);
    fc->top_radius = atm->bottom_radius_m + 1.0;
    if (fog_species_moments(fc, atm))
        return 1;
    const double mu0 = sky->sun_dir.z;
    scaled_layer sl[PLANE_COLUMN_MAX_LAYERS];
    plane_layer pl[PLANE_COLUMN_MAX_LAYERS];
    for (int l = 0; l < fc->layers; l++)
        fog_layer_at(fc, atm, l, 0, &sl[l], &pl[l]);
    fog_air_beam_cosines(fc, sky, 0, sl, pl);
    double above = 0.0, Ep, Es, T[FM_MAX_WAVELENGTHS];
    for (int l = 0; l < fc->layers; l++)
        above += sl[l].tau * mu0 / (pl[l].mu0 > 0.0 ? pl[l].mu0 : mu0);
    const double flux = column_flux(fc, sky, pl, &Ep, &Es);
    sun_irradiance_lookup(&sky->sun_table, atm, &sky->sun, fc->top_radius, mu0, T);
    const double scale = atm->grid.solar_irradiance[0] * T[0] / exp(-above / mu0); /* as fog_sums.c */
    const double E = scale * mu0 * (flux - exp(-above / mu0)), Emap = E * Es / Ep;
    double se = 0.0;
    const double ref = N > 0 ? cloud_irradiance(sky, 1.0, N, seed, &se) : E;
    printf("sun %s albedo %s %s: column %.6g, its nodes at the sphere's slant %.6g; paths %.6g +- %.2f %%: "
           "column %+.2f %%, mapped %+.2f %%\n",
           argv[1], argv[2], p.atmosphere_file ? p.atmosphere_file : "built-in", E, Emap, ref, 100.0 * se / ref,
           100.0 * (E / ref - 1.0), 100.0 * (Emap / ref - 1.0));
    free(fc->chi);
    free(fc);
    fm_sky_destroy(sky);
    return 0;
}
