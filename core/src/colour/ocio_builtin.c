/* ocio.h without OpenColorIO: the colour spaces of firmament's own config, compiled in
 * (ocio_builtin_table.c), for the builds that cannot link OpenColorIO (the Windows build,
 * docs/decisions/2026-12-06-windows-build.md).  The same arithmetic as OpenColorIO's processors for
 * the transforms that config uses, in double precision: a curve, then a 3x3 matrix to the reference.
 * tests/unit/test_ocio_builtin.cpp compares it with OpenColorIO reading the config. */
#include "colour/ocio.h"
#include "colour/ocio_builtin.h"
#include "base/platform.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct ocio_config {
    int unused;
};

/* Nonzero when the file at path is firmament's own config (its line "name: firmament"). */
static int is_own_config(const char *path)
{
    FILE *f = path && path[0] ? platform_fopen(path, "r") : NULL;
    char line[256];
    int own = 0;
    while (f && !own && fgets(line, sizeof line, f))
        own = strncmp(line, "name: firmament", 15) == 0 && (line[15] == '\n' || line[15] == '\r' || !line[15]);
    if (f)
        fclose(f);
    return own;
}

ocio_config *ocio_config_open(const char *path, char *msg, size_t msg_size)
{
    if (!is_own_config(path)) {
        snprintf(msg, msg_size,
                 "cannot use the OpenColorIO config '%s': this build has no OpenColorIO and knows only the "
                 "colour spaces of firmament's own config (--list-colorspaces)",
                 path ? path : "");
        return NULL;
    }
    return calloc(1, sizeof(ocio_config));
}

void ocio_config_close(ocio_config *cfg)
{
    free(cfg);
}

int ocio_colorspace_count(const ocio_config *cfg)
{
    return builtin_space_count;
}

const char *ocio_colorspace_name(const ocio_config *cfg, int index)
{
    return index >= 0 && index < builtin_space_count ? builtin_spaces[index].name : NULL;
}

/* OpenColorIO compares names ignoring (ASCII) case. */
static int same_name(const char *a, const char *b)
{
    for (; *a && tolower((unsigned char)*a) == tolower((unsigned char)*b); a++, b++)
        ;
    return *a == *b;
}

/* A space by name, alias or role. */
static const builtin_space *find_space(const char *name)
{
    for (int i = 0; i < builtin_role_count; i++)
        if (same_name(name, builtin_roles[i].name))
            name = builtin_roles[i].space;
    for (int i = 0; i < builtin_space_count; i++) {
        const builtin_space *s = &builtin_spaces[i];
        if (same_name(name, s->name))
            return s;
        for (int a = 0; a < 3 && s->aliases[a]; a++)
            if (same_name(name, s->aliases[a]))
                return s;
    }
    return NULL;
}

const char *ocio_colorspace_find(const ocio_config *cfg, const char *name)
{
    const builtin_space *s = find_space(name);
    return s ? s->name : NULL;
}

int ocio_colorspace_is_data(const ocio_config *cfg, const char *name)
{
    const builtin_space *s = find_space(name);
    return s && s->is_data;
}

/* OpenColorIO's ExponentWithLinearTransform: y = ((x + offset) / (1 + offset))^gamma above the break
 * x_b = offset / (gamma - 1), where the line y = x / slope through the origin meets the power curve
 * with the same value and slope; below it (negative values too) the line. */
static double curve_slope(const builtin_space *s)
{
    double xb = s->offset / (s->gamma - 1.0);
    return xb / pow((xb + s->offset) / (1.0 + s->offset), s->gamma);
}

static double decode(const builtin_space *s, double x)
{
    double xb = s->offset / (s->gamma - 1.0);
    return x < xb ? x / curve_slope(s) : pow((x + s->offset) / (1.0 + s->offset), s->gamma);
}

static double encode(const builtin_space *s, double y)
{
    double slope = curve_slope(s), yb = s->offset / (s->gamma - 1.0) / slope;
    return y < yb ? y * slope : (1.0 + s->offset) * pow(y, 1.0 / s->gamma) - s->offset;
}

/* The inverse of a 3x3 matrix by its adjugate; the config's matrices are well conditioned. */
static void invert3(const double m[9], double inv[9])
{
    double c[9] = {m[4] * m[8] - m[5] * m[7], m[5] * m[6] - m[3] * m[8], m[3] * m[7] - m[4] * m[6],
                   m[2] * m[7] - m[1] * m[8], m[0] * m[8] - m[2] * m[6], m[1] * m[6] - m[0] * m[7],
                   m[1] * m[5] - m[2] * m[4], m[2] * m[3] - m[0] * m[5], m[0] * m[4] - m[1] * m[3]};
    double det = m[0] * c[0] + m[1] * c[1] + m[2] * c[2];
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            inv[3 * r + k] = c[3 * k + r] / det;
}

static void convert(const builtin_space *src, const builtin_space *dst, float *rgb, size_t n)
{
    if (src->is_data || dst->is_data) /* OpenColorIO: to or from data is no conversion */
        return;
    double from_ref[9], m[9];
    invert3(dst->to_reference, from_ref);
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++)
            m[3 * r + k] = from_ref[3 * r] * src->to_reference[k] + from_ref[3 * r + 1] * src->to_reference[3 + k] +
                           from_ref[3 * r + 2] * src->to_reference[6 + k];
    for (size_t i = 0; i < n; i++) {
        double v[3];
        for (int c = 0; c < 3; c++)
            v[c] = src->curve == BUILTIN_LINEAR ? rgb[3 * i + c] : decode(src, rgb[3 * i + c]);
        for (int r = 0; r < 3; r++) {
            double y = m[3 * r] * v[0] + m[3 * r + 1] * v[1] + m[3 * r + 2] * v[2];
            rgb[3 * i + r] = (float)(dst->curve == BUILTIN_LINEAR ? y : encode(dst, y));
        }
    }
}

int ocio_convert(const ocio_config *cfg, const char *src, const char *dst, float *rgb, size_t n, char *msg,
                 size_t msg_size)
{
    const builtin_space *a = find_space(src), *b = find_space(dst);
    if (!a || !b) {
        snprintf(msg, msg_size, "cannot convert from '%s' to '%s': colour space '%s' is unknown", src, dst,
                 a ? dst : src);
        return 1;
    }
    convert(a, b, rgb, n);
    return 0;
}

int ocio_display_view(const ocio_config *cfg, const char *src, const char *display, const char *view, float *rgb,
                      size_t n, char *msg, size_t msg_size)
{
    const builtin_space *a = find_space(src);
    for (int i = 0; a && i < builtin_view_count; i++)
        if (strcmp(display, builtin_views[i].display) == 0 && strcmp(view, builtin_views[i].view) == 0) {
            convert(a, find_space(builtin_views[i].space), rgb, n);
            return 0;
        }
    snprintf(msg, msg_size, "cannot apply display '%s' view '%s': %s", display, view,
             a ? "no such display and view" : "unknown source colour space");
    return 1;
}
