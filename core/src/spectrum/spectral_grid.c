#include "spectrum/spectral_grid.h"

#include "data/tables.h"
#include "spectrum/solar.h"

#include <math.h>
#include <string.h>

void spectral_grid_visible(spectral_grid *grid)
{
    memset(grid, 0, sizeof *grid);
    grid->colour = 1;
    const double h = FM_VISIBLE_STEP_NM;
    int count = (int)lround((FM_VISIBLE_LAST_NM - FM_VISIBLE_FIRST_NM) / h) + 1;
    grid->count = count;
    for (int k = 0; k < count; k++) {
        double c = FM_VISIBLE_FIRST_NM + h * k;
        grid->lambda_nm[k] = c;
        grid->solar_irradiance[k] = solar_irradiance_hat_mean(c, h);
        /* integral over the CIE table (1 nm trapezoid) of xyz * E * hat_k */
        double acc[3] = {0, 0, 0};
        for (int i = 0; i < FM_CIE_COUNT; i++) {
            double l = FM_CIE_FIRST_NM + i;
            double hat = 1.0 - fabs(l - c) / h;
            if (hat <= 0.0)
                continue;
            double w = (i == 0 || i == FM_CIE_COUNT - 1) ? 0.5 : 1.0;
            double e = solar_irradiance_at(l);
            for (int j = 0; j < 3; j++)
                acc[j] += w * fm_cie1931_xyz_1nm[i][j] * e * hat;
        }
        for (int j = 0; j < 3; j++)
            grid->xyz_weight[k][j] = acc[j] / grid->solar_irradiance[k];
    }
}

void spectral_grid_single(spectral_grid *grid, double lambda_nm)
{
    memset(grid, 0, sizeof *grid);
    grid->count = 1;
    grid->colour = 0;
    grid->lambda_nm[0] = lambda_nm;
    grid->solar_irradiance[0] = solar_irradiance_at(lambda_nm);
}

void spectral_grid_set_solar(spectral_grid *grid, spectrum_fn irradiance, const void *ctx)
{
    if (!grid->colour) {
        for (int k = 0; k < grid->count; k++)
            grid->solar_irradiance[k] = irradiance(ctx, grid->lambda_nm[k]);
        return;
    }
    const double h = FM_VISIBLE_STEP_NM;
    for (int k = 0; k < grid->count; k++) {
        double c = grid->lambda_nm[k];
        /* hat-weighted mean (1 nm trapezoid; the hat vanishes at both ends) */
        double num = 0.0, den = 0.0;
        for (double l = c - h + 1.0; l < c + h; l += 1.0) {
            double hat = 1.0 - fabs(l - c) / h;
            num += hat * irradiance(ctx, l);
            den += hat;
        }
        double e_k = num / den;
        double acc[3] = {0, 0, 0}, flat[3] = {0, 0, 0};
        for (int i = 0; i < FM_CIE_COUNT; i++) {
            double l = FM_CIE_FIRST_NM + i;
            double hat = 1.0 - fabs(l - c) / h;
            if (hat <= 0.0)
                continue;
            double w = (i == 0 || i == FM_CIE_COUNT - 1) ? 0.5 : 1.0;
            double e = irradiance(ctx, l);
            for (int j = 0; j < 3; j++) {
                acc[j] += w * fm_cie1931_xyz_1nm[i][j] * e * hat;
                flat[j] += w * fm_cie1931_xyz_1nm[i][j] * hat;
            }
        }
        grid->solar_irradiance[k] = e_k;
        for (int j = 0; j < 3; j++)
            grid->xyz_weight[k][j] = e_k > 0.0 ? acc[j] / e_k : flat[j];
    }
}

void spectral_grid_to_xyz(const spectral_grid *grid, const double *values, double xyz[3])
{
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    for (int k = 0; k < grid->count; k++)
        for (int j = 0; j < 3; j++)
            xyz[j] += values[k] * grid->xyz_weight[k][j];
}

double spectral_grid_luminance(const spectral_grid *grid, const double *values)
{
    if (!grid->colour)
        return values[0];
    double xyz[3];
    spectral_grid_to_xyz(grid, values, xyz);
    return xyz[1];
}
