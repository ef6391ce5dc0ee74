/* The skies of issue "Speed" (the default sky and a sunset) and the file of their converged
 * reference (tests/data/bench_reference/SKY-WIDTH.txt), shared by the benchmark's tool
 * (bench/sky_bench.c) and the test that keeps the cached references current
 * (tests/physics/test_bench_reference.c).
 *
 * Reference file: '#' comment lines, then "W H N" (the map's size and the probe count), then per
 * probe "x y Y se" (pixel, CIE Y in W m^-2 sr^-1 and its standard error). */
#ifndef FM_BENCH_SKIES_H
#define FM_BENCH_SKIES_H

#include "firmament/firmament.h"

#include <stdio.h>

typedef struct bench_sky {
    const char *name, *args; /* args: the same sky as firmament render options */
    double sun_elevation, sun_azimuth, turbidity;
    const char *biome;
} bench_sky;

/* The sky called name ("default", "sunset", or "biome:NAME": sun 30 through biome NAME at turbidity
 * 1), or NULL.  The biome sky lives in static storage, overwritten by the next such call. */
const bench_sky *bench_sky_find(const char *name);

/* Its parameters for fm_sky_create. */
fm_sky_params bench_sky_params(const bench_sky *b);

/* Reads a reference file's header past its comments: 1 with W, H and N set, 0 if malformed. */
int bench_reference_header(FILE *f, int *W, int *H, int *n);

/* Reads the next probe: 1 with a pixel inside W x H and Y > 0, 0 otherwise. */
int bench_reference_probe(FILE *f, int W, int H, int *x, int *y, double *Y, double *se);

#endif
