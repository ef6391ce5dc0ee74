/* The next direction of a path at a vertex (path.h): in the air, from the medium's phase function,
 * the sun guide or the sky guide; at the ground, cosine-weighted or from the sun guide.  The
 * techniques are combined by one-sample MIS with the balance heuristic, every wavelength's pdf in
 * it, so the path's spectral weights (q: pdf ratios to the hero's, w: f / p) stay exact. */
#ifndef FM_TRANSPORT_PATH_DIRECTION_H
#define FM_TRANSPORT_PATH_DIRECTION_H

#include "base/rng.h"
#include "transport/path_context.h"

/* Mixture phase function sigma_s-weighted over species at densities n: fills p[k] for every grid
 * wavelength (returns the scattering coefficients in sigma_s[k]). */
void medium_phase(const atmosphere *atm, const double *n, double cos_theta, double *p, double *sigma_s);

/* A new direction at the scattering vertex x with densities n (scattering coefficients sig_s),
 * arrived along the unit vector d, drawn at hero wavelength h; updates q and w. */
vec3 scatter_direction(const path_context *ctx, vec3 x, const double *n, const double *sig_s, vec3 d, int h, rng *r,
                       double *q, double *w);

/* A direction leaving the Lambertian ground whose outward unit normal is `normal` into *out;
 * updates q and w.  Returns 0 when the direction drawn goes into the ground (no light). */
int ground_direction(const path_context *ctx, vec3 normal, int h, rng *r, double *q, double *w, vec3 *out);

#endif
