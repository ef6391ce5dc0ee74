/* A custom atmosphere read from a JSON file (schema: docs/atmosphere-file.md): the planet radius,
 * the top of the atmosphere and explicit constituents, each a dimensionless density profile times
 * per-wavelength scattering and absorption coefficients (m^-1 where the profile is 1) and a phase
 * function; optionally the ground albedo and the solar spectrum at the top of the atmosphere.
 *
 * A constituent becomes one atmosphere species whose "number density" is the profile value and
 * whose "cross sections" are the coefficients, so every estimator sees it unchanged.  Values given
 * at listed wavelengths are interpolated linearly onto the render's grid; a grid wavelength outside
 * the listed range is an error (a single listed value means a constant).
 *
 * Every problem in the file fails with FM_ERR_INVALID_ARGUMENT for the parameter "atmosphere_file"
 * and a message "FILE: $.json.path: what is wrong" ("FILE:LINE:COLUMN: ..." for JSON syntax). */
#ifndef FM_ATMOSPHERE_ATMOSPHERE_FILE_H
#define FM_ATMOSPHERE_ATMOSPHERE_FILE_H

#include "atmosphere/atmosphere.h"

/* Builds atm (majorants included) from the file at path for the wavelengths of grid.
 * Solar spectrum: the file's, if it has one, is taken as the irradiance at 1 AU and multiplied by
 * solar_scale (the caller's 1/d^2); otherwise grid's spectrum is kept exactly as passed.
 * Ground albedo: the file's when it gives one, else ground_albedo. */
fm_status atmosphere_init_from_file(atmosphere *atm, const char *path, const spectral_grid *grid, double solar_scale,
                                    double ground_albedo, fm_error *err);

#endif
