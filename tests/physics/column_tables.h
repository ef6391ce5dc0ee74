/* The fast path's tables for a sky as a render makes them from the plane-parallel column
 * (render/fog_table.h), and the comparison of their radiance against the reference estimator within
 * a relative tolerance plus 3 standard errors; shared by the column's tests in fog, under and above
 * cloud decks and in twilight (issue 48). */
#ifndef FM_TEST_COLUMN_TABLES_H
#define FM_TEST_COLUMN_TABLES_H

#include "render/ms_table.h"
#include "render/render.h"

#include <stdint.h>

typedef struct column_tables {
    render_job job;
    ms_table ms;
    fm_render_params rp;
    twilight_sampling *tw; /* NULL in daylight; the job's twilight */
} column_tables;

/* Starts a render of the sky 64 pixels wide with the fine fog table (the observer's level above a
 * deck taken when from_above) and seed: the render's start and its twilight sampling. The caller
 * checks which table applies, then makes them (column_tables_make). */
void column_tables_start(const fm_sky *sky, uint64_t seed, int from_above, column_tables *t);
/* The tables at the sky's sun; fails the test unless the multiple scattering is the column's (no
 * paths per node). */
void column_tables_make(column_tables *t);
void column_tables_free(column_tables *t);

/* The radiance of the single-scattering and the multiple-scattering tables at elevation e and
 * azimuth phi from the sun's (radians). */
double column_tables_radiance(const column_tables *t, double e, double phi);

/* Prints the fast path's value against the reference's (+- se) and returns whether
 * |fast - ref| <= rel * ref + 3 se ("  OUTSIDE" printed when not). */
int within_reference(double fast, double ref, double se, double rel, const char *what);
/* The same, failing the test (check_abs) when outside. */
void check_within_reference(double fast, double ref, double se, double rel, const char *what);

#endif
