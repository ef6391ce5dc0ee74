#include "image/exr_attributes.h"

#include <stdio.h>
#include <string.h>

/* Reads a NUL-terminated name of at most cap - 1 bytes; its length, or -1 (end of file, too long). */
static int read_name(FILE *f, char *name, int cap)
{
    for (int n = 0; n < cap; n++) {
        int ch = fgetc(f);
        if (ch == EOF)
            return -1;
        if (!(name[n] = (char)ch))
            return n;
    }
    return -1;
}

static int64_t read_u32(FILE *f)
{
    unsigned char b[4];
    if (fread(b, 1, 4, f) != 4)
        return -1;
    return (int64_t)((uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24);
}

/* The bytes an attribute of a fixed-size type holds (OpenEXR's file layout), or -1 for the others. */
static int64_t fixed_size(const char *type)
{
    static const struct {
        const char *type;
        int bytes;
    } fixed[] = {{"box2i", 16},    {"box2f", 16}, {"compression", 1},     {"lineOrder", 1}, {"envmap", 1},
                 {"deepImageState", 1}, {"float", 4}, {"int", 4},        {"double", 8},    {"v2i", 8},
                 {"v2f", 8},       {"v2d", 16},   {"v3i", 12},           {"v3f", 12},      {"v3d", 24},
                 {"m33f", 36},     {"m33d", 72},  {"m44f", 64},          {"m44d", 128},    {"chromaticities", 32},
                 {"keycode", 28},  {"timecode", 8}, {"rational", 8},     {"tiledesc", 9}};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        if (!strcmp(type, fixed[i].type))
            return fixed[i].bytes;
    return -1;
}

/* Whether the channel list at f's position ends (its empty name) after exactly `bytes` bytes. */
static int channels_take(FILE *f, int64_t bytes)
{
    char name[256];
    int64_t used = 0;
    for (int n; (n = read_name(f, name, sizeof name)) > 0;) {
        used += n + 1 + 16; /* the name, its NUL, type, pLinear and reserved, x and y sampling */
        if (used >= bytes || fseek(f, 16, SEEK_CUR) != 0)
            return 0;
    }
    return used + 1 == bytes;
}

/* Whether the attribute of `type` declaring `bytes` at f's position takes them exactly, f then past it. */
static int attribute_fits(FILE *f, const char *type, int64_t bytes, int64_t file_bytes)
{
    if (bytes > INT32_MAX || ftell(f) + bytes > file_bytes)
        return 0;
    int64_t fixed = fixed_size(type);
    if (fixed >= 0 && bytes != fixed)
        return 0;
    if (!strcmp(type, "chlist"))
        return channels_take(f, bytes);
    if (!strcmp(type, "preview")) { /* width, height, then 4 bytes a pixel */
        int64_t w = read_u32(f), h = read_u32(f);
        return w >= 0 && h >= 0 && 8 + 4 * w * h == bytes && fseek(f, (long)(bytes - 8), SEEK_CUR) == 0;
    }
    return fseek(f, (long)bytes, SEEK_CUR) == 0;
}

/* Each header ends with an empty name; a multipart file's headers, with one more. */
int exr_attributes_fit(const char *path, int64_t file_bytes)
{
    FILE *f = fopen(path, "rb");
    unsigned char head[8];
    int fit = f && fread(head, 1, sizeof head, f) == sizeof head;
    const int multipart = fit && (head[5] & 0x10) != 0; /* version flag 0x1000 */
    char name[256], type[256];
    for (int after_empty = 0; fit;) {
        int n = read_name(f, name, sizeof name);
        if (n == 0 && (!multipart || after_empty))
            break;
        if ((after_empty = n == 0))
            continue;
        fit = n > 0 && read_name(f, type, sizeof type) > 0;
        int64_t bytes = fit ? read_u32(f) : -1;
        fit = bytes >= 0 && attribute_fits(f, type, bytes, file_bytes);
    }
    if (f)
        fclose(f);
    return fit;
}
