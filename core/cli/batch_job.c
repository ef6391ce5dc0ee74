#include "batch_job.h"

#include "args.h"
#include "option_table.h"
#include "preset_args.h"
#include "report.h"

#include "base/platform.h"
#include "base/text.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const job_info_keys[] = {"sky_cover_tenths", "name", "description", NULL};

/* Options a job may not hold: the batch sets how it runs, and a job is one map. */
static const char *const refused_options[] = {"threads", "progress", "time-start", "time-end", "step",
                                              "list-colorspaces", "help", "output", "sidecar", NULL};

static int listed(const char *const *list, const char *s)
{
    for (int i = 0; list[i]; i++)
        if (strcmp(list[i], s) == 0)
            return 1;
    return 0;
}

int job_argv_add(job_argv *a, const char *s)
{
    if (a->argc + 1 >= (int)(sizeof a->argv / sizeof a->argv[0]))
        return -1;
    if (!(a->argv[a->argc] = text_copy(s)))
        return -1;
    a->argv[++a->argc] = NULL;
    return 0;
}

void job_argv_free(job_argv *a)
{
    for (int i = 0; i < a->argc; i++)
        free(a->argv[i]);
    a->argc = 0;
}

static int is_absolute(const char *p)
{
    return p[0] == '/' || p[0] == '\\' || (p[0] && p[1] == ':');
}

char *manifest_path(const manifest *m, const cJSON *job, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(job, key);
    if (!cJSON_IsString(v))
        return NULL;
    const char *dir = is_absolute(v->valuestring) ? "" : m->dir;
    size_t n = strlen(dir) + strlen(v->valuestring) + 1;
    char *p = malloc(n);
    if (p)
        snprintf(p, n, "%s%s", dir, v->valuestring);
    return p;
}

int job_add_setting(job_argv *a, const cJSON *item, const char *who, char *msg, size_t msg_size)
{
    char flag[64], value[64];
    snprintf(flag, sizeof flag, "--%s", item->string);
    for (char *c = flag; *c; c++)
        if (*c == '_')
            *c = '-';
    const option_spec *o = option_find(flag);
    if (!o || (o->flags & NOT_PARSED && strcmp(o->flag, "preset") != 0) || listed(refused_options, o->flag)) {
        snprintf(msg, msg_size, "key '%s' is not a render option %s may set", item->string, who);
        return 2;
    }
    const char *text = value;
    if (o->kind == OPTION_SWITCH) {
        if (!cJSON_IsBool(item)) {
            snprintf(msg, msg_size, "key '%s' must be true or false", item->string);
            return 2;
        }
        return cJSON_IsTrue(item) && job_argv_add(a, flag) ? 2 : 0;
    }
    if (cJSON_IsString(item))
        text = item->valuestring;
    else if (cJSON_IsNumber(item))
        snprintf(value, sizeof value, "%.17g", item->valuedouble);
    else {
        snprintf(msg, msg_size, "key '%s' must be a number or a string", item->string);
        return 2;
    }
    if (job_argv_add(a, flag) || job_argv_add(a, text)) {
        snprintf(msg, msg_size, "out of memory");
        return 2;
    }
    return 0;
}

int job_to_argv(const manifest *m, const cJSON *job, job_argv *a, char *msg, size_t msg_size)
{
    a->argc = 0;
    if (job_argv_add(a, "render")) {
        snprintf(msg, msg_size, "out of memory");
        return 2;
    }
    if (!cJSON_IsString(cJSON_GetObjectItemCaseSensitive(job, "output"))) {
        snprintf(msg, msg_size, "no \"output\" path");
        return 2;
    }
    for (const char *const *k = (const char *const[]){"output", "sidecar", NULL}; *k; k++) {
        char *p = manifest_path(m, job, *k);
        int failed = p && (job_argv_add(a, (*k)[0] == 'o' ? "-o" : "--sidecar") || job_argv_add(a, p));
        free(p);
        if (failed) {
            snprintf(msg, msg_size, "out of memory");
            return 2;
        }
    }
    for (const cJSON *item = job->child; item; item = item->next) {
        if (!strcmp(item->string, "output") || !strcmp(item->string, "sidecar") || listed(job_info_keys, item->string))
            continue;
        int code = job_add_setting(a, item, "a job", msg, msg_size);
        if (code)
            return code;
    }
    return 0;
}

int job_check(const manifest *m, const cJSON *job, char *msg, size_t msg_size)
{
    job_argv a = {0};
    char why[512];
    int code = job_to_argv(m, job, &a, why, sizeof why);
    preset_args pre = {0};
    options opt;
    if (!code && preset_args_expand(a.argc, a.argv, &pre, why, sizeof why))
        code = 2;
    else if (!code && options_parse(pre.argc, pre.argv, &opt, why, sizeof why) != PARSE_RUN)
        code = 2;
    if (code)
        snprintf(msg, msg_size, "%s", why);
    preset_args_free(&pre);
    job_argv_free(&a);
    return code;
}

/* The whole file (malloc'd, NUL-terminated), or NULL with errno set. */
static char *read_text(const char *path)
{
    FILE *f = platform_fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    while (buf) {
        n += fread(buf + n, 1, cap - n - 1, f);
        if (n < cap - 1)
            break;
        char *bigger = realloc(buf, cap *= 2);
        if (!bigger)
            free(buf);
        buf = bigger;
    }
    int bad = ferror(f);
    fclose(f);
    if (buf && bad) {
        free(buf);
        errno = EIO;
        return NULL;
    }
    if (buf)
        buf[n] = '\0';
    return buf;
}

static int add_job(manifest *m, cJSON *job, int line)
{
    cJSON **jobs = realloc(m->jobs, (size_t)(m->count + 1) * sizeof *jobs);
    if (jobs)
        m->jobs = jobs;
    int *lines = jobs ? realloc(m->line, (size_t)(m->count + 1) * sizeof *lines) : NULL;
    if (lines)
        m->line = lines;
    if (!jobs || !lines)
        return -1;
    m->jobs[m->count] = job;
    m->line[m->count++] = line;
    return 0;
}

int manifest_read(const char *path, manifest *m, char *msg, size_t msg_size)
{
    memset(m, 0, sizeof *m);
    m->path = path;
    const char *slash = platform_last_separator(path);
    size_t dir_len = slash ? (size_t)(slash - path + 1) : 0;
    m->dir = malloc(dir_len + 1);
    char *text = m->dir ? read_text(path) : NULL;
    if (!text) {
        snprintf(msg, msg_size, "cannot read the manifest '%s': %s", path, strerror(errno));
        return 2;
    }
    snprintf(m->dir, dir_len + 1, "%.*s", (int)dir_len, path);
    int code = 0, line = 0;
    for (char *s = text; *s && !code; line++) {
        char *end = strchr(s, '\n');
        if (end)
            *end = '\0';
        char why[512];
        cJSON *job = NULL;
        if (strspn(s, " \t\r") != strlen(s)) {
            job = cJSON_Parse(s);
            if (!cJSON_IsObject(job)) {
                snprintf(msg, msg_size, "%s: line %d: not a JSON object", path, line + 1);
                code = 2;
            } else if (job_check(m, job, why, sizeof why)) {
                snprintf(msg, msg_size, "%s: line %d: %s", path, line + 1, why);
                code = 2;
            } else if (add_job(m, job, line + 1)) {
                snprintf(msg, msg_size, "out of memory");
                code = 2;
            } else {
                job = NULL;
            }
        }
        cJSON_Delete(job);
        s = end ? end + 1 : s + strlen(s);
    }
    free(text);
    if (!code && m->count == 0) {
        snprintf(msg, msg_size, "%s: no jobs", path);
        code = 2;
    }
    return code;
}

int manifest_open(const char *path, manifest *m)
{
    char msg[1024];
    if (!manifest_read(path, m, msg, sizeof msg))
        return 0;
    report_error("%s", msg);
    manifest_free(m);
    return 2;
}

void manifest_free(manifest *m)
{
    for (int i = 0; i < m->count; i++)
        cJSON_Delete(m->jobs[i]);
    free(m->jobs);
    free(m->line);
    free(m->dir);
    memset(m, 0, sizeof *m);
}

int write_file_atomic(const char *path, const char *text, size_t size)
{
    const char *slash = platform_last_separator(path);
    size_t dir_len = slash ? (size_t)(slash - path + 1) : 0;
    size_t n = strlen(path) + 16;
    char *tmp = malloc(n);
    if (!tmp)
        return -1;
    snprintf(tmp, n, "%.*s.%s.XXXXXX", (int)dir_len, path, path + dir_len);
    int ok = platform_create_unique(tmp) == 0;
    FILE *f = ok ? platform_fopen(tmp, "wb") : NULL;
    ok = f && fwrite(text, 1, size, f) == size;
    ok = f && fclose(f) == 0 && ok;
    ok = ok && platform_rename_replace(tmp, path) == 0;
    int e = errno;
    if (!ok)
        platform_remove(tmp);
    free(tmp);
    errno = e;
    return ok ? 0 : -1;
}
