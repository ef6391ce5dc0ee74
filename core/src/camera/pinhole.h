/* Pinhole (rectilinear) camera: a W x H image on the plane at unit distance along the look direction
 * f, level (no roll): its x axis r is horizontal, to the right of the look direction, and its y axis
 * u = r x f points up, toward the zenith side.  With s = 2 tan(fov / 2) / W the image-plane size of
 * a pixel, position (x, y) in pixel units (y down) is the plane point
 *     X = (x - W/2) s,   Y = (H/2 - y) s,   direction = normalise(f + X r + Y u),
 * and a pixel [X0, X1] x [Y0, Y1] subtends exactly
 *     F(X1, Y1) - F(X0, Y1) - F(X1, Y0) + F(X0, Y0),   F(X, Y) = atan(X Y / sqrt(1 + X^2 + Y^2))
 * (the solid angle of a rectangle on the plane, the integral of (1 + X^2 + Y^2)^(-3/2) dX dY). */
#ifndef FM_CAMERA_PINHOLE_H
#define FM_CAMERA_PINHOLE_H

#include "base/vec.h"

typedef struct pinhole {
    int width, height;
    double scale;             /* s: image-plane units per pixel */
    vec3 forward, right, up;  /* f, r, u */
} pinhole;

/* fov: horizontal field of view (rad, in (0, pi)); azimuth from north toward east and elevation of
 * the look direction (rad).  At elevation +-90 degrees r still follows the azimuth (continuity). */
void pinhole_init(pinhole *p, int width, int height, double fov, double azimuth, double elevation);

vec3 pinhole_direction(const pinhole *p, double x, double y);

/* Image position of direction d; returns 0 when d does not point in front of the camera. */
int pinhole_project(const pinhole *p, vec3 d, double *x, double *y);

/* Solid angle per square pixel (sr) at (x, y). */
double pinhole_jacobian(const pinhole *p, double x, double y);

/* The direction through (x, y) into *d, and the solid angle per square pixel there (sr). */
double pinhole_sample(const pinhole *p, double x, double y, vec3 *d);

/* Solid angle (sr) of the image rectangle [x0, x1] x [y0, y1] (pixel units). */
double pinhole_rect_solid_angle(const pinhole *p, double x0, double y0, double x1, double y1);

/* Vertical field of view (rad). */
double pinhole_vertical_fov(const pinhole *p);

#endif
