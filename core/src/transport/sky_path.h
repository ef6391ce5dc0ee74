/* The path tracer's settings for a sky: which tables it reads and how it samples by day (the
 * estimator's tuning; twilight.h adds the twilight sampling on top). */
#ifndef FM_TRANSPORT_SKY_PATH_H
#define FM_TRANSPORT_SKY_PATH_H

#include "sky.h"
#include "transport/path.h"

/* A path context for the sky, counting the orders min_order .. max_order (0: unlimited). */
path_context sky_path_context(const fm_sky *sky, int min_order, int max_order);

#endif
