/* The wavelengths every path carries.  A colour render uses nodes every 10 nm from 380 to 780 nm;
 * spectra are piecewise linear between nodes ("hat" basis), so
 *     XYZ = sum_k L(lambda_k) * xyz_weight[k]
 * integrates L(l) xyz(l) dl.  The solar spectrum's fine structure (Fraunhofer lines) is folded into
 * the weights: node k's solar irradiance is the hat-weighted mean E_k, and
 *     xyz_weight[k] = integral(xyz(l) E(l) hat_k(l) dl) / E_k,
 * which keeps the quadrature error below 0.1% in XYZ for sky and sun spectra (checked against a
 * 1 nm integration).  A monochromatic render uses a single node. */
#ifndef FM_SPECTRUM_SPECTRAL_GRID_H
#define FM_SPECTRUM_SPECTRAL_GRID_H

#define FM_MAX_WAVELENGTHS 48

#define FM_VISIBLE_FIRST_NM 380.0
#define FM_VISIBLE_LAST_NM 780.0
#define FM_VISIBLE_STEP_NM 10.0

typedef struct spectral_grid {
    int count;                                   /* K */
    int colour;                                  /* 1: visible grid with XYZ weights; 0: one wavelength */
    double lambda_nm[FM_MAX_WAVELENGTHS];
    double solar_irradiance[FM_MAX_WAVELENGTHS]; /* W m^-2 nm^-1 at 1 AU */
    double xyz_weight[FM_MAX_WAVELENGTHS][3];    /* nm */
} spectral_grid;

void spectral_grid_visible(spectral_grid *grid);
void spectral_grid_single(spectral_grid *grid, double lambda_nm);

/* Replaces the grid's solar spectrum by another one, irradiance(ctx, lambda_nm) in W m^-2 nm^-1
 * (e.g. a custom atmosphere's): a single-wavelength grid takes its value at the node; a colour grid
 * recomputes the node means E_k and the XYZ weights as above, from 1 nm samples within one step of
 * each node (where E_k is 0 the weights are those of a flat spectrum: nothing is lit there). */
typedef double (*spectrum_fn)(const void *ctx, double lambda_nm);
void spectral_grid_set_solar(spectral_grid *grid, spectrum_fn irradiance, const void *ctx);

/* XYZ of values given at the grid's nodes (colour grids only). */
void spectral_grid_to_xyz(const spectral_grid *grid, const double *values, double xyz[3]);

/* The luminance-like value of node values: CIE Y for a colour grid, else the first node's value
 * (the one value of a monochromatic grid). */
double spectral_grid_luminance(const spectral_grid *grid, const double *values);

#endif
