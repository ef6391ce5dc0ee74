/* A camera: how image positions map to directions (+X east, +Y north, +Z up) and back, what solid
 * angle each pixel covers, and where the image ends.  One interface over the equirectangular map
 * (equirect.h), the upward fisheye (fisheye.h) and the pinhole view (pinhole.h); positions (x, y) are
 * in pixel units from the image's top-left corner, pixel (px, py) covering [px, px+1] x [py, py+1]. */
#ifndef FM_CAMERA_CAMERA_H
#define FM_CAMERA_CAMERA_H

#include "camera/fisheye.h"
#include "camera/pinhole.h"
#include "firmament/firmament.h"

typedef struct camera {
    fm_camera_type type;
    int width, height;
    fisheye fish; /* FM_CAMERA_FISHEYE */
    pinhole pin;  /* FM_CAMERA_PINHOLE */
} camera;

/* Checks the parameters of params->type (the others are ignored) and the image height they give for
 * an already valid width; errors name the field ("camera.fov_deg: ..."). */
fm_status camera_init(camera *c, const fm_camera *params, int width, fm_error *err);

const char *camera_type_name(fm_camera_type type);            /* "equirect", "fisheye", "pinhole" */
const char *camera_fisheye_projection_name(fm_fisheye_projection projection); /* "equidistant", ... */

/* Direction through position (x, y); returns 1 when it is part of the image (0 outside the
 * fisheye's circle, where d still continues the mapping). */
int camera_direction(const camera *c, double x, double y, vec3 *d);

/* Continuous image position of direction d (possibly outside the image); 0 when the camera cannot
 * place it (behind a pinhole camera, the fisheye's nadir). */
int camera_project(const camera *c, vec3 d, double *x, double *y);

/* The pixel that shows direction d; 0 when no pixel does. */
int camera_pixel(const camera *c, vec3 d, int *px, int *py);

/* Solid angle per square pixel (sr) at (x, y); 0 outside the image. */
double camera_jacobian(const camera *c, double x, double y);

/* camera_direction and camera_jacobian in one: the direction into *d, the Jacobian returned (0
 * outside the image). */
double camera_sample(const camera *c, double x, double y, vec3 *d);

/* Solid angle (sr) of the part of pixel (px, py) that belongs to the image: closed forms for the
 * equirect and pinhole cameras, Green's theorem for the fisheye (exact to rounding). */
double camera_pixel_solid_angle(const camera *c, int px, int py);

/* Solid angle of the whole image: 4 pi, 2 pi, or the pinhole's frustum. */
double camera_solid_angle(const camera *c);

/* The part [lo, hi] of the vertical segment at x, y in [y0, y1], that belongs to the image; 0 when
 * none does. */
int camera_column_span(const camera *c, double x, double y0, double y1, double *lo, double *hi);
/* The same for the horizontal segment at y, x in [x0, x1]. */
int camera_row_span(const camera *c, double y, double x0, double x1, double *lo, double *hi);

#endif
