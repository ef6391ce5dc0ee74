/* Internal helpers around fm_image. */
#ifndef FM_IMAGE_IMAGE_H
#define FM_IMAGE_IMAGE_H

#include "firmament/firmament.h"

/* Zero-filled image; optional sun-disk and standard-error planes.  NULL when out of memory. */
fm_image *image_create(int width, int height, int channels, fm_image_content content, int with_disk, int with_error);

#endif
