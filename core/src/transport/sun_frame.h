/* The frame of a point's sky: its up direction, the sun's direction projected on its horizontal
 * plane and the horizontal 90 degrees from that; directions in it by elevation and azimuth from the
 * sun.  (Where the sun stands at the point's zenith or nadir, any horizontal will do.) */
#ifndef FM_TRANSPORT_SUN_FRAME_H
#define FM_TRANSPORT_SUN_FRAME_H

#include "base/units.h"
#include "base/vec.h"

#include <math.h>

typedef struct sun_frame {
    vec3 up, sun_h, side;
} sun_frame;

/* The frame at the point x (Earth-centred) for the sun direction sun_dir. */
static inline sun_frame sun_frame_at(vec3 x, vec3 sun_dir)
{
    sun_frame f;
    f.up = v3_normalize(x);
    vec3 h = v3_madd(sun_dir, f.up, -v3_dot(sun_dir, f.up));
    if (v3_length(h) < 1e-9)
        h = frame_from_normal(f.up).t;
    f.sun_h = v3_normalize(h);
    f.side = v3_cross(f.up, f.sun_h);
    return f;
}

/* The direction of elevation asin(sin_e) and azimuth phi (rad) from the sun's. */
static inline vec3 sun_frame_direction(const sun_frame *f, double sin_e, double phi)
{
    double cos_e = safe_sqrt(1.0 - sin_e * sin_e);
    vec3 h = v3_add(v3_scale(f->sun_h, cos(phi)), v3_scale(f->side, sin(phi)));
    return v3_normalize(v3_madd(v3_scale(h, cos_e), f->up, sin_e));
}

/* The point at radius r reached from the frame's point by travelling the angle beta (rad of arc)
 * toward the sun: its local sun stands beta higher. */
static inline vec3 sun_frame_toward_sun(const sun_frame *f, double beta, double r)
{
    return v3_scale(v3_add(v3_scale(f->up, cos(beta)), v3_scale(f->sun_h, sin(beta))), r);
}

/* Elevation (rad) of row edge j of a grid over a point's sky whose horizon is at elevation eh (<= 0):
 * `down` rows from the nadir to eh and `up` rows from eh to the zenith, crowded (quadratically) at
 * the horizon, where the sunlit air is seen at twilight. */
static inline double sun_frame_row_elevation(int j, double eh, int down, int up)
{
    if (j <= down) {
        double v = (double)(down - j) / down;
        return eh - (0.5 * FM_PI + eh) * v * v;
    }
    double v = (double)(j - down) / up;
    return eh + (0.5 * FM_PI - eh) * v * v;
}

#endif
