/* Deterministic quadrature of order-1 radiance (no random numbers):
 *     L1(x, w) = integral_0^t_end T(0, t) sum_c sigma_s,c(t) p_c(w . s) E0 Tbar(x_t, s) dt
 *              + [ground hit] T(0, t_end) albedo / pi E0 Tbar_horizontal(ground)
 * along the view ray, with Gauss-Legendre on pieces between altitude breakpoints (subdivided so that
 * no piece is optically thick), the view transmittance from nested quadratures of the species
 * columns, and the sun from the same table the path tracer uses.  It is the fast path's single
 * scattering; the path tracer restricted to order 1 estimates the same integral.  When the context
 * carries a ground_irradiance table, the ground term also reflects that diffuse irradiance. */
#ifndef FM_TRANSPORT_SINGLE_SCATTER_H
#define FM_TRANSPORT_SINGLE_SCATTER_H

#include "transport/path.h"

/* Adds L1 (per grid wavelength) for the ray from origin in direction dir to L. */
void single_scatter_radiance(const path_context *ctx, vec3 origin, vec3 dir, double *L);

#endif
