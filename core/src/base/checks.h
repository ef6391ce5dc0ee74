/* Debug checks of the physics' preconditions, for assert(): directions of unit length,
 * probabilities in [0, 1].  With NDEBUG (release builds) they cost nothing. */
#ifndef FM_BASE_CHECKS_H
#define FM_BASE_CHECKS_H

#include "base/vec.h"

#include <math.h>

/* |d| = 1 to within the rounding of a normalised vector (a few ulp; 1e-9 leaves room for products
 * of rotations) */
static inline int is_unit(vec3 d) { return fabs(v3_dot(d, d) - 1.0) < 1e-9; }

static inline int is_probability(double p) { return p >= 0.0 && p <= 1.0; }

#endif
