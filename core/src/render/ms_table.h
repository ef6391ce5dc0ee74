/* The fast path's table of multiple scattering (orders >= 2): its nodes' path estimates (one pass,
 * and in deep twilight at final quality a second one while the nodes are still noisy), their
 * moments for standard errors, and the smooth fit that averages their noise (sky_grid_fit.h).
 *
 * By day and in twilight down to deep twilight, order 2 and the orders above it are kept apart
 * ("parted": `grid` holds order 2, `later` the orders above) and fitted apart, each through its
 * own shape (next_order_shape.h), then added; in deep twilight the table is fitted whole, each node
 * divided by its view ray's own light (its shape).  At twilight in colour the chromaticity goes
 * through the ratios X / Y and Z / Y, fitted apart from the luminance. */
#ifndef FM_RENDER_MS_TABLE_H
#define FM_RENDER_MS_TABLE_H

#include "render/quality.h"
#include "transport/sky_grid.h"
#include "transport/twilight.h"

struct render_job;

typedef struct ms_table {
    sky_grid grid;          /* the radiance per node: order 2 when parted, else every order >= 2; once
                             * fitted, every order >= 2 */
    double *y, *var;        /* per node: the luminance estimate of `grid` and its variance */
    double *sum;            /* [node][K]: the sum of the node's paths' estimates at every grid wavelength */
    node_moments *moments;  /* per node: its paths' moments */
    double *shape;          /* per node: in deep twilight its view ray's light (table_node_paths' shape),
                             * else the shape of the part being fitted */
    int paths;              /* paths per node so far */
    int rising_segments;    /* the paths take the sunlight of rising segments along them (ms_table.c) */
    /* parted only (else NULL): the light of orders 3 and up, per node and in a table of its own */
    node_orders *orders;
    double *later_sum;      /* [node][K] */
    sky_grid later;
    double *later_y, *later_var;
    /* twilight in colour only (else NULL): per node X / Y and Z / Y and their variances */
    double *ratio[2], *ratio_var[2];
    double *block;          /* the one allocation behind the per-node arrays of doubles */
    /* fog around the observer (fog_table.h), else NULL: the light scattered two or more times within
     * the droplets' truncated peak by angle from the sun, per grid wavelength, in two parts (the
     * layout is fog_peak.c's) */
    double *peak;
} ms_table;

/* The table of a quality level (its rows, columns and paths), below the horizon at `horizon` (rad),
 * with `channels` image channels per node for a grid of K wavelengths; parted and chroma as above.
 * FM_ERR_OUT_OF_MEMORY leaves nothing to free. */
fm_status ms_table_init(ms_table *t, const quality_settings *q, double horizon, int channels, int K, int parted,
                        int chroma);
void ms_table_free(ms_table *t); /* accepts a table that was never initialised, zeroed */

/* Whether a table should be parted: all but deep twilight (tw NULL by day). */
int ms_table_parted(const twilight_sampling *tw);

/* Runs the table's paths (and deep twilight's second pass when it is worth it), and sets the
 * image's paths per node. */
fm_status ms_table_fill(struct render_job *job, double sun_elevation_deg);

/* The sky nodes' relative standard error, root mean square over the nodes with light (0 if none):
 * what deep twilight's final maps aim at (ms_table_fill's second pass). */
double ms_table_sky_node_noise(const ms_table *t);

/* Adds the paths of `more` (a table of the same layout and sky, filled with other seeds) to the job's
 * table: their sums and moments, the estimates, variances and ratios then over both tables' paths
 * (weighted by their paths), the shape kept as more's; ready for ms_table_fit.  A parted table's
 * orders above 2 alike (both tables parted, or neither): the live sky refines its twilight tables by
 * rounds of paths (live.h). */
void ms_table_add(struct render_job *job, const ms_table *more);

/* Whether a table's paths may be shared with other suns' (ms_table_fill_shared): by day, without a
 * deck, whose estimates depend on the sun.  A table with the rising segments' estimator (ms_table.c)
 * may share only as the first of its walks' tables (ms_table_walk_rising). */
int ms_table_walk_rising(const struct render_job *job);
int ms_table_walk_shareable(const struct render_job *job);

/* ms_table_fill for the tables of `count` jobs (PATH_SUNS_MAX at most) whose skies differ only in
 * the sun's elevation, all shareable, with one seed and number of paths, none but the first with
 * the rising segments' estimator: each node's walks are traced once and scored for every job's sun
 * (path_context.suns), so the tables share their noise; the first's rising segments take their
 * light along them for its sun alone. */
fm_status ms_table_fill_shared(struct render_job *const *jobs, int count);

/* Observer on the ground: adds the table's sky half to the diffuse ground irradiance (orders >= 2). */
fm_status ms_table_add_to_ground(struct render_job *job);

/* Fits the table (after the single-scattering table is complete: order 2's shape comes from it). */
fm_status ms_table_fit(struct render_job *job, double sun_elevation);

#endif
