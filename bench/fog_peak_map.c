/* fog-peak-map TAU SUN_DEG PATHS [SEED [VIEW [AZIMUTH]]]: fog 0-200 m of optical depth TAU (550 nm)
 * around an observer on the ground, the sun SUN_DEG up, the views 2-12 degrees below the sun toward it
 * (those above 1 degree) and 4 above, or the one VIEW degrees from the sun's elevation (any, AZIMUTH
 * degrees from the sun's, 0 by default): the fast path
 * against the reference's plain paths (PATHS per view; 0: none, the fast path's parts alone), with
 * the droplets' truncated peak's light at the view (fog_peak.h: its table along the sun's slant, S,
 * and its weight by view, w) and the weight that would meet the reference, (ref - fast) / S + w
 * (issue 48; docs/decisions/2026-12-07-fog-sun14.md).  The reference's random numbers are SEED's and
 * the cell's (cell_item: TAU, sun, view and azimuth), so that no two cells of a map share draws (a
 * cell's item was its place in the list, and a column of the map one draw: a +4.3 % at optical
 * depth 3 was that; docs/decisions/2026-12-07-fog-ring.md).  Not a test: a map at the precision CI
 * has no time for. */
#include "check.h"

#include "column_tables.h"
#include "render/fog_peak.h"
#include "render/fog_table.h"
#include "render/render.h"
#include "transport/single_scatter.h"
#include "transport/sky_path.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* The reference's item for a cell: its optical depth, sun, view and azimuth to a thousandth, a
 * hundredth and tenths of a degree. */
static uint64_t cell_item(double tau, double sun_deg, double view_deg, double phi_deg)
{
    return ((uint64_t)llround(1000.0 * tau) << 40) ^ ((uint64_t)llround(100.0 * (sun_deg + 90.0)) << 24) ^
           ((uint64_t)llround(10.0 * (view_deg + 90.0)) << 12) ^ (uint64_t)llround(10.0 * phi_deg);
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: fog-peak-map TAU SUN_DEG PATHS [SEED [VIEW [AZIMUTH]]]\n");
        return 2;
    }
    const double tau = atof(argv[1]), sun_deg = atof(argv[2]);
    const int N = atoi(argv[3]);
    const uint64_t seed = argc > 4 ? (uint64_t)atoll(argv[4]) : 9;
    fm_sky_params p = fm_sky_params_default();
    p.clouds = "fog";
    p.cloud_thickness_km = 0.2;
    p.cloud_tau550 = tau;
    p.wavelength_nm = 550.0;
    p.sun_elevation_deg = sun_deg;
    p.sun_azimuth_deg = 180.0;
    fm_sky *sky = test_sky(&p);
    column_tables t;
    column_tables_start(sky, 0, 1, &t);
    if (t.tw || !fog_table_applies(&t.job)) {
        fprintf(stderr, "the column does not apply\n");
        return 1;
    }
    column_tables_make(&t);
    path_context all = sky_path_context(sky, 1, 0);
    const double *peak = t.job.ms->peak;
    double offsets[] = {-2, -4, -6, -8, -10, -12, 4};
    const int views = argc > 5 ? 1 : (int)(sizeof offsets / sizeof offsets[0]);
    const double phi = argc > 6 ? atof(argv[6]) * FM_DEG : 0.0;
    if (argc > 5)
        offsets[0] = atof(argv[5]);
    printf("tau %g sun %g paths %d seed %llu\n", tau, sun_deg, N, (unsigned long long)seed);
    printf("%6s %5s %11s %11s %6s %7s %7s %7s %7s %6s %7s\n", "view", "elev", "fast", "ref", "se%", "err%", "S+%",
           "S-%", "S%", "w", "w_need");
    for (int i = 0; i < views; i++) {
        const double e = (sun_deg + offsets[i]) * FM_DEG;
        if (e < 1.0 * FM_DEG && argc <= 5)
            continue;
        const vec3 dir = render_view_direction(sky, e, phi);
        double L = 0.0, se;
        float v[1];
        single_scatter_radiance(&all, sky->observer, dir, &L);
        fog_table_peak(&t.job, dir, v);
        L += v[0];
        sky_grid_lookup(&t.ms.grid, e, phi, v);
        L += v[0];
        const double x = v3_dot(dir, sky->sun_dir), w = fog_peak_view_at(peak, 1, 0, dir.z);
        const double Sp = fog_peak_at(peak, 0, x), Sm = fog_peak_at(peak + FOG_PEAK_ANGLES, 0, x);
        const double S = Sp + Sm;
        se = 0.0;
        const uint64_t item = cell_item(tau, sun_deg, offsets[i], phi / FM_DEG);
        const double ref = N > 0 ? test_path_radiance(&all, sky->observer, dir, N, seed, item, &se) : L;
        printf("%+6.0f %5.1f %11.5g %11.5g %6.2f %+7.2f %7.2f %7.2f %7.2f %6.3f %7.2f\n", offsets[i], e / FM_DEG, L,
               ref, 100.0 * se / ref, 100.0 * (L / ref - 1.0), 100.0 * Sp / ref, 100.0 * Sm / ref, 100.0 * S / ref,
               w, w + (ref - L) / S);
        fflush(stdout);
    }
    column_tables_free(&t);
    fm_sky_destroy(sky);
    return 0;
}
