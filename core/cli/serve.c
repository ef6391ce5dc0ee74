/* firmament serve (serve.h).  Two threads: the reader parses each line of standard input as it
 * arrives and answers a bad one at once; a good one waits in a single slot, where a newer request
 * replaces it (the replaced one is answered "superseded": a viewport wants the latest sky, not
 * every one).  The main thread takes the waiting request, renders it and answers.  Replies are
 * whole lines, written under the lock and flushed one by one; notes go to standard error. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime (Windows: winpthreads' pthread_time.h) */
#include "serve.h"

#include "args.h"
#include "numbers.h"
#include "output_args.h"
#include "report.h"
#include "serve_cache.h"
#include "serve_request.h"
#include "usage.h"

#include "base/json_file.h"
#include "base/platform.h"

#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2, LINE_MAX_BYTES = 1 << 20 };

/* The signal that stops the server (as `render`'s): the render in progress polls it and stops. */
static atomic_int cancel_signal;
/* Stops a round of refinement (fm_sky_live_refine) at once: a request arrived, the input ended, or
 * a signal. */
static atomic_int refine_cancel;

static void on_signal(int sig)
{
    atomic_store(&cancel_signal, sig);
    atomic_store(&refine_cancel, 1);
}

typedef struct server {
    pthread_mutex_t lock; /* guards waiting, input_ended and standard output */
    pthread_cond_t wake;
    request *waiting;     /* the latest request not yet taken, or NULL */
    int input_ended;
} server;

/* ---- replies ---------------------------------------------------------------------------------- */

static cJSON *new_reply(const cJSON *id, const char *status)
{
    cJSON *r = cJSON_CreateObject();
    cJSON_AddItemToObject(r, "id", id ? cJSON_Duplicate(id, 1) : cJSON_CreateNull());
    cJSON_AddStringToObject(r, "status", status);
    return r;
}

static cJSON *error_reply(const cJSON *id, const char *status, const char *field, const char *message)
{
    cJSON *r = new_reply(id, status);
    cJSON_AddItemToObject(r, "field", field && field[0] ? cJSON_CreateString(field) : cJSON_CreateNull());
    cJSON_AddStringToObject(r, "message", message);
    return r;
}

/* One line on standard output, flushed; the caller holds the lock.  Frees reply. */
static void write_reply_locked(cJSON *reply)
{
    char *text = reply ? cJSON_PrintUnformatted(reply) : NULL;
    if (text) {
        fputs(text, stdout);
        fputc('\n', stdout);
        fflush(stdout);
    }
    cJSON_free(text);
    cJSON_Delete(reply);
}

static void put_reply(server *sv, cJSON *reply)
{
    pthread_mutex_lock(&sv->lock);
    write_reply_locked(reply);
    pthread_mutex_unlock(&sv->lock);
}

/* A library error as `render` words it: the field's flag ("--sun-elevation: ..."), and the request
 * key that set it ("sun_elevation"). */
static cJSON *library_error_reply(const cJSON *id, const fm_error *err)
{
    char message[600], field[64] = "";
    const char *flag = err->parameter[0] ? options_flag_for(err->parameter) : NULL;
    size_t plen = strlen(err->parameter);
    if (flag && strncmp(err->message, err->parameter, plen) == 0 && err->message[plen] == ':')
        snprintf(message, sizeof message, "%s%s", flag, err->message + plen);
    else
        snprintf(message, sizeof message, "%s", err->message);
    request_field_of(message, field, sizeof field);
    return error_reply(id, "error", field, message);
}

/* ---- the reader thread -------------------------------------------------------------------------- */

/* The next line of f without its end (malloc'd), or NULL at the end of the input.  A line longer
 * than LINE_MAX_BYTES is read to its end and comes back empty with *too_long set. */
static char *read_line(FILE *f, int *too_long)
{
    size_t cap = 512, n = 0;
    char *buf = malloc(cap);
    int ch = EOF;
    *too_long = 0;
    while (buf && (ch = getc(f)) != EOF && ch != '\n') {
        if (*too_long)
            continue;
        if (n + 1 >= cap) {
            char *bigger = cap < LINE_MAX_BYTES ? realloc(buf, cap * 2) : NULL;
            if (!bigger) {
                *too_long = 1;
                n = 0;
                continue;
            }
            buf = bigger;
            cap *= 2;
        }
        buf[n++] = (char)ch;
    }
    if (!buf || (ch == EOF && n == 0 && !*too_long)) {
        free(buf);
        return NULL;
    }
    if (n > 0 && buf[n - 1] == '\r')
        n--;
    buf[n] = '\0';
    return buf;
}

/* r becomes the waiting request; the one it replaces is answered "superseded". */
static void offer(server *sv, request *r)
{
    pthread_mutex_lock(&sv->lock);
    request *replaced = sv->waiting;
    sv->waiting = r;
    atomic_store(&refine_cancel, 1);
    if (replaced)
        write_reply_locked(new_reply(replaced->id, "superseded"));
    pthread_cond_signal(&sv->wake);
    pthread_mutex_unlock(&sv->lock);
    request_free(replaced);
}

static void *read_requests(void *arg)
{
    server *sv = arg;
    char *text;
    int too_long;
    for (long line = 1; (text = read_line(stdin, &too_long)); line++) {
        if (too_long) {
            char msg[96];
            snprintf(msg, sizeof msg, "line %ld: longer than %d bytes", line, LINE_MAX_BYTES);
            put_reply(sv, error_reply(NULL, "error", NULL, msg));
        } else if (strspn(text, " \t") != strlen(text)) { /* blank lines are no requests */
            cJSON *id;
            request_error why;
            request *r = request_parse(text, line, &id, &why);
            if (r)
                offer(sv, r);
            else
                put_reply(sv, error_reply(id, "error", why.field, why.message));
            cJSON_Delete(id);
        }
        free(text);
    }
    pthread_mutex_lock(&sv->lock);
    sv->input_ended = 1;
    atomic_store(&refine_cancel, 1);
    pthread_cond_signal(&sv->wake);
    pthread_mutex_unlock(&sv->lock);
    return NULL;
}

/* ---- the main thread ---------------------------------------------------------------------------- */

/* The waiting request, after waiting for one when `wait`; NULL when the input ended with none
 * waiting, or on a signal (the waiting request then stays): *over set; or without `wait`, when none
 * waits. */
static request *next_request(server *sv, int wait, int *over)
{
    pthread_mutex_lock(&sv->lock);
    while (wait && !sv->waiting && !sv->input_ended && !atomic_load(&cancel_signal)) {
        /* a signal handler cannot signal the condition: look at the flag every 50 ms */
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 50000000L;
        if (until.tv_nsec >= 1000000000L) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000L;
        }
        pthread_cond_timedwait(&sv->wake, &sv->lock, &until);
    }
    request *r = atomic_load(&cancel_signal) ? NULL : sv->waiting;
    if (r)
        sv->waiting = NULL;
    *over = !r && (sv->input_ended || atomic_load(&cancel_signal));
    pthread_mutex_unlock(&sv->lock);
    return r;
}

/* The map and sidecar the request asks for must be writable, and two files. */
static cJSON *check_paths(const request *r)
{
    fm_error err = {0};
    char msg[600];
    if (fm_output_check_path(r->opt.output, &err)) {
        snprintf(msg, sizeof msg, "-o: %s", err.message);
        return error_reply(r->id, "error", "output", msg);
    }
    if (fm_output_check_path(r->sidecar, &err)) {
        snprintf(msg, sizeof msg, "--sidecar: %s", err.message);
        return error_reply(r->id, "error", "sidecar", msg);
    }
    if (strcmp(r->opt.output, r->sidecar) == 0 || platform_same_file(r->opt.output, r->sidecar) == 1) {
        snprintf(msg, sizeof msg, "-o and --sidecar would both write '%s'", r->sidecar);
        return error_reply(r->id, "error", "sidecar", msg);
    }
    return NULL;
}

/* When a request began and ended its stages: taken, atmosphere found, map rendered, files in place. */
enum { T_START, T_ATMOSPHERE, T_RENDER, T_WRITE, T_COUNT };

static void add_seconds(cJSON *obj, const char *name, double s)
{
    cJSON_AddNumberToObject(obj, name, round(s * 1e4) / 1e4);
}

/* "done" with the files, the time taken (and per stage), where the atmosphere came from and the
 * sidecar's fields. */
static cJSON *done_reply(const request *r, const double t[T_COUNT], live_source from, live_band band, int refined)
{
    cJSON *reply = new_reply(r->id, "done");
    cJSON_AddStringToObject(reply, "output", r->opt.output);
    cJSON_AddStringToObject(reply, "sidecar", r->sidecar);
    add_seconds(reply, "seconds", t[T_WRITE] - t[T_START]);
    cJSON *stages = cJSON_AddObjectToObject(reply, "stage_seconds");
    add_seconds(stages, "atmosphere", t[T_ATMOSPHERE] - t[T_START]);
    add_seconds(stages, "render", t[T_RENDER] - t[T_ATMOSPHERE]);
    add_seconds(stages, "write", t[T_WRITE] - t[T_RENDER]);
    cJSON_AddStringToObject(reply, "cache", live_source_name(from));
    cJSON_AddStringToObject(reply, "twilight_band", live_band_name(band));
    if (refined >= 0)
        cJSON_AddNumberToObject(reply, "refined", refined);
    fm_error err = {0};
    fm_status s;
    json_reader rd = {r->sidecar, "sidecar", &err};
    cJSON *fields = json_reader_load(&rd, &s);
    for (const cJSON *f = fields ? fields->child : NULL; f; f = f->next)
        if (!cJSON_GetObjectItemCaseSensitive(reply, f->string))
            cJSON_AddItemToObject(reply, f->string, cJSON_Duplicate(f, 1));
    cJSON_Delete(fields);
    return reply;
}

/* The request's map and its reply; *used the atmosphere it was rendered from (owned by the cache,
 * valid until its next call), NULL when it failed. */
static cJSON *serve_request(request *r, live_cache *cache, const fm_colour_config *colour, int threads,
                            fm_sky_live **used)
{
    *used = NULL;
    double t[T_COUNT] = {platform_monotonic_seconds()};
    options *opt = &r->opt;
    opt->sky.threads = threads;
    opt->render.threads = threads;
    opt->render.cancel = &cancel_signal;
    cJSON *bad = check_paths(r);
    if (bad)
        return bad;
    fm_error err = {0};
    if (fm_colour_config_check(colour, opt->colorspace, &err)) {
        char msg[600];
        snprintf(msg, sizeof msg, "--colorspace: %s", err.message);
        return error_reply(r->id, "error", "colorspace", msg);
    }
    fm_sky_params sky;
    fm_sky_live *live = NULL;
    live_source from = LIVE_BUILT;
    live_band band = LIVE_BAND_PENDING;
    fm_output *out = NULL;
    fm_image *img = NULL;
    /* the files' temporaries first: a request whose files cannot be made fails before a build */
    fm_status s = fm_sky_params_resolve_sun(&opt->sky, &sky, &err);
    if (!s && !(s = fm_output_open(opt->output, r->sidecar, &out, &err)))
        s = output_set_format(opt, out, &err);
    if (!s)
        s = live_cache_get(cache, &sky, sky.sun_elevation_deg, &cancel_signal, &live, &from, &band, &err);
    t[T_ATMOSPHERE] = platform_monotonic_seconds();
    if (!s)
        s = fm_sky_live_render(live, sky.sun_elevation_deg, sky.sun_azimuth_deg, &opt->render, &img, &err);
    if (!s && img->content == FM_IMAGE_XYZ)
        s = fm_image_to_colorspace(img, colour, opt->colorspace, &err);
    t[T_RENDER] = platform_monotonic_seconds();
    if (!s && !(s = fm_output_stage(out, img, &cancel_signal, &err)))
        s = fm_output_publish(&out, 1, &err);
    t[T_WRITE] = platform_monotonic_seconds();
    fm_output_close(out); /* removes the temporary files a failure left */
    fm_image_destroy(img);
    if (s == FM_ERR_CANCELLED || (s && atomic_load(&cancel_signal)))
        return error_reply(r->id, "cancelled", NULL, "interrupted; nothing was written");
    if (s)
        return library_error_reply(r->id, &err);
    *used = live;
    return done_reply(r, t, from, band,
                      fm_sky_live_reads_refined(live, sky.sun_elevation_deg) ? fm_sky_live_rounds(live) : -1);
}

/* The server's state between requests: the last request done and the atmosphere it was rendered
 * from, whose twilight tables the server refines while no request waits. */
typedef struct idle_work {
    request *last;
    fm_sky_live *live;
} idle_work;

/* One request served and answered; it becomes the last when done. */
static void serve_one(server *sv, idle_work *w, request *r, live_cache *cache, const fm_colour_config *colour,
                      int threads)
{
    fm_sky_live *used;
    put_reply(sv, serve_request(r, cache, colour, threads, &used));
    request_free(w->last);
    w->last = used ? r : NULL;
    w->live = used;
    if (!used)
        request_free(r);
}

/* One round of refinement of the last atmosphere's twilight tables (saved to the cache); when it
 * completes and the last request's map reads the band, that map again, answered again with its id
 * and the rounds ("refined").  A request arriving cancels the round at once: nothing changes. */
static void refine_round(server *sv, idle_work *w, live_cache *cache, const fm_colour_config *colour, int threads)
{
    fm_error err = {0};
    fm_status s = live_cache_refine(cache, w->live, &refine_cancel, &err);
    if (s == FM_ERR_CANCELLED)
        return;
    if (s) {
        report_error("serve: refining the twilight tables: %s", err.message);
        w->live = NULL; /* not again */
        return;
    }
    fm_sky_params sun;
    if (w->last && fm_sky_params_resolve_sun(&w->last->opt.sky, &sun, &err) == FM_OK &&
        fm_sky_live_reads_refined(w->live, sun.sun_elevation_deg)) {
        request *r = w->last;
        w->last = NULL;
        serve_one(sv, w, r, cache, colour, threads);
    }
}

/* ---- the command -------------------------------------------------------------------------------- */

typedef struct serve_options {
    const char *cache_dir; /* NULL: none */
    char default_dir[4096];
    long long keep, threads, refine;
} serve_options;

/* -1 to go on, else the exit code. */
static int parse_serve_options(int argc, char **argv, serve_options *so)
{
    so->keep = 2;
    so->threads = 0;
    so->refine = 64;
    so->cache_dir = fm_default_cache_dir(so->default_dir, sizeof so->default_dir) == 0 ? so->default_dir : NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--help") || !strcmp(a, "-h")) {
            command_print_help(stdout, command_find("serve", NULL));
            return 0;
        } else if (!strcmp(a, "--no-cache")) {
            so->cache_dir = NULL;
        } else if (!strcmp(a, "--cache") || !strcmp(a, "--memory") || !strcmp(a, "--threads") ||
                   !strcmp(a, "--refine")) {
            if (!v) {
                report_error("serve: %s needs a value", a);
                return EXIT_USAGE;
            }
            i++;
            if (!strcmp(a, "--cache") && !v[0]) {
                report_error("serve: --cache: an empty folder name (--no-cache keeps no files)");
                return EXIT_USAGE;
            } else if (!strcmp(a, "--cache")) {
                so->cache_dir = v;
            } else if (!strcmp(a, "--memory") && !parse_whole(v, 1, 64, &so->keep)) {
                report_error("serve: --memory: '%s' is not a whole number in [1, 64]", v);
                return EXIT_USAGE;
            } else if (!strcmp(a, "--threads") && !parse_whole(v, 0, 256, &so->threads)) {
                report_error("serve: --threads: '%s' is not a whole number in [0, 256]", v);
                return EXIT_USAGE;
            } else if (!strcmp(a, "--refine") && !parse_whole(v, 0, 64, &so->refine)) {
                report_error("serve: --refine: '%s' is not a whole number in [0, 64]", v);
                return EXIT_USAGE;
            }
        } else {
            report_error("serve: unknown option '%s' (firmament serve --help lists them)", a);
            return EXIT_USAGE;
        }
    }
    return -1;
}

/* After a signal: the waiting request is answered (unless standard output is what closed), then
 * the process ends at once, as the reader may be inside a read of standard input. */
static void stop(server *sv, live_cache *cache, fm_colour_config *colour)
{
    int sig = atomic_load(&cancel_signal);
    pthread_mutex_lock(&sv->lock);
    request *w = sv->waiting;
    sv->waiting = NULL;
#ifdef SIGPIPE
    if (w && sig != SIGPIPE)
#else
    if (w)
#endif
        write_reply_locked(error_reply(w->id, "cancelled", NULL, "interrupted; nothing was written"));
    pthread_mutex_unlock(&sv->lock);
    request_free(w);
    live_cache_close(cache);
    fm_colour_config_close(colour);
    report_error("serve: interrupted (signal %d)", sig);
    fflush(stdout);
    fflush(stderr);
    _Exit(128 + sig);
}

int run_serve(int argc, char **argv)
{
    serve_options so;
    int code = parse_serve_options(argc, argv, &so);
    if (code >= 0)
        return code;
    fm_error err = {0};
    fm_colour_config *colour = NULL;
    if (fm_colour_config_open(NULL, &colour, &err)) {
        report_error("%s", err.message);
        return EXIT_RUNTIME;
    }
    live_cache *cache = live_cache_open(so.cache_dir, (int)so.keep);
    server sv = {.waiting = NULL, .input_ended = 0};
    pthread_t reader;
    if (!cache || pthread_mutex_init(&sv.lock, NULL) || pthread_cond_init(&sv.wake, NULL)) {
        report_error("serve: out of memory");
        live_cache_close(cache);
        fm_colour_config_close(colour);
        return EXIT_RUNTIME;
    }
    platform_on_interrupt(on_signal);
    if (pthread_create(&reader, NULL, read_requests, &sv)) {
        report_error("serve: cannot start the thread that reads requests");
        live_cache_close(cache);
        fm_colour_config_close(colour);
        return EXIT_RUNTIME;
    }
    idle_work w = {NULL, NULL};
    for (int over = 0; !over;) {
        const int refine = w.live && fm_sky_live_refinable(w.live) && fm_sky_live_rounds(w.live) < so.refine;
        if (refine)
            atomic_store(&refine_cancel, 0); /* before looking: a request after it cancels the round */
        request *r = next_request(&sv, !refine, &over);
        if (r)
            serve_one(&sv, &w, r, cache, colour, (int)so.threads);
        else if (!over && refine)
            refine_round(&sv, &w, cache, colour, (int)so.threads);
    }
    request_free(w.last);
    if (atomic_load(&cancel_signal))
        stop(&sv, cache, colour);
    pthread_join(reader, NULL);
    pthread_cond_destroy(&sv.wake);
    pthread_mutex_destroy(&sv.lock);
    live_cache_close(cache);
    fm_colour_config_close(colour);
    return 0;
}
