#include "output_args.h"

#include "base/platform.h"

#include <stdlib.h>
#include <string.h>

char *default_sidecar(const char *output)
{
    size_t n = strlen(output);
    const char *slash = platform_last_separator(output);
    const char *dot = strrchr(output, '.');
    if (dot && (!slash || dot > slash) && dot != output && dot - 1 != slash)
        n = (size_t)(dot - output);
    char *s = malloc(n + 6);
    if (s) {
        memcpy(s, output, n);
        memcpy(s + n, ".json", 6);
    }
    return s;
}

fm_status output_set_format(const options *opt, fm_output *out, fm_error *err)
{
    return opt->format == FORMAT_HDR ? fm_output_set_radiance(out, err)
                                     : fm_output_set_format(out, opt->half, opt->compression, err);
}
