#include "base/exp_array.h"

#include <math.h>

/* clang ignores "#pragma GCC target" below: it takes the vector path only where AVX2 is on anyway
 * (the fuzz build, tests/fuzz/, is made with clang) */
#if defined(__x86_64__) && defined(__GLIBC__) && defined(__SSE2__) && (!defined(__clang__) || defined(__AVX2__))
#include <immintrin.h>

/* glibc's vector functions (x86-64 vector function ABI; each an IFUNC choosing the best code for
 * the CPU), declared here because math.h declares them only under -ffast-math: two lanes (SSE) on
 * every x86-64, four (AVX2) where the CPU has it. */
__m128d _ZGVbN2v_exp(__m128d x);
__m128d _ZGVbN2v_expm1(__m128d x);
__m128d _ZGVbN2v_log(__m128d x);

#pragma GCC push_options
#pragma GCC target("avx2")
__m256d _ZGVdN4v_exp(__m256d x);
__m256d _ZGVdN4v_expm1(__m256d x);
__m256d _ZGVdN4v_log(__m256d x);

enum { EXP, EXPM1, LOG };

static __m256d four(__m256d v, int f)
{
    return f == EXP ? _ZGVdN4v_exp(v) : f == EXPM1 ? _ZGVdN4v_expm1(v) : _ZGVdN4v_log(v);
}

static int four_lanes(const double *x, double *out, int n, int f)
{
    int i = 0;
    for (; i + 3 < n; i += 4)
        _mm256_storeu_pd(out + i, four(_mm256_loadu_pd(x + i), f));
    return i;
}
#pragma GCC pop_options

static __m128d two(__m128d v, int f)
{
    return f == EXP ? _ZGVbN2v_exp(v) : f == EXPM1 ? _ZGVbN2v_expm1(v) : _ZGVbN2v_log(v);
}

static double one(double v, int f) { return f == EXP ? exp(v) : f == EXPM1 ? expm1(v) : log(v); }

static void array(const double *x, double *out, int n, int f)
{
    /* a load and a bit test of libgcc's CPU model, filled in before main */
    int i = __builtin_cpu_supports("avx2") ? four_lanes(x, out, n, f) : 0;
    for (; i + 1 < n; i += 2)
        _mm_storeu_pd(out + i, two(_mm_loadu_pd(x + i), f));
    if (i < n)
        out[i] = one(x[i], f);
}

void exp_array(const double *x, double *out, int n) { array(x, out, n, EXP); }

void expm1_array(const double *x, double *out, int n) { array(x, out, n, EXPM1); }

void log_array(const double *x, double *out, int n) { array(x, out, n, LOG); }
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

void log_array(const double *x, double *out, int n)
{
    for (int i = 0; i < n; i++)
        out[i] = log(x[i]);
}
#endif
