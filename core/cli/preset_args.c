#include "preset_args.h"
#include "args.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int given(int argc, char **argv, const char *flag)
{
    size_t n = strlen(flag);
    for (int i = 1; i < argc; i++)
        if (strncmp(argv[i], flag, n) == 0 && (argv[i][n] == '\0' || argv[i][n] == '='))
            return 1;
    return 0;
}

/* A preset value that an explicit option replaces as a whole: the sun's angles give way to a time
 * given on the command line, turbidity and aod550 to each other, the aerosol and ozone settings to
 * a custom atmosphere, the view's settings to another --camera. */
static int superseded(const char *key, int argc, char **argv)
{
    int time = given(argc, argv, "--time") || given(argc, argv, "--time-start");
    int atmosphere = given(argc, argv, "--atmosphere");
    if (!strcmp(key, "sun_elevation") || !strcmp(key, "sun_azimuth"))
        return time;
    if (!strcmp(key, "time"))
        return given(argc, argv, "--time-start");
    if (!strcmp(key, "turbidity"))
        return atmosphere || given(argc, argv, "--aod550");
    if (!strcmp(key, "aod550"))
        return atmosphere || given(argc, argv, "--turbidity");
    if (!strcmp(key, "biome") || !strcmp(key, "humidity") || !strcmp(key, "ozone_du"))
        return atmosphere;
    if (!strcmp(key, "camera") || !strcmp(key, "fisheye_projection") || !strcmp(key, "fov") ||
        !strcmp(key, "look_azimuth") || !strcmp(key, "look_elevation") || !strcmp(key, "aspect"))
        return given(argc, argv, "--camera");
    return 0;
}

int preset_args_expand(int argc, char **argv, preset_args *out, char *msg, size_t msg_size)
{
    memset(out, 0, sizeof *out);
    out->argc = argc;
    out->argv = argv;
    const char *name = NULL;
    int at = -1, span = 0;
    for (int i = 1; i < argc; i++) {
        const char *v = NULL;
        int n = 0;
        if (strcmp(argv[i], "--preset") == 0) {
            if (i + 1 >= argc) {
                snprintf(msg, msg_size, "--preset needs a value");
                return 2;
            }
            v = argv[i + 1];
            n = 2;
        } else if (strncmp(argv[i], "--preset=", 9) == 0) {
            v = argv[i] + 9;
            n = 1;
        }
        if (!v)
            continue;
        if (name) {
            snprintf(msg, msg_size, "--preset: given twice");
            return 2;
        }
        name = v;
        at = i;
        span = n;
        i += n - 1;
    }
    if (!name)
        return 0;

    fm_error err = {0};
    out->preset = malloc(sizeof *out->preset);
    const int most = (int)(sizeof out->preset->settings / sizeof out->preset->settings[0]);
    out->flags = calloc((size_t)most, sizeof *out->flags);
    out->argv = calloc((size_t)argc + 2 * (size_t)most + 1, sizeof *out->argv);
    out->argv_owned = out->argv != NULL;
    if (!out->preset || !out->flags || !out->argv) {
        snprintf(msg, msg_size, "out of memory");
        return 2;
    }
    if (fm_sky_preset_load(name, NULL, out->preset, &err)) {
        /* "preset: ..." -> "--preset: ..." */
        snprintf(msg, msg_size, "--%s", err.message);
        return 2;
    }
    /* The preset alone must parse: a value the parser refuses is reported against the file. */
    int k = 0;
    out->argv[k++] = argv[0];
    for (int i = 0; i < out->preset->count; i++) {
        fm_preset_setting *s = &out->preset->settings[i];
        snprintf(out->flags[i], sizeof out->flags[i], "--%s", s->key);
        for (char *c = out->flags[i]; *c; c++)
            if (*c == '_')
                *c = '-';
        out->argv[k++] = out->flags[i];
        out->argv[k++] = s->value;
    }
    options probe;
    char why[512];
    if (options_parse(k, out->argv, &probe, why, sizeof why) == PARSE_ERROR) {
        snprintf(msg, msg_size, "--preset: %s: %s", out->preset->path, why);
        return 2;
    }
    /* The settings an explicit option supersedes are left out; then the user's options follow. */
    k = 1;
    for (int i = 0; i < out->preset->count; i++)
        if (!superseded(out->preset->settings[i].key, argc, argv)) {
            out->argv[k++] = out->flags[i];
            out->argv[k++] = out->preset->settings[i].value;
        }
    for (int i = 1; i < argc; i++)
        if (i < at || i >= at + span)
            out->argv[k++] = argv[i];
    out->argv[k] = NULL;
    out->argc = k;
    return 0;
}

void preset_args_free(preset_args *p)
{
    if (p->argv_owned)
        free(p->argv);
    free(p->preset);
    free(p->flags);
    memset(p, 0, sizeof *p);
}
