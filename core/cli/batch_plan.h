/* firmament batch plan: a manifest from presets x places x dates x clock times (the sun above a
 * limit), or from the hours of an EPW weather file (docs/batch.md). */
#ifndef FM_CLI_BATCH_PLAN_H
#define FM_CLI_BATCH_PLAN_H

/* argv[0] is "plan"; returns the exit code. */
int batch_plan(int argc, char **argv);

#endif
