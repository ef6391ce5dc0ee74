// exr_recode.h over OpenEXR's C++ library (Imf).  Exceptions never cross into C.
#include "image/exr_recode.h"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <algorithm>
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
        header.lineOrder() = Imf::INCREASING_Y; // the strips below are written top to bottom
        const Imath::Box2i window = header.dataWindow();
        const size_t width = (size_t)(window.max.x - window.min.x + 1);

        // Each channel is read and written in its stored type (half stays half, float stays float);
        // the only change to the pixels is DWA's own quantisation.  Strips of 256 lines (a whole
        // number of chunks for every codec) keep memory to a strip's, whatever the header claims.
        const int strip = 256;
        std::vector<std::vector<char>> planes;
        for (Imf::ChannelList::ConstIterator c = header.channels().begin(); c != header.channels().end(); ++c)
            planes.emplace_back(width * strip * (c.channel().type == Imf::HALF ? 2 : 4));
        Imf::OutputFile out(dst, header);
        for (int y0 = window.min.y; y0 <= window.max.y; y0 += strip) {
            const int y1 = std::min(y0 + strip - 1, window.max.y);
            Imf::FrameBuffer frame;
            size_t i = 0;
            for (Imf::ChannelList::ConstIterator c = header.channels().begin(); c != header.channels().end(); ++c) {
                const size_t bytes = c.channel().type == Imf::HALF ? 2 : 4;
                // the slice's base is the address of pixel (0, 0) in the data window's coordinates
                char *base = planes[i++].data() - (window.min.x + y0 * (ptrdiff_t)width) * (ptrdiff_t)bytes;
                frame.insert(c.name(), Imf::Slice(c.channel().type, base, bytes, bytes * width));
            }
            in.setFrameBuffer(frame);
            in.readPixels(y0, y1);
            out.setFrameBuffer(frame);
            out.writePixels(y1 - y0 + 1);
        }
        return 0;
    } catch (const std::exception &e) {
        if (msg && msg_size)
            std::snprintf(msg, msg_size, "%s", e.what());
        return 1;
    }
}
