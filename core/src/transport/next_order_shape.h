/* An approximation, smooth and free of noise, of the light that a field of radiance reaching the
 * observer gives when scattered once more toward the observer: the shape through which the
 * multiple-scattering table's parts are fitted (render.c, fit_table; sky_grid_fit.h), since it
 * carries the aerosols' aureole, which no few cosines of the azimuth hold.
 *
 * Order n + 1 toward the observer along d is
 *     L(d) = integral_0^t_end T(0, t) sum_c sigma_c(x_t) integral_4pi p_c(d . d') F(x_t, d') dd' dt,
 * F(x, d') the light of order n arriving at x from d'.  The shape takes every point's F to be the
 * observer's own, F(d'), which holds where most of the scattering air is, near the observer, and
 * then the two integrals part:
 *     S(d) = sum_c tau_c(d) (p_c * F)(d),   tau_c(d) = integral_0^t_end T(0, t) sigma_c(x_t) dt,
 * the scattering path of species c along the view ray times F convolved with the species' phase
 * function (one wavelength).  With F the single-scattering table, S is the shape of order 2; with F
 * the fitted order-2 table (the single-scattering table below the horizon, whose downward rows hold
 * the ground's light), the shape of the orders above.  Desert dust at sun 30, 550 nm, the row of view
 * directions through the sun: order 2 over its shape rises smoothly from 0.69 toward the sun to 0.93
 * opposite it, its 5th cosine of the azimuth -0.009 of its mean where order 2's own is 0.53
 * (test_second_order). */
#ifndef FM_TRANSPORT_NEXT_ORDER_SHAPE_H
#define FM_TRANSPORT_NEXT_ORDER_SHAPE_H

#include "atmosphere/atmosphere.h"
#include "base/vec.h"

/* The field F above: the radiance arriving at the observer from direction d (any unit). */
typedef double (*radiance_field)(void *ctx, vec3 d);

/* S(d) above for the observer at `observer` (Earth-centred, m), at grid wavelength k, the sun toward
 * sun_dir; F(ctx, d') the field at that wavelength. */
double next_order_shape(const atmosphere *atm, vec3 observer, vec3 d, vec3 sun_dir, int k, radiance_field F,
                        void *ctx);

/* The quadrature's points about the sun are the same for every d: F there, computed once
 * (next_order_sun_field, NEXT_ORDER_SUN_POINTS values) for a table's many directions, and then
 * next_order_shape_with that, the same sum as next_order_shape's. */
#define NEXT_ORDER_SUN_POINTS (48 * 24)
void next_order_sun_field(vec3 sun_dir, radiance_field F, void *ctx, double *field);
double next_order_shape_with(const atmosphere *atm, vec3 observer, vec3 d, vec3 sun_dir, int k, radiance_field F,
                             void *ctx, const double *sun_field);

#endif
