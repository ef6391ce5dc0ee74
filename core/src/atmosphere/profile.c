#include "atmosphere/profile.h"

#include <math.h>
#include <stdlib.h>

fm_status profile_sample(density_profile *p, density_fn fn, void *ctx, double top_m, double dz_m)
{
    p->dz_m = dz_m;
    p->count = (int)ceil(top_m / dz_m - 1e-9) + 1;
    p->n = malloc(sizeof(double) * (size_t)p->count);
    if (!p->n)
        return FM_ERR_OUT_OF_MEMORY;
    for (int i = 0; i < p->count; i++)
        p->n[i] = fn(ctx, i * dz_m);
    return FM_OK;
}

void profile_free(density_profile *p)
{
    free(p->n);
    p->n = NULL;
    p->count = 0;
}

double profile_max(const density_profile *p, double z0_m, double z1_m)
{
    double m = fmax(profile_density(p, z0_m), profile_density(p, z1_m));
    int i0 = (int)ceil(z0_m / p->dz_m), i1 = (int)floor(z1_m / p->dz_m);
    if (i0 < 0)
        i0 = 0;
    if (i1 > p->count - 1)
        i1 = p->count - 1;
    for (int i = i0; i <= i1; i++)
        m = fmax(m, p->n[i]);
    return m;
}

double profile_column(const density_profile *p)
{
    double s = 0.0;
    for (int i = 0; i + 1 < p->count; i++)
        s += 0.5 * (p->n[i] + p->n[i + 1]) * p->dz_m;
    return s;
}
