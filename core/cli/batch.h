/* firmament batch: many maps as independent, restartable jobs (docs/batch.md).
 *   batch plan    writes a manifest, JSON Lines: one job per line, the keys of a sky preset plus
 *                 "output", "sidecar" and "seed" (and "sky_cover_tenths" from a weather file);
 *   batch run     renders jobs I..I+N-1 of a manifest through `firmament render`'s own path;
 *   batch slurm   writes (and submits) an sbatch script running the manifest as a job array;
 *   batch summary gathers the sidecars into a CSV and a heat map. */
#ifndef FM_CLI_BATCH_H
#define FM_CLI_BATCH_H

/* `firmament render` with argv (argv[0] the command's name) for one job: job is the job's JSON
 * object text, written into the sidecar as "job". */
typedef int (*batch_render_fn)(int argc, char **argv, const char *job);

/* argv[0] is "batch"; returns the exit code. */
int run_batch(int argc, char **argv, batch_render_fn render);

#endif
