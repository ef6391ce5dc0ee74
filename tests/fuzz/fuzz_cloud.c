/* libFuzzer target: the cloud readers (aerosol/cloud_file.h) on arbitrary bytes, as a cloud file
 * (--cloud FILE) and as a custom atmosphere file's "clouds" array. */
#include "aerosol/cloud_file.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_file(data, size, ".json");
    if (path) {
        cloud_layer layers[FM_MAX_CLOUD_LAYERS];
        int count;
        fm_error err = {0};
        fm_sky_params p = fm_sky_params_default();
        p.clouds = path;
        cloud_layers_from_params(&p, layers, &count, &err);
        p.clouds = NULL;
        p.atmosphere_file = path;
        cloud_layers_from_params(&p, layers, &count, &err);
    }
    return 0;
}
