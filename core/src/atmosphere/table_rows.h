/* The radii of the transmittance tables' rows (column table, sun table).
 *
 * Rows are uniform in Bruneton's x_r = rho / H, rho = sqrt(r^2 - rb^2), H = sqrt(rt^2 - rb^2)
 * (dense near the ground: 6 m, 25 m, 56 m, ... up for 128 rows and a 100 km atmosphere, 200 m
 * apart at 2 km), plus a row at every profile node inside a species' edge (the ramp at the top of
 * an aerosol layer, atmosphere.edge_altitude_m: its ends and the nodes between).  The column above
 * a point bends sharply there; interpolating across a 100 m ramp between rows 200 m apart made the
 * sunlight of the urban sunset's haze top 17% too dark and the whole sky 0.8%. */
#ifndef FM_ATMOSPHERE_TABLE_ROWS_H
#define FM_ATMOSPHERE_TABLE_ROWS_H

#include "atmosphere/atmosphere.h"

#include <math.h>

typedef struct table_rows {
    int count;        /* rows */
    int cells;        /* uniform steps of x_r over [0, 1] in the index below */
    double horizon_m; /* H = sqrt(rt^2 - rb^2) */
    double per_horizon; /* 1 / horizon_m */
    double *x;        /* [count] ascending x_r of each row, x[0] = 0, x[count - 1] = 1 */
    double *per_step; /* [count - 1] 1 / (x[i + 1] - x[i]): a lookup multiplies, it does not divide */
    int *first;       /* [cells] the last row at or below the start of each step */
} table_rows;

/* sqrt(rt^2 - rb^2): the distance from the ground to the top along the horizon, the scale of the
 * tables' radius mapping (Bruneton's H). */
double top_horizon_distance(const atmosphere *atm);

/* uniform_count rows uniform in x_r (>= 2) and the rows of the profiles' edges;
 * FM_ERR_OUT_OF_MEMORY on allocation failure. */
fm_status table_rows_init(table_rows *rows, const atmosphere *atm, int uniform_count, fm_error *err);
void table_rows_free(table_rows *rows);

/* The radius (m) of row i. */
double table_rows_radius(const table_rows *rows, const atmosphere *atm, int i);

/* The row i in [0, count - 2] at or below x_r = x (clamped to [0, 1]) and the fraction *t in
 * [0, 1] toward row i + 1. */
static inline int table_rows_locate_x(const table_rows *rows, double x, double *t)
{
    x = x > 0.0 ? (x < 1.0 ? x : 1.0) : 0.0;
    int j = (int)(x * rows->cells);
    int i = rows->first[j < rows->cells ? j : rows->cells - 1];
    while (i + 2 < rows->count && rows->x[i + 1] <= x)
        i++;
    if (i > rows->count - 2)
        i = rows->count - 2;
    double t_i = (x - rows->x[i]) * rows->per_step[i]; /* within 2 ulp of the quotient */
    *t = t_i < 1.0 ? t_i : 1.0;
    return i;
}

/* The same below radius r (clamped to the atmosphere). */
static inline int table_rows_locate(const table_rows *rows, const atmosphere *atm, double r, double *t)
{
    double rb = atm->bottom_radius_m;
    double rho2 = r * r - rb * rb;
    return table_rows_locate_x(rows, rho2 > 0.0 ? sqrt(rho2) * rows->per_horizon : 0.0, t);
}

#endif
