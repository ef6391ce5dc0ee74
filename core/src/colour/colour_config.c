/* fm_colour_config: firmament's side of colour management.  Finds the config (given path, $OCIO,
 * or the shipped presets/ocio/config.ocio), names the space that rendered XYZ is in, and converts
 * images through OpenColorIO (colour/ocio.h). */
#define _POSIX_C_SOURCE 200809L
#include "base/status.h"
#include "colour/ocio.h"
#include "presets.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct fm_colour_config {
    ocio_config *ocio;
    char path[1024];
    const char *xyz; /* the config's name for the space that fm_render's XYZ is in */
};

fm_status fm_colour_config_open(const char *path, fm_colour_config **out, fm_error *err)
{
    *out = NULL;
    fm_colour_config *c = calloc(1, sizeof *c);
    if (!c)
        return fm_fail(err, FM_ERR_OUT_OF_MEMORY, "out of memory");
    const char *env = getenv("OCIO");
    if (path && path[0])
        snprintf(c->path, sizeof c->path, "%s", path);
    else if (env && env[0])
        snprintf(c->path, sizeof c->path, "%s", env);
    else {
        fm_status found = presets_locate(NULL, c->path, sizeof c->path - 20, err);
        if (found) {
            free(c);
            return found;
        }
        strcat(c->path, "/ocio/config.ocio");
    }
    char msg[480];
    c->ocio = ocio_config_open(c->path, msg, sizeof msg);
    if (!c->ocio) {
        free(c);
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s", msg);
    }
    c->xyz = ocio_colorspace_find(c->ocio, "CIE XYZ D65");
    if (!c->xyz)
        c->xyz = ocio_colorspace_find(c->ocio, "cie_xyz_d65_interchange");
    if (!c->xyz) {
        fm_fail(err, FM_ERR_INVALID_ARGUMENT,
                "the OpenColorIO config '%s' has no \"CIE XYZ D65\" colour space nor a cie_xyz_d65_interchange role",
                c->path);
        fm_colour_config_close(c);
        return FM_ERR_INVALID_ARGUMENT;
    }
    *out = c;
    return FM_OK;
}

void fm_colour_config_close(fm_colour_config *cfg)
{
    if (!cfg)
        return;
    ocio_config_close(cfg->ocio);
    free(cfg);
}

const char *fm_colour_config_path(const fm_colour_config *cfg)
{
    return cfg->path;
}

int fm_colour_config_count(const fm_colour_config *cfg)
{
    return ocio_colorspace_count(cfg->ocio);
}

const char *fm_colour_config_name(const fm_colour_config *cfg, int index)
{
    return ocio_colorspace_name(cfg->ocio, index);
}

fm_status fm_colour_convert(const fm_colour_config *cfg, const char *src, const char *dst, float *rgb, size_t n,
                            fm_error *err)
{
    char msg[480];
    if (ocio_convert(cfg->ocio, src, dst, rgb, n, msg, sizeof msg))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s", msg);
    return FM_OK;
}

fm_status fm_colour_display(const fm_colour_config *cfg, const char *src, const char *display, const char *view,
                            float *rgb, size_t n, fm_error *err)
{
    char msg[480];
    if (ocio_display_view(cfg->ocio, src ? src : cfg->xyz, display, view, rgb, n, msg, sizeof msg))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "%s", msg);
    return FM_OK;
}

static fm_status unknown_space(const fm_colour_config *cfg, const char *name, fm_error *err)
{
    char list[400] = "";
    size_t used = 0;
    for (int i = 0; i < fm_colour_config_count(cfg) && used < sizeof list; i++) {
        int n = snprintf(list + used, sizeof list - used, "%s\"%s\"", i ? ", " : "", fm_colour_config_name(cfg, i));
        used += n > 0 ? (size_t)n : 0;
    }
    return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "unknown colour space \"%s\"; the config has %s", name, list);
}

/* The space's matrix to XYZ, from the images of the unit vectors; returns 0 when the conversion is
 * not linear (a display encoding): then a sum is not mapped to the sum of the images. */
static int linear_matrix(const fm_colour_config *cfg, const char *space, double m[3][3], fm_error *err, fm_status *s)
{
    float v[5][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.25f, 0.5f, 0.125f}, {2.5f, 5.0f, 1.25f}};
    if ((*s = fm_colour_convert(cfg, space, cfg->xyz, &v[0][0], 5, err)))
        return 0;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            m[r][c] = v[c][r];
    /* linear: (0.25, 0.5, 0.125) maps to M times it, and 10 times it to 10 times that */
    for (int r = 0; r < 3; r++) {
        double expect = 0.25 * m[r][0] + 0.5 * m[r][1] + 0.125 * m[r][2];
        double scale = fmax(1.0, fabs(m[r][0]) + fabs(m[r][1]) + fabs(m[r][2]));
        if (fabs(v[3][r] - expect) > 1e-5 * scale || fabs(v[4][r] - 10.0 * expect) > 1e-4 * scale)
            return 0;
    }
    return 1;
}

static void chromaticity(const double xyz[3], float *xy)
{
    double sum = xyz[0] + xyz[1] + xyz[2];
    xy[0] = sum != 0.0 ? (float)(xyz[0] / sum) : 0.0f;
    xy[1] = sum != 0.0 ? (float)(xyz[1] / sum) : 0.0f;
}

/* The canonical name of a scene-linear space of the config and its matrix to XYZ. */
static fm_status resolve_linear(const fm_colour_config *cfg, const char *name, const char **space, double m[3][3],
                                fm_error *err)
{
    *space = ocio_colorspace_find(cfg->ocio, name);
    if (!*space)
        return unknown_space(cfg, name, err);
    if (strlen(*space) >= sizeof ((fm_image *)0)->colorspace)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "the colour space name \"%s\" is too long", *space);
    if (ocio_colorspace_is_data(cfg->ocio, *space))
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "colour space \"%s\" holds data, not colour", *space);
    fm_status s = FM_OK;
    if (!linear_matrix(cfg, *space, m, err, &s))
        return s ? s
                 : fm_fail(err, FM_ERR_INVALID_ARGUMENT,
                           "colour space \"%s\" is not scene-linear; the EXR holds radiance, so choose a linear "
                           "space",
                           *space);
    return FM_OK;
}

fm_status fm_colour_config_check(const fm_colour_config *cfg, const char *name, fm_error *err)
{
    const char *space;
    double m[3][3];
    return resolve_linear(cfg, name, &space, m, err);
}

fm_status fm_image_to_colorspace(fm_image *image, const fm_colour_config *cfg, const char *name, fm_error *err)
{
    if (image->content != FM_IMAGE_XYZ)
        return fm_fail(err, FM_ERR_INVALID_ARGUMENT, "only an XYZ image can be converted to a colour space");
    const char *space;
    double m[3][3];
    fm_status s = resolve_linear(cfg, name, &space, m, err);
    if (s)
        return s;
    size_t n = (size_t)image->width * (size_t)image->height;
    if ((s = fm_colour_convert(cfg, cfg->xyz, space, image->pixels, n, err)))
        return s;
    if (image->sun_disk && (s = fm_colour_convert(cfg, cfg->xyz, space, image->sun_disk, n, err)))
        return s;
    for (int i = 0; i < 4; i++) {
        double xyz[3];
        for (int r = 0; r < 3; r++)
            xyz[r] = i < 3 ? m[r][i] : m[r][0] + m[r][1] + m[r][2];
        chromaticity(xyz, &image->chromaticities[2 * i]);
    }
    memcpy(image->rgb_to_xyz, m, sizeof m);
    snprintf(image->colorspace, sizeof image->colorspace, "%s", space);
    image->content = FM_IMAGE_RGB;
    return FM_OK;
}
