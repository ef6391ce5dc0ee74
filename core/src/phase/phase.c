#include "phase/phase.h"

#include "phase/phase_hg.h"
#include "phase/phase_rayleigh.h"
#include "phase/phase_table.h"

#include <stddef.h>

fm_status phase_init_tabulated(phase_function *p, int wavelength_count, int angle_count, const double *theta_rad,
                               const double *values, fm_error *err)
{
    phase_table *t = NULL;
    fm_status st = phase_table_create(&t, wavelength_count, angle_count, theta_rad, values, err);
    if (st != FM_OK)
        return st;
    p->kind = PHASE_TABULATED;
    p->table = t;
    return FM_OK;
}

void phase_free(phase_function *p)
{
    phase_table_destroy(p->table);
    p->table = NULL;
}

double phase_evaluate(const phase_function *p, int k, double cos_theta)
{
    switch (p->kind) {
    case PHASE_RAYLEIGH:
        return phase_rayleigh_eval(cos_theta, p->param[k]);
    case PHASE_HENYEY_GREENSTEIN:
        return phase_hg_eval(cos_theta, p->param[k]);
    case PHASE_TABULATED:
        return phase_table_eval(p->table, k, cos_theta);
    case PHASE_NONE:
        break;
    }
    return 0.0;
}

void phase_evaluate_all(const phase_function *p, int K, double cos_theta, double *out)
{
    switch (p->kind) {
    case PHASE_RAYLEIGH:
        for (int k = 0; k < K; k++)
            out[k] = phase_rayleigh_eval(cos_theta, p->param[k]);
        return;
    case PHASE_HENYEY_GREENSTEIN:
        for (int k = 0; k < K; k++)
            out[k] = phase_hg_eval(cos_theta, p->param[k]);
        return;
    case PHASE_TABULATED:
        phase_table_eval_all(p->table, K, cos_theta, out);
        return;
    case PHASE_NONE:
        break;
    }
    for (int k = 0; k < K; k++)
        out[k] = 0.0;
}

double phase_sample(const phase_function *p, int k, double u)
{
    switch (p->kind) {
    case PHASE_RAYLEIGH:
        return phase_rayleigh_sample(u, p->param[k]);
    case PHASE_HENYEY_GREENSTEIN:
        return phase_hg_sample(u, p->param[k]);
    case PHASE_TABULATED:
        return phase_table_sample(p->table, k, u);
    case PHASE_NONE:
        break;
    }
    return 2.0 * u - 1.0; /* never used: an absorber is never chosen to scatter */
}

double phase_asymmetry(const phase_function *p, int k)
{
    switch (p->kind) {
    case PHASE_HENYEY_GREENSTEIN:
        return p->param[k];
    case PHASE_TABULATED:
        return phase_table_asymmetry(p->table, k);
    case PHASE_RAYLEIGH: /* symmetric about 90 degrees */
    case PHASE_NONE:
        break;
    }
    return 0.0;
}
