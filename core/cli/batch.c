#define _POSIX_C_SOURCE 200809L /* popen */
#include "batch.h"
#include "batch_job.h"
#include "batch_plan.h"
#include "batch_summary.h"
#include "numbers.h"
#include "report.h"
#include "usage.h"

#include "base/executable.h"
#include "base/platform.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* The value after argv[*i] (advancing *i), or NULL with the error reported. */
static const char *value_of(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        report_error("batch: %s needs a value", argv[*i]);
        return NULL;
    }
    return argv[++*i];
}

static int whole_arg(int argc, char **argv, int *i, long long lo, long long hi, long long *out)
{
    const char *flag = argv[*i], *v = value_of(argc, argv, i);
    if (!v)
        return 0;
    if (!parse_whole(v, lo, hi, out)) {
        report_error("batch: %s: '%s' is not a whole number in [%lld, %lld]", flag, v, lo, hi);
        return 0;
    }
    return 1;
}

/* ---- batch run --------------------------------------------------------------------------------- */

/* The job's map and sidecar exist and the sidecar records this very job. */
static int job_done(const manifest *m, const cJSON *job)
{
    char *exr = manifest_path(m, job, "output");
    char *json = manifest_path(m, job, "sidecar");
    int done = 0;
    if (exr && json && platform_path_kind(exr) == PLATFORM_FILE) {
        FILE *f = platform_fopen(json, "rb");
        char *text = NULL;
        long n = 0;
        if (f && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0 &&
            (text = malloc((size_t)n + 1)) && fread(text, 1, (size_t)n, f) == (size_t)n) {
            text[n] = '\0';
            cJSON *sidecar = cJSON_Parse(text);
            done = cJSON_Compare(cJSON_GetObjectItemCaseSensitive(sidecar, "job"), job, 1);
            cJSON_Delete(sidecar);
        }
        free(text);
        if (f)
            fclose(f);
    }
    free(exr);
    free(json);
    return done;
}

static int batch_run(int argc, char **argv, batch_render_fn render)
{
    const char *path = NULL;
    long long index = -1, count = 1, threads = 0;
    int skip = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--index")) {
            if (!whole_arg(argc, argv, &i, 0, 100000000, &index))
                return EXIT_USAGE;
        } else if (!strcmp(argv[i], "--count")) {
            if (!whole_arg(argc, argv, &i, 1, 100000000, &count))
                return EXIT_USAGE;
        } else if (!strcmp(argv[i], "--threads")) {
            if (!whole_arg(argc, argv, &i, 0, 1024, &threads))
                return EXIT_USAGE;
        } else if (!strcmp(argv[i], "--skip-existing")) {
            skip = 1;
        } else if (argv[i][0] == '-' || path) {
            report_error("batch run: unexpected '%s' (%s)", argv[i], command_usage_line("batch run"));
            return EXIT_USAGE;
        } else {
            path = argv[i];
        }
    }
    if (!path || index < 0) {
        report_error("%s", command_usage_line("batch run"));
        return EXIT_USAGE;
    }
    manifest m;
    if (manifest_open(path, &m))
        return EXIT_USAGE;
    if (index >= m.count) {
        report_error("batch run: --index %lld: the manifest has %d jobs (0 to %d)", index, m.count, m.count - 1);
        manifest_free(&m);
        return EXIT_USAGE;
    }
    /* an array's last task may ask for more than is left */
    int last = (int)(index + count < m.count ? index + count : m.count);
    int code = 0, rendered = 0, skipped = 0, failed = 0;
    char threads_text[24];
    snprintf(threads_text, sizeof threads_text, "%lld", threads);
    double start = platform_monotonic_seconds();
    for (int j = (int)index; j < last; j++) {
        const cJSON *job = m.jobs[j];
        const cJSON *out = cJSON_GetObjectItemCaseSensitive(job, "output");
        if (skip && job_done(&m, job)) {
            printf("job %d: skipped, %s is done\n", j, out->valuestring);
            skipped++;
            continue;
        }
        job_argv a = {0};
        char msg[512] = "out of memory";
        char *text = cJSON_PrintUnformatted(job);
        double t0 = platform_monotonic_seconds();
        int c = text && !job_to_argv(&m, job, &a, msg, sizeof msg) && !job_argv_add(&a, "--threads") &&
                        !job_argv_add(&a, threads_text) && !job_argv_add(&a, "--progress") && !job_argv_add(&a, "none")
                    ? render(a.argc, a.argv, text)
                    : (report_error("%s", msg), EXIT_RUNTIME);
        job_argv_free(&a);
        free(text);
        if (c == 0) {
            printf("job %d: rendered %s in %.2f s\n", j, out->valuestring, platform_monotonic_seconds() - t0);
            rendered++;
        } else {
            report_error("batch run: job %d (%s line %d) failed", j, path, m.line[j]);
            failed++;
            code = code ? code : c;
        }
        fflush(stdout);
        if (c >= 128) /* interrupted: the rest is not started */
            break;
    }
    printf("batch: %d rendered, %d skipped, %d failed in %.2f s\n", rendered, skipped, failed,
           platform_monotonic_seconds() - start);
    manifest_free(&m);
    return code;
}

/* ---- batch slurm ------------------------------------------------------------------------------- */

/* s in single quotes for sh, into out */
static void shell_quote(const char *s, char *out, size_t size)
{
    size_t n = 0;
    if (n + 1 < size)
        out[n++] = '\'';
    for (; *s && n + 5 < size; s++) {
        if (*s == '\'') {
            memcpy(out + n, "'\\''", 4);
            n += 4;
        } else {
            out[n++] = *s;
        }
    }
    if (n + 1 < size)
        out[n++] = '\'';
    out[n < size ? n : size - 1] = '\0';
}

/* path made absolute (its directory resolved), malloc'd */
static char *absolute_path(const char *path)
{
    const char *slash = platform_last_separator(path);
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path + (slash == path)) : 1, slash ? path : ".");
    char *real = platform_resolve_dir(dir);
    if (!real)
        return NULL;
    const char *base = slash ? slash + 1 : path;
    size_t n = strlen(real) + strlen(base) + 2;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%s%s%s", real, real[strlen(real) - 1] == '/' ? "" : "/", base);
    free(real);
    return out;
}

typedef struct slurm_args {
    const char *manifest, *script, *partition, *time;
    long long per_task, max_concurrent, cpus;
    int skip, submit;
} slurm_args;

static int parse_slurm_args(int argc, char **argv, slurm_args *s)
{
    *s = (slurm_args){.per_task = 1, .cpus = 1};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "--jobs-per-task")) {
            if (!whole_arg(argc, argv, &i, 1, 1000000, &s->per_task))
                return 0;
        } else if (!strcmp(a, "--max-concurrent")) {
            if (!whole_arg(argc, argv, &i, 1, 1000000, &s->max_concurrent))
                return 0;
        } else if (!strcmp(a, "--cpus-per-task")) {
            if (!whole_arg(argc, argv, &i, 1, 1024, &s->cpus))
                return 0;
        } else if (!strcmp(a, "--partition") || !strcmp(a, "--time") || !strcmp(a, "-o")) {
            const char *v = value_of(argc, argv, &i);
            if (!v)
                return 0;
            if (strpbrk(v, "\n\r")) {
                report_error("batch slurm: %s: a value on one line, please", a);
                return 0;
            }
            *(a[1] == 'o' ? &s->script : a[2] == 'p' ? &s->partition : &s->time) = v;
        } else if (!strcmp(a, "--skip-existing")) {
            s->skip = 1;
        } else if (!strcmp(a, "--submit")) {
            s->submit = 1;
        } else if (a[0] == '-' || s->manifest) {
            report_error("batch slurm: unexpected '%s' (%s)", a, command_usage_line("batch slurm"));
            return 0;
        } else {
            s->manifest = a;
        }
    }
    if (!s->manifest)
        report_error("%s", command_usage_line("batch slurm"));
    return s->manifest != NULL;
}

/* The sbatch script: task t runs jobs t*K .. t*K+K-1. */
static char *slurm_script(const slurm_args *s, int jobs, const char *exe, const char *manifest_abs, const char *logs)
{
    long long tasks = (jobs + s->per_task - 1) / s->per_task;
    char q_exe[4200], q_manifest[4200], limit[32] = "";
    shell_quote(exe, q_exe, sizeof q_exe);
    shell_quote(manifest_abs, q_manifest, sizeof q_manifest);
    if (s->max_concurrent)
        snprintf(limit, sizeof limit, "%%%lld", s->max_concurrent);
    size_t size = 16384 + 3 * strlen(manifest_abs) + strlen(exe) + strlen(logs);
    char *text = malloc(size);
    if (!text)
        return NULL;
    int n = snprintf(text, size,
                     "#!/bin/sh\n"
                     "# firmament batch slurm: the %d jobs of %s, %lld per task (firmament batch run).\n"
                     "#SBATCH --job-name=firmament\n"
                     "#SBATCH --array=0-%lld%s\n"
                     "#SBATCH --cpus-per-task=%lld\n"
                     "#SBATCH --output=%s/slurm-%%A_%%a.out\n",
                     jobs, manifest_abs, s->per_task, tasks - 1, limit, s->cpus, logs);
    if (s->partition)
        n += snprintf(text + n, size - (size_t)n, "#SBATCH --partition=%s\n", s->partition);
    if (s->time)
        n += snprintf(text + n, size - (size_t)n, "#SBATCH --time=%s\n", s->time);
    snprintf(text + n, size - (size_t)n,
             "exec %s batch run %s --index $((SLURM_ARRAY_TASK_ID * %lld)) --count %lld "
             "--threads \"${SLURM_CPUS_PER_TASK:-%lld}\"%s\n",
             q_exe, q_manifest, s->per_task, s->per_task, s->cpus, s->skip ? " --skip-existing" : "");
    return text;
}

/* sbatch --parsable SCRIPT: the array's id into id, 0 on success */
static int submit(const char *script, char *id, size_t size)
{
#ifdef _WIN32
    (void)script;
    (void)id;
    (void)size;
    report_error("batch slurm: --submit: sbatch is not run on Windows; copy the script to the cluster");
    return EXIT_USAGE;
#else
    char q[4200], cmd[4300];
    shell_quote(script, q, sizeof q);
    snprintf(cmd, sizeof cmd, "sbatch --parsable %s", q);
    FILE *p = popen(cmd, "r");
    if (!p || !fgets(id, (int)size, p)) {
        if (p)
            pclose(p);
        report_error("batch slurm: sbatch did not submit '%s' (is Slurm installed and running?)", script);
        return EXIT_RUNTIME;
    }
    id[strcspn(id, ";\r\n")] = '\0';
    int status = pclose(p);
    if (status != 0) {
        report_error("batch slurm: sbatch failed (status %d) for '%s'", status, script);
        return EXIT_RUNTIME;
    }
    return 0;
#endif
}

static int batch_slurm(int argc, char **argv)
{
    slurm_args s;
    if (!parse_slurm_args(argc, argv, &s))
        return EXIT_USAGE;
    manifest m;
    if (manifest_open(s.manifest, &m))
        return EXIT_USAGE;
    int jobs = m.count;
    manifest_free(&m);
    char exe_dir[4096], exe[4200], default_script[4200];
    if (executable_dir(exe_dir, sizeof exe_dir) != 0) {
        report_error("batch slurm: cannot tell where the firmament executable is");
        return EXIT_RUNTIME;
    }
    snprintf(exe, sizeof exe, "%s/firmament", exe_dir);
    char *manifest_abs = absolute_path(s.manifest);
    if (!s.script) {
        size_t n = strlen(s.manifest);
        const char *dot = strrchr(s.manifest, '.');
        const char *slash = platform_last_separator(s.manifest);
        if (dot && (!slash || dot > slash))
            n = (size_t)(dot - s.manifest);
        snprintf(default_script, sizeof default_script, "%.*s.sbatch", (int)n, s.manifest);
        s.script = default_script;
    }
    char *script_abs = manifest_abs ? absolute_path(s.script) : NULL;
    char *logs = script_abs ? malloc(strlen(script_abs) + 1) : NULL;
    if (logs) {
        strcpy(logs, script_abs);
        *(char *)platform_last_separator(logs) = '\0';
    }
    char *text = logs ? slurm_script(&s, jobs, exe, manifest_abs, logs) : NULL;
    int code = 0;
    if (!text) {
        report_error("batch slurm: cannot resolve '%s' or '%s'", s.manifest, s.script);
        code = EXIT_USAGE;
    } else if (write_file_atomic(s.script, text, strlen(text))) {
        report_error("batch slurm: cannot write '%s': %s", s.script, strerror(errno));
        code = EXIT_USAGE;
    } else {
        long long tasks = (jobs + s.per_task - 1) / s.per_task;
        printf("wrote %s: %d jobs as an array of %lld tasks of %lld\n", s.script, jobs, tasks, s.per_task);
        char id[64];
        if (s.submit && !(code = submit(s.script, id, sizeof id)))
            printf("submitted job array %s; follow it with: squeue -j %s   (finished: sacct -j %s)\n", id, id, id);
        else if (!s.submit)
            printf("submit it with: sbatch %s\n", s.script);
    }
    free(text);
    free(logs);
    free(script_abs);
    free(manifest_abs);
    return code;
}

int run_batch(int argc, char **argv, batch_render_fn render)
{
    const char *sub = argc > 1 ? argv[1] : "";
    if (!strcmp(sub, "plan"))
        return batch_plan(argc - 1, argv + 1);
    if (!strcmp(sub, "run"))
        return batch_run(argc - 1, argv + 1, render);
    if (!strcmp(sub, "slurm"))
        return batch_slurm(argc - 1, argv + 1);
    if (!strcmp(sub, "summary"))
        return batch_summary(argc - 1, argv + 1);
    report_error("%s", command_usage_line("batch"));
    return EXIT_USAGE;
}
