#include "atmosphere/table_rows.h"

#include "atmosphere/profile.h"
#include "base/status.h"

#include <math.h>
#include <stdlib.h>

/* Edges closer than this are the two ends of one ramp, whose nodes between get rows too. */
#define RAMP_MAX_M 400.0

static int ascending(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The altitudes (m) of the extra rows: every edge and the profile nodes between the ends of a
 * ramp; returns their count (at most max_count). */
static int edge_altitudes(const atmosphere *atm, double *z, int max_count)
{
    double edges[FM_MAX_EDGES];
    int n_edges = atm->edge_count;
    for (int i = 0; i < n_edges; i++)
        edges[i] = atm->edge_altitude_m[i];
    qsort(edges, (size_t)n_edges, sizeof edges[0], ascending);
    double dz = atm->profile_dz_m > 0.0 ? atm->profile_dz_m : FM_PROFILE_SPACING_M;
    int n = 0;
    for (int i = 0; i < n_edges && n < max_count; i++) {
        z[n++] = edges[i];
        if (i + 1 < n_edges && edges[i + 1] - edges[i] <= RAMP_MAX_M)
            for (double zi = edges[i] + dz; zi < edges[i + 1] - 0.5 * dz && n < max_count; zi += dz)
                z[n++] = zi;
    }
    return n;
}

double top_horizon_distance(const atmosphere *atm)
{
    double rb = atm->bottom_radius_m, rt = atm->top_radius_m;
    return sqrt(rt * rt - rb * rb);
}

fm_status table_rows_init(table_rows *rows, const atmosphere *atm, int uniform_count, fm_error *err)
{
    enum { MAX_EXTRA = FM_MAX_EDGES * 8 };
    double z_extra[MAX_EXTRA];
    int n_extra = edge_altitudes(atm, z_extra, MAX_EXTRA);
    double rb = atm->bottom_radius_m;
    rows->horizon_m = top_horizon_distance(atm);
    rows->cells = uniform_count - 1;
    rows->per_horizon = 1.0 / rows->horizon_m;
    rows->x = malloc(sizeof(double) * (size_t)(uniform_count + n_extra));
    rows->per_step = malloc(sizeof(double) * (size_t)(uniform_count + n_extra));
    rows->first = malloc(sizeof(int) * (size_t)rows->cells);
    if (!rows->x || !rows->per_step || !rows->first) {
        table_rows_free(rows);
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory for the tables' rows");
    }
    int n = 0;
    for (int i = 0; i < uniform_count; i++)
        rows->x[n++] = (double)i / (uniform_count - 1);
    for (int i = 0; i < n_extra; i++) {
        double r = rb + z_extra[i];
        double x = sqrt(r * r - rb * rb) / rows->horizon_m;
        if (x > 0.0 && x < 1.0)
            rows->x[n++] = x;
    }
    qsort(rows->x, (size_t)n, sizeof rows->x[0], ascending);
    /* an edge on a uniform row is one row */
    int m = 1;
    for (int i = 1; i < n; i++)
        if (rows->x[i] > rows->x[m - 1])
            rows->x[m++] = rows->x[i];
    rows->count = m;
    for (int i = 0; i + 1 < m; i++)
        rows->per_step[i] = 1.0 / (rows->x[i + 1] - rows->x[i]);
    for (int j = 0, i = 0; j < rows->cells; j++) {
        double start = (double)j / rows->cells;
        while (i + 1 < m && rows->x[i + 1] <= start)
            i++;
        rows->first[j] = i;
    }
    return FM_OK;
}

void table_rows_free(table_rows *rows)
{
    free(rows->x);
    free(rows->per_step);
    free(rows->first);
    rows->x = rows->per_step = NULL;
    rows->first = NULL;
}

double table_rows_radius(const table_rows *rows, const atmosphere *atm, int i)
{
    double rb = atm->bottom_radius_m;
    double rho = rows->horizon_m * rows->x[i];
    return sqrt(rho * rho + rb * rb);
}
