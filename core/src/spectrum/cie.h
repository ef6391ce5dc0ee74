/* CIE 1931 2-degree colour matching functions (data/cie1931.c) and spectrum -> XYZ integration. */
#ifndef FM_SPECTRUM_CIE_H
#define FM_SPECTRUM_CIE_H

/* x, y, z matching functions at lambda (nm), linear between the 1 nm table values; 0 outside
 * 380-780 nm. */
void cie_xyz_at(double lambda_nm, double xyz[3]);

/* XYZ of a spectrum tabulated at n increasing wavelengths (piecewise linear), integrated over
 * 380-780 nm in 1 nm trapezoid steps: sum of S(l) xyz(l) dl. */
void cie_spectrum_to_xyz(const double *lambda_nm, const double *values, int n, double xyz[3]);

#endif
