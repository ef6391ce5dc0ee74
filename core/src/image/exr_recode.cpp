// exr_recode.h over OpenEXR's C++ library (Imf).  Exceptions never cross into C.
#include "image/exr_recode.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <cstdio>
#include <exception>
#include <vector>

int recode_exr(const char *src, const char *dst, recode_target target, float dwa_level, char *msg,
               size_t msg_size)
{
    try {
        Imf::InputFile in(src);
        Imf::Header header = in.header(); // every attribute, typed as written
        if (target == RECODE_DWAA) {
            header.compression() = Imf::DWAA_COMPRESSION;
            header.dwaCompressionLevel() = dwa_level;
        } else {
            header.compression() = Imf::ZIP_COMPRESSION;
        }
        const Imath::Box2i window = header.dataWindow();
        const size_t width = (size_t)(window.max.x - window.min.x + 1);
        const size_t height = (size_t)(window.max.y - window.min.y + 1);

        // Each channel is read and written in its stored type (half stays half, float stays float);
        // the only change to the pixels is DWA's own quantisation.
        std::vector<std::vector<char>> planes;
        Imf::FrameBuffer frame;
        for (Imf::ChannelList::ConstIterator c = header.channels().begin(); c != header.channels().end(); ++c) {
            const size_t bytes = c.channel().type == Imf::HALF ? 2 : 4;
            planes.emplace_back(width * height * bytes);
            // the slice's base is the address of pixel (0, 0) in the data window's coordinates
            char *base = planes.back().data() -
                         (window.min.x + window.min.y * (ptrdiff_t)width) * (ptrdiff_t)bytes;
            frame.insert(c.name(), Imf::Slice(c.channel().type, base, bytes, bytes * width));
        }
        in.setFrameBuffer(frame);
        in.readPixels(window.min.y, window.max.y);

        Imf::OutputFile out(dst, header);
        out.setFrameBuffer(frame);
        out.writePixels((int)height);
        return 0;
    } catch (const std::exception &e) {
        if (msg && msg_size)
            std::snprintf(msg, msg_size, "%s", e.what());
        return 1;
    }
}
