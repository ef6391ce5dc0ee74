/* A check of an EXR's header attributes, for the files that go to OpenEXR's C++ library (DWA:
 * exr_recode.h): that library allocates what an attribute claims before reading it, and reads a
 * known type by its own layout rather than by the size the attribute declares, so a corrupt header
 * of a few bytes' file can make it allocate gigabytes (a string that claims 2 GB, or a channel list
 * shorter than declared that puts the next attribute's size anywhere). */
#ifndef FM_IMAGE_EXR_ATTRIBUTES_H
#define FM_IMAGE_EXR_ATTRIBUTES_H

#include <stdint.h>

/* Whether every attribute of the file's headers claims no more bytes than the file holds after it,
 * and the known types' contents take exactly the bytes they declare (so that any reader walks the
 * header as the declared sizes do). */
int exr_attributes_fit(const char *path, int64_t file_bytes);

#endif
