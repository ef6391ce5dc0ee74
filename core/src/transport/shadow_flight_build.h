/* Building the flights' table (shadow_flight.h) from single-scattering quadrature (single_scatter.h). */
#ifndef FM_TRANSPORT_SHADOW_FLIGHT_BUILD_H
#define FM_TRANSPORT_SHADOW_FLIGHT_BUILD_H

#include "transport/path_context.h"
#include "transport/shadow_flight.h"

#include <stdatomic.h>

/* Builds I from single_scatter_radiance with `single` (orders 1..1) at points above and toward the
 * sun from `observer`, on `threads` threads.  FM_ERR_OUT_OF_MEMORY, FM_ERR_CANCELLED (*cancel set) or
 * FM_ERR_INTERNAL (its threads could not run), else FM_OK. */
fm_status shadow_flight_build(shadow_flight_table *t, const path_context *single, vec3 observer, int threads,
                              const atomic_int *cancel);

#endif
