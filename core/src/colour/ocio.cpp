// The OpenColorIO C++ API behind the C interface of ocio.h.
// Exceptions never cross into C: each call catches them and returns the message.
#include "colour/ocio.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace OCIO = OCIO_NAMESPACE;

struct ocio_config {
    OCIO::ConstConfigRcPtr config;
};

namespace {

void put_message(char *msg, size_t size, const std::string &text)
{
    if (msg && size)
        std::snprintf(msg, size, "%s", text.c_str());
}

// OCIO messages may span lines; the callers want one line.
std::string one_line(const char *what)
{
    std::string s = what ? what : "";
    for (char &c : s)
        if (c == '\n' || c == '\r')
            c = ' ';
    return s;
}

void silence_library()
{
    // Library code never prints: OCIO's own log lines would go to stderr.
    OCIO::SetLoggingLevel(OCIO::LOGGING_LEVEL_NONE);
}

// Applies the processor to n triples as an image of lines of LINE pixels and one short line for the
// rest: OCIO converts line by line through one buffer of a line per call, so lines of a million
// pixels cost a 16 MB buffer, zeroed page by page, which would take longer than the conversion.
int apply(OCIO::ConstProcessorRcPtr processor, float *rgb, size_t n)
{
    OCIO::ConstCPUProcessorRcPtr cpu = processor->getDefaultCPUProcessor();
    const size_t LINE = 4096;
    size_t lines = n / LINE, rest = n % LINE;
    if (lines > 0) {
        OCIO::PackedImageDesc desc(rgb, static_cast<long>(LINE), static_cast<long>(lines), 3);
        cpu->apply(desc);
    }
    if (rest > 0) {
        OCIO::PackedImageDesc desc(rgb + 3 * lines * LINE, static_cast<long>(rest), 1, 3);
        cpu->apply(desc);
    }
    return 0;
}

} // namespace

extern "C" ocio_config *ocio_config_open(const char *path, char *msg, size_t msg_size)
{
    silence_library();
    std::string where = path && path[0] ? path : (std::getenv("OCIO") ? std::getenv("OCIO") : "");
    if (where.empty()) {
        put_message(msg, msg_size, "no OpenColorIO config given and $OCIO is not set");
        return nullptr;
    }
    try {
        OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(where.c_str());
        config->validate();
        auto *cfg = new ocio_config;
        cfg->config = config;
        return cfg;
    } catch (const std::exception &e) {
        put_message(msg, msg_size, "cannot use the OpenColorIO config '" + where + "': " + one_line(e.what()));
        return nullptr;
    }
}

extern "C" void ocio_config_close(ocio_config *cfg)
{
    delete cfg;
}

extern "C" int ocio_colorspace_count(const ocio_config *cfg)
{
    return cfg->config->getNumColorSpaces();
}

extern "C" const char *ocio_colorspace_name(const ocio_config *cfg, int index)
{
    return cfg->config->getColorSpaceNameByIndex(index);
}

extern "C" const char *ocio_colorspace_find(const ocio_config *cfg, const char *name)
{
    try {
        OCIO::ConstColorSpaceRcPtr cs = cfg->config->getColorSpace(name);
        return cs ? cs->getName() : nullptr;
    } catch (const std::exception &) {
        return nullptr;
    }
}

extern "C" int ocio_colorspace_is_data(const ocio_config *cfg, const char *name)
{
    try {
        OCIO::ConstColorSpaceRcPtr cs = cfg->config->getColorSpace(name);
        return cs && cs->isData();
    } catch (const std::exception &) {
        return 0;
    }
}

extern "C" int ocio_convert(const ocio_config *cfg, const char *src, const char *dst, float *rgb, size_t n, char *msg,
                            size_t msg_size)
{
    try {
        return apply(cfg->config->getProcessor(src, dst), rgb, n);
    } catch (const std::exception &e) {
        put_message(msg, msg_size,
                    std::string("cannot convert from '") + src + "' to '" + dst + "': " + one_line(e.what()));
        return 1;
    }
}

extern "C" int ocio_display_view(const ocio_config *cfg, const char *src, const char *display, const char *view,
                                 float *rgb, size_t n, char *msg, size_t msg_size)
{
    try {
        return apply(cfg->config->getProcessor(src, display, view, OCIO::TRANSFORM_DIR_FORWARD), rgb, n);
    } catch (const std::exception &e) {
        put_message(msg, msg_size,
                    std::string("cannot apply display '") + display + "' view '" + view + "': " + one_line(e.what()));
        return 1;
    }
}
