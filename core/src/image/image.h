/* Internal helpers around fm_image. */
#ifndef FM_IMAGE_IMAGE_H
#define FM_IMAGE_IMAGE_H

#include "firmament/firmament.h"

/* Zero-filled image; optional sun-disk and standard-error planes.  NULL when out of memory. */
fm_image *image_create(int width, int height, int channels, fm_image_content content, int with_disk, int with_error);

/* Records a spectral map's wavelengths and XYZ weights (n <= FM_IMAGE_MAX_WAVELENGTHS; xyz_weight
 * row-major n x 3). */
void image_set_wavelengths(fm_image *img, int n, const double *lambda_nm, const double *xyz_weight);

/* CIE XYZ of one pixel's three channel values v, by the map's content: XYZ as is, an RGB space by
 * its own matrix, Rec.709 by the standard one. */
void image_colour_to_xyz(const fm_image *img, const double v[3], double xyz[3]);

/* Creates an empty "<dir>/.<name>.XXXXXX" beside path (a long name cut short), for writing and
 * renaming over path; returns its malloc'd name, or NULL with err filled (also when path is a
 * directory). */
char *image_reserve_temp(const char *path, fm_error *err);
/* Fails (FM_ERR_INVALID_ARGUMENT, one line) when path exists and is not a regular file: a FIFO or
 * a device would block the reader or never end. */
fm_status image_check_regular(const char *path, fm_error *err);
/* After writing tmp with status s: renames it over path when s is FM_OK, else removes it; frees tmp
 * and returns s, or the rename's failure. */
fm_status image_finish_temp(char *tmp, const char *path, fm_status s, fm_error *err);

/* The preview PNG (fm_image_write_preview) written into file as is; path is the name it will have,
 * for the messages. */
fm_status image_write_preview_file(const fm_image *img, const fm_colour_config *cfg, const char *file,
                                   const char *path, double exposure_ev, fm_error *err);

#endif
