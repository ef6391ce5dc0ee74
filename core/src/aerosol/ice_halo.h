/* The 22-degree halo: light refracted through two side faces of a hexagonal ice crystal, which meet
 * at 60 degrees, by randomly oriented crystals (geometric optics: the minimum deviation of a
 * 60-degree prism, D_min = 2 asin(n sin 30 deg) - 60 deg = 21.97 deg for ice's n = 1.3116 at 550 nm,
 * Warren & Brandt 2008, J. Geophys. Res. 113, D14220; R. Greenler, "Rainbows, Halos and Glories",
 * 1980, ch. 2; W. Tape, "Atmospheric Halos", AGU 1994).
 *
 * The distribution of the deviation is computed once by tracing rays of every direction (a uniform
 * grid over the sphere in the crystal's frame, which is what random orientation means) through the
 * prism: in through one face, out through the other, weighted by the entrance face's projected
 * area and the Fresnel transmittance of both surfaces (unpolarised); rays that the second face
 * reflects totally do not reach the halo.  Left out: the faces' finite extent (which rays reach the
 * second face rather than an end face: it sets the halo's share, not its shape or inner edge) and
 * dispersion (one index: the halo is white with its edge at 22.0 degrees, where the red edge of a
 * real halo is at 21.7 and the blue at 22.4). */
#ifndef FM_AEROSOL_ICE_HALO_H
#define FM_AEROSOL_ICE_HALO_H

#define ICE_REFRACTIVE_INDEX 1.3116 /* 550 nm (Warren & Brandt 2008) */

/* The halo's phase function (sr^-1, normalised over the sphere; 0 inside the minimum deviation). */
double ice_halo_phase(double cos_theta);

/* Its mean cosine of the scattering angle. */
double ice_halo_asymmetry(void);

/* The minimum deviation (radians) of a 60-degree prism of index n. */
double ice_halo_minimum_deviation(double n);

#endif
