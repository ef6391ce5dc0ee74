/* The mean radiance over a pixel's footprint, for any camera: a pixel's value is the solid-angle
 * weighted mean of the radiance over the directions it covers (the part inside the image, for the
 * fisheye's rim), so that value x pixel solid angle is the flux it receives.
 *
 * The pixel is cut into slices, sub-columns or sub-rows, whichever cross the lines of equal elevation
 * more steeply; each slice is clipped exactly to the image (the fisheye's circle) and split exactly
 * where it crosses the horizon elevation, where radiance jumps from sky to ground (found by
 * bisection), and each part is sampled at the midpoints of equal sub-intervals weighted by the
 * camera's solid angle per pixel area.  Away from the horizon `samples` x `samples` points suffice
 * (the sky is smooth); within a band around it, where radiance climbs steeply toward the horizon,
 * samples are at most `fine` apart in angle along both axes. */
#ifndef FM_CAMERA_FOOTPRINT_H
#define FM_CAMERA_FOOTPRINT_H

#include "camera/camera.h"

/* Radiance toward unit direction d of elevation `elevation` (rad): `channels` values into out. */
typedef void (*footprint_radiance)(void *ctx, vec3 d, double elevation, float *out);

typedef struct footprint_settings {
    int samples;       /* per axis, away from the horizon */
    double horizon;    /* elevation (rad) of the discontinuity */
    double fine;       /* largest angular step near the horizon (rad) */
    double band_below; /* the band that gets fine steps: [horizon - band_below, horizon + band_above] */
    double band_above;
    int max_samples;   /* per axis and part */
} footprint_settings;

/* Steps of 0.1 degrees within 3 degrees below and 10 above the horizon (the equirect rows' band, at
 * half their 0.2 degree step: free at useful sizes, whose pixels are finer than that anyway, and it
 * keeps pixels wholly within a steep rise, like the fisheye's rim, right to 0.1%). */
footprint_settings footprint_default_settings(int samples, double horizon);

/* Mean radiance over pixel (px, py) into out[0..channels); 0 for a pixel outside the image.
 * Returns the number of radiance evaluations. */
int footprint_average(const camera *c, int px, int py, const footprint_settings *s, footprint_radiance f, void *ctx,
                      int channels, double *out);

#endif
