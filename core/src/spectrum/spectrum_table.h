/* Piecewise-linear functions given as (x, y) samples with increasing x. */
#ifndef FM_SPECTRUM_TABLE_H
#define FM_SPECTRUM_TABLE_H

/* y at x by linear interpolation; 0 outside [x[0], x[n-1]]. */
double table_interpolate(const double *x, const double *y, int n, double at);

/* Same for tables stored as rows {x, y, ...} with `stride` doubles per row. */
double table_interpolate_rows(const double *rows, int n, int stride, int column, double at);

/* Row values of a table with rows at first, first + 1, ... (count rows of `columns` values),
 * linearly interpolated at x; returns 0 (out left untouched) outside the table. */
int table_interpolate_uniform(const double *rows, int count, int columns, double first, double x, double *out);

/* Integral of the piecewise-linear function times the hat function centred on c with half-width h
 * (1 at c, 0 beyond c +- h), computed exactly on the union of breakpoints. */
double table_hat_integral_rows(const double *rows, int n, int stride, int column, double c, double h);

#endif
