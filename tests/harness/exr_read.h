/* Reading our own EXRs back through OpenEXR's C API, for tests. */
#ifndef FM_TEST_EXR_READ_H
#define FM_TEST_EXR_READ_H

#include <openexr.h>

typedef struct test_exr {
    int width, height, channels;
    char names[48][24]; /* up to 48 channels (spectral maps) */
    float *pixels; /* interleaved in names[] order */
} test_exr;

/* Reads every channel as float; fails the test on error.  Keeps the context open in *ctxt when
 * ctxt is not NULL (for attribute queries; close with exr_finish). */
test_exr test_exr_read(const char *path, exr_context_t *ctxt);
void test_exr_free(test_exr *img);

#endif
