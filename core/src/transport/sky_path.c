#include "transport/sky_path.h"

#include <math.h>

/* The share of scattering directions drawn about the sun from the sun guide; one-sample MIS keeps
 * any share unbiased, a quarter was the least noisy: docs/decisions/2026-12-06-sun-guide-fraction.md */
#define SUN_GUIDE_FRACTION 0.25

/* The sun guide (path.h): the phase function of the aerosol species with the largest scattering
 * column at the grid's middle wavelength, whose forward peak makes the next vertex's sunlight
 * large; none without aerosols (Rayleigh scattering has no peak to find). */
static const phase_function *sun_guide_phase(const atmosphere *atm)
{
    const int k = atm->grid.count / 2;
    const phase_function *best = NULL;
    double best_column = 0.0;
    for (int c = 0; c < atm->scattering_count; c++) {
        const species *sp = &atm->species[c];
        if (sp->phase.kind == PHASE_RAYLEIGH)
            continue;
        double column = sp->sigma_s[k] * profile_column(&sp->profile);
        if (column > best_column) {
            best_column = column;
            best = &sp->phase;
        }
    }
    return best;
}

/* Where a vertex counts as in cloud for the guides (path_context.cloud_sigma_per_m): from half the
 * thinnest cloud layer's mean extinction at 550 nm, if below FM_DENSE_SIGMA_PER_M.  In a thin layer
 * of ice (cirrostratus: 0.67 per km) the crystals' forward peak weighs a direction the phase
 * function drew up to 4 times while the guides take three quarters of the directions, and under it
 * at dusk the light comes through the layer, scattered there several times: a path's weight grew
 * by that at each vertex in it (docs/decisions/2026-12-07-thin-layers-dusk.md). */
#define CLOUD_SIGMA_SHARE 0.5
static double cloud_sigma(const fm_sky *sky)
{
    double sigma = FM_DENSE_SIGMA_PER_M;
    for (int i = 0; i < sky->composition.cloud_count; i++)
        sigma = fmin(sigma, CLOUD_SIGMA_SHARE * sky_cloud_sigma550_per_m(sky, i));
    return sigma;
}

path_context sky_path_context(const fm_sky *sky, int min_order, int max_order)
{
    return (path_context){
        .cloud_sigma_per_m = cloud_sigma(sky),
        .sun_guide = sun_guide_phase(&sky->atm),
        .sun_guide_fraction = SUN_GUIDE_FRACTION,
        .atm = &sky->atm,
        .sun = &sky->sun,
        .sun_table = &sky->sun_table,
        .columns = &sky->columns,
        .mid_depth = &sky->mid_depth,
        .segment_sunlight = SEGMENT_SUNLIGHT_UMBRA,
        .sky_guide = NULL,
        .sky_guide_fraction = 0.0,
        .sun_dir = sky->sun_dir,
        .min_order = min_order,
        .max_order = max_order,
        .skip_ground_first = 0,
        .ground_diffuse = NULL,
    };
}
