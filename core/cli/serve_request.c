#include "serve_request.h"

#include "option_table.h"
#include "output_args.h"

#include "base/text.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Options `render` takes that a request may not: a request makes one map and its sidecar (the
 * rest of what a job may not set, batch_job.c refuses). */
static const char *const not_served[] = {"preview", "spectral", "sun-disk-map", "print-atmosphere", "exposure", NULL};

void request_field_of(const char *message, char *field, size_t size)
{
    field[0] = '\0';
    size_t n = strcspn(message, ": ");
    const option_spec *o = NULL;
    if (n > 2 && message[0] == '-' && message[1] == '-') {
        char flag[64];
        snprintf(flag, sizeof flag, "%.*s", (int)n, message);
        o = option_find(flag);
    } else if (n == 2 && message[0] == '-') {
        for (int i = 0; i < option_count && !o; i++)
            if (option_specs[i].short_flag == message[1])
                o = &option_specs[i];
    }
    if (!o)
        return;
    snprintf(field, size, "%s", o->flag);
    for (char *c = field; *c; c++)
        if (*c == '-')
            *c = '_';
}

static int is_not_served(const char *key)
{
    char flag[64];
    snprintf(flag, sizeof flag, "%s", key);
    for (char *c = flag; *c; c++)
        if (*c == '_')
            *c = '-';
    for (int i = 0; not_served[i]; i++)
        if (strcmp(not_served[i], flag) == 0)
            return 1;
    return 0;
}

static int fail(request_error *why, const char *field, const char *message)
{
    snprintf(why->field, sizeof why->field, "%s", field);
    snprintf(why->message, sizeof why->message, "%s", message);
    return 2;
}

/* The request's argv: -o, --sidecar, then each setting in the line's order. */
static int request_argv(const cJSON *obj, job_argv *a, request_error *why)
{
    char msg[512];
    if (job_argv_add(a, "render"))
        return fail(why, "", "out of memory");
    const cJSON *output = cJSON_GetObjectItemCaseSensitive(obj, "output");
    if (!cJSON_IsString(output))
        return fail(why, "output", output ? "\"output\" must be a path (a string)" : "no \"output\" path");
    const cJSON *sidecar = cJSON_GetObjectItemCaseSensitive(obj, "sidecar");
    if (sidecar && !cJSON_IsString(sidecar))
        return fail(why, "sidecar", "\"sidecar\" must be a path (a string)");
    if (job_argv_add(a, "-o") || job_argv_add(a, output->valuestring) ||
        (sidecar && (job_argv_add(a, "--sidecar") || job_argv_add(a, sidecar->valuestring))))
        return fail(why, "", "out of memory");
    for (const cJSON *item = obj->child; item; item = item->next) {
        if (!strcmp(item->string, "id") || !strcmp(item->string, "output") || !strcmp(item->string, "sidecar"))
            continue;
        if (is_not_served(item->string)) {
            snprintf(msg, sizeof msg, "key '%s': firmament serve writes a map and its sidecar only", item->string);
            return fail(why, item->string, msg);
        }
        if (job_add_setting(a, item, "a request", msg, sizeof msg))
            return fail(why, item->string, msg);
    }
    return 0;
}

request *request_parse(const char *text, long line, cJSON **id, request_error *why)
{
    *id = NULL;
    cJSON *obj = cJSON_Parse(text);
    request *r = cJSON_IsObject(obj) ? calloc(1, sizeof *r) : NULL;
    char msg[512];
    int code = 0;
    if (!cJSON_IsObject(obj)) {
        snprintf(msg, sizeof msg, "line %ld: not a JSON object", line);
        code = fail(why, "", msg);
    } else {
        const cJSON *given = cJSON_GetObjectItemCaseSensitive(obj, "id");
        *id = given ? cJSON_Duplicate(given, 1) : NULL;
        if (!r || (given && !*id))
            code = fail(why, "", "out of memory");
    }
    if (!code && (code = request_argv(obj, &r->args, why)) == 0) {
        if (preset_args_expand(r->args.argc, r->args.argv, &r->pre, msg, sizeof msg)) {
            code = 2;
        } else {
            switch (options_parse(r->pre.argc, r->pre.argv, &r->opt, msg, sizeof msg)) {
            case PARSE_RUN:
                break;
            case PARSE_EXIT_OK: /* --help and --list-colorspaces are refused before */
                snprintf(msg, sizeof msg, "nothing to render");
                code = 2;
                break;
            case PARSE_ERROR:
                code = 2;
                break;
            }
        }
        if (code) {
            request_field_of(msg, why->field, sizeof why->field);
            snprintf(why->message, sizeof why->message, "%s", msg);
        }
    }
    if (!code) {
        r->sidecar = r->opt.sidecar ? text_copy(r->opt.sidecar) : default_sidecar(r->opt.output);
        if (!r->sidecar)
            code = fail(why, "", "out of memory");
    }
    cJSON_Delete(obj);
    if (code) {
        request_free(r);
        return NULL;
    }
    if (*id && !(r->id = cJSON_Duplicate(*id, 1))) {
        fail(why, "", "out of memory");
        request_free(r);
        return NULL;
    }
    return r;
}

void request_free(request *r)
{
    if (!r)
        return;
    preset_args_free(&r->pre);
    job_argv_free(&r->args);
    cJSON_Delete(r->id);
    free(r->sidecar);
    free(r);
}
