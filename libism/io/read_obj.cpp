// Wavefront OBJ: "v x y z ..." and "f a b c ..." lines; every other statement
// (vt, vn, g, o, s, usemtl, l, ...) is ignored.
#include "io/mesh_parse.hpp"

#include <climits>

namespace ism::io::detail {
namespace {

// A corner "i", "i/t", "i//n" or "i/t/n": the 0-based vertex, resolving
// negative (relative) indices against the `vertices` read so far.
int corner_index(std::string_view word, std::size_t vertices, const std::string& name,
                 std::size_t line) {
  const std::string_view index = word.substr(0, word.find('/'));
  std::int64_t i = 0;
  if (!parse_integer(index, i)) fail_at(name, line, quoted(word) + " is not a vertex index");
  if (i == 0) fail_at(name, line, "vertex index 0 (OBJ counts from 1)");
  const std::int64_t resolved = i > 0 ? i - 1 : std::int64_t(vertices) + i;
  if (resolved < 0)
    fail_at(name, line,
            "relative index " + std::to_string(i) + " before the first vertex (" +
                std::to_string(vertices) + " read so far)");
  if (resolved >= INT_MAX)
    fail_at(name, line, "vertex index " + std::to_string(i) + " is too large");
  return int(resolved);
}

}  // namespace

PolygonSoup parse_obj(std::string_view bytes, const std::string& name) {
  PolygonSoup soup;
  Lines lines(strip_byte_order_mark(bytes, name));
  std::string_view line;
  std::string joined;  // a statement continued over lines ending in '\'
  while (lines.next(line)) {
    const std::size_t number = lines.number();
    if (!line.empty() && line.back() == '\\') {
      joined.clear();
      std::string_view part = line;
      while (!part.empty() && part.back() == '\\') {
        joined.append(part.substr(0, part.size() - 1)).push_back(' ');
        if (!lines.next(part)) part = {};
      }
      joined.append(part);
      line = joined;
    }
    if (const auto hash = line.find('#'); hash != std::string_view::npos)
      line = line.substr(0, hash);
    Words words(line);
    const std::string_view keyword = words.next();
    if (keyword == "v") {
      Vec3 p;
      for (int k = 0; k < 3; ++k)
        if (!parse_double(words.next(), p[k]))
          fail_at(name, number, "a vertex needs three numbers x y z");
      soup.positions.push_back(p);  // w or colours after x y z are ignored
    } else if (keyword == "f") {
      std::vector<int> face;
      while (!words.done())
        face.push_back(corner_index(words.next(), soup.positions.size(), name, number));
      if (face.empty()) fail_at(name, number, "a face without vertices");
      soup.faces.push_back(std::move(face));
    }
  }
  return soup;
}

void ObjLineCounter::feed(std::string_view chunk) {
  for (const char c : chunk) {
    if (c == '\n') {
      state_ = 0;
    } else if (state_ == 0) {
      if (c == 'v')
        state_ = 1;
      else if (c == 'f')
        state_ = 2;
      // Bytes of a byte-order mark keep the line's start (an upper bound either way).
      else if (!is_space(c) && static_cast<unsigned char>(c) < 0x80)
        state_ = 3;
    } else if (state_ == 1 || state_ == 2) {
      if (is_space(c)) ++(state_ == 1 ? vertices_ : faces_);
      state_ = 3;
    }
  }
}

}  // namespace ism::io::detail
