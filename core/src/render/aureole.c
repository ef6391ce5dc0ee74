#include "render/aureole.h"

#include "spectrum/spectral_grid.h"
#include "transport/sky_grid.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

#define INNER 0.6                  /* of the radius: the grid's value alone within it */
#define HORIZON_BAND (1.5 * FM_DEG) /* the blend's fall toward the horizon */

fm_status aureole_init(aureole *a, int channels)
{
    a->channels = channels;
    a->values = calloc(aureole_floats(a), sizeof(float));
    return a->values ? FM_OK : FM_ERR_OUT_OF_MEMORY;
}

void aureole_free(aureole *a)
{
    free(a->values);
    a->values = NULL;
}

int aureole_locate(const aureole_frame *f, double e, double phi, aureole_place *p)
{
    if (fabs(e - f->sun) >= AUREOLE_RADIUS) /* most of a map: no trigonometry */
        return 0;
    const double ce = cos(e), se = sin(e), cp = cos(phi);
    const double c = ce * cp * f->cos_s + se * f->sin_s; /* cos gamma */
    if (!(c > f->cos_radius))
        return 0;
    const double x = se * f->cos_s - ce * cp * f->sin_s, y = ce * sin(phi); /* toward the zenith, aside */
    p->gamma = atan2(sqrt(x * x + y * y), c);
    p->psi = atan2(fabs(y), x);
    return 1;
}

void aureole_direction(const aureole_frame *f, double gamma, double psi, double *e, double *phi)
{
    const double cg = cos(gamma), sg = sin(gamma);
    const double h = cg * f->cos_s - sg * cos(psi) * f->sin_s, b = sg * sin(psi), z = cg * f->sin_s + sg * cos(psi) * f->cos_s;
    *e = asin(fmax(-1.0, fmin(1.0, z)));
    *phi = atan2(fabs(b), h);
}

void aureole_node(int row, int col, double *gamma, double *psi)
{
    const double u = (double)row / (AUREOLE_ROWS - 1);
    *gamma = AUREOLE_RADIUS * u * u;
    *psi = FM_PI * col / (AUREOLE_COLS - 1);
}

static double smooth_fall(double t) /* 1 at t <= 0, 0 at t >= 1, smooth in between */
{
    return t <= 0.0 ? 1.0 : (t >= 1.0 ? 0.0 : 0.5 * (1.0 + cos(FM_PI * t)));
}

double aureole_weight(const aureole_place *p, double e, double horizon)
{
    return smooth_fall((p->gamma - INNER * AUREOLE_RADIUS) / ((1.0 - INNER) * AUREOLE_RADIUS)) *
           smooth_fall((horizon + HORIZON_BAND - e) / HORIZON_BAND);
}

void aureole_lookup_log(const aureole *a, const aureole_place *p, float *out)
{
    const int C = a->channels;
    double fr = sqrt(fmax(0.0, p->gamma) / AUREOLE_RADIUS) * (AUREOLE_ROWS - 1), fc = p->psi / FM_PI * (AUREOLE_COLS - 1);
    int r = (int)fr, c = (int)fc;
    r = r < 0 ? 0 : (r > AUREOLE_ROWS - 2 ? AUREOLE_ROWS - 2 : r);
    c = c < 0 ? 0 : (c > AUREOLE_COLS - 2 ? AUREOLE_COLS - 2 : c);
    const double tr = fmin(1.0, fmax(0.0, fr - r)), tc = fmin(1.0, fmax(0.0, fc - c));
    const float *v00 = &a->values[((size_t)r * AUREOLE_COLS + c) * C], *v01 = v00 + C;
    const float *v10 = v00 + (size_t)AUREOLE_COLS * C, *v11 = v10 + C;
    for (int k = 0; k < C; k++)
        out[k] = (float)((1.0 - tr) * ((1.0 - tc) * v00[k] + tc * v01[k]) + tr * ((1.0 - tc) * v10[k] + tc * v11[k]));
}

void aureole_blend(const aureole *a, const aureole_frame *f, double e, double phi, double horizon, float *v)
{
    aureole_place p;
    if (!aureole_locate(f, e, phi, &p))
        return;
    assert(aureole_seen(f->sun, horizon) || !(aureole_weight(&p, e, horizon) > 0.0));
    const double w = aureole_weight(&p, e, horizon);
    if (!(w > 0.0))
        return;
    float g[FM_MAX_WAVELENGTHS];
    aureole_lookup_log(a, &p, g);
    for (int c = 0; c < a->channels; c++)
        v[c] = (float)exp(w * g[c] + (1.0 - w) * log(fmax(v[c], FM_GRID_FLOOR)));
}
