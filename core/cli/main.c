/* The firmament executable: parse, render, write, exit.  The only place that prints or exits.
 * Exit codes: 0 ok, 1 runtime failure, 2 bad usage or input, 128 + signal when interrupted. */
#include "args.h"
#include "batch.h"
#include "numbers.h"
#include "option_table.h"
#include "output_args.h"
#include "preset_args.h"
#include "report.h"
#include "serve.h"
#include "sun_command.h"
#include "time_args.h"
#include "usage.h"
#include "revision.h" /* FIRMAMENT_REVISION, written at build time (cmake/revision.cmake) */

#include "base/platform.h"
#include "firmament/firmament.h"

#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { EXIT_RUNTIME = 1, EXIT_USAGE = 2 };

/* Set by SIGINT/SIGTERM/SIGHUP/SIGPIPE (Windows: Ctrl-C, Ctrl-Break, closing the console) to the
 * signal number; the library polls it and stops.  (A closed pipe, e.g. `--progress json | head -1`,
 * would otherwise kill the process before it removes its temporary files.) */
static atomic_int cancel_signal;

static void on_signal(int sig)
{
    atomic_store(&cancel_signal, sig);
}

static void install_signal_handlers(void)
{
    platform_on_interrupt(on_signal);
}

/* render --preset: the expanded options and the user's own, to tell who set a refused value */
static struct {
    const preset_args *pre;
    int argc;
    char **argv;
    const char *job; /* batch run: the job's JSON object, for the sidecar */
} origin;

static int on_command_line(const char *flag)
{
    size_t n = strlen(flag);
    for (int i = 1; i < origin.argc; i++)
        if (strncmp(origin.argv[i], flag, n) == 0 && (origin.argv[i][n] == '\0' || origin.argv[i][n] == '='))
            return 1;
    return 0;
}

/* The preset file that set flag, or NULL when the user gave it (or there is no preset). */
static const char *preset_source(const char *flag)
{
    if (!origin.pre || !origin.pre->preset || on_command_line(flag))
        return NULL;
    for (int i = 0; i < origin.pre->preset->count; i++)
        if (strcmp(origin.pre->flags[i], flag) == 0)
            return origin.pre->preset->path;
    return NULL;
}

/* Whether the user set flag, on the command line or in the preset. */
static int flag_set(const char *flag)
{
    return on_command_line(flag) || preset_source(flag);
}

/* One line naming the problem; for a parameter, the command-line flag that set it (and the preset
 * file, when the value came from there). */
static void report_library_error_then(const fm_error *err, const char *suffix)
{
    /* a pinhole's height follows from the width and the aspect: blame the width where the aspect is
     * the default one */
    const char *field = strcmp(err->parameter, "camera.aspect") == 0 && !flag_set("--aspect") ? "width" : err->parameter;
    const char *flag = err->parameter[0] ? options_flag_for(field) : NULL;
    size_t plen = strlen(err->parameter);
    if (flag && strncmp(err->message, err->parameter, plen) == 0 && err->message[plen] == ':') {
        const char *from = preset_source(flag);
        if (from)
            report_error("--preset: %s: %s%s%s", from, flag, err->message + plen, suffix);
        else
            report_error("%s%s%s", flag, err->message + plen, suffix);
    } else {
        report_error("%s%s", err->message, suffix);
    }
}

static void report_library_error(const fm_error *err)
{
    report_library_error_then(err, "");
}

/* What stopped a run: a closed standard output (e.g. `--progress json | head -1`) says so here,
 * and main then says nothing more about it */
static const char *stop_reason(void)
{
#ifdef SIGPIPE
    if (atomic_load(&cancel_signal) == SIGPIPE)
        return "standard output closed";
#endif
    return "interrupted";
}

static int exit_code_for(fm_status s)
{
    if (s == FM_ERR_CANCELLED) {
        int sig = atomic_load(&cancel_signal);
        return 128 + (sig ? sig : SIGINT);
    }
    return s == FM_ERR_INVALID_ARGUMENT ? EXIT_USAGE : EXIT_RUNTIME;
}

/* The colour config and the checked --colorspace; prints --list-colorspaces.  Returns -1 to go
 * on, else the exit code. */
static int open_colour(const options *opt, fm_colour_config **cfg)
{
    fm_error err = {0};
    fm_status s = fm_colour_config_open(NULL, cfg, &err);
    if (!s && opt->list_colorspaces) {
        for (int i = 0; i < fm_colour_config_count(*cfg); i++)
            printf("%s\n", fm_colour_config_name(*cfg, i));
        return 0;
    }
    if (!s && (s = fm_colour_config_check(*cfg, opt->colorspace, &err))) {
        const char *from = preset_source("--colorspace");
        if (from)
            report_error("--preset: %s: --colorspace: %s", from, err.message);
        else
            report_error("--colorspace: %s", err.message);
        return exit_code_for(s);
    }
    if (s) {
        report_library_error(&err);
        return exit_code_for(s);
    }
    return -1;
}

/* path with its directory resolved (links, ".", ".."), so that two spellings of one file compare
 * equal; a copy of path itself where the directory cannot be resolved (malloc'd, NULL: no memory) */
static char *resolved_path(const char *path)
{
    const char *slash = platform_last_separator(path);
    size_t dir_len = slash ? (slash == path ? 1 : (size_t)(slash - path)) : 0;
    char *dir = malloc(dir_len + 2);
    if (dir)
        snprintf(dir, dir_len + 2, "%.*s", slash ? (int)dir_len : 1, slash ? path : ".");
    char *real = dir ? platform_resolve_dir(dir) : NULL;
    const char *base = slash ? slash + 1 : path;
    size_t n = (real ? strlen(real) : 0) + strlen(path) + 2;
    char *out = malloc(n);
    if (out)
        snprintf(out, n, "%s%s%s", real ? real : "", real ? "/" : "", real ? base : path);
    free(real);
    free(dir);
    return out;
}

static int same_file(const char *a, const char *b)
{
    int same = platform_same_file(a, b);
    if (same >= 0)
        return same;
    char *ra = resolved_path(a), *rb = resolved_path(b);
    same = ra && rb ? strcmp(ra, rb) == 0 : strcmp(a, b) == 0;
    free(ra);
    free(rb);
    return same;
}

/* Before the render: every output (paths[i], or NULL where not asked for; names[i] the option that
 * set it) must be writable and no two may be one file, else one line and exit 2, nothing written.
 * Returns 0 when all is well. */
static int check_outputs(const char *const *paths, const char *const *names, int n)
{
    for (int i = 0; i < n; i++) {
        fm_error err = {0};
        if (paths[i] && fm_output_check_path(paths[i], &err)) {
            report_error("%s: %s", names[i], err.message);
            return EXIT_USAGE;
        }
        for (int j = 0; j < i; j++)
            if (paths[i] && paths[j] && same_file(paths[i], paths[j])) {
                report_error("%s and %s would both write '%s'", names[j], names[i], paths[i]);
                return EXIT_USAGE;
            }
    }
    return 0;
}

/* --spectral and --preview, staged with the map: they appear when it does, or not at all. */
static fm_status stage_extras(const options *opt, fm_output *out, const fm_image *spectral, const fm_image *img,
                              const fm_colour_config *colour, const char *preview, fm_error *err)
{
    fm_status s;
    if (opt->spectral && (s = fm_output_stage_spectral(out, opt->spectral, spectral, img, &cancel_signal, err)))
        return s;
    if (preview) {
        if (atomic_load(&cancel_signal))
            return FM_ERR_CANCELLED; /* reported as an interruption, not through err */
        double ev = opt->have_exposure ? opt->exposure_ev : fm_image_auto_exposure(img);
        if ((s = fm_output_stage_preview(out, preview, img, colour, ev, err)))
            return s;
    }
    return FM_OK;
}

/* ---- time series: render --time-start HH:MM --time-end HH:MM --step MIN ------------------------ */

/* path with _NNNN before its extension: sky.exr -> sky_0003.exr, out -> out_0003 */
static char *numbered_path(const char *path, int index)
{
    size_t n = strlen(path), stem = n;
    const char *slash = platform_last_separator(path);
    const char *dot = strrchr(path, '.');
    if (dot && (!slash || dot > slash) && dot != path && dot - 1 != slash)
        stem = (size_t)(dot - path);
    char *s = malloc(n + 16);
    if (s)
        snprintf(s, n + 16, "%.*s_%04d%s", (int)stem, path, index, path + stem);
    return s;
}

/* One fm_sky for the whole series: its atmosphere and tables are built once, and fm_sky_set_time
 * moves the sun for each frame (the maps are the same bits as separate runs at those times). */
static int run_series(options *opt, const fm_colour_config *colour)
{
    fm_error err = {0};
    fm_sky *sky = NULL;
    int code = 0, written = 0, night = 0;
    char *first = NULL, *last = NULL;
    reporter rep;
    reporter_init(&rep, opt->progress);
    opt->render.progress = reporter_progress;
    opt->render.progress_user = &rep;
    opt->render.cancel = &cancel_signal;
    install_signal_handlers();

    if (platform_path_kind(opt->output) == PLATFORM_DIRECTORY) {
        report_error("-o: '%s' is a directory; a series needs a file name to number (e.g. '%s/sky.exr')",
                     opt->output, opt->output);
        return EXIT_USAGE;
    }
    /* every frame's files writable and distinct before the first render */
    for (int i = 0; i < opt->frames && !code; i++) {
        char *exr = numbered_path(opt->output, i);
        char *json = exr ? (opt->sidecar ? numbered_path(opt->sidecar, i) : default_sidecar(exr)) : NULL;
        char *preview = opt->preview ? numbered_path(opt->preview, i) : NULL;
        if (!exr || !json || (opt->preview && !preview)) {
            report_error("out of memory");
            code = EXIT_RUNTIME;
        } else {
            const char *paths[] = {exr, json, preview};
            const char *names[] = {"-o", opt->sidecar ? "--sidecar" : "the sidecar", "--preview"};
            code = check_outputs(paths, names, 3);
        }
        free(exr);
        free(json);
        free(preview);
    }
    if (code)
        return code;
    fm_status s = fm_sky_create(&opt->sky, &sky, &err);
    if (s) {
        report_library_error(&err);
        return exit_code_for(s);
    }
    for (int i = 0; i < opt->frames && !code; i++) {
        int t = opt->time_start_s + (int)lround(i * opt->step_min * 60.0);
        char *exr = numbered_path(opt->output, i);
        char *json = exr ? (opt->sidecar ? numbered_path(opt->sidecar, i) : default_sidecar(exr)) : NULL;
        char *preview = opt->preview ? numbered_path(opt->preview, i) : NULL;
        fm_output *out = NULL;
        fm_image *img = NULL;
        if (!exr || !json || (opt->preview && !preview)) {
            report_error("out of memory");
            code = EXIT_RUNTIME;
        } else if ((s = fm_sky_set_time(sky, t / 3600, t / 60 % 60, t % 60, &err))) {
            report_library_error(&err);
            code = exit_code_for(s);
        } else {
            const fm_sky_params *sp = fm_sky_get_params(sky);
            char when[16];
            format_time_of_day(t, when, sizeof when);
            int dark = sp->sun_elevation_deg < -18.0;
            night += dark;
            reporter_frame_start(&rep, i, opt->frames, when, sp->sun_elevation_deg, sp->sun_azimuth_deg, dark);
            if ((s = fm_output_open(exr, json, &out, &err))) {
                report_library_error(&err);
                code = s == FM_ERR_IO ? EXIT_USAGE : exit_code_for(s);
            } else if ((s = output_set_format(opt, out, &err)) ||
                       (s = fm_render(sky, &opt->render, &img, &err)) ||
                       (img->content == FM_IMAGE_XYZ &&
                        (s = fm_image_to_colorspace(img, colour, opt->colorspace, &err))) ||
                       (s = stage_extras(opt, out, NULL, img, colour, preview, &err)) ||
                       (s = fm_output_stage(out, img, &cancel_signal, &err)) ||
                       (s = fm_output_publish(&out, 1, &err))) {
                reporter_finish_line(&rep);
                char kept[96];
                snprintf(kept, sizeof kept, "; frame %d was not written (%d before it were kept)", i, written);
                if (s == FM_ERR_CANCELLED)
                    report_error("%s%s", stop_reason(), kept);
                else
                    report_library_error_then(&err, kept);
                code = exit_code_for(s);
            } else {
                reporter_frame_done(&rep, i, exr, json);
                written++;
            }
        }
        fm_output_close(out);
        fm_image_destroy(img);
        free(json);
        free(preview);
        if (!code && i == 0)
            first = exr;
        else if (!code) {
            free(last);
            last = exr;
        } else
            free(exr);
    }
    if (!code)
        reporter_series_done(&rep, written, night, first, last ? last : first);
    free(first);
    free(last);
    fm_sky_destroy(sky);
    return code;
}

/* --sun-disk-map: stages the map with the disk for its own file, then takes the disk out of img,
 * which the main output then holds without it. */
static int run_render_options(int argc, char **argv);

static fm_status stage_disk_map(fm_output *disk_out, fm_image *img, fm_error *err)
{
    fm_status s = fm_output_stage(disk_out, img, &cancel_signal, err);
    if (s)
        return s;
    fm_image_remove_sun_disk(img);
    return FM_OK;
}

static int run_render_job(int argc, char **argv, const char *job)
{
    preset_args pre;
    char msg[512];
    /* else the first file it cannot find (the colour config) would be blamed, not the variable */
    const char *presets = getenv("FIRMAMENT_PRESETS");
    if (presets && presets[0] && platform_path_kind(presets) != PLATFORM_DIRECTORY) {
        report_error("FIRMAMENT_PRESETS: '%s' is not a directory (unset it to use the presets shipped with firmament)", presets);
        return EXIT_USAGE;
    }
    if (preset_args_expand(argc, argv, &pre, msg, sizeof msg)) {
        report_error("%s", msg);
        preset_args_free(&pre);
        return EXIT_USAGE;
    }
    origin.pre = &pre;
    origin.argc = argc;
    origin.argv = argv;
    origin.job = job;
    int code = run_render_options(pre.argc, pre.argv);
    origin.pre = NULL;
    origin.job = NULL;
    preset_args_free(&pre);
    return code;
}
/* --print-atmosphere: the sky's composition (what the sidecar's "atmosphere" holds) without a render;
 * milliseconds (no tables built), so the add-on calls it as the aerosol settings change. */
static int print_atmosphere(const options *opt)
{
    fm_error err = {0};
    fm_composition c;
    fm_status s = fm_composition_compute(&opt->sky, &c, &err);
    if (s) {
        report_library_error(&err);
        return exit_code_for(s);
    }
    double cloud_tau = 0.0;
    for (int i = 0; i < c.cloud_count; i++)
        cloud_tau += c.cloud[i].tau550;
    printf("{\"biome\": \"%s\", \"rayleigh_optical_depth_550nm\": %.9g, \"ozone_optical_depth_550nm\": %.9g, "
           "\"aerosol_optical_depth_550nm\": %.9g, \"turbidity\": %.9g, \"humidity_percent\": %.9g, "
           "\"extinction_550nm_ground_per_km\": %.9g, \"visibility_km\": %.9g, \"cloud_layers\": %d, "
           "\"cloud_optical_depth_550nm\": %.9g}\n",
           c.biome, c.rayleigh_tau550, c.ozone_tau550, c.aerosol_tau550, c.turbidity, c.humidity_percent,
           c.rayleigh_ext550_ground_per_km + c.aerosol_ext550_ground_per_km, c.visibility_km, c.cloud_count, cloud_tau);
    return 0;
}

static int run_render_options(int argc, char **argv)
{
    options opt;
    char msg[512];
    switch (options_parse(argc, argv, &opt, msg, sizeof msg)) {
    case PARSE_EXIT_OK:
        return 0;
    case PARSE_ERROR:
        report_error("%s", msg);
        return EXIT_USAGE;
    case PARSE_RUN:
        break;
    }
    if (opt.print_atmosphere)
        return print_atmosphere(&opt);
    fm_colour_config *colour = NULL;
    int colour_code = open_colour(&opt, &colour);
    if (colour_code >= 0 || opt.frames > 0) {
        int series_code = colour_code >= 0 ? colour_code : run_series(&opt, colour);
        fm_colour_config_close(colour);
        return series_code;
    }
    char *sidecar = opt.sidecar ? NULL : default_sidecar(opt.output);
    const char *sidecar_path = opt.sidecar ? opt.sidecar : sidecar;
    if (!sidecar_path) {
        report_error("out of memory");
        return EXIT_RUNTIME;
    }

    fm_error err = {0};
    fm_sky *sky = NULL;
    fm_output *out = NULL, *disk_out = NULL;
    fm_image *img = NULL, *spectral = NULL; /* spectral: the --spectral map, img made from it */
    char *disk_sidecar = opt.sun_disk_map ? default_sidecar(opt.sun_disk_map) : NULL;
    int code = 0;
    if (opt.sun_disk_map && !disk_sidecar) {
        report_error("out of memory");
        free(sidecar);
        fm_colour_config_close(colour);
        return EXIT_RUNTIME;
    }
    reporter rep;
    reporter_init(&rep, opt.progress);
    opt.render.progress = reporter_progress;
    opt.render.progress_user = &rep;
    opt.render.cancel = &cancel_signal;
    install_signal_handlers();

    fm_status s;
    const char *paths[] = {opt.output, sidecar_path, opt.preview, opt.spectral, opt.sun_disk_map, disk_sidecar};
    const char *names[] = {"-o",         opt.sidecar ? "--sidecar" : "the sidecar", "--preview", "--spectral",
                           "--sun-disk-map", "the disk map's sidecar"};
    if ((code = check_outputs(paths, names, 6)))
        goto done;
    if ((s = fm_sky_create(&opt.sky, &sky, &err))) {
        report_library_error(&err);
        code = exit_code_for(s);
        goto done;
    }
    /* Fail on an unwritable path now, not after the render. */
    if ((s = fm_output_open(opt.output, sidecar_path, &out, &err)) ||
        (opt.sun_disk_map && (s = fm_output_open(opt.sun_disk_map, disk_sidecar, &disk_out, &err)))) {
        report_library_error(&err);
        code = s == FM_ERR_IO ? EXIT_USAGE : exit_code_for(s);
        goto done;
    }
    if ((s = output_set_format(&opt, out, &err)) || (origin.job && (s = fm_output_set_job(out, origin.job, &err))) ||
        (disk_out && (s = output_set_format(&opt, disk_out, &err))) ||
        (s = fm_render(sky, &opt.render, &img, &err)) ||
        (opt.spectral && (spectral = img, img = NULL, s = fm_image_spectral_to_xyz(spectral, &img, &err))) ||
        (img->content == FM_IMAGE_XYZ && (s = fm_image_to_colorspace(img, colour, opt.colorspace, &err))) ||
        (disk_out && (s = stage_disk_map(disk_out, img, &err))) ||
        (s = stage_extras(&opt, out, spectral, img, colour, opt.preview, &err)) ||
        (s = fm_output_stage(out, img, &cancel_signal, &err)) ||
        (s = fm_output_publish((fm_output *const[]){out, disk_out}, disk_out ? 2 : 1, &err))) {
        reporter_finish_line(&rep);
        if (s == FM_ERR_CANCELLED)
            report_error("%s; nothing was written", stop_reason());
        else
            report_library_error(&err);
        code = exit_code_for(s);
        goto done;
    }
    reporter_done(&rep, opt.output, sidecar_path);
done:
    fm_output_close(out); /* removes temporary files left by a failure */
    fm_output_close(disk_out);
    free(disk_sidecar);
    fm_colour_config_close(colour);
    fm_image_destroy(spectral);
    fm_image_destroy(img);
    fm_sky_destroy(sky);
    free(sidecar);
    return code;
}

/* firmament info FILE.exr: the header, "name (type): value" per line. */
static void print_attribute(void *user, const char *name, const char *type, const char *value)
{
    (void)user;
    put_escaped(stdout, name);
    fputs(" (", stdout);
    put_escaped(stdout, type);
    fputs("): ", stdout);
    put_escaped(stdout, value);
    fputc('\n', stdout);
}

static int run_info(int argc, char **argv)
{
    if (argc != 2 || argv[1][0] == '-') {
        report_error("%s", command_usage_line("info"));
        return EXIT_USAGE;
    }
    fm_error err = {0};
    fm_status s = fm_exr_attributes(argv[1], print_attribute, NULL, &err);
    if (s) {
        report_library_error(&err);
        return exit_code_for(s);
    }
    return 0;
}

/* firmament compare A.exr REF.exr [--exclude-sun DEG] [--json]: relative luminance error of A
 * against the reference REF. */
static int run_compare(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL};
    double exclude = 0.0;
    int n = 0, json = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--exclude-sun") == 0 && i + 1 < argc) {
            if (!parse_decimal(argv[++i], &exclude) || !(exclude >= 0.0 && exclude <= 180.0)) {
                report_error("--exclude-sun: '%s' is not an angle in [0, 180] degrees", argv[i]);
                return EXIT_USAGE;
            }
        } else if (strcmp(argv[i], "--json") == 0) {
            json = 1;
        } else if (argv[i][0] == '-' && argv[i][1]) {
            report_error("compare: unknown option '%s'", argv[i]);
            return EXIT_USAGE;
        } else if (n < 2) {
            paths[n++] = argv[i];
        } else {
            report_error("compare: unexpected argument '%s'", argv[i]);
            return EXIT_USAGE;
        }
    }
    if (n != 2) {
        report_error("%s", command_usage_line("compare"));
        return EXIT_USAGE;
    }
    fm_image *a = NULL, *b = NULL;
    fm_error err = {0};
    fm_comparison c;
    int code = 0;
    if (fm_image_read_exr(paths[0], &a, &err) || fm_image_read_exr(paths[1], &b, &err)) {
        report_error("%s", err.message);
        code = EXIT_USAGE;
    } else if (fm_image_compare(a, b, exclude, &c, &err)) {
        report_error("%s", err.message);
        code = EXIT_USAGE;
    } else if (json) {
        printf("{\"pixels\": %ld, \"rms\": %.6g, \"p99\": %.6g, \"mean\": %.6g, \"max\": %.6g, "
               "\"chromaticity\": %.6g}\n",
               c.pixels, c.rms, c.p99, c.mean, c.max, c.chromaticity);
    } else {
        printf("pixels        %ld\n"
               "rms relative  %.4f %%\n"
               "p99 relative  %.4f %%\n"
               "mean (bias)   %+.4f %%\n"
               "max relative  %.4f %%\n"
               "chromaticity  %.2e (mean |delta xy|)\n",
               c.pixels, 100.0 * c.rms, 100.0 * c.p99, 100.0 * c.mean, 100.0 * c.max, c.chromaticity);
    }
    fm_image_destroy(a);
    fm_image_destroy(b);
    return code;
}

/* `firmament help [COMMAND [SUBCOMMAND]]`: the same text as `COMMAND --help`. */
static int run_help(int argc, char **argv)
{
    if (argc < 2) {
        command_print_help(stdout, &commands[0]);
        return 0;
    }
    const command_usage *usage = command_find(argv[1], argc > 2 ? argv[2] : NULL);
    if (!usage) {
        report_error("help: unknown command '%s' (try: firmament --help)", argv[1]);
        return EXIT_USAGE;
    }
    command_print_help(stdout, usage);
    return 0;
}

static int run_command(int argc, char **argv);

/* Output that could not reach stdout (a full disk, /dev/full) is an error, not a success. */
int main(int argc, char **argv)
{
    platform_utf8_args(&argc, &argv);
    int code = run_command(argc, argv);
    if (fflush(stdout) != 0 || ferror(stdout)) {
#ifdef SIGPIPE
        if (code && atomic_load(&cancel_signal) == SIGPIPE) /* said already */
            return code;
#endif
        report_error("cannot write to standard output: %s", strerror(errno ? errno : EIO));
        return code ? code : EXIT_RUNTIME;
    }
    return code;
}

/* `firmament options --json`: the table of render options, for programs such as the add-on. */
static int run_options(int argc, char **argv)
{
    if (argc != 2 || strcmp(argv[1], "--json") != 0) {
        report_error("%s", command_usage_line("options"));
        return EXIT_USAGE;
    }
    option_print_json(stdout);
    return 0;
}

static int run_command(int argc, char **argv)
{
    if (argc < 2) {
        report_error("no command (try: firmament render, firmament sun, or firmament --help)");
        return EXIT_USAGE;
    }
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        command_print_help(stdout, &commands[0]);
        return 0;
    }
    if (strcmp(cmd, "help") == 0)
        return run_help(argc - 1, argv + 1);
    if (strcmp(cmd, "--version") == 0) {
        printf("firmament %s (%s, %s, %s)\n", FIRMAMENT_VERSION, FIRMAMENT_REVISION, FIRMAMENT_BUILD_TYPE,
               FIRMAMENT_TARGET);
        return 0;
    }
    const command_usage *usage = command_find(cmd, argc > 2 ? argv[2] : NULL);
    if (usage && command_help_asked(argc - 1, argv + 1)) { /* --help anywhere after the command */
        command_print_help(stdout, usage);
        return 0;
    }
    if (strcmp(cmd, "render") == 0)
        return run_render_job(argc - 1, argv + 1, NULL);
    if (strcmp(cmd, "batch") == 0)
        return run_batch(argc - 1, argv + 1, run_render_job);
    if (strcmp(cmd, "options") == 0)
        return run_options(argc - 1, argv + 1);
    if (strcmp(cmd, "compare") == 0)
        return run_compare(argc - 1, argv + 1);
    if (strcmp(cmd, "info") == 0)
        return run_info(argc - 1, argv + 1);
    if (strcmp(cmd, "sun") == 0)
        return run_sun(argc - 1, argv + 1);
    if (strcmp(cmd, "serve") == 0)
        return run_serve(argc - 1, argv + 1);
    report_error("unknown command '%s' (try: firmament render, or firmament --help)", cmd);
    return EXIT_USAGE;
}
