#include "spectrum/cie.h"

#include "data/tables.h"
#include "spectrum/spectrum_table.h"

#include <math.h>

void cie_xyz_at(double lambda_nm, double xyz[3])
{
    double f = lambda_nm - FM_CIE_FIRST_NM;
    if (!(f >= 0.0) || f > FM_CIE_COUNT - 1) {
        xyz[0] = xyz[1] = xyz[2] = 0.0;
        return;
    }
    int i = (int)f;
    if (i >= FM_CIE_COUNT - 1)
        i = FM_CIE_COUNT - 2;
    double t = f - i;
    for (int c = 0; c < 3; c++)
        xyz[c] = fm_cie1931_xyz_1nm[i][c] * (1.0 - t) + fm_cie1931_xyz_1nm[i + 1][c] * t;
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
