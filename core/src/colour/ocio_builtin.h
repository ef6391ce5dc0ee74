/* The colour spaces of presets/ocio/config.ocio compiled in, for builds without OpenColorIO (the
 * Windows build): ocio_builtin.c implements ocio.h from these tables, which
 * tools/ocio_builtin_table.py generates from the config (ocio_builtin_table.c). */
#ifndef FM_COLOUR_OCIO_BUILTIN_H
#define FM_COLOUR_OCIO_BUILTIN_H

#include <stddef.h>

typedef enum { BUILTIN_LINEAR, BUILTIN_EXPONENT_WITH_LINEAR } builtin_curve;

typedef struct builtin_space {
    const char *name;
    const char *aliases[3];
    int is_data;
    /* to the reference: the curve (OCIO's ExponentWithLinearTransform, forward), then the matrix */
    builtin_curve curve;
    double gamma, offset;
    double to_reference[9]; /* row-major 3x3, RGB -> CIE XYZ D65 */
} builtin_space;

typedef struct builtin_pair {
    const char *name, *space; /* a role and its colour space */
} builtin_pair;

typedef struct builtin_view {
    const char *display, *view, *space;
} builtin_view;

extern const builtin_space builtin_spaces[];
extern const int builtin_space_count;
extern const builtin_pair builtin_roles[];
extern const int builtin_role_count;
extern const builtin_view builtin_views[];
extern const int builtin_view_count;

#endif
