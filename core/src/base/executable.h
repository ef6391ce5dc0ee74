/* Where the running executable lives, so that it finds the files shipped beside it (presets, the
 * colour config) wherever it was copied or installed. */
#ifndef FM_BASE_EXECUTABLE_H
#define FM_BASE_EXECUTABLE_H

#include <stddef.h>

/* Writes the directory holding the running executable (absolute, no trailing separator, UTF-8) into
 * out and returns 0; returns -1 (out = "") where the platform cannot say or the path does not fit. */
int executable_dir(char *out, size_t size);

#endif
