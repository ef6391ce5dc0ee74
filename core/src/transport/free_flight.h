/* Free-flight sampling in the spherical shell by delta (Woodcock) tracking.
 *
 * Majorants are piecewise constant over spherical shells (atmosphere.h), one per grid wavelength:
 * in shell i, shell_majorant[i][k] bounds the extinction at wavelength k, so tentative collisions
 * are exact for the continuous, altitude-dependent medium whatever dominates it (ozone high up,
 * aerosols low down), and tight enough that few tentative collisions are null.  Distances are
 * sampled with the hero wavelength's majorant; the walk also returns every wavelength's majorant
 * optical depth so the path can carry the exact pdf of each wavelength (spectral MIS).
 * A segment is the part of a ray inside the atmosphere, from its origin to the ground or the top;
 * positions along it are distances t >= 0 from the origin. */
#ifndef FM_TRANSPORT_FREE_FLIGHT_H
#define FM_TRANSPORT_FREE_FLIGHT_H

#include "atmosphere/atmosphere.h"
#include "base/vec.h"

typedef struct ray_segment {
    vec3 origin, dir;  /* Earth-centred position (m) and unit direction */
    double s0;         /* origin . dir: t + s0 is the signed distance from the closest approach */
    double p2;         /* squared distance of the ray's line from the centre (m^2) */
    double t_end;      /* distance to the ground or the top */
    int hits_ground;
} ray_segment;

void ray_segment_init(ray_segment *seg, const atmosphere *atm, vec3 origin, vec3 dir);

static inline double ray_segment_radius(const ray_segment *seg, double t)
{
    double s = t + seg->s0;
    return sqrt(seg->p2 + s * s);
}

/* Majorant optical depth over [t0, t1] for every grid wavelength. */
void free_flight_majorant_depth(const atmosphere *atm, const ray_segment *seg, double t0, double t1, double *depth);

/* Walks from t0 until wavelength `hero`'s majorant optical depth reaches tau.  Returns 1 and the
 * tentative collision's distance in *t_out (0: the segment ended first, *t_out = t_end).  depth[k]
 * receives every wavelength's majorant depth over [t0, *t_out]; *shell the shell of the collision. */
int free_flight_advance(const atmosphere *atm, const ray_segment *seg, double t0, double tau, int hero,
                        double *t_out, double *depth, int *shell);

/* Whether radius r (m) lies in the atmosphere's shell, to within the rounding of a point computed on
 * the ground or at the top (1e-9 of the radius: 6 mm). */
static inline int atmosphere_shell_contains(const atmosphere *atm, double r)
{
    return r >= atm->bottom_radius_m * (1.0 - 1e-9) && r <= atm->top_radius_m * (1.0 + 1e-9);
}

/* Shell index containing radius r. */
int atmosphere_shell_of(const atmosphere *atm, double r);

#endif
