// Reading mesh files: the file into memory, the format's parser, then the
// checks every format shares (indices are vertices, there are faces).
#include "io/io.hpp"
#include "io/mesh_parse.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>

namespace ism::io {

namespace detail {

void fail(const std::string& name, const std::string& why) {
  throw FileError(name + ": " + why);
}

void fail_at(const std::string& name, std::size_t line, const std::string& why) {
  throw FileError(name + ":" + std::to_string(line) + ": " + why);
}

void check_count(const std::string& name, const char* what, std::uint64_t count,
                 std::size_t min_bytes, std::size_t bytes_left) {
  if (min_bytes > 0 && count > bytes_left / min_bytes)
    fail(name, "the header declares " + std::to_string(count) + " " + what + ", more than the " +
                   std::to_string(bytes_left) + " bytes after it can hold (truncated or corrupt)");
}

std::string quoted(std::string_view content) {
  constexpr std::size_t kMax = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < content.size() && i < kMax; ++i) {
    const unsigned char c = static_cast<unsigned char>(content[i]);
    out += c >= 0x20 && c < 0x7f ? char(c) : '?';
  }
  if (content.size() > kMax) out += "...";
  return out + "'";
}

std::string number_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string_view strip_byte_order_mark(std::string_view text, const std::string& name) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") return text.substr(3);
  if (text.substr(0, 2) == "\xFF\xFE" || text.substr(0, 2) == "\xFE\xFF")
    fail(name, "UTF-16 or UTF-32 text (byte-order mark); save the file as ASCII or UTF-8");
  return text;
}

}  // namespace detail

namespace {

std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// The format, or a FileError naming the readable ones.
MeshFormat format_or_fail(const std::filesystem::path& path) {
  const auto format = mesh_format_of(path);
  if (!format)
    throw FileError(path.string() + ": unsupported mesh format (use .obj, .ply, .off or .stl)");
  return *format;
}

// The file's size; a FileError when it is not a regular file.
std::uint64_t regular_file_size(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw FileError(path.string() + ": no such file");
  if (!std::filesystem::is_regular_file(path, ec))
    throw FileError(path.string() + ": not a regular file");
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) throw FileError(path.string() + ": cannot open the file");
  return size;
}

// At most `limit` bytes from the start of the file.
std::string read_bytes(const std::filesystem::path& path, std::uint64_t limit) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string() + ": cannot open the file");
  std::string bytes;
  bytes.resize(std::size_t(limit));
  in.read(bytes.data(), std::streamsize(limit));
  bytes.resize(std::size_t(in.gcount()));
  if (in.bad()) throw FileError(path.string() + ": cannot read the file");
  return bytes;
}

}  // namespace

std::optional<MeshFormat> mesh_format_of(const std::filesystem::path& path) {
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return MeshFormat::obj;
  if (ext == ".off") return MeshFormat::off;
  if (ext == ".ply") return MeshFormat::ply;
  if (ext == ".stl") return MeshFormat::stl;
  return std::nullopt;
}

bool is_readable_mesh_extension(const std::filesystem::path& path) {
  return mesh_format_of(path).has_value();
}

PolygonSoup parse_polygon_soup(std::string_view bytes, MeshFormat format, const std::string& name) {
  PolygonSoup soup;
  switch (format) {
    case MeshFormat::obj:
      soup = detail::parse_obj(bytes, name);
      break;
    case MeshFormat::off:
      soup = detail::parse_off(bytes, name);
      break;
    case MeshFormat::ply:
      soup = detail::parse_ply(bytes, name);
      break;
    case MeshFormat::stl:
      soup = detail::parse_stl(bytes, name);
      break;
  }
  const std::size_t n = soup.positions.size();
  for (const auto& face : soup.faces)
    for (int v : face)
      if (v < 0 || std::size_t(v) >= n) {
        // OBJ counts from 1, the others from 0: name the index as the file has it.
        const bool obj = format == MeshFormat::obj;
        throw FileError(name + ": a face refers to vertex " + std::to_string(obj ? v + 1L : v) +
                        (obj ? "" : " (0-based)") + ", which does not exist (the file has " +
                        std::to_string(n) + " vertices)");
      }
  if (soup.faces.empty()) throw FileError(name + ": the file has no faces");
  return soup;
}

TriangleMesh read_triangles_exact(const std::filesystem::path& path) {
  const PolygonSoup soup = parse_polygon_soup(read_bytes(path, regular_file_size(path)),
                                              format_or_fail(path), path.string());
  TriangleMesh mesh;
  mesh.positions = soup.positions;
  mesh.triangles.reserve(soup.faces.size());
  for (const auto& f : soup.faces) {
    if (f.size() != 3) throw FileError(path.string() + ": a face that is not a triangle");
    mesh.triangles.push_back({f[0], f[1], f[2]});
  }
  return mesh;
}

PolygonSoup read_polygon_soup(const std::filesystem::path& path) {
  const MeshFormat format = format_or_fail(path);
  const std::uint64_t size = regular_file_size(path);
  const std::string bytes = read_bytes(path, size);
  PolygonSoup soup = parse_polygon_soup(bytes, format, path.string());
  static_assert(sizeof(Vec3) == 3 * sizeof(double), "positions are contiguous doubles");
  // One Eigen expression over all coordinates: a per-vertex loop of
  // `p = p.cast<float>().cast<double>()` compiled (GCC 12, -O3, Eigen 3.4)
  // to code that left the last (n mod 4) vertices at double precision.
  Eigen::Map<Eigen::ArrayXd> coordinates(
      soup.positions.empty() ? nullptr : soup.positions[0].data(),
      Eigen::Index(3 * soup.positions.size()));
  coordinates = coordinates.cast<float>().cast<double>().eval();
  return soup;
}

MeshFileSize peek_mesh_size(const std::filesystem::path& path) {
  const MeshFormat format = format_or_fail(path);
  const std::uint64_t size = regular_file_size(path);
  const std::string name = path.string();
  if (format == MeshFormat::obj) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw FileError(name + ": cannot open the file");
    detail::ObjLineCounter counter;
    std::string chunk(detail::kPeekBytes, '\0');
    while (in.read(chunk.data(), std::streamsize(chunk.size())) || in.gcount() > 0)
      counter.feed(std::string_view(chunk.data(), std::size_t(in.gcount())));
    return counter.size(size);
  }
  const std::string head = read_bytes(path, std::min<std::uint64_t>(size, detail::kPeekBytes));
  switch (format) {
    case MeshFormat::off:
      return detail::peek_off(head, size, name);
    case MeshFormat::ply:
      return detail::peek_ply(head, size, name);
    default:
      return detail::peek_stl(head, size);
  }
}

}  // namespace ism::io
