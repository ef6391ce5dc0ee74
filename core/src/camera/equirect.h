/* Equirectangular camera in Blender's Environment Texture layout (verified in Blender 3.4, see
 * ARCHITECTURE.md section 4): a W x H map, H = W / 2; image column coordinate u in [0, 1) from
 * the left edge, row coordinate v in [0, 1] from the top;
 *     azimuth (from north toward east) = 2 pi (u - 0.25),   so north is at u = 0.25, east at 0.5,
 *     elevation = pi (0.5 - v),                              the top row is the zenith.
 * Axes: +X east, +Y north, +Z up. */
#ifndef FM_CAMERA_EQUIRECT_H
#define FM_CAMERA_EQUIRECT_H

#include "base/vec.h"

/* Direction through image position (x, y) in pixel units (x in [0, W), y in [0, H)). */
vec3 equirect_direction(int width, int height, double x, double y);

/* Elevation and azimuth (rad) through image position (x, y). */
void equirect_angles(int width, int height, double x, double y, double *elevation, double *azimuth);

/* Pixel containing direction d; returns 0 for a degenerate direction. */
int equirect_pixel(int width, int height, vec3 d, int *px, int *py);

/* Solid angle (sr) of any pixel of row py. */
double equirect_pixel_solid_angle(int width, int height, int py);

#endif
