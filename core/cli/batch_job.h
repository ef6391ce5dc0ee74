/* A batch manifest (JSON Lines, one job per line) and its jobs as `firmament render` arguments.
 * A job's keys are render options written as a sky preset writes them ("sun_elevation" for
 * --sun-elevation, "preset" for --preset), "output" and "sidecar" (paths relative to the
 * manifest's directory), and the keys that only describe the job (job_info_keys). */
#ifndef FM_CLI_BATCH_JOB_H
#define FM_CLI_BATCH_JOB_H

#include <cjson/cJSON.h>
#include <stddef.h>

/* Keys of a job that are not render options: written to the sidecar with the job, not rendered. */
extern const char *const job_info_keys[];

typedef struct manifest {
    int count;
    cJSON **jobs; /* count objects */
    int *line;    /* the line number (from 1) of each job */
    char *dir;    /* the manifest's directory with its separator, or "" */
    const char *path;
} manifest;

/* Reads and checks every line of path (a job's keys, types and values as `render` would parse
 * them).  Returns 0, or 2 with one line in msg naming the line and the key. */
int manifest_read(const char *path, manifest *m, char *msg, size_t msg_size);
void manifest_free(manifest *m);
/* manifest_read, its error reported (one line): 0, or the exit code 2 with m freed. */
int manifest_open(const char *path, manifest *m);

/* The job's path under key ("output", "sidecar"), resolved against the manifest's directory
 * (malloc'd; NULL when absent or out of memory). */
char *manifest_path(const manifest *m, const cJSON *job, const char *key);

/* argv of `render` for the job: argv[0] "render", then --key value pairs (malloc'd strings, freed
 * by job_argv_free).  Returns 0, or 2 with one line in msg. */
typedef struct job_argv {
    int argc;
    char *argv[160];
} job_argv;
int job_to_argv(const manifest *m, const cJSON *job, job_argv *a, char *msg, size_t msg_size);
int job_argv_add(job_argv *a, const char *s);
/* --key value (or --key for a switch) for one setting item, a preset's key ("sun_elevation"): 0, or
 * 2 with one line in msg for a key that is no render option who ("a job") may set, or a value of
 * the wrong JSON type.  The value itself is checked when the argv is parsed. */
int job_add_setting(job_argv *a, const cJSON *item, const char *who, char *msg, size_t msg_size);
void job_argv_free(job_argv *a);

/* Checks a job as `render` would parse it (keys, values, options that go together); 0 or 2 with msg. */
int job_check(const manifest *m, const cJSON *job, char *msg, size_t msg_size);

/* Writes text to path through a temporary beside it, renamed when complete: 0, or -1 (errno set). */
int write_file_atomic(const char *path, const char *text, size_t size);

#endif
