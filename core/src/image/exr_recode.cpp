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
#include <stdexcept>
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
        const int64_t width64 = (int64_t)window.max.x - window.min.x + 1, height = (int64_t)window.max.y - window.min.y + 1;
        size_t channels = 0;
        for (Imf::ChannelList::ConstIterator c = header.channels().begin(); c != header.channels().end(); ++c)
            channels++;
        // the C library's check of the same file (exr_read.c) may have read another header than this
        if (width64 < 1 || height < 1 || width64 > EXR_MAX_SIDE || height > EXR_MAX_SIDE || channels > EXR_MAX_CHANNELS)
            throw std::runtime_error("its header claims more pixels or channels than are read");
        const size_t width = (size_t)width64;

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
