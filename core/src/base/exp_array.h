/* exp, expm1 and log over a spectral array.  The per-wavelength transmittances exp(-depth_k) of the
 * path tracer's loops (41 values at a time) were a quarter of its time as one libm call each.  On
 * x86-64 with glibc, fours (AVX2 CPUs) or pairs go through glibc's vector functions (libmvec,
 * within 4 ulp; the scalar ones within 1); elsewhere these are the scalar functions.  The same
 * inputs give the same bits on a given machine, whatever the thread. */
#ifndef FM_BASE_EXP_ARRAY_H
#define FM_BASE_EXP_ARRAY_H

/* out[i] = exp(x[i]) for i < n; out may be x. */
void exp_array(const double *x, double *out, int n);

/* out[i] = expm1(x[i]) (exp(x) - 1, accurate for small x) for i < n; out may be x. */
void expm1_array(const double *x, double *out, int n);

/* out[i] = log(x[i]) for i < n; out may be x. */
void log_array(const double *x, double *out, int n);

#endif
