/* DWA compression, which OpenEXR 3.1's C library can neither encode nor decode
 * (EXR_ERR_FEATURE_NOT_IMPLEMENTED): a C interface over OpenEXR's C++ library, which can.  Only
 * exr_recode.cpp sees C++. */
#ifndef FM_IMAGE_EXR_RECODE_H
#define FM_IMAGE_EXR_RECODE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum recode_target { RECODE_ZIP, RECODE_DWAA } recode_target;

/* The largest image that is read or recoded: a side (pixels) and channels (R, G, B and A, or Y). */
#define EXR_MAX_SIDE ((int64_t)1 << 16)
#define EXR_MAX_CHANNELS 4

/* Rewrites the scanline EXR at src as dst with another compression (DWAA at dwa_level: OpenEXR's
 * default is 45, higher is smaller and lossier), keeping every header attribute and every pixel
 * as stored, except that DWA is lossy: it quantises the channels it knows as colour (R, G, B, Y,
 * ...) through half precision, even 32-bit float ones, so values beyond 65504 do not survive it.
 * A header beyond EXR_MAX_SIDE or EXR_MAX_CHANNELS, as the C++ library reads it, is refused.
 * Returns 0 on success, else nonzero with one line in msg. */
int recode_exr(const char *src, const char *dst, recode_target target, float dwa_level, char *msg,
               size_t msg_size);

#ifdef __cplusplus
}
#endif

#endif
