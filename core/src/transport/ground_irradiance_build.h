/* Building the diffuse ground irradiance table (ground_irradiance.h): order 1 by quadrature
 * (single_scatter.h), orders >= 2 by paths (path.h). */
#ifndef FM_TRANSPORT_GROUND_IRRADIANCE_BUILD_H
#define FM_TRANSPORT_GROUND_IRRADIANCE_BUILD_H

#include "transport/ground_irradiance.h"
#include "transport/path_context.h"

#include <stdatomic.h>

/* The order-1 quadrature: rows in elevation, columns in azimuth over half the sky (each at most
 * FM_GAUSS_MAX, base/quadrature.h), Gauss-Legendre points per piece along each ray (single_scatter.h). */
typedef struct ground_quadrature {
    int rows, cols, points;
} ground_quadrature;

/* Builds the table for local sun zenith angles within max_offset (rad) of theta_s: order 1 from
 * all_orders' sun and atmosphere on the given grid, orders >= 2 from `paths` paths of all_orders
 * (its min_order raised to 2); paths = 0 leaves orders >= 2 to the caller (ground_irradiance_add). */
fm_status ground_irradiance_build(ground_irradiance *g, const path_context *all_orders, double theta_s,
                                  double max_offset, ground_quadrature quadrature, int paths, uint64_t seed,
                                  int threads, const atomic_int *cancel);
#endif
