#include "spectrum/spectrum_table.h"

#include <math.h>

static int find_segment(const double *x, int n, int stride, double at)
{
    /* Largest i with x[i] <= at, in [0, n-2]. */
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (x[(long)mid * stride] <= at)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double table_interpolate_rows(const double *rows, int n, int stride, int column, double at)
{
    if (n < 2 || !(at >= rows[0]) || at > rows[(long)(n - 1) * stride])
        return 0.0;
    int i = find_segment(rows, n, stride, at);
    double x0 = rows[(long)i * stride], x1 = rows[(long)(i + 1) * stride];
    double y0 = rows[(long)i * stride + column], y1 = rows[(long)(i + 1) * stride + column];
    double t = (at - x0) / (x1 - x0);
    return y0 + (y1 - y0) * t;
}

double table_interpolate(const double *x, const double *y, int n, double at)
{
    if (n < 2 || !(at >= x[0]) || at > x[n - 1])
        return 0.0;
    int i = find_segment(x, n, 1, at);
    double t = (at - x[i]) / (x[i + 1] - x[i]);
    return y[i] + (y[i + 1] - y[i]) * t;
}

double table_hat_integral_rows(const double *rows, int n, int stride, int column, double c, double h)
{
    /* Between consecutive breakpoints (table samples and c - h, c, c + h) the product of the two
     * linear functions is quadratic, so Simpson's rule is exact on each piece. */
    double a = c - h, b = c + h;
    int i = 0;
    while (i < n && rows[(long)i * stride] <= a)
        i++;
    double total = 0.0, prev = a;
    while (prev < b) {
        double next = b;
        if (prev < c && c < next)
            next = c;
        if (i < n && rows[(long)i * stride] < next)
            next = rows[(long)i * stride];
        double m = 0.5 * (prev + next);
        double f0 = table_interpolate_rows(rows, n, stride, column, prev) * (1.0 - fabs(prev - c) / h);
        double f1 = table_interpolate_rows(rows, n, stride, column, m) * (1.0 - fabs(m - c) / h);
        double f2 = table_interpolate_rows(rows, n, stride, column, next) * (1.0 - fabs(next - c) / h);
        total += (next - prev) / 6.0 * (f0 + 4.0 * f1 + f2);
        if (i < n && rows[(long)i * stride] <= next)
            i++;
        prev = next;
    }
    return total;
}

int table_interpolate_uniform(const double *rows, int count, int columns, double first, double x, double *out)
{
    double f = x - first;
    if (!(f >= 0.0) || f > count - 1)
        return 0;
    int i = (int)f;
    if (i >= count - 1)
        i = count - 2;
    double t = f - i;
    for (int c = 0; c < columns; c++)
        out[c] = rows[(long)i * columns + c] * (1.0 - t) + rows[(long)(i + 1) * columns + c] * t;
    return 1;
}
