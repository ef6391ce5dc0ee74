#define _POSIX_C_SOURCE 200809L
#include "report.h"

#include "base/platform.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double now_seconds(void)
{
    return platform_monotonic_seconds();
}

void reporter_init(reporter *r, progress_mode mode)
{
    if (mode == PROGRESS_AUTO)
        mode = platform_stderr_is_terminal() ? PROGRESS_TTY : PROGRESS_NONE;
    r->mode = mode;
    r->last_fraction = -1.0;
    r->last_time = 0.0;
    r->start_time = now_seconds();
    r->frame_start_time = r->start_time;
    r->last_stage = NULL;
}

/* JSON string contents: our stage names and paths need only quote and backslash escaping,
 * control characters are dropped. */
static void print_json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        if ((unsigned char)*s >= 0x20)
            fputc(*s, f);
    }
    fputc('"', f);
}

void reporter_progress(void *user, double fraction, const char *stage)
{
    reporter *r = user;
    double t = now_seconds();
    int new_stage = !r->last_stage || strcmp(stage, r->last_stage) != 0;
    if (!new_stage && fraction < 1.0 && (fraction - r->last_fraction < 0.005 || t - r->last_time < 0.1))
        return;
    r->last_fraction = fraction;
    r->last_time = t;
    r->last_stage = stage;
    if (r->mode == PROGRESS_TTY) {
        int width = 30, filled = (int)(fraction * width + 0.5);
        fprintf(stderr, "\r[%.*s%*s] %3d%% %-22s", filled, "##############################", width - filled, "",
                (int)(fraction * 100.0 + 0.5), stage);
        fflush(stderr);
    } else if (r->mode == PROGRESS_JSON) {
        printf("{\"event\": \"progress\", \"fraction\": %.4f, \"stage\": ", fraction);
        print_json_string(stdout, stage);
        printf("}\n");
        fflush(stdout);
    }
}

void reporter_finish_line(reporter *r)
{
    if (r->mode == PROGRESS_TTY && r->last_stage) {
        fputc('\n', stderr);
        r->last_stage = NULL;
    }
}

void reporter_done(reporter *r, const char *output, const char *sidecar)
{
    double seconds = now_seconds() - r->start_time;
    reporter_finish_line(r);
    if (r->mode == PROGRESS_JSON) {
        printf("{\"event\": \"done\", \"output\": ");
        print_json_string(stdout, output);
        printf(", \"sidecar\": ");
        print_json_string(stdout, sidecar);
        printf(", \"seconds\": %.3f, \"peak_memory_mib\": %.1f}\n", seconds, platform_peak_memory_mib());
        fflush(stdout);
    } else if (r->mode == PROGRESS_TTY) {
        fprintf(stderr, "wrote %s and %s in %.1f s\n", output, sidecar, seconds);
    }
}

/* ---- time series ------------------------------------------------------------------------------ */

void reporter_frame_start(reporter *r, int index, int frames, const char *time, double elevation_deg,
                          double azimuth_deg, int night)
{
    r->frame_start_time = now_seconds();
    r->last_fraction = -1.0;
    r->last_stage = NULL;
    if (r->mode == PROGRESS_JSON) {
        printf("{\"event\": \"frame\", \"index\": %d, \"frames\": %d, \"time\": ", index, frames);
        print_json_string(stdout, time);
        printf(", \"sun_elevation_deg\": %.4f, \"sun_azimuth_deg\": %.4f, \"night\": %s}\n", elevation_deg,
               azimuth_deg, night ? "true" : "false");
        fflush(stdout);
    } else if (r->mode == PROGRESS_TTY) {
        fprintf(stderr, "frame %d/%d  %s  sun %.2f deg up, azimuth %.2f deg%s\n", index + 1, frames, time,
                elevation_deg, azimuth_deg, night ? "  (below -18 deg: night, dark sky)" : "");
    }
}

void reporter_frame_done(reporter *r, int index, const char *output, const char *sidecar)
{
    double seconds = now_seconds() - r->frame_start_time;
    reporter_finish_line(r);
    if (r->mode == PROGRESS_JSON) {
        printf("{\"event\": \"frame_done\", \"index\": %d, \"output\": ", index);
        print_json_string(stdout, output);
        printf(", \"sidecar\": ");
        print_json_string(stdout, sidecar);
        printf(", \"seconds\": %.3f}\n", seconds);
        fflush(stdout);
    } else if (r->mode == PROGRESS_TTY) {
        fprintf(stderr, "wrote %s and %s in %.1f s\n", output, sidecar, seconds);
    }
}

void reporter_series_done(reporter *r, int frames, int night_frames, const char *first, const char *last)
{
    double seconds = now_seconds() - r->start_time;
    reporter_finish_line(r);
    if (r->mode == PROGRESS_JSON) {
        printf("{\"event\": \"done\", \"frames\": %d, \"night_frames\": %d, \"output\": ", frames, night_frames);
        print_json_string(stdout, first);
        printf(", \"last_output\": ");
        print_json_string(stdout, last);
        printf(", \"seconds\": %.3f, \"peak_memory_mib\": %.1f}\n", seconds, platform_peak_memory_mib());
        fflush(stdout);
    } else if (r->mode == PROGRESS_TTY) {
        fprintf(stderr, "wrote %d frames, %s to %s, in %.1f s", frames, first, last, seconds);
        if (night_frames)
            fprintf(stderr, "; %d with the sun below -18 deg (night: dark maps)", night_frames);
        fputc('\n', stderr);
    }
}

/* a name or path that holds a newline would otherwise break an error's one line in two */
void put_escaped(FILE *f, const char *s)
{
    for (; *s; s++) {
        unsigned char c = (unsigned char)*s;
        if (c == '\n')
            fputs("\\n", f);
        else if (c == '\t')
            fputs("\\t", f);
        else if (c == '\r')
            fputs("\\r", f);
        else if (c < 0x20 || c == 0x7f)
            fprintf(f, "\\x%02x", c);
        else
            fputc(c, f);
    }
}

void report_error(const char *fmt, ...)
{
    va_list ap, size_ap;
    va_start(ap, fmt);
    va_copy(size_ap, ap);
    int n = vsnprintf(NULL, 0, fmt, size_ap);
    va_end(size_ap);
    char small[1024], *line = small;
    if (n >= 0 && (size_t)n >= sizeof small)
        line = malloc((size_t)n + 1);
    fputs("firmament: ", stderr);
    if (line && n >= 0) {
        vsnprintf(line, (size_t)n + 1, fmt, ap);
        put_escaped(stderr, line);
    } else {
        vfprintf(stderr, fmt, ap); /* no memory for the line: as it comes */
    }
    fputc('\n', stderr);
    if (line != small)
        free(line);
    va_end(ap);
}
