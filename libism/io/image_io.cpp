#include "io/image_io.hpp"

#include "io/io.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <OpenImageIO/imageio.h>

#include <cstring>
#include <stdexcept>

namespace ism::io {
namespace {

// The frame buffers below point straight into the caller's vectors.
static_assert(sizeof(Eigen::Vector3f) == 3 * sizeof(float));
static_assert(sizeof(std::array<unsigned char, 3>) == 3);

constexpr const char* kChannels[3] = {"R", "G", "B"};

void check_size(int width, int height, std::size_t n_pixels) {
  if (width <= 0 || height <= 0 ||
      n_pixels != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::invalid_argument("image of " + std::to_string(width) + "x" + std::to_string(height) +
                                " pixels given " + std::to_string(n_pixels) + " values");
}

// The three interleaved float slices of an RGB buffer covering `window`.
Imf::FrameBuffer rgb_frame_buffer(const float* data, const Imath::Box2i& window) {
  const std::size_t x_stride = 3 * sizeof(float);
  const std::size_t y_stride = x_stride * static_cast<std::size_t>(window.max.x - window.min.x + 1);
  Imf::FrameBuffer frame;
  for (int c = 0; c < 3; ++c)
    frame.insert(kChannels[c], Imf::Slice::Make(Imf::FLOAT, data + c, window, x_stride, y_stride));
  return frame;
}

}  // namespace

void write_exr_rgb(const std::filesystem::path& path, int width, int height,
                   const std::vector<Eigen::Vector3f>& pixels, const ExrAttributes& attributes) {
  check_size(width, height, pixels.size());
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : kChannels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  for (const auto& [name, value] : attributes) {
    // Header::insert throws Iex exceptions for these; report them as the
    // caller's mistake rather than a file problem.
    if (name.empty()) throw std::invalid_argument("EXR attribute with an empty name");
    try {
      header.insert(name, Imf::StringAttribute(value));
    } catch (const std::exception& e) {
      throw std::invalid_argument("EXR attribute '" + name + "': " + e.what());
    }
  }
  try {
    Imf::OutputFile file(path.string().c_str(), header);
    file.setFrameBuffer(rgb_frame_buffer(pixels.front().data(), header.dataWindow()));
    file.writePixels(height);
  } catch (const std::exception& e) {
    // OpenEXR's messages usually repeat the file name; keep them whole anyway.
    throw FileError(path.string() + ": cannot write OpenEXR: " + e.what());
  }
}

std::vector<Eigen::Vector3f> read_exr_rgb(const std::filesystem::path& path, int& width,
                                          int& height, ExrAttributes* attributes) {
  // Checked up front: OpenEXR's message for a missing file is less direct.
  if (!std::filesystem::exists(path)) throw FileError(path.string() + ": no such file");
  try {
    Imf::InputFile file(path.string().c_str());
    const Imf::Header& header = file.header();
    for (const char* name : kChannels) {
      const Imf::Channel* channel = header.channels().findChannel(name);
      if (!channel) throw FileError(path.string() + ": OpenEXR has no channel " + name);
      if (channel->xSampling != 1 || channel->ySampling != 1)
        throw FileError(path.string() + ": OpenEXR channel " + name + " is subsampled");
    }
    const Imath::Box2i window = header.dataWindow();
    width = window.max.x - window.min.x + 1;
    height = window.max.y - window.min.y + 1;
    std::vector<Eigen::Vector3f> pixels(static_cast<std::size_t>(width) *
                                        static_cast<std::size_t>(height));
    file.setFrameBuffer(rgb_frame_buffer(pixels.front().data(), window));
    file.readPixels(window.min.y, window.max.y);
    if (attributes) {
      attributes->clear();
      for (auto it = header.begin(); it != header.end(); ++it)
        // By type name: dynamic_cast across the shared library is not needed.
        if (std::strcmp(it.attribute().typeName(), Imf::StringAttribute::staticTypeName()) == 0)
          attributes->emplace_back(
              it.name(), static_cast<const Imf::StringAttribute&>(it.attribute()).value());
    }
    return pixels;
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    throw FileError(path.string() + ": cannot read OpenEXR: " + e.what());
  }
}

void write_png_preview(const std::filesystem::path& path, int width, int height,
                       const std::vector<std::array<unsigned char, 3>>& pixels) {
  check_size(width, height, pixels.size());
  // "png" names the format, so a preview.tmp still comes out as PNG.
  auto out = OIIO::ImageOutput::create("png");
  if (!out) throw FileError(path.string() + ": OpenImageIO has no PNG writer: " + OIIO::geterror());
  const OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
  const bool ok = out->open(path.string(), spec) &&
                  out->write_image(OIIO::TypeDesc::UINT8, pixels.front().data()) && out->close();
  if (!ok) throw FileError(path.string() + ": cannot write PNG: " + out->geterror());
}

}  // namespace ism::io
