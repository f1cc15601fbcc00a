// The PNG writer, a module that image_io.cpp loads on its first PNG: linked
// into the programs, OpenImageIO brought some 250 shared libraries (video,
// GIS and PDF codecs among them) whose loading took ~0.45 s at every start
// of every tool, on a sphere a quarter of the run. Only this file sees it.
#include <OpenImageIO/imageio.h>

#include <cstddef>
#include <cstdio>
#include <exception>
#include <string>

extern "C" __attribute__((visibility("default"))) int ism_write_png(const char* path, int width,
                                                                    int height, int channels,
                                                                    const unsigned char* pixels,
                                                                    char* error,
                                                                    std::size_t error_size) {
  auto fail = [&](const std::string& why) {
    std::snprintf(error, error_size, "%s", why.c_str());
    return 0;
  };
  try {
    // "png" names the format, so a preview.tmp still comes out as PNG.
    auto out = OIIO::ImageOutput::create("png");
    if (!out) return fail("OpenImageIO has no PNG writer: " + OIIO::geterror());
    const OIIO::ImageSpec spec(width, height, channels, OIIO::TypeDesc::UINT8);
    const bool ok =
        out->open(path, spec) && out->write_image(OIIO::TypeDesc::UINT8, pixels) && out->close();
    if (!ok) return fail("cannot write PNG: " + out->geterror());
    return 1;
  } catch (const std::exception& e) {
    return fail(std::string("cannot write PNG: ") + e.what());
  }
}
