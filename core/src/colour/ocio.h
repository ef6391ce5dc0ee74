/* The one door to OpenColorIO (a C++ library): a C interface, so that nothing else in the core sees
 * C++.  Every colour-space conversion of firmament goes through it.  Functions that can fail
 * return 0 on success, else nonzero with one line of text in msg. */
#ifndef FM_COLOUR_OCIO_H
#define FM_COLOUR_OCIO_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct ocio_config ocio_config;

/* Reads the config at path; NULL or "" reads $OCIO.  Returns NULL on failure (msg says why). */
ocio_config *ocio_config_open(const char *path, char *msg, size_t msg_size);
void ocio_config_close(ocio_config *cfg); /* accepts NULL */

int ocio_colorspace_count(const ocio_config *cfg);
const char *ocio_colorspace_name(const ocio_config *cfg, int index);
/* The canonical name of a colour space given by name, alias or role, or NULL when unknown. */
const char *ocio_colorspace_find(const ocio_config *cfg, const char *name);

/* Nonzero when the named space holds data (never converted). */
int ocio_colorspace_is_data(const ocio_config *cfg, const char *name);

/* Converts n interleaved RGB (or XYZ) float triples in place from space src to space dst. */
int ocio_convert(const ocio_config *cfg, const char *src, const char *dst, float *rgb, size_t n, char *msg,
                 size_t msg_size);

/* Applies the display/view transform (e.g. display "sRGB", view "Standard") to n triples in place. */
int ocio_display_view(const ocio_config *cfg, const char *src, const char *display, const char *view, float *rgb,
                      size_t n, char *msg, size_t msg_size);

#ifdef __cplusplus
}
#endif

#endif
