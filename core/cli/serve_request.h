/* One request of `firmament serve`: a JSON object on one line, the keys of a sky preset (a render
 * option with '_' for '-', "preset" for --preset), "output" and "sidecar" paths and an optional
 * "id", read through the option table exactly as `render` reads its options (docs/cli.md). */
#ifndef FM_CLI_SERVE_REQUEST_H
#define FM_CLI_SERVE_REQUEST_H

#include "args.h"
#include "batch_job.h"
#include "preset_args.h"

#include <cjson/cJSON.h>
#include <stddef.h>

typedef struct request {
    cJSON *id;        /* the request's "id" (its own copy), or NULL */
    job_argv args;    /* `render`'s argv made from the request */
    preset_args pre;  /* args with the preset's settings in front */
    options opt;      /* parsed from pre: its strings point into args and pre */
    char *sidecar;    /* the sidecar's path: the request's, or the output's with .json (malloc'd) */
} request;

/* What is wrong with a line: the request key at fault ("" when none) and one line, the message
 * `render` gives for the same option ("--sun-elevation: 100 is outside [-90, 90] degrees"). */
typedef struct request_error {
    char field[64];
    char message[1024];
} request_error;

/* The request on text (line `line` of the input, from 1, without its newline); NULL with *why
 * filled on a bad line.  *id gets a copy of the line's "id" when it has one (also on failure; NULL
 * otherwise). */
request *request_parse(const char *text, long line, cJSON **id, request_error *why);
void request_free(request *r); /* accepts NULL */

/* The request key ("sun_elevation", "output") of the option a message starts with ("--sun-elevation:",
 * "-o:"), into field; "" when it starts with none. */
void request_field_of(const char *message, char *field, size_t size);

#endif
