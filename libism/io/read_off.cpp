// OFF (Geomview): a keyword line "[ST][C][N]OFF" (optionally " BINARY"), the
// counts "V F [E]" on it or on the next line, V vertex lines, F face lines
// "k i1 ... ik [colour]". Extra values on a line are ignored. The fused
// "OFF490 518 0" of some ModelNet files is read as "OFF" and its counts.
#include "io/mesh_parse.hpp"

#include <bit>
#include <climits>

namespace ism::io::detail {
namespace {

// The minimal sizes of an ASCII vertex ("0 0 0" and a separator) and face
// ("0" and a separator), and of a binary face (two 32-bit integers).
constexpr std::size_t kTextVertexBytes = 6, kTextFaceBytes = 2, kBinaryFaceBytes = 8;

struct OffHeader {
  bool binary = false;
  int vertex_floats = 3;  // per vertex in a binary file: x y z, normal, colour, texture
  std::int64_t vertices = 0, faces = 0;
  std::size_t body = 0;  // offset of the first byte after the counts (ASCII) or keyword line
  std::size_t line = 0;  // lines consumed (ASCII)
};

// The next line with content (comments cut), or false at the end.
bool content_line(Lines& lines, std::string_view& line) {
  while (lines.next(line)) {
    if (const auto hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    if (!Words(line).done()) return true;
  }
  return false;
}

OffHeader read_header(std::string_view text, const std::string& name) {
  OffHeader h;
  Lines lines(text);
  std::string_view line;
  if (!content_line(lines, line)) fail(name, "empty file, not an OFF mesh");
  Words words(line);
  std::string_view keyword = words.next();
  const std::size_t off = keyword.find("OFF");
  if (off == std::string_view::npos) fail_at(name, lines.number(), "no OFF keyword");
  std::string_view prefix = keyword.substr(0, off);
  const bool texture = prefix.substr(0, 2) == "ST";
  if (texture) prefix.remove_prefix(2);
  const bool colour = !prefix.empty() && prefix.front() == 'C';
  if (colour) prefix.remove_prefix(1);
  const bool normal = !prefix.empty() && prefix.front() == 'N';
  if (normal) prefix.remove_prefix(1);
  if (!prefix.empty() && (prefix.front() == '4' || prefix.front() == 'n'))
    fail_at(name, lines.number(), quoted(keyword) + ": only 3D OFF is supported");
  if (!prefix.empty()) fail_at(name, lines.number(), quoted(keyword) + " is not an OFF keyword");
  h.vertex_floats = 3 + (normal ? 3 : 0) + (colour ? 4 : 0) + (texture ? 2 : 0);

  // The counts follow the keyword (fused digits), on its line, or on the next.
  std::string counts(keyword.substr(off + 3));
  counts += ' ';
  counts += words.rest();
  if (Words(counts).next() == "BINARY") {
    h.binary = true;
    h.body = text.size() - lines.rest().size();
    return h;
  }
  if (Words(counts).done()) {
    if (!content_line(lines, line)) fail(name, "the file ends before the counts line");
    counts = line;
  }
  Words numbers(counts);
  std::int64_t edges = 0;
  if (!parse_integer(numbers.next(), h.vertices) || !parse_integer(numbers.next(), h.faces))
    fail_at(name, lines.number(), "expected the counts 'vertices faces edges'");
  const std::string_view third = numbers.next();
  if (!third.empty() && !parse_integer(third, edges))
    fail_at(name, lines.number(), "expected the counts 'vertices faces edges'");
  if (h.vertices < 0 || h.faces < 0)
    fail_at(name, lines.number(),
            "negative count (" + std::to_string(h.vertices) + " vertices, " +
                std::to_string(h.faces) + " faces)");
  h.body = text.size() - lines.rest().size();
  h.line = lines.number();
  return h;
}

PolygonSoup parse_text_body(std::string_view text, const OffHeader& h, const std::string& name) {
  const std::size_t left = text.size() - h.body;
  check_count(name, "vertices", std::uint64_t(h.vertices), kTextVertexBytes - 1, left);
  check_count(name, "faces", std::uint64_t(h.faces), kTextFaceBytes - 1, left);
  if (std::uint64_t(h.vertices) * (kTextVertexBytes - 1) +
          std::uint64_t(h.faces) * (kTextFaceBytes - 1) >
      left)
    fail(name, "the header declares " + std::to_string(h.vertices) + " vertices and " +
                   std::to_string(h.faces) + " faces, more than the " + std::to_string(left) +
                   " bytes after it can hold (truncated or corrupt)");
  PolygonSoup soup;
  soup.positions.reserve(std::size_t(h.vertices));
  soup.faces.reserve(std::size_t(h.faces));
  Lines lines(text.substr(h.body));
  std::string_view line;
  auto where = [&] { return h.line + lines.number(); };
  for (std::int64_t i = 0; i < h.vertices; ++i) {
    if (!content_line(lines, line))
      fail(name, "the file ends after " + std::to_string(i) + " of " + std::to_string(h.vertices) +
                     " vertices");
    Words words(line);
    Vec3 p;
    for (int k = 0; k < 3; ++k)
      if (!parse_double(words.next(), p[k]))
        fail_at(name, where(), "a vertex needs three numbers x y z");
    soup.positions.push_back(p);
  }
  for (std::int64_t i = 0; i < h.faces; ++i) {
    if (!content_line(lines, line))
      fail(name, "the file ends after " + std::to_string(i) + " of " + std::to_string(h.faces) +
                     " faces");
    Words words(line);
    std::int64_t k = 0;
    if (!parse_integer(words.next(), k) || k < 0)
      fail_at(name, where(), "a face line starts with its number of vertices");
    if (std::uint64_t(k) > line.size() / 2 + 1)
      fail_at(name, where(), "a face of " + std::to_string(k) + " vertices lists fewer");
    std::vector<int>& face = soup.faces.emplace_back();
    face.reserve(std::size_t(k));
    for (std::int64_t j = 0; j < k; ++j) {
      std::int64_t v = 0;
      if (!parse_integer(words.next(), v))
        fail_at(name, where(), "a face of " + std::to_string(k) + " vertices lists fewer");
      if (v < 0 || v > INT_MAX)
        fail_at(name, where(), "vertex index " + std::to_string(v) + " out of range");
      face.push_back(int(v));
    }
  }
  return soup;
}

// Binary OFF stores big-endian 32-bit integers and floats.
class BigEndian {
 public:
  BigEndian(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}
  std::uint32_t u32() {
    if (bytes_.size() - at_ < 4) fail(name_, "the binary data ends early (truncated file)");
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes_[at_ + k]);
    at_ += 4;
    return v;
  }
  std::int32_t i32() { return static_cast<std::int32_t>(u32()); }
  float f32() { return std::bit_cast<float>(u32()); }
  std::size_t left() const { return bytes_.size() - at_; }

 private:
  std::string_view bytes_;
  const std::string& name_;
  std::size_t at_ = 0;
};

PolygonSoup parse_binary_body(std::string_view text, const OffHeader& h, const std::string& name) {
  BigEndian in(text.substr(h.body), name);
  const std::int32_t nv = in.i32(), nf = in.i32();
  in.i32();  // edges
  if (nv < 0 || nf < 0)
    fail(name,
         "negative count (" + std::to_string(nv) + " vertices, " + std::to_string(nf) + " faces)");
  const std::size_t vertex_bytes = 4 * std::size_t(h.vertex_floats);
  check_count(name, "vertices", std::uint64_t(nv), vertex_bytes, in.left());
  check_count(name, "faces", std::uint64_t(nf), kBinaryFaceBytes,
              in.left() - std::size_t(nv) * vertex_bytes);
  PolygonSoup soup;
  soup.positions.reserve(std::size_t(nv));
  soup.faces.reserve(std::size_t(nf));
  for (std::int32_t i = 0; i < nv; ++i) {
    Vec3 p;
    for (int k = 0; k < 3; ++k) p[k] = in.f32();
    for (int k = 3; k < h.vertex_floats; ++k) in.f32();
    soup.positions.push_back(p);
  }
  for (std::int32_t i = 0; i < nf; ++i) {
    const std::int32_t k = in.i32();
    if (k < 0 || std::size_t(k) > in.left() / 4)
      fail(name, "face " + std::to_string(i) + " declares " + std::to_string(k) +
                     " vertices, more than the file holds");
    std::vector<int>& face = soup.faces.emplace_back();
    face.reserve(std::size_t(k));
    for (std::int32_t j = 0; j < k; ++j) face.push_back(in.i32());
    const std::int32_t colours = in.i32();
    if (colours < 0 || colours > 4)
      fail(name, "face " + std::to_string(i) + " has " + std::to_string(colours) +
                     " colour components (0 to 4 allowed)");
    for (std::int32_t j = 0; j < colours; ++j) in.f32();
  }
  return soup;
}

}  // namespace

PolygonSoup parse_off(std::string_view bytes, const std::string& name) {
  const std::string_view text = strip_byte_order_mark(bytes, name);
  const OffHeader h = read_header(text, name);
  return h.binary ? parse_binary_body(text, h, name) : parse_text_body(text, h, name);
}

MeshFileSize peek_off(std::string_view head, std::uint64_t file_bytes, const std::string& name) {
  const std::string_view text = strip_byte_order_mark(head, name);
  const OffHeader h = read_header(text, name);
  std::uint64_t nv = 0, nf = 0, vertex_cap = 0, face_cap = 0;
  if (h.binary) {
    // Counts follow the keyword line as binary integers.
    BigEndian in(text.substr(h.body), name);
    nv = std::uint32_t(std::max(0, in.i32()));
    nf = std::uint32_t(std::max(0, in.i32()));
    vertex_cap = file_bytes / (4 * std::uint64_t(h.vertex_floats));
    face_cap = file_bytes / kBinaryFaceBytes;
  } else {
    nv = std::uint64_t(h.vertices);
    nf = std::uint64_t(h.faces);
    vertex_cap = file_bytes / (kTextVertexBytes - 1);
    face_cap = file_bytes / (kTextFaceBytes - 1);
  }
  return {file_bytes, std::min(nv, vertex_cap), std::min(nf, face_cap),
          nv > vertex_cap || nf > face_cap};
}

}  // namespace ism::io::detail
