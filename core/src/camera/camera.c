#include "camera/camera.h"

#include "base/param_range.h"
#include "base/status.h"
#include "base/units.h"
#include "camera/equirect.h"

#include <math.h>

/* The height is bound like the width. */
static int pinhole_height(const fm_camera *p, int width)
{
    const fm_param_range *size = fm_param_range_of("width");
    if (!isfinite(p->aspect) || !(p->aspect > 0.0))
        return 0;
    double h = 2.0 * round(0.5 * width / p->aspect); /* even, like the width */
    return h >= size->min && h <= size->max ? (int)h : 0;
}

int fm_camera_height(const fm_camera *params, int width)
{
    switch (params->type) {
    case FM_CAMERA_EQUIRECT:
        return width / 2;
    case FM_CAMERA_FISHEYE:
        return width;
    case FM_CAMERA_PINHOLE:
        return pinhole_height(params, width);
    }
    return 0;
}

const char *camera_type_name(fm_camera_type type)
{
    return type == FM_CAMERA_FISHEYE ? "fisheye" : (type == FM_CAMERA_PINHOLE ? "pinhole" : "equirect");
}

const char *camera_fisheye_projection_name(fm_fisheye_projection projection)
{
    return projection == FM_FISHEYE_EQUISOLID ? "equisolid" : "equidistant";
}

fm_status camera_init(camera *c, const fm_camera *p, int width, fm_error *err)
{
    c->type = p->type;
    c->width = width;
    switch (p->type) {
    case FM_CAMERA_EQUIRECT:
        c->height = width / 2;
        return FM_OK;
    case FM_CAMERA_FISHEYE:
        if (p->fisheye_projection != FM_FISHEYE_EQUIDISTANT && p->fisheye_projection != FM_FISHEYE_EQUISOLID)
            return fm_fail_parameter(err, "camera.fisheye_projection", "%d is not a known projection",
                                     (int)p->fisheye_projection);
        c->height = width;
        fisheye_init(&c->fish, width, p->fisheye_projection == FM_FISHEYE_EQUISOLID);
        return FM_OK;
    case FM_CAMERA_PINHOLE: {
        fm_status s;
        if ((s = param_check(err, "camera.fov_deg", p->fov_deg)) ||
            (s = param_check(err, "camera.look_azimuth_deg", p->look_azimuth_deg)) ||
            (s = param_check(err, "camera.look_elevation_deg", p->look_elevation_deg)))
            return s;
        if (!isfinite(p->aspect) || !(p->aspect > 0.0))
            return fm_fail_parameter(err, "camera.aspect", "%g is not a positive width / height ratio", p->aspect);
        c->height = pinhole_height(p, width);
        if (c->height == 0)
            return fm_fail_parameter(err, "camera.aspect",
                                     "width %d / aspect %g gives a height of %.4g pixels, outside [%g, %g]", width,
                                     p->aspect, 2.0 * round(0.5 * width / p->aspect), fm_param_range_of("width")->min,
                                     fm_param_range_of("width")->max);
        pinhole_init(&c->pin, width, c->height, p->fov_deg * FM_DEG, p->look_azimuth_deg * FM_DEG,
                     p->look_elevation_deg * FM_DEG);
        return FM_OK;
    }
    }
    return fm_fail_parameter(err, "camera.type", "%d is not a known camera", (int)p->type);
}

int camera_direction(const camera *c, double x, double y, vec3 *d)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return fisheye_direction(&c->fish, x, y, d);
    case FM_CAMERA_PINHOLE:
        *d = pinhole_direction(&c->pin, x, y);
        return 1;
    case FM_CAMERA_EQUIRECT:
    default:
        *d = equirect_direction(c->width, c->height, x, y);
        return 1;
    }
}

int camera_project(const camera *c, vec3 d, double *x, double *y)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return fisheye_project(&c->fish, d, x, y);
    case FM_CAMERA_PINHOLE:
        return pinhole_project(&c->pin, d, x, y);
    case FM_CAMERA_EQUIRECT:
    default: {
        double len = v3_length(d);
        if (!(len > 0.0))
            return 0;
        double u = 0.25 + atan2(d.x, d.y) / (2.0 * FM_PI);
        *x = (u - floor(u)) * c->width;
        *y = (0.5 - asin(clamp_cosine(d.z / len)) / FM_PI) * c->height;
        return 1;
    }
    }
}

int camera_pixel(const camera *c, vec3 d, int *px, int *py)
{
    if (c->type == FM_CAMERA_EQUIRECT)
        return equirect_pixel(c->width, c->height, d, px, py);
    double x, y;
    if (!camera_project(c, d, &x, &y) || !(x >= 0.0 && x < c->width && y >= 0.0 && y < c->height))
        return 0;
    if (c->type == FM_CAMERA_FISHEYE) {
        double R = c->fish.radius_px;
        if (hypot(x - R, y - R) > R)
            return 0;
    }
    *px = (int)x;
    *py = (int)y;
    return 1;
}

double camera_jacobian(const camera *c, double x, double y)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return fisheye_jacobian(&c->fish, x, y);
    case FM_CAMERA_PINHOLE:
        return pinhole_jacobian(&c->pin, x, y);
    case FM_CAMERA_EQUIRECT:
    default: {
        double e, a;
        equirect_angles(c->width, c->height, x, y, &e, &a);
        return 2.0 * FM_PI / c->width * FM_PI / c->height * cos(e);
    }
    }
}

double camera_sample(const camera *c, double x, double y, vec3 *d)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return fisheye_sample(&c->fish, x, y, d);
    case FM_CAMERA_PINHOLE:
        return pinhole_sample(&c->pin, x, y, d);
    case FM_CAMERA_EQUIRECT:
    default:
        camera_direction(c, x, y, d);
        return camera_jacobian(c, x, y);
    }
}

double camera_pixel_solid_angle(const camera *c, int px, int py)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return fisheye_pixel_integral(&c->fish, px, py, 0);
    case FM_CAMERA_PINHOLE:
        return pinhole_rect_solid_angle(&c->pin, px, py, px + 1, py + 1);
    case FM_CAMERA_EQUIRECT:
    default:
        return equirect_pixel_solid_angle(c->width, c->height, py);
    }
}

double camera_solid_angle(const camera *c)
{
    switch (c->type) {
    case FM_CAMERA_FISHEYE:
        return 2.0 * FM_PI;
    case FM_CAMERA_PINHOLE:
        return pinhole_rect_solid_angle(&c->pin, 0.0, 0.0, c->width, c->height);
    case FM_CAMERA_EQUIRECT:
    default:
        return 4.0 * FM_PI;
    }
}

int camera_column_span(const camera *c, double x, double y0, double y1, double *lo, double *hi)
{
    if (c->type == FM_CAMERA_FISHEYE)
        return fisheye_column_span(&c->fish, x, y0, y1, lo, hi);
    *lo = fmax(y0, 0.0);
    *hi = fmin(y1, c->height);
    return *hi > *lo;
}

int camera_row_span(const camera *c, double y, double x0, double x1, double *lo, double *hi)
{
    if (c->type == FM_CAMERA_FISHEYE) /* the circle is symmetric in x and y */
        return fisheye_column_span(&c->fish, y, x0, x1, lo, hi);
    *lo = fmax(x0, 0.0);
    *hi = fmin(x1, c->width);
    return *hi > *lo;
}
