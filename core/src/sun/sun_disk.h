/* The Sun as a finite, limb-darkened disk.
 *
 * Angular radius: the IAU nominal solar radius over the Earth-Sun distance (0.26645 degrees at
 * 1 AU).  Limb darkening: the centre-to-limb polynomials of Neckel & Labs (1994), interpolated in
 * wavelength (data/limb_darkening_neckel_labs.c):
 *     I(lambda, mu'') / I(lambda, 1) = sum_m A_m(lambda) mu''^m,
 * mu'' = cosine of the heliocentric angle = sqrt(1 - x^2 - y^2) at a point (x, y) of the unit disk.
 * The disk's total irradiance at the top of the atmosphere is the extraterrestrial spectrum E0, so
 * its radiance is E0 I / (Omega * mean(I)).
 *
 * Irradiance from a partially visible or unevenly attenuated disk: the transmittance toward a point
 * of the disk depends (spherical symmetry) only on that point's zenith angle, which varies across
 * the disk along its vertical diameter.  With y = sin(phi) the vertical position on the disk, the
 * limb-darkened chord integral is sum_m A_m B_m cos^(m+2)(phi) with B_m = integral of
 * (1 - t^2)^(m/2) over [-1, 1]; Gauss-Legendre in phi then integrates the disk exactly for smooth
 * transmittance and handles a horizon cutting through it. */
#ifndef FM_SUN_SUN_DISK_H
#define FM_SUN_SUN_DISK_H

#include "spectrum/spectral_grid.h"

#define FM_SUN_CHORD_POINTS 12
/* Points of the whole-disk rule for a disk well above the horizon (sun_disk.coarse) */
#define FM_SUN_COARSE_CHORD_POINTS 3

/* Chord quadrature over the disk part above an elevation offset: nodes are offsets delta (rad,
 * positive toward the zenith) from the centre; weights are per wavelength and sum to 1 over the
 * whole disk.  Only the part with delta > delta_min is included (delta_min <= -radius: all).
 * Returns the number of nodes. */
typedef struct sun_chord_rule {
    int n;
    double delta[FM_SUN_CHORD_POINTS];
    double weight[FM_SUN_CHORD_POINTS][FM_MAX_WAVELENGTHS];
} sun_chord_rule;

/* The limb-darkening polynomial's terms: Neckel & Labs' a_0 .. a_5 in powers of mu2. */
#define SUN_LD_TERMS 6

typedef struct sun_disk {
    double angular_radius;                    /* rad */
    double solid_angle;                       /* sr */
    double ld[FM_MAX_WAVELENGTHS][SUN_LD_TERMS]; /* limb-darkening polynomial per grid wavelength */
    double ld_mean[FM_MAX_WAVELENGTHS];       /* disk mean of the polynomial */
    double chord_b[SUN_LD_TERMS];             /* B_m */
    double chord_norm[FM_MAX_WAVELENGTHS];    /* sum_m A_m B_m C_(m+2): the full-disk chord integral */
    /* The whole disk with FM_SUN_COARSE_CHORD_POINTS nodes in delta, weights summing to 1: where
     * the disk is well above the horizon, the transmittance across its 0.53 degrees is a
     * low-degree polynomial in delta and three chords integrate it as well as the full rule
     * (sun_transmittance_direct). */
    sun_chord_rule coarse;
    sun_chord_rule full; /* the 12-chord rule of the whole disk, computed once */
} sun_disk;

void sun_disk_init(sun_disk *sun, const spectral_grid *grid, double earth_sun_distance_au);

/* Neckel & Labs coefficients at a wavelength (clamped to 303-1099 nm). */
void sun_limb_darkening_coefficients(double lambda_nm, double a[SUN_LD_TERMS]);

/* I / I(centre) at heliocentric cosine mu2 for grid wavelength k. */
static inline double sun_limb_darkening(const sun_disk *sun, int k, double mu2)
{
    const double *a = sun->ld[k];
    return a[0] + mu2 * (a[1] + mu2 * (a[2] + mu2 * (a[3] + mu2 * (a[4] + mu2 * a[5]))));
}

/* The chord rule (FM_SUN_CHORD_POINTS nodes) over the disk part above delta_min. */
void sun_chord_rule_above(const sun_disk *sun, int wavelengths, double delta_min, sun_chord_rule *rule);

#endif
