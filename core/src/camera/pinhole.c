#include "camera/pinhole.h"

#include <math.h>

void pinhole_init(pinhole *p, int width, int height, double fov, double azimuth, double elevation)
{
    p->width = width;
    p->height = height;
    p->scale = 2.0 * tan(0.5 * fov) / width;
    p->forward = direction_from_elevation_azimuth(elevation, azimuth);
    p->right = v3(cos(azimuth), -sin(azimuth), 0.0); /* east when looking north */
    p->up = v3_cross(p->right, p->forward);
}

static void plane(const pinhole *p, double x, double y, double *X, double *Y)
{
    *X = (x - 0.5 * p->width) * p->scale;
    *Y = (0.5 * p->height - y) * p->scale;
}

vec3 pinhole_direction(const pinhole *p, double x, double y)
{
    double X, Y;
    plane(p, x, y, &X, &Y);
    return v3_normalize(v3_add(p->forward, v3_add(v3_scale(p->right, X), v3_scale(p->up, Y))));
}

int pinhole_project(const pinhole *p, vec3 d, double *x, double *y)
{
    double z = v3_dot(d, p->forward);
    if (!(z > 0.0))
        return 0;
    *x = 0.5 * p->width + v3_dot(d, p->right) / z / p->scale;
    *y = 0.5 * p->height - v3_dot(d, p->up) / z / p->scale;
    return 1;
}

double pinhole_jacobian(const pinhole *p, double x, double y)
{
    double X, Y;
    plane(p, x, y, &X, &Y);
    double q = 1.0 + X * X + Y * Y;
    return p->scale * p->scale / (q * sqrt(q));
}

static double corner(double X, double Y)
{
    return atan(X * Y / sqrt(1.0 + X * X + Y * Y));
}

double pinhole_rect_solid_angle(const pinhole *p, double x0, double y0, double x1, double y1)
{
    double X0, Y0, X1, Y1;
    plane(p, x0, y1, &X0, &Y0); /* y grows downward: y1 is the lower edge */
    plane(p, x1, y0, &X1, &Y1);
    return corner(X1, Y1) - corner(X0, Y1) - corner(X1, Y0) + corner(X0, Y0);
}

double pinhole_vertical_fov(const pinhole *p)
{
    return 2.0 * atan(0.5 * p->height * p->scale);
}

double pinhole_sample(const pinhole *p, double x, double y, vec3 *d)
{
    double X, Y;
    plane(p, x, y, &X, &Y);
    double q = 1.0 + X * X + Y * Y, inv = 1.0 / sqrt(q);
    *d = v3_scale(v3_add(p->forward, v3_add(v3_scale(p->right, X), v3_scale(p->up, Y))), inv);
    return p->scale * p->scale * inv / q;
}
