/* Radiance RGBE pictures (.hdr): Greg Ward's format as Radiance's own programs read it (header
 * "#?RADIANCE", FORMAT=32-bit_rle_rgbe, EXPOSURE, PRIMARIES, a blank line, the resolution string
 * "-Y H +X W", then 4 bytes a pixel, top row first; written flat, without run-length encoding,
 * which every reader accepts).  The pixel values are the map's, as in the EXR; the header's
 * comment lines give the units, the factor to Radiance's convention and every metadata entry.
 * The file is written to the given path as is; output.c chooses a temporary path and renames. */
#ifndef FM_IMAGE_IMAGE_HDR_H
#define FM_IMAGE_IMAGE_HDR_H

#include "image/metadata.h"

/* Radiance's luminous efficacy of its "watts" (luminance = 179 x its Y), against firmament's 683
 * lm/W: values x 683/179 are Radiance radiances. */
#define FM_RADIANCE_EFFICACY 179.0

fm_status image_write_hdr(const char *path, const fm_image *img, const metadata *meta, const atomic_int *cancel,
                          fm_error *err);

#endif
