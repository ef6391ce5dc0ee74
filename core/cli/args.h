/* Command-line parsing for `firmament render`: one options struct, filled by getopt_long from the
 * table of options (option_table.h).  Each value is checked as it is read, against the library's
 * range for its field; what the library refuses later names the field, and options_flag_for()
 * turns that field back into the flag. */
#ifndef FM_CLI_ARGS_H
#define FM_CLI_ARGS_H

#include "firmament/firmament.h"

#include <stddef.h>

typedef enum output_format { FORMAT_FROM_NAME = -1, FORMAT_EXR = 0, FORMAT_HDR } output_format;

typedef enum progress_mode { PROGRESS_AUTO, PROGRESS_TTY, PROGRESS_JSON, PROGRESS_NONE } progress_mode;

typedef struct options {
    fm_sky_params sky;
    fm_render_params render;
    const char *output;      /* EXR path */
    const char *sidecar;     /* JSON path, or NULL for the default (output with .json) */
    progress_mode progress;
    const char *colorspace; /* OpenColorIO colour space of the EXR (name or alias) */
    int list_colorspaces;   /* --list-colorspaces: print them and exit */
    int print_atmosphere;   /* --print-atmosphere: print the composition as JSON and exit */
    const char *preview;    /* PNG path or NULL */
    int half;               /* half-float EXR */
    const char *spectral;   /* spectral EXR path or NULL */
    const char *sun_disk_map; /* --sun-disk-map: a second EXR with the disk, the main one without; or NULL */
    fm_exr_compression compression;
    output_format format;   /* --format, else from the output's extension (.hdr: Radiance) */
    double exposure_ev;     /* preview exposure when have_exposure, else automatic */
    int have_exposure;
    /* A time series (--time-start, --time-end, --step): frames > 0 maps at time_start_s +
     * round(i * step_min * 60) seconds of the local day; sky.hour..second hold the first. */
    int frames;
    int time_start_s, time_end_s;
    double step_min;
} options;

typedef enum parse_result { PARSE_RUN, PARSE_EXIT_OK, PARSE_ERROR } parse_result;

/* The defaults of every option (before parsing). */
void options_set_defaults(options *opt);

/* Parses argv (after the subcommand).  On PARSE_ERROR, msg holds one line. */
parse_result options_parse(int argc, char **argv, options *opt, char *msg, size_t msg_size);

/* "--sun-elevation" for the library field "sun_elevation_deg", or NULL. */
const char *options_flag_for(const char *field);

void options_print_usage(void);

#endif
