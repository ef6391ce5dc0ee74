/* libFuzzer target: the atmosphere file reader (atmosphere_init_from_file) on arbitrary bytes, for
 * the visible grid; what it accepts is also built (majorants) and freed. */
#include "atmosphere/atmosphere_file.h"
#include "fuzz_file.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static spectral_grid grid;
    static int ready;
    if (!ready) {
        spectral_grid_visible(&grid);
        ready = 1;
    }
    const char *path = fuzz_file(data, size, ".json");
    if (path) {
        atmosphere atm;
        fm_error err = {0};
        if (atmosphere_init_from_file(&atm, path, &grid, 1.0, 0.2, &err) == FM_OK)
            atmosphere_free(&atm);
    }
    return 0;
}
