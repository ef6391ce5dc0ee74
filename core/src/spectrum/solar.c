#include "spectrum/solar.h"

#include "data/tables.h"
#include "spectrum/spectrum_table.h"

double solar_irradiance_at(double lambda_nm)
{
    return table_interpolate_rows(&fm_solar_astm_g173[0][0], FM_SOLAR_COUNT, 2, 1, lambda_nm);
}

double solar_irradiance_hat_mean(double c_nm, double h_nm)
{
    return table_hat_integral_rows(&fm_solar_astm_g173[0][0], FM_SOLAR_COUNT, 2, 1, c_nm, h_nm) / h_nm;
}
