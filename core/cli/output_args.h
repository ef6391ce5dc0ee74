/* What the options say about the files a render writes: the sidecar's default name and the map's
 * format, for `render` and `serve` alike. */
#ifndef FM_CLI_OUTPUT_ARGS_H
#define FM_CLI_OUTPUT_ARGS_H

#include "args.h"

/* The sidecar's default path: the output with its extension (if any) replaced by .json (malloc'd;
 * NULL: no memory). */
char *default_sidecar(const char *output);

/* The map's file format: an EXR with its pixel type and compression, or a Radiance picture. */
fm_status output_set_format(const options *opt, fm_output *out, fm_error *err);

#endif
