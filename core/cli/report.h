/* What the executable prints: one-line errors on stderr, and progress as a bar on stderr (tty) or
 * as JSON lines on stdout for programs such as the Blender add-on:
 *     {"event": "progress", "fraction": 0.42, "stage": "multiple scattering"}
 *     {"event": "done", "output": "sky.exr", "sidecar": "sky.json", "seconds": 3.1, "peak_memory_mib": 90}
 * (time series: see reporter_frame_start). */
#ifndef FM_CLI_REPORT_H
#define FM_CLI_REPORT_H

#include <stdio.h>

#include "args.h"

typedef struct reporter {
    progress_mode mode;
    double last_fraction, last_time, start_time;
    const char *last_stage;
    double frame_start_time; /* time series: when the current frame began */
} reporter;

void reporter_init(reporter *r, progress_mode mode);
/* fm_progress_fn */
void reporter_progress(void *user, double fraction, const char *stage);
void reporter_done(reporter *r, const char *output, const char *sidecar);
/* Ends a tty bar line before other output. */
void reporter_finish_line(reporter *r);

/* Time series (`render --time-start ...`): each frame is announced with its time and sun, and
 * finished with its files; a summary ends the series.  JSON lines:
 *     {"event": "frame", "index": 0, "frames": 6, "time": "06:00:00", "sun_elevation_deg": -3.2,
 *      "sun_azimuth_deg": 62.1, "night": false}
 *     {"event": "frame_done", "index": 0, "output": "sky_0000.exr", "sidecar": "sky_0000.json", "seconds": 1.2}
 *     {"event": "done", "frames": 6, "night_frames": 0, "output": "sky_0000.exr", "last_output": "sky_0005.exr",
 *      "seconds": 7.9, "peak_memory_mib": 95}
 * "night": the sun's centre below -18 degrees (astronomical night): the map is rendered, dark. */
void reporter_frame_start(reporter *r, int index, int frames, const char *time, double elevation_deg,
                          double azimuth_deg, int night);
void reporter_frame_done(reporter *r, int index, const char *output, const char *sidecar);
void reporter_series_done(reporter *r, int frames, int night_frames, const char *first, const char *last);

/* s on f with its control characters written as escapes (\n, \t, \r, \xNN), as errors print
 * the names they quote: text from a file never moves the terminal's cursor or splits a line. */
void put_escaped(FILE *f, const char *s);

void report_error(const char *fmt, ...)
#if defined(__MINGW32__) /* its C99 printf (__USE_MINGW_ANSI_STDIO), not msvcrt's */
    __attribute__((format(gnu_printf, 1, 2)))
#elif defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
