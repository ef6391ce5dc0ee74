/* render --preset NAME|FILE.json: the preset's settings become options placed before the user's
 * own, so that options given on the command line override the preset's values. */
#ifndef FM_CLI_PRESET_ARGS_H
#define FM_CLI_PRESET_ARGS_H

#include "firmament/firmament.h"

#include <stddef.h>

typedef struct preset_args {
    int argc;
    char **argv;          /* argv[0], the preset's options, the user's options without --preset */
    fm_sky_preset *preset; /* NULL when no --preset was given (argv is then the caller's) */
    char (*flags)[40];    /* "--turbidity", ... the preset's option names */
    int argv_owned;       /* argv was allocated here */
} preset_args;

/* Returns 0 on success; else 2 with one line in msg (unknown preset, malformed file, a value that
 * the option parser refuses, --preset twice or without a value). */
int preset_args_expand(int argc, char **argv, preset_args *out, char *msg, size_t msg_size);
void preset_args_free(preset_args *p);

#endif
