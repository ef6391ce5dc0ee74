/* Building the flights' table (shadow_flight.h) from single-scattering quadrature (single_scatter.h). */
#ifndef FM_TRANSPORT_SHADOW_FLIGHT_BUILD_H
#define FM_TRANSPORT_SHADOW_FLIGHT_BUILD_H

#include "transport/path_context.h"
#include "transport/shadow_flight.h"

#include <stdatomic.h>

/* I over local sun elevations sun_step (rad) apart from the observer's up to up_to (rad), at every
 * level: a point's I depends on its altitude and its local sun elevation alone (a horizontally
 * homogeneous atmosphere), so one set of columns serves the tables of every sun below (the live sky's
 * nodes).  A table's own columns are SHADOW_FLIGHT_SUN_STEP apart; the live sky's shared ones
 * SHADOW_FLIGHT_COLUMN_STEP, half the work: I only places samples, and interpolated geometrically
 * over 2 degrees it places them as well (its paths as noisy:
 * docs/decisions/2026-12-06-live-deep-twilight-cost.md). */
#define SHADOW_FLIGHT_COLUMN_STEP (2.0 * FM_DEG)
typedef struct shadow_flight_columns {
    double sun0, sun_step; /* rad: column 0's local sun elevation, and the step */
    int suns;
    double *value;         /* [level][sun] */
} shadow_flight_columns;

fm_status shadow_flight_columns_build(shadow_flight_columns *c, const path_context *single, vec3 observer,
                                      double up_to, double sun_step, int threads, const atomic_int *cancel);
void shadow_flight_columns_free(shadow_flight_columns *c);

/* Builds I from single_scatter_radiance with `single` (orders 1..1) at points above and toward the
 * sun from `observer`, on `threads` threads; from `shared` (interpolated between its columns) when it is
 * not NULL and covers the table's local sun elevations: I only places samples (shadow_flight.h), so
 * the estimator stays unbiased.  FM_ERR_OUT_OF_MEMORY, FM_ERR_CANCELLED (*cancel set) or
 * FM_ERR_INTERNAL (its threads could not run), else FM_OK. */
fm_status shadow_flight_build(shadow_flight_table *t, const path_context *single, vec3 observer,
                              const shadow_flight_columns *shared, int threads, const atomic_int *cancel);

#endif
