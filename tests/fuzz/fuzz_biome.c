/* libFuzzer target: the biome reader (biome_load) on arbitrary bytes. */
#include "aerosol/biome.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_file(data, size, ".json");
    if (path) {
        biome b;
        fm_error err = {0};
        biome_load(path, NULL, &b, &err);
    }
    return 0;
}
