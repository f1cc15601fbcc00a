#include "io/image_io.hpp"

#include "io/io.hpp"
#include "io/mesh_parse.hpp"

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>

#include <dlfcn.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <optional>
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

// What an OpenEXR file may decode to, checked on its header before OpenEXR
// sees the file. OpenEXR 3.1's C++ reader allocates an attribute's declared
// size (and a preview's width x height, an ID manifest's sizes), and a data
// window's line-offset table and pixels, before it knows whether the file
// holds them (a 327-byte file asked for 1.7 GB). It also reads typed
// attributes by their type, not by their declared size, so this check
// requires every attribute it knows to fill its declared size exactly: the
// header OpenEXR parses is then the one checked here.
struct ExrLayout {
  std::int64_t width = 0, height = 0;
  int compression = 0;                  // Imf::Compression
  std::int64_t tile_x = 0, tile_y = 0;  // 0: scanlines
};

// Deflate expands at most 1032:1; no OpenEXR compression of pixel data our
// reader accepts decodes to more than about this per byte of file.
constexpr std::int64_t kMaxExrExpansion = 1100;

// Sizes of the attribute types with a fixed size.
std::optional<std::uint32_t> fixed_attribute_size(const std::string& type) {
  static const std::pair<const char*, std::uint32_t> sizes[] = {
      {"box2i", 16},      {"box2f", 16},   {"chromaticities", 32},
      {"compression", 1}, {"double", 8},   {"envmap", 1},
      {"float", 4},       {"int", 4},      {"keycode", 28},
      {"lineOrder", 1},   {"m33f", 36},    {"m33d", 72},
      {"m44f", 64},       {"m44d", 128},   {"rational", 8},
      {"tiledesc", 9},    {"timecode", 8}, {"v2i", 8},
      {"v2f", 8},         {"v2d", 16},     {"v3i", 12},
      {"v3f", 12},        {"v3d", 24},     {"deepImageState", 1}};
  for (const auto& [name, size] : sizes)
    if (type == name) return size;
  return std::nullopt;
}

ExrLayout check_exr_header(const std::filesystem::path& path) {
  const std::string name = path.string();
  auto fail = [&](const std::string& why) -> void {
    throw FileError(name + ": cannot read OpenEXR: " + why);
  };
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) fail("not a regular file");
  const std::uint64_t size = std::filesystem::file_size(path, ec);
  std::ifstream in(path, std::ios::binary);
  std::string bytes(std::size_t(std::min<std::uint64_t>(size, 1 << 20)), '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  bytes.resize(std::size_t(in.gcount()));
  std::size_t at = 0;
  auto u32 = [&]() -> std::uint32_t {
    if (bytes.size() - at < 4) fail("the header ends early");
    std::uint32_t v = 0;
    for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
    at += 4;
    return v;
  };
  if (u32() != 20000630u) fail("not an OpenEXR file");
  const std::uint32_t version = u32();
  if ((version & 0xff) != 2) fail("unknown version " + std::to_string(version & 0xff));
  if (version & 0x800u) fail("deep data is not supported");
  if (version & 0x1000u) fail("multi-part files are not supported");
  const std::size_t max_name = version & 0x400u ? 255 : 31;
  // A NUL-terminated name of 1 to max_name characters (empty: the end).
  auto text = [&](std::size_t end_of_value) {
    const std::size_t end = bytes.find('\0', at);
    if (end == std::string::npos || end >= end_of_value || end - at > max_name)
      fail("a name in the header is not terminated or too long");
    std::string t = bytes.substr(at, end - at);
    at = end + 1;
    return t;
  };
  ExrLayout layout;
  bool window = false;
  for (;;) {
    const std::string attribute = text(bytes.size());
    if (attribute.empty()) break;
    const std::string type = text(bytes.size());
    if (type.empty()) fail("attribute " + detail::quoted(attribute) + " has no type");
    const std::uint32_t value_size = u32();
    if (value_size > bytes.size() - at)
      fail("attribute " + detail::quoted(attribute) + " declares " + std::to_string(value_size) +
           " bytes, more than the file holds");
    const std::size_t value = at, end = at + value_size;
    const auto fixed = fixed_attribute_size(type);
    if (fixed && value_size != *fixed)
      fail("attribute " + detail::quoted(attribute) + " of type " + detail::quoted(type) + " has " +
           std::to_string(value_size) + " bytes, not " + std::to_string(*fixed));
    if (type == "chlist") {
      // Channels: name, pixel type, pLinear and 3 reserved bytes, x and y
      // sampling; an empty name ends the list, which must end the value.
      while (!text(end).empty()) {
        if (end - at < 16) fail("channel list overruns its attribute");
        at += 16;
      }
      if (at != end) fail("channel list does not fill its attribute");
    } else if (type == "stringvector") {
      while (at < end) {
        if (end - at < 4) fail("string vector overruns its attribute");
        const std::uint32_t n = u32();
        if (n > end - at) fail("string vector overruns its attribute");
        at += n;
      }
    } else if (type == "preview") {
      if (value_size < 8) fail("preview attribute too short");
      const std::uint64_t w = u32(), h = u32();
      if (8 + 4 * w * h != value_size) fail("preview image does not fill its attribute");
    } else if (type == "idmanifest") {
      fail("ID manifests are not supported");
    } else if (type == "floatvector" && value_size % 4 != 0) {
      fail("float vector of " + std::to_string(value_size) + " bytes");
    }
    at = value;
    if (attribute == "dataWindow" && type == "box2i") {
      std::int32_t box[4];
      for (auto& b : box) b = static_cast<std::int32_t>(u32());
      layout.width = std::int64_t(box[2]) - box[0] + 1;
      layout.height = std::int64_t(box[3]) - box[1] + 1;
      window = true;
    } else if (attribute == "compression" && type == "compression") {
      layout.compression = static_cast<unsigned char>(bytes[at]);
    } else if (attribute == "tiles" && type == "tiledesc") {
      layout.tile_x = u32();
      layout.tile_y = u32();
      if (layout.tile_x <= 0 || layout.tile_y <= 0) fail("tiles of zero size");
    }
    at = end;
  }
  if (!window) fail("no dataWindow");
  if (layout.width <= 0 || layout.height <= 0 || layout.width > INT32_MAX ||
      layout.height > INT32_MAX)
    fail("data window of " + std::to_string(layout.width) + "x" + std::to_string(layout.height) +
         " pixels");
  // Every scanline block or tile has an 8-byte entry in the offset table.
  const std::int64_t lines_per_block[] = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
  const std::int64_t per_block =
      layout.compression >= 0 && layout.compression < 10 ? lines_per_block[layout.compression] : 1;
  const bool tiled = layout.tile_x > 0;
  const std::int64_t blocks = tiled ? ((layout.width + layout.tile_x - 1) / layout.tile_x) *
                                          ((layout.height + layout.tile_y - 1) / layout.tile_y)
                                    : (layout.height + per_block - 1) / per_block;
  if (blocks > std::int64_t(size / 8))
    fail(std::to_string(layout.width) + "x" + std::to_string(layout.height) + " pixels in " +
         std::to_string(blocks) + " blocks, more than the file's " + std::to_string(size) +
         " bytes can index");
  // The pixels decoded as float RGB, and the buffer of one block or tile.
  const double allowed = double(kMaxExrExpansion) * double(size) + double(1 << 20);
  const double decoded = 12.0 * double(layout.width) * double(layout.height);
  const double block = tiled ? 16.0 * double(layout.tile_x) * double(layout.tile_y)
                             : 16.0 * double(layout.width) * double(per_block);
  if (decoded > allowed || block > allowed)
    fail(std::to_string(layout.width) + "x" + std::to_string(layout.height) +
         " pixels, more than a " + std::to_string(size) + "-byte file can hold");
  return layout;
}

}  // namespace

void write_exr_rgb(const std::filesystem::path& path, int width, int height,
                   const std::vector<Eigen::Vector3f>& pixels, const ExrAttributes& attributes,
                   const std::vector<float>& alpha) {
  check_size(width, height, pixels.size());
  if (!alpha.empty()) check_size(width, height, alpha.size());
  Imf::Header header(width, height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : kChannels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  if (!alpha.empty()) header.channels().insert("A", Imf::Channel(Imf::FLOAT));
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
    Imf::FrameBuffer frame = rgb_frame_buffer(pixels.front().data(), header.dataWindow());
    if (!alpha.empty())
      frame.insert("A", Imf::Slice::Make(Imf::FLOAT, alpha.data(), header.dataWindow(),
                                         sizeof(float), sizeof(float) * std::size_t(width)));
    file.setFrameBuffer(frame);
    file.writePixels(height);
  } catch (const std::exception& e) {
    // OpenEXR's messages usually repeat the file name; keep them whole anyway.
    throw FileError(path.string() + ": cannot write OpenEXR: " + e.what());
  }
}

std::vector<Eigen::Vector3f> read_exr_rgb(const std::filesystem::path& path, int& width,
                                          int& height, ExrAttributes* attributes,
                                          std::vector<float>* alpha) {
  // Checked up front: OpenEXR's message for a missing file is less direct.
  if (!std::filesystem::exists(path)) throw FileError(path.string() + ": no such file");
  const ExrLayout layout = check_exr_header(path);
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
    // The window OpenEXR read must be the one checked (a header may repeat it).
    if (std::int64_t(window.max.x) - window.min.x + 1 != layout.width ||
        std::int64_t(window.max.y) - window.min.y + 1 != layout.height)
      throw FileError(path.string() + ": cannot read OpenEXR: inconsistent data window");
    width = int(layout.width);
    height = int(layout.height);
    std::vector<Eigen::Vector3f> pixels(static_cast<std::size_t>(width) *
                                        static_cast<std::size_t>(height));
    Imf::FrameBuffer frame = rgb_frame_buffer(pixels.front().data(), window);
    const Imf::Channel* a = header.channels().findChannel("A");
    if (alpha) alpha->clear();
    if (alpha && a) {
      if (a->xSampling != 1 || a->ySampling != 1)
        throw FileError(path.string() + ": OpenEXR channel A is subsampled");
      alpha->assign(pixels.size(), 0.0f);
      frame.insert("A", Imf::Slice::Make(Imf::FLOAT, alpha->data(), window, sizeof(float),
                                         sizeof(float) * std::size_t(width)));
    }
    file.setFrameBuffer(frame);
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

namespace {

// The PNG writer module (png_module.cpp), loaded on first use: next to the
// program (or Python module) holding this code, else where the build put it.
using WritePng = int (*)(const char*, int, int, int, const unsigned char*, char*, std::size_t);

struct PngModule {
  WritePng write = nullptr;
  std::string failure;  // why it was not found (when write is null)
};

PngModule load_png_module() {
  PngModule module;
  std::vector<std::string> places;
  Dl_info self{};
  if (dladdr(reinterpret_cast<void*>(&load_png_module), &self) && self.dli_fname)
    places.push_back(
        (std::filesystem::path(self.dli_fname).parent_path() / "libism_png.so").string());
#ifdef ISM_PNG_MODULE
  if (places.empty() || std::filesystem::path(places[0]) != std::filesystem::path(ISM_PNG_MODULE))
    places.push_back(ISM_PNG_MODULE);
#endif
  for (const std::string& place : places) {
    if (void* handle = dlopen(place.c_str(), RTLD_NOW | RTLD_LOCAL))
      if (void* symbol = dlsym(handle, "ism_write_png")) {
        module.write = reinterpret_cast<WritePng>(symbol);
        return module;
      }
    const char* error = dlerror();
    module.failure += (module.failure.empty() ? "" : "; ") + std::string(error ? error : place);
  }
  if (places.empty()) module.failure = "no place to look for libism_png.so";
  return module;
}

void write_png(const std::filesystem::path& path, int width, int height, int channels,
               const unsigned char* pixels) {
  static const PngModule module = load_png_module();  // (once, thread-safe)
  if (!module.write)
    throw FileError(path.string() + ": cannot write PNG: the PNG writer module is missing (" +
                    module.failure + ")");
  char error[512] = "";
  if (!module.write(path.string().c_str(), width, height, channels, pixels, error, sizeof error))
    throw FileError(path.string() + ": " + error);
}

}  // namespace

void write_png_preview(const std::filesystem::path& path, int width, int height,
                       const std::vector<std::array<unsigned char, 3>>& pixels) {
  check_size(width, height, pixels.size());
  write_png(path, width, height, 3, pixels.front().data());
}

void write_png_grey(const std::filesystem::path& path, int width, int height,
                    const std::vector<unsigned char>& pixels) {
  check_size(width, height, pixels.size());
  write_png(path, width, height, 1, pixels.data());
}

}  // namespace ism::io
