#include "presets.h"

#include <stdlib.h>
#include <sys/stat.h>

static int is_directory(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

const char *presets_dir(const char *given)
{
    if (given && given[0])
        return given;
    const char *env = getenv("FIRMAMENT_PRESETS");
    if (env && env[0])
        return env;
    return is_directory(FIRMAMENT_SOURCE_PRESETS) ? FIRMAMENT_SOURCE_PRESETS : FIRMAMENT_INSTALLED_PRESETS;
}
