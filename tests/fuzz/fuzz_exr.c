/* libFuzzer target: the EXR reader behind `compare` (fm_image_read_exr) and `info`
 * (fm_exr_attributes) on arbitrary bytes. */
#include "firmament/firmament.h"
#include "fuzz_file.h"

static void ignore(void *user, const char *name, const char *type, const char *value)
{
    (void)user, (void)name, (void)type, (void)value;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_file(data, size, ".exr");
    if (path) {
        fm_image *img = NULL;
        fm_error err = {0};
        if (fm_image_read_exr(path, &img, &err) == FM_OK)
            fm_image_destroy(img);
        fm_exr_attributes(path, ignore, NULL, &err);
    }
    return 0;
}
