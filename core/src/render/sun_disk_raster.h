/* The sun disk in a rendered map: the limb-darkened disk, attenuated along each line of sight,
 * integrated over each pixel's footprint and added to the pixels (and kept apart in
 * fm_image.sun_disk). */
#ifndef FM_RENDER_SUN_DISK_RASTER_H
#define FM_RENDER_SUN_DISK_RASTER_H

#include "camera/camera.h"
#include "sky.h"

/* Adds the disk to img (which has a sun_disk plane) as cam sees it; FM_ERR_OUT_OF_MEMORY when its
 * tables cannot be allocated. */
fm_status sun_disk_rasterise(const fm_sky *sky, const camera *cam, fm_image *img);

#endif
