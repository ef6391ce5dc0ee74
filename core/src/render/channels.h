/* A render's image channels from spectral radiance. */
#ifndef FM_RENDER_CHANNELS_H
#define FM_RENDER_CHANNELS_H

#include "atmosphere/atmosphere.h"

/* Spectral radiance (K values) -> C image channels: XYZ (colour, C = 3), else the K values
 * themselves (monochromatic C = K = 1; spectral maps C = K). */
static inline void render_channels(const atmosphere *atm, int C, const double *L, float *out)
{
    if (atm->grid.colour && C == 3) {
        double xyz[3];
        spectral_grid_to_xyz(&atm->grid, L, xyz);
        out[0] = (float)xyz[0];
        out[1] = (float)xyz[1];
        out[2] = (float)xyz[2];
    } else {
        for (int c = 0; c < C; c++)
            out[c] = (float)L[c];
    }
}

#endif
