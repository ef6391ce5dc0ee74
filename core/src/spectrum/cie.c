#include "spectrum/cie.h"

#include "data/tables.h"
#include "spectrum/spectrum_table.h"

#include <math.h>

void cie_xyz_at(double lambda_nm, double xyz[3])
{
    if (!table_interpolate_uniform(&fm_cie1931_xyz_1nm[0][0], FM_CIE_COUNT, 3, FM_CIE_FIRST_NM, lambda_nm, xyz))
        xyz[0] = xyz[1] = xyz[2] = 0.0;
}

void cie_spectrum_to_xyz(const double *lambda_nm, const double *values, int n, double xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (int i = 0; i < FM_CIE_COUNT; i++) {
        double l = FM_CIE_FIRST_NM + i;
        double w = (i == 0 || i == FM_CIE_COUNT - 1) ? 0.5 : 1.0; /* trapezoid, 1 nm */
        double s = table_interpolate(lambda_nm, values, n, l);
        for (int c = 0; c < 3; c++)
            xyz[c] += w * s * fm_cie1931_xyz_1nm[i][c];
    }
}
