// STL: triangles with their own three corners, as text ("solid", facets of
// "vertex x y z" lines) or binary (80-byte header, a 32-bit little-endian
// count, 50 bytes per triangle). STL has no vertex indices: corners with
// exactly equal coordinates are one vertex, which is what connects the faces.
#include "io/mesh_parse.hpp"

#include <bit>
#include <cstring>
#include <unordered_map>

namespace ism::io::detail {
namespace {

constexpr std::size_t kHeaderBytes = 84, kTriangleBytes = 50;
// A text facet takes at least "vertex 0 0 0" three times and "endloop".
constexpr std::size_t kMinTextFacetBytes = 3 * 13 + 7;

std::uint32_t le32(std::string_view bytes, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

// Positions joined by exact equality (0.0 and -0.0 alike).
class Corners {
 public:
  explicit Corners(PolygonSoup& soup) : soup_(soup) {}
  int index(const Vec3& p) {
    std::array<std::uint64_t, 3> key;
    for (int k = 0; k < 3; ++k) key[k] = std::bit_cast<std::uint64_t>(p[k] == 0.0 ? 0.0 : p[k]);
    const auto [it, added] = seen_.try_emplace(key, int(soup_.positions.size()));
    if (added) soup_.positions.push_back(p);
    return it->second;
  }

 private:
  struct Hash {
    std::size_t operator()(const std::array<std::uint64_t, 3>& k) const {
      return std::size_t((k[0] * 0x9E3779B97F4A7C15ull) ^ (k[1] * 0xC2B2AE3D27D4EB4Full) ^ k[2]);
    }
  };
  PolygonSoup& soup_;
  std::unordered_map<std::array<std::uint64_t, 3>, int, Hash> seen_;
};

bool binary_fits(std::string_view bytes) {
  return bytes.size() >= kHeaderBytes &&
         kHeaderBytes + kTriangleBytes * std::uint64_t(le32(bytes, 80)) <= bytes.size();
}

PolygonSoup parse_binary(std::string_view bytes, const std::string& name) {
  if (bytes.size() < kHeaderBytes) fail(name, "too short for a binary STL and not a text STL");
  const std::uint32_t n = le32(bytes, 80);
  check_count(name, "triangles", n, kTriangleBytes, bytes.size() - kHeaderBytes);
  PolygonSoup soup;
  soup.faces.reserve(n);
  Corners corners(soup);
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::size_t at = kHeaderBytes + kTriangleBytes * std::size_t(t) + 12;  // after the normal
    std::vector<int>& face = soup.faces.emplace_back();
    face.reserve(3);
    for (int c = 0; c < 3; ++c) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) p[k] = std::bit_cast<float>(le32(bytes, at + 12 * c + 4 * k));
      face.push_back(corners.index(p));
    }
  }
  return soup;
}

// Text STL, read leniently: the corners of each "outer loop ... endloop";
// other words (solid, facet normal, endsolid) are passed over.
PolygonSoup parse_text(std::string_view text, const std::string& name) {
  PolygonSoup soup;
  Corners corners(soup);
  std::vector<int> loop;
  Words words(text);
  while (!words.done()) {
    const std::string_view word = words.next();
    if (word == "vertex") {
      Vec3 p;
      for (int k = 0; k < 3; ++k)
        if (!parse_double(words.next(), p[k]))
          fail(name, "facet " + std::to_string(soup.faces.size()) +
                         ": a vertex needs three numbers x y z");
      loop.push_back(corners.index(p));
    } else if ((word == "endloop" || word == "endfacet") && !loop.empty()) {
      soup.faces.push_back(std::move(loop));
      loop.clear();
    }
  }
  if (!loop.empty()) soup.faces.push_back(std::move(loop));
  return soup;
}

bool starts_as_text(std::string_view text) {
  Words words(text);
  return words.next() == "solid";
}

}  // namespace

PolygonSoup parse_stl(std::string_view bytes, const std::string& name) {
  // Binary files may start with "solid" too: a size that matches the count
  // exactly decides for binary.
  const bool exact_binary =
      bytes.size() >= kHeaderBytes &&
      kHeaderBytes + kTriangleBytes * std::uint64_t(le32(bytes, 80)) == bytes.size();
  const std::string_view text = strip_byte_order_mark(bytes, name);
  if (!exact_binary && starts_as_text(text)) {
    PolygonSoup soup = parse_text(text, name);
    if (!soup.faces.empty() || !binary_fits(bytes)) return soup;
  }
  return parse_binary(bytes, name);
}

MeshFileSize peek_stl(std::string_view head, std::uint64_t file_bytes) {
  const std::uint64_t text_faces = file_bytes / kMinTextFacetBytes;
  std::uint64_t faces = text_faces;
  if (head.size() >= kHeaderBytes)
    faces = std::max(text_faces, std::min<std::uint64_t>(
                                     le32(head, 80), (file_bytes - kHeaderBytes) / kTriangleBytes));
  return {file_bytes, 3 * faces, faces};
}

}  // namespace ism::io::detail
