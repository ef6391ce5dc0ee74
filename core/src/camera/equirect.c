#include "camera/equirect.h"

#include "base/units.h"

void equirect_angles(int width, int height, double x, double y, double *elevation, double *azimuth)
{
    *azimuth = 2.0 * FM_PI * (x / width - 0.25);
    *elevation = FM_PI * (0.5 - y / height);
}

vec3 equirect_direction(int width, int height, double x, double y)
{
    double e, a;
    equirect_angles(width, height, x, y, &e, &a);
    return direction_from_elevation_azimuth(e, a);
}

int equirect_pixel(int width, int height, vec3 d, int *px, int *py)
{
    double len = v3_length(d);
    if (!(len > 0.0))
        return 0;
    double e = asin(clamp_cosine(d.z / len));
    double a = atan2(d.x, d.y); /* from north toward east */
    double u = 0.25 + a / (2.0 * FM_PI);
    u -= floor(u);
    double v = 0.5 - e / FM_PI;
    int x = (int)(u * width), y = (int)(v * height);
    *px = x < 0 ? 0 : (x >= width ? width - 1 : x);
    *py = y < 0 ? 0 : (y >= height ? height - 1 : y);
    return 1;
}

double equirect_pixel_solid_angle(int width, int height, int py)
{
    double top = FM_PI * (0.5 - (double)py / height);
    double bottom = FM_PI * (0.5 - (double)(py + 1) / height);
    return 2.0 * FM_PI / width * (sin(top) - sin(bottom));
}
