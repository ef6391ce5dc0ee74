/* Small double-precision 3-vectors and orthonormal frames. */
#ifndef FM_BASE_VEC_H
#define FM_BASE_VEC_H

#include "base/units.h"

#include <math.h>

typedef struct vec3 {
    double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline vec3 v3_madd(vec3 a, vec3 b, double s) { return v3(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double v3_length(vec3 a) { return sqrt(v3_dot(a, a)); }
static inline vec3 v3_normalize(vec3 a) { return v3_scale(a, 1.0 / v3_length(a)); }

/* Clamps a cosine into [-1, 1] before acos/sqrt(1 - mu^2). */
static inline double clamp_cosine(double mu) { return mu < -1.0 ? -1.0 : (mu > 1.0 ? 1.0 : mu); }
static inline double safe_sqrt(double a) { return a > 0.0 ? sqrt(a) : 0.0; }
/* x clamped into [lo, hi] (lo for NaN), as fmin(fmax(x, lo), hi) without two libm calls. */
static inline double clamp_between(double x, double lo, double hi) { return x > lo ? (x < hi ? x : hi) : lo; }
/* fmax without its NaN rules, which keep the compiler from inlining it (a call each: 5% of the
 * multiple-scattering time in the spectral loops, 16% of the shadow flights' light lookup); for
 * values that are never NaN. */
static inline double larger(double a, double b) { return a > b ? a : b; }

/* Orthonormal basis (t, b, n) around unit n (Duff et al. 2017, "Building an orthonormal basis,
 * revisited"): a local direction (x, y, z) maps to x t + y b + z n. */
typedef struct frame {
    vec3 t, b, n;
} frame;

static inline frame frame_from_normal(vec3 n)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double b = n.x * n.y * a;
    frame f;
    f.t = v3(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    f.b = v3(b, sign + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

static inline vec3 frame_to_world(const frame *f, vec3 local)
{
    return v3_add(v3_add(v3_scale(f->t, local.x), v3_scale(f->b, local.y)), v3_scale(f->n, local.z));
}

/* A cosine-weighted direction about the frame's normal (pdf cos / pi) from u1, u2 uniform in [0, 1);
 * u1 < 1, so it points strictly into the normal's hemisphere. */
static inline vec3 frame_cosine_direction(const frame *f, double u1, double u2)
{
    double sr = sqrt(u1), phi = 2.0 * FM_PI * u2;
    return v3_normalize(frame_to_world(f, v3(sr * cos(phi), sr * sin(phi), sqrt(1.0 - u1))));
}

/* Direction from elevation above the horizontal and azimuth from north toward east (radians):
 * +X east, +Y north, +Z up. */
static inline vec3 direction_from_elevation_azimuth(double elevation, double azimuth)
{
    double ce = cos(elevation);
    return v3(ce * sin(azimuth), ce * cos(azimuth), sin(elevation));
}

#endif
