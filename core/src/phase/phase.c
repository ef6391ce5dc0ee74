#include "phase/phase.h"

#include "phase/phase_rayleigh.h"

double phase_evaluate(const phase_function *p, int k, double cos_theta)
{
    switch (p->kind) {
    case PHASE_RAYLEIGH:
        return phase_rayleigh_eval(cos_theta, p->param[k]);
    case PHASE_NONE:
        break;
    }
    return 0.0;
}

double phase_sample(const phase_function *p, int k, double u)
{
    switch (p->kind) {
    case PHASE_RAYLEIGH:
        return phase_rayleigh_sample(u, p->param[k]);
    case PHASE_NONE:
        break;
    }
    return 2.0 * u - 1.0; /* never used: an absorber is never chosen to scatter */
}
