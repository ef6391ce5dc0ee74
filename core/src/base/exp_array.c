#include "base/exp_array.h"

#include <math.h>

#if defined(__x86_64__) && defined(__GLIBC__) && defined(__SSE2__)
#include <emmintrin.h>

/* glibc's two-lane functions (x86-64 vector function ABI, SSE variant; IFUNCs choosing the best code
 * for the CPU).  Declared here because math.h declares them only under -ffast-math. */
__m128d _ZGVbN2v_exp(__m128d x);
__m128d _ZGVbN2v_expm1(__m128d x);

void exp_array(const double *x, double *out, int n)
{
    int i = 0;
    for (; i + 1 < n; i += 2)
        _mm_storeu_pd(out + i, _ZGVbN2v_exp(_mm_loadu_pd(x + i)));
    if (i < n)
        out[i] = exp(x[i]);
}

void expm1_array(const double *x, double *out, int n)
{
    int i = 0;
    for (; i + 1 < n; i += 2)
        _mm_storeu_pd(out + i, _ZGVbN2v_expm1(_mm_loadu_pd(x + i)));
    if (i < n)
        out[i] = expm1(x[i]);
}
#else
void exp_array(const double *x, double *out, int n)
{
    for (int i = 0; i < n; i++)
        out[i] = exp(x[i]);
}

void expm1_array(const double *x, double *out, int n)
{
    for (int i = 0; i < n; i++)
        out[i] = expm1(x[i]);
}
#endif
