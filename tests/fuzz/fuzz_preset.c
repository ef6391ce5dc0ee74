/* libFuzzer target: the sky preset reader (fm_sky_preset_load) on arbitrary bytes. */
#include "firmament/firmament.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_file(data, size, ".json");
    if (path) {
        fm_sky_preset preset;
        fm_error err = {0};
        fm_sky_preset_load(path, NULL, &preset, &err);
    }
    return 0;
}
