/* What the executable prints: one-line errors on stderr, and progress as a bar on stderr (tty) or
 * as JSON lines on stdout for programs such as the Blender add-on:
 *     {"event": "progress", "fraction": 0.42, "stage": "multiple scattering"}
 *     {"event": "done", "output": "sky.exr", "sidecar": "sky.json", "seconds": 3.1, "peak_memory_mib": 90} */
#ifndef FM_CLI_REPORT_H
#define FM_CLI_REPORT_H

#include "args.h"

typedef struct reporter {
    progress_mode mode;
    double last_fraction, last_time, start_time;
    const char *last_stage;
} reporter;

void reporter_init(reporter *r, progress_mode mode);
/* fm_progress_fn */
void reporter_progress(void *user, double fraction, const char *stage);
void reporter_done(reporter *r, const char *output, const char *sidecar);
/* Ends a tty bar line before other output. */
void reporter_finish_line(reporter *r);

void report_error(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
