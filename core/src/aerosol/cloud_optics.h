/* The optics of a water cloud type on a wavelength grid (Mie theory over its droplet spectrum: about
 * 2.5 s of CPU for the 41 wavelengths of a colour render), kept on disk between builds.
 *
 * A cache file holds the tables of one type and grid under a key hashing everything they are computed
 * from: the droplet spectrum, the grid's wavelengths, the phase table's angles, the water index table
 * and the output of the Mie solver on a small probe spectrum (so a change to the solver or its
 * quadrature changes the key, as does a compiler that rounds differently).  A file that is missing,
 * refused (base/sealed_file.h: another key or version, truncated, corrupt) or holds an impossible
 * value is recomputed and replaced; a folder that cannot be written only costs the computation. */
#ifndef FM_AEROSOL_CLOUD_OPTICS_H
#define FM_AEROSOL_CLOUD_OPTICS_H

#include "aerosol/cloud.h"
#include "spectrum/spectral_grid.h"

typedef struct cloud_water_table {
    int count;                          /* the grid's K */
    double ext_rel[FM_MAX_WAVELENGTHS]; /* extinction relative to 550 nm */
    double ssa[FM_MAX_WAVELENGTHS];     /* single-scattering albedo */
    double *phase;                      /* [K][CLOUD_ANGLE_COUNT] at cloud_angle_rad (sr^-1), malloc'd */
} cloud_water_table;

typedef enum cloud_optics_source { CLOUD_OPTICS_COMPUTED, CLOUD_OPTICS_FROM_CACHE } cloud_optics_source;

/* The table of water type t on grid; cache_dir: the folder of the cache files (created with its
 * parents), NULL or "" for none; threads: for the Mie integrals (0 = all cores); source may be NULL. */
fm_status cloud_water_table_get(const cloud_type *t, const spectral_grid *grid, int threads, const char *cache_dir,
                                cloud_water_table *out, cloud_optics_source *source, fm_error *err);
void cloud_water_table_free(cloud_water_table *table);

/* The cache file of type t on grid under cache_dir (size PLATFORM_PATH_MAX is plenty); 0, or -1 when
 * the name does not fit. */
int cloud_water_table_path(const cloud_type *t, const spectral_grid *grid, const char *cache_dir, char *out,
                           size_t size);

#endif
