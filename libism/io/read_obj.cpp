// Wavefront OBJ: "v x y z [r g b]", "vt u v" and "f a b c ..." lines (corners
// "i", "i/t", "i//n", "i/t/n"); every other statement (vn, g, o, s, usemtl, l,
// ...) is ignored.
#include "io/mesh_parse.hpp"

#include <climits>

namespace ism::io::detail {
namespace {

// An OBJ index (of a vertex or a texture coordinate, `what`): 0-based,
// negative (relative) indices resolved against the `count` read so far.
int resolve_index(std::string_view index, std::string_view word, std::size_t count,
                  const char* what, const std::string& name, std::size_t line) {
  std::int64_t i = 0;
  if (!parse_integer(index, i)) fail_at(name, line, quoted(word) + " is not a " + what + " index");
  if (i == 0) fail_at(name, line, std::string(what) + " index 0 (OBJ counts from 1)");
  const std::int64_t resolved = i > 0 ? i - 1 : std::int64_t(count) + i;
  if (resolved < 0)
    fail_at(name, line,
            "relative index " + std::to_string(i) + " before the first " + what + " (" +
                std::to_string(count) + " read so far)");
  if (resolved >= INT_MAX)
    fail_at(name, line, std::string(what) + " index " + std::to_string(i) + " is too large");
  return int(resolved);
}

// A corner "i", "i/t", "i//n" or "i/t/n": the 0-based vertex and texture
// coordinate (-1 when absent).
std::array<int, 2> corner_index(std::string_view word, std::size_t vertices, std::size_t texcoords,
                                const std::string& name, std::size_t line) {
  const std::size_t slash = word.find('/');
  const int v = resolve_index(word.substr(0, slash), word, vertices, "vertex", name, line);
  if (slash == std::string_view::npos) return {v, -1};
  const std::string_view rest = word.substr(slash + 1);
  const std::string_view t = rest.substr(0, rest.find('/'));
  if (t.empty()) return {v, -1};
  return {v, resolve_index(t, word, texcoords, "texture coordinate", name, line)};
}

}  // namespace

PolygonSoup parse_obj(std::string_view bytes, const std::string& name) {
  PolygonSoup soup;
  Lines lines(strip_byte_order_mark(bytes, name));
  std::string_view line;
  std::string joined;          // a statement continued over lines ending in '\'
  std::size_t coloured = 0;    // vertices with r g b after x y z
  std::vector<int> texcoords;  // (reused: one face at a time)
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
      soup.positions.push_back(p);
      // "v x y z r g b": a colour (kept when every vertex has one); a w alone
      // is ignored.
      Vec3 rgb;
      bool colour = true;
      for (int k = 0; k < 3 && colour; ++k) colour = parse_double(words.next(), rgb[k]);
      if (colour && words.done()) {
        soup.colors.resize(soup.positions.size(), Vec3::Zero());
        soup.colors.back() = rgb;
        ++coloured;
      }
    } else if (keyword == "vt") {
      std::array<double, 2> uv;
      for (int k = 0; k < 2; ++k)
        if (!parse_double(words.next(), uv[std::size_t(k)]))
          fail_at(name, number, "a texture coordinate needs two numbers u v");
      soup.texcoords.push_back(uv);
    } else if (keyword == "f") {
      std::vector<int> face;
      texcoords.clear();
      bool textured = false;
      while (!words.done()) {
        const auto [v, t] =
            corner_index(words.next(), soup.positions.size(), soup.texcoords.size(), name, number);
        face.push_back(v);
        texcoords.push_back(t);
        textured = textured || t >= 0;
      }
      if (face.empty()) fail_at(name, number, "a face without vertices");
      if (textured) {
        for (std::size_t f = soup.face_texcoords.size(); f < soup.faces.size(); ++f)
          soup.face_texcoords.emplace_back(soup.faces[f].size(), -1);
        soup.face_texcoords.push_back(texcoords);
      } else if (!soup.face_texcoords.empty()) {
        soup.face_texcoords.emplace_back(face.size(), -1);
      }
      soup.faces.push_back(std::move(face));
    }
  }
  if (coloured == soup.positions.size())
    soup.colors.resize(soup.positions.size());
  else
    soup.colors.clear();
  for (const auto& corners : soup.face_texcoords)
    for (int t : corners)
      if (t >= int(soup.texcoords.size()))
        fail(name, "texture coordinate index " + std::to_string(t + 1) + " but only " +
                       std::to_string(soup.texcoords.size()) + " in the file");
  if (soup.face_texcoords.empty()) soup.texcoords.clear();
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
