/* Upward-looking hemispherical (fisheye) camera: a square image of S x S pixels whose inscribed circle
 * (radius R = S / 2 pixels, centred on the image) holds the upper hemisphere.  The zenith is at the
 * centre, the horizontal on the circle.  Orientation as seen by someone looking up at the sky: north
 * up, east LEFT, south down, west right, i.e. the same unmirrored view from inside the sphere as the
 * equirectangular map (whose azimuth grows to the right).  With rho = r / R and theta the zenith angle:
 *     equidistant  rho = theta / (pi/2)
 *     equisolid    rho = sqrt(2) sin(theta / 2)      (equal-area: 1 - cos theta = rho^2)
 * and a direction at azimuth a (from north toward east) sits at
 *     x = R (1 - rho sin a),   y = R (1 - rho cos a)   (pixel units, y down).
 * Beyond the circle (the image's corners) the mapping continues below the horizontal; those
 * directions are not part of the image. */
#ifndef FM_CAMERA_FISHEYE_H
#define FM_CAMERA_FISHEYE_H

#include "base/vec.h"

typedef struct fisheye {
    int size;         /* width = height in pixels */
    double radius_px; /* R = size / 2 */
    int equisolid;    /* 0: equidistant */
} fisheye;

void fisheye_init(fisheye *f, int size, int equisolid);

/* Zenith angle (rad) at normalised radius rho, and back. */
double fisheye_theta(const fisheye *f, double rho);
double fisheye_rho(const fisheye *f, double theta);

/* Direction through image position (x, y) in pixel units; returns 1 inside the image circle. */
int fisheye_direction(const fisheye *f, double x, double y, vec3 *d);

/* The direction through (x, y) into *d, and the solid angle per square pixel there (sr), 0 outside
 * the circle: fisheye_direction and fisheye_jacobian in one. */
double fisheye_sample(const fisheye *f, double x, double y, vec3 *d);

/* Image position of direction d (any length > 0); returns 0 for the nadir, where it is undefined. */
int fisheye_project(const fisheye *f, vec3 d, double *x, double *y);

/* Solid angle per square pixel (sr) at (x, y); 0 outside the circle. */
double fisheye_jacobian(const fisheye *f, double x, double y);

/* Integral over the part of pixel (px, py) inside the circle of dOmega (cosine = 0), or of
 * cos(theta) dOmega (cosine = 1): exact to rounding, by Green's theorem (see fisheye.c). */
double fisheye_pixel_integral(const fisheye *f, int px, int py, int cosine);

/* The part [lo, hi] of the vertical segment x, y in [y0, y1] inside the circle; 0 when none (by
 * symmetry, also the horizontal segment y = x, x in [y0, y1]). */
int fisheye_column_span(const fisheye *f, double x, double y0, double y1, double *lo, double *hi);

#endif
