/* OpenEXR output through OpenEXR's C API (OpenEXRCore): scanline, ZIP (or PIZ), 32-bit float
 * (or half when the values fit: the sun disk exceeds half-float range), chromaticities of the colour space, envmap = latlong (equirectangular maps only), whiteLuminance
 * (683 cd/m^2 for RGB = 1), and every metadata entry as a typed "firmament.<group>.<key>" attribute.
 * The file is written to the given path as is; output.c chooses a temporary path and renames. */
#ifndef FM_IMAGE_IMAGE_EXR_H
#define FM_IMAGE_IMAGE_EXR_H

#include "image/metadata.h"

/* half: 16-bit channels (the caller has checked the range); compression: FM_EXR_*; threads: those
 * that compress the chunks (0 = one per core). */
fm_status image_write_exr(const char *path, const fm_image *img, const metadata *meta, int half,
                          fm_exr_compression compression, int threads, const atomic_int *cancel, fm_error *err);

#endif
