#include "presets.h"

#include "base/executable.h"
#include "base/platform.h"
#include "base/status.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int is_directory(const char *path)
{
    return platform_path_kind(path) == PLATFORM_DIRECTORY;
}

/* A presets folder is recognised by its biomes/ (every render with a named biome reads it). */
static int holds_presets(const char *dir)
{
    char sub[1100];
    return snprintf(sub, sizeof sub, "%s/biomes", dir) < (int)sizeof sub && is_directory(sub);
}

/* Relative to the executable's folder: a copy with presets/ beside it, the add-on zip and the
 * package (bin/firmament, presets/), an installation (bin/, share/firmament/presets/). */
static const char *const beside_executable[] = {"presets", "../presets", "../share/firmament/presets"};

fm_status presets_locate(const char *given, char *out, size_t size, fm_error *err)
{
    const char *env = getenv("FIRMAMENT_PRESETS");
    const char *chosen = given && given[0] ? given : env && env[0] ? env : NULL;
    if (chosen) {
        if ((size_t)snprintf(out, size, "%s", chosen) >= size)
            return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "presets folder path too long: '%.200s...'", chosen);
        return FM_OK;
    }
    char exe[900];
    int have_exe = executable_dir(exe, sizeof exe) == 0;
    for (size_t i = 0; have_exe && i < sizeof beside_executable / sizeof beside_executable[0]; i++)
        if ((size_t)snprintf(out, size, "%s/%s", exe, beside_executable[i]) < size && holds_presets(out))
            return FM_OK;
    const char *source = FIRMAMENT_SOURCE_PRESETS; /* "" in the portable build (scripts/package) */
    if (source[0] && holds_presets(source) && (size_t)snprintf(out, size, "%s", source) < size)
        return FM_OK;
    out[0] = '\0';
    return fm_fail(err, FM_ERR_INVALID_ARGUMENT,
                   "firmament's presets were not found (no presets/ holding biomes/ beside the executable in "
                   "'%.300s' nor one level up%s%.300s): set FIRMAMENT_PRESETS to that folder",
                   have_exe ? exe : "(unknown)", source[0] ? ", nor " : "", source);
}

typedef struct json_names {
    char names[48][64];
    int count;
} json_names;

/* Keeps the names of up to 48 .json files, without the extension. */
static void add_json_name(void *ctx, const char *name)
{
    json_names *j = ctx;
    size_t n = strlen(name);
    if (j->count < 48 && n > 5 && n < 64 && strcmp(name + n - 5, ".json") == 0) {
        snprintf(j->names[j->count], sizeof j->names[j->count], "%.*s", (int)(n - 5), name);
        j->count++;
    }
}

int presets_list(const char *dir, const char *what, char *out, size_t size)
{
    json_names found = {.count = 0};
    platform_list_dir(dir, add_json_name, &found);
    char(*names)[64] = found.names;
    int count = found.count;
    for (int i = 1; i < count; i++) /* insertion sort: a handful of names */
        for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
            char t[64];
            memcpy(t, names[j], sizeof t);
            memcpy(names[j], names[j - 1], sizeof t);
            memcpy(names[j - 1], t, sizeof t);
        }
    out[0] = '\0';
    size_t used = 0;
    for (int i = 0; i < count && used < size; i++)
        used += (size_t)snprintf(out + used, size - used, "%s%s", i ? ", " : "", names[i]);
    if (count == 0)
        snprintf(out, size, "no %s files found in %.400s", what, dir);
    return count;
}

/* The names of the .json files in the presets folder's sub/ (comma-separated into out). */
static fm_status names_in(const char *presets_directory, const char *sub, const char *what, char *out, size_t size,
                          fm_error *err)
{
    char dir[900];
    out[0] = '\0';
    fm_status status = presets_locate(presets_directory, dir, sizeof dir - 16, err);
    if (status != FM_OK)
        return status;
    strcat(dir, "/");
    strcat(dir, sub);
    char names[sizeof dir + 64];
    if (presets_list(dir, what, names, sizeof names) == 0)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s", names);
    snprintf(out, size, "%s", names);
    return FM_OK;
}

fm_status fm_biome_names(const char *presets_directory, char *out, size_t size, fm_error *err)
{
    return names_in(presets_directory, "biomes", "biome", out, size, err);
}

fm_status fm_cloud_names(const char *presets_directory, char *out, size_t size, fm_error *err)
{
    return names_in(presets_directory, "clouds", "cloud", out, size, err);
}

static int is_path(const char *s)
{
    size_t n = strlen(s);
    return strchr(s, '/') != NULL || (n > 5 && strcmp(s + n - 5, ".json") == 0);
}

fm_status presets_find(const char *name_or_path, const char *presets_dir, const char *sub, const char *field,
                       const char *what, const char *known_first, char *path, size_t size, fm_error *err)
{
    /* never a shortened path: that would read another file */
    if (strlen(name_or_path) >= size - 16)
        return fm_fail_parameter(err, field, "'%.60s...' is %zu bytes, longer than the %zu a %s name or path may have",
                                 name_or_path, strlen(name_or_path), size - 17, what);
    if (is_path(name_or_path)) {
        snprintf(path, size, "%s", name_or_path);
        return FM_OK;
    }
    char dir[900];
    fm_status found = presets_locate(presets_dir, dir, sizeof dir - 16, err);
    if (found)
        return found;
    strcat(dir, "/");
    strcat(dir, sub);
    int valid = name_or_path[0] != '\0';
    for (const char *c = name_or_path; *c; c++)
        valid = valid && ((*c >= 'a' && *c <= 'z') || (*c >= '0' && *c <= '9') || *c == '-' || *c == '_');
    snprintf(path, size, "%s/%s.json", dir, name_or_path);
    FILE *f = valid ? platform_fopen(path, "r") : NULL;
    if (!f) {
        char names[600];
        presets_list(dir, what, names, sizeof names);
        return fm_fail_parameter(err, field, "unknown %s '%s' (known: %s%s)", what, name_or_path, known_first, names);
    }
    fclose(f);
    return FM_OK;
}
