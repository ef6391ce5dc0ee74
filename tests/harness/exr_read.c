#include "exr_read.h"

#include "check.h"

#include <stdlib.h>
#include <string.h>

test_exr test_exr_read(const char *path, exr_context_t *keep)
{
    test_exr img = {0};
    exr_context_t c;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    if (exr_start_read(&c, path, &init) != EXR_ERR_SUCCESS)
        fail_msg("cannot open %s", path);
    exr_attr_box2i_t dw;
    assert_int_equal(exr_get_data_window(c, 0, &dw), EXR_ERR_SUCCESS);
    img.width = dw.max.x - dw.min.x + 1;
    img.height = dw.max.y - dw.min.y + 1;
    const exr_attr_chlist_t *cl;
    assert_int_equal(exr_get_channels(c, 0, &cl), EXR_ERR_SUCCESS);
    img.channels = cl->num_channels;
    assert_true(img.channels <= 48);
    for (int i = 0; i < img.channels; i++)
        strncpy(img.names[i], cl->entries[i].name.str, sizeof img.names[i] - 1);
    img.pixels = calloc((size_t)img.width * img.height * img.channels, sizeof(float));
    int32_t lines;
    exr_get_scanlines_per_chunk(c, 0, &lines);
    exr_decode_pipeline_t d = EXR_DECODE_PIPELINE_INITIALIZER;
    int started = 0;
    for (int y = 0; y < img.height; y += lines) {
        exr_chunk_info_t ci;
        assert_int_equal(exr_read_scanline_chunk_info(c, 0, dw.min.y + y, &ci), EXR_ERR_SUCCESS);
        if (started)
            assert_int_equal(exr_decoding_update(c, 0, &ci, &d), EXR_ERR_SUCCESS);
        else
            assert_int_equal(exr_decoding_initialize(c, 0, &ci, &d), EXR_ERR_SUCCESS);
        for (int k = 0; k < d.channel_count; k++) {
            exr_coding_channel_info_t *ch = &d.channels[k];
            int off = 0;
            for (int i = 0; i < img.channels; i++)
                if (strcmp(img.names[i], ch->channel_name) == 0)
                    off = i;
            ch->decode_to_ptr = (uint8_t *)&img.pixels[((size_t)(ci.start_y - dw.min.y) * img.width) * img.channels + off];
            ch->user_pixel_stride = img.channels * 4;
            ch->user_line_stride = img.width * img.channels * 4;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
        }
        if (!started) {
            assert_int_equal(exr_decoding_choose_default_routines(c, 0, &d), EXR_ERR_SUCCESS);
            started = 1;
        }
        assert_int_equal(exr_decoding_run(c, 0, &d), EXR_ERR_SUCCESS);
    }
    exr_decoding_destroy(c, &d);
    if (keep)
        *keep = c;
    else
        exr_finish(&c);
    return img;
}

void test_exr_free(test_exr *img)
{
    free(img->pixels);
    img->pixels = NULL;
}
