#include "bench_skies.h"

#include <string.h>

static const bench_sky SKIES[] = {
    {"default", "--sun-elevation 30 --sun-azimuth 180 --biome rural --turbidity 1", 30.0, 180.0, 1.0, "rural"},
    {"sunset", "--sun-elevation 2 --sun-azimuth 180 --biome urban --turbidity 2", 2.0, 180.0, 2.0, "urban"},
};

const bench_sky *bench_sky_find(const char *name)
{
    for (size_t i = 0; i < sizeof SKIES / sizeof SKIES[0]; i++)
        if (strcmp(SKIES[i].name, name) == 0)
            return &SKIES[i];
    /* "biome:NAME": the biomes' comparison sky (bench.sh --biomes), sun 30 through that biome at
     * turbidity 1; an unknown biome fails where the sky is made */
    static char biome[64], args[160];
    static bench_sky b;
    const char *prefix = "biome:";
    if (strncmp(name, prefix, strlen(prefix)) != 0 || strlen(name + strlen(prefix)) >= sizeof biome)
        return NULL;
    strcpy(biome, name + strlen(prefix));
    snprintf(args, sizeof args, "--sun-elevation 30 --sun-azimuth 180 --biome %s --turbidity 1", biome);
    b = (bench_sky){name, args, 30.0, 180.0, 1.0, biome};
    return &b;
}

fm_sky_params bench_sky_params(const bench_sky *b)
{
    fm_sky_params p = fm_sky_params_default();
    p.sun_elevation_deg = b->sun_elevation;
    p.sun_azimuth_deg = b->sun_azimuth;
    p.biome = b->biome;
    p.turbidity = b->turbidity;
    return p;
}

int bench_reference_header(FILE *f, int *W, int *H, int *n)
{
    char line[512] = "";
    while (fgets(line, sizeof line, f) && line[0] == '#')
        continue;
    return sscanf(line, "%d %d %d", W, H, n) == 3 && *W >= 8 && *H >= 4 && *n >= 1;
}

int bench_reference_probe(FILE *f, int W, int H, int *x, int *y, double *Y, double *se)
{
    return fscanf(f, "%d %d %lf %lf", x, y, Y, se) == 4 && *Y > 0.0 && *se >= 0.0 && *x >= 0 && *y >= 0 &&
           *x < W && *y < H;
}
