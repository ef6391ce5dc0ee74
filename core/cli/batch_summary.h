/* firmament batch summary MANIFEST [-o CSV] [--png PNG]: the sidecars of a manifest's jobs as one
 * CSV (time, sun, direct, diffuse and global illuminance, AOD, sky cover, flags) and a heat map of
 * the global horizontal illuminance, day of year x hour of day (PNG). */
#ifndef FM_CLI_BATCH_SUMMARY_H
#define FM_CLI_BATCH_SUMMARY_H

/* argv[0] is "summary"; returns the exit code. */
int batch_summary(int argc, char **argv);

#endif
