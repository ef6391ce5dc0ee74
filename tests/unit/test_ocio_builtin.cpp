// The compiled-in colour spaces of the builds without OpenColorIO (colour/ocio_builtin.c, the
// Windows build) against OpenColorIO itself reading the same config (presets/ocio/config.ocio):
// the same spaces in the same order, the same names, aliases and roles, and the same conversions
// between every pair of spaces and through every display view, within float precision.  Needs the
// Linux build's OpenColorIO; the builtin side is C (ocio.h) linked here without ocio.cpp.
#include "colour/ocio.h"

#include <OpenColorIO/OpenColorIO.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace OCIO = OCIO_NAMESPACE;

static int failures = 0;

static void check(bool ok, const std::string &what)
{
    if (!ok) {
        std::printf("FAIL: %s\n", what.c_str());
        failures++;
    }
}

// Colours across the range a sky map holds: dark, bright (the sun disk), negative (out of gamut),
// and around the sRGB curve's break (0.04).
static std::vector<float> samples()
{
    const float v[] = {0.0f, 1e-4f, 0.003f, 0.0392f, 0.0393f, 0.05f, 0.18f, 0.5f, 1.0f, 3.5f, 250.0f, -0.02f};
    std::vector<float> rgb;
    for (float r : v)
        for (float g : {0.0f, 0.0393f, 0.5f, 2.0f})
            for (float b : {0.003f, 0.18f, 1.0f}) {
                rgb.push_back(r);
                rgb.push_back(g);
                rgb.push_back(b);
            }
    return rgb;
}

// Relative to the triple's size (matrices mix channels), with a floor for values near 0.
static double difference(const float *a, const float *b)
{
    double scale = 1e-3, d = 0.0;
    for (int c = 0; c < 3; c++)
        scale = std::fmax(scale, std::fabs(b[c]));
    for (int c = 0; c < 3; c++)
        d = std::fmax(d, std::fabs(a[c] - b[c]) / scale);
    return d;
}

static void compare(OCIO::ConstProcessorRcPtr processor, const std::vector<float> &in, const std::vector<float> &mine,
                    const std::string &what)
{
    std::vector<float> ref = in;
    OCIO::PackedImageDesc desc(ref.data(), static_cast<long>(ref.size() / 3), 1, 3);
    processor->getDefaultCPUProcessor()->apply(desc);
    double worst = 0.0;
    for (size_t i = 0; i < ref.size(); i += 3)
        worst = std::fmax(worst, difference(&mine[i], &ref[i]));
    // OpenColorIO evaluates in float (its sRGB power by a fast approximation): a few 1e-6.
    check(worst < 2e-5, what + ": differs from OpenColorIO by " + std::to_string(worst));
}

int main()
{
    const std::string path = std::string(FM_SOURCE_DIR) + "/presets/ocio/config.ocio";
    OCIO::ConstConfigRcPtr config = OCIO::Config::CreateFromFile(path.c_str());
    char msg[512] = "";
    ocio_config *mine = ocio_config_open(path.c_str(), msg, sizeof msg);
    check(mine != nullptr, std::string("the builtin accepts firmament's config: ") + msg);
    if (!mine)
        return 1;
    check(!ocio_config_open((std::string(FM_SOURCE_DIR) + "/presets/skies/golden-hour.json").c_str(), msg, sizeof msg),
          "another file is refused");

    const int n = config->getNumColorSpaces();
    check(ocio_colorspace_count(mine) == n, "the number of colour spaces");
    for (int i = 0; i < n && i < ocio_colorspace_count(mine); i++) {
        OCIO::ConstColorSpaceRcPtr cs = config->getColorSpace(config->getColorSpaceNameByIndex(i));
        std::string name = cs->getName();
        check(name == ocio_colorspace_name(mine, i), "space " + std::to_string(i) + " is " + name);
        check(ocio_colorspace_is_data(mine, name.c_str()) == (cs->isData() ? 1 : 0), name + ": isdata");
        for (size_t a = 0; a < cs->getNumAliases(); a++) {
            const char *found = ocio_colorspace_find(mine, cs->getAlias(a));
            check(found && name == found, name + ": alias " + cs->getAlias(a));
        }
    }
    for (int r = 0; r < config->getNumRoles(); r++) {
        const char *found = ocio_colorspace_find(mine, config->getRoleName(r));
        OCIO::ConstColorSpaceRcPtr cs = config->getColorSpace(config->getRoleName(r));
        check(found && cs && std::strcmp(found, cs->getName()) == 0,
              std::string("role ") + config->getRoleName(r));
    }
    check(ocio_colorspace_find(mine, "linear rec.709") != nullptr, "names ignore case");
    check(ocio_colorspace_find(mine, "Linear Rec.2100") == nullptr, "an unknown name is not found");

    const std::vector<float> in = samples();
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            const char *src = config->getColorSpaceNameByIndex(i), *dst = config->getColorSpaceNameByIndex(j);
            std::vector<float> out = in;
            check(ocio_convert(mine, src, dst, out.data(), out.size() / 3, msg, sizeof msg) == 0,
                  std::string(src) + " -> " + dst + ": " + msg);
            compare(config->getProcessor(src, dst), in, out, std::string(src) + " -> " + dst);
        }
    for (int d = 0; d < config->getNumDisplays(); d++) {
        const char *display = config->getDisplay(d);
        for (int v = 0; v < config->getNumViews(display); v++) {
            const char *view = config->getView(display, v);
            std::vector<float> out = in;
            check(ocio_display_view(mine, "CIE XYZ D65", display, view, out.data(), out.size() / 3, msg, sizeof msg) ==
                      0,
                  std::string(display) + " / " + view + ": " + msg);
            compare(config->getProcessor("CIE XYZ D65", display, view, OCIO::TRANSFORM_DIR_FORWARD), in, out,
                    std::string("display ") + display + " / " + view);
        }
    }
    ocio_config_close(mine);
    std::printf("%s: %d failure(s)\n", failures ? "FAILED" : "ok", failures);
    return failures ? 1 : 0;
}
