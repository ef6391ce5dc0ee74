/* How noisy one map is, from two renders of the same sky that differ only in their seed (bench/bench.sh
 * --twilight).  Each map's error is its own noise, independent between the seeds, so one map's
 * relative standard deviation is the RMS of the pair's log ratio over sqrt 2.  All figures are over
 * the sky half of equirect maps (the rows above the horizontal), each pixel weighted by its solid
 * angle:
 *   - luminance, red_green, blue_green: one map's relative standard deviation of CIE Y and of the
 *     ratios R / G and B / G (of linear Rec.709);
 *   - grain: the part of it that changes from one pixel to the next (the RMS of the difference of
 *     neighbouring pixels' log ratios, over 2): what shows as grain, against broad blotches;
 *   - de_mean, de_p99: the colour difference CIEDE2000 between the two maps as displayed (linear
 *     Rec.709 times 2^EV, clipped to [0, 1], CIELAB of D65 white), its mean and 99th percentile:
 *     about 1 is the smallest difference seen side by side;
 *   - flicker (seed_flicker): one map's noise in the ratio of two frames of a time series rendered
 *     with the same seed (frames a, b of seed 1 against frames a, b of seed 2), luminance. */
#ifndef FM_BENCH_SEED_NOISE_H
#define FM_BENCH_SEED_NOISE_H

#include "image/image.h"

typedef struct seed_noise {
    double luminance, red_green, blue_green, grain; /* relative, 0.01 = 1% */
    double de_mean, de_p99;
} seed_noise;

/* 0 with *out filled; 1 when the maps are not two equirect colour maps of one size (said on stderr). */
int seed_noise_measure(const fm_image *a, const fm_image *b, double exposure_ev, seed_noise *out);

/* The CIEDE2000 colour difference of two CIELAB colours (Sharma, Wu & Dalal 2005; k_L = k_C = k_H = 1). */
double seed_noise_ciede2000(const double lab1[3], const double lab2[3]);

/* 0 with *flicker set; 1 as above.  a1, b1: frames a and b of seed 1; a2, b2 those of seed 2. */
int seed_flicker(const fm_image *a1, const fm_image *b1, const fm_image *a2, const fm_image *b2, double *flicker);

#endif
