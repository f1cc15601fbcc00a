// PLY (Turk's polygon file format): a text header of elements and their
// properties up to "end_header", then the elements in order, as text or
// binary (little or big endian). Of the vertex element we take x y z (and
// red green blue when all three are there), of the face element its vertex_indices (or
// vertex_index) list; every other element and property is read past.
#include "io/mesh_parse.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <optional>

namespace ism::io::detail {
namespace {

enum class Type { int8, uint8, int16, uint16, int32, uint32, float32, float64 };

std::optional<Type> type_named(std::string_view word) {
  static const std::pair<const char*, Type> names[] = {
      {"char", Type::int8},      {"int8", Type::int8},       {"uchar", Type::uint8},
      {"uint8", Type::uint8},    {"short", Type::int16},     {"int16", Type::int16},
      {"ushort", Type::uint16},  {"uint16", Type::uint16},   {"int", Type::int32},
      {"int32", Type::int32},    {"uint", Type::uint32},     {"uint32", Type::uint32},
      {"float", Type::float32},  {"float32", Type::float32}, {"double", Type::float64},
      {"float64", Type::float64}};
  for (const auto& [n, t] : names)
    if (word == n) return t;
  return std::nullopt;
}

std::size_t size_of(Type t) {
  switch (t) {
    case Type::int8:
    case Type::uint8:
      return 1;
    case Type::int16:
    case Type::uint16:
      return 2;
    case Type::int32:
    case Type::uint32:
    case Type::float32:
      return 4;
    case Type::float64:
      return 8;
  }
  return 1;
}

struct Property {
  std::string name;
  Type type = Type::float32;
  std::optional<Type> count_type;  // set for a list property
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  // Bytes (binary) or words (text) one element takes at least.
  std::size_t min_bytes() const {
    std::size_t n = 0;
    for (const Property& p : properties) n += size_of(p.count_type.value_or(p.type));
    return n;
  }
};

enum class Encoding { ascii, little_endian, big_endian };

struct Header {
  Encoding encoding = Encoding::ascii;
  std::vector<Element> elements;
  std::size_t body = 0;  // offset of the first byte after "end_header\n"
  std::size_t lines = 0;
};

constexpr std::size_t kMaxHeaderBytes = kPeekBytes;

Header read_header(std::string_view text, const std::string& name) {
  Lines lines(text);
  std::string_view line;
  if (!lines.next(line) || line != "ply") fail(name, "not a PLY file (no 'ply' on the first line)");
  Header h;
  bool format = false;
  for (;;) {
    if (text.size() - lines.bytes_left() > kMaxHeaderBytes)
      fail(name, "no end_header in the first " + std::to_string(kMaxHeaderBytes) + " bytes");
    if (!lines.next(line)) fail(name, "the file ends inside the PLY header");
    const std::size_t at = lines.number();
    Words words(line);
    const std::string_view keyword = words.next();
    if (keyword == "end_header") break;
    if (keyword.empty() || keyword == "comment" || keyword == "obj_info") continue;
    if (keyword == "format") {
      const std::string_view kind = words.next();
      if (kind == "ascii")
        h.encoding = Encoding::ascii;
      else if (kind == "binary_little_endian")
        h.encoding = Encoding::little_endian;
      else if (kind == "binary_big_endian")
        h.encoding = Encoding::big_endian;
      else
        fail_at(name, at, "unknown PLY format " + quoted(kind));
      format = true;
    } else if (keyword == "element") {
      Element& e = h.elements.emplace_back();
      e.name = words.next();
      std::int64_t count = -1;
      if (e.name.empty() || !parse_integer(words.next(), count) || count < 0)
        fail_at(name, at, "expected 'element NAME COUNT' with COUNT >= 0");
      e.count = std::uint64_t(count);
    } else if (keyword == "property") {
      if (h.elements.empty()) fail_at(name, at, "a property before any element");
      Property p;
      std::string_view type = words.next();
      if (type == "list") {
        p.count_type = type_named(words.next());
        type = words.next();
        if (!p.count_type || *p.count_type == Type::float32 || *p.count_type == Type::float64)
          fail_at(name, at, "a list property needs an integer count type");
      }
      const auto t = type_named(type);
      p.name = words.next();
      if (!t || p.name.empty()) fail_at(name, at, "expected 'property TYPE NAME'");
      p.type = *t;
      h.elements.back().properties.push_back(std::move(p));
    } else {
      fail_at(name, at, "unknown PLY header line " + quoted(line));
    }
  }
  if (!format) fail(name, "the PLY header has no format line");
  h.body = text.size() - lines.bytes_left();
  h.lines = lines.number();
  return h;
}

// Where the vertex and face data sit in their elements.
struct Layout {
  int vertex = -1, face = -1;  // element indices
  int x = -1, y = -1, z = -1;  // property indices in the vertex element
  int red = -1, green = -1, blue = -1;
  int corners = -1;  // list property of the face element
};

Layout layout_of(const Header& h, const std::string& name) {
  Layout l;
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Element& el = h.elements[e];
    if (el.name == "vertex") {
      if (l.vertex >= 0) fail(name, "two vertex elements in the PLY header");
      l.vertex = int(e);
      for (std::size_t p = 0; p < el.properties.size(); ++p) {
        const Property& prop = el.properties[p];
        int* slot = prop.name == "x"       ? &l.x
                    : prop.name == "y"     ? &l.y
                    : prop.name == "z"     ? &l.z
                    : prop.name == "red"   ? &l.red
                    : prop.name == "green" ? &l.green
                    : prop.name == "blue"  ? &l.blue
                                           : nullptr;
        if (!slot) continue;
        if (prop.count_type) fail(name, "vertex property " + prop.name + " is a list");
        *slot = int(p);
      }
      if (l.x < 0 || l.y < 0 || l.z < 0) fail(name, "the vertex element lacks x, y or z");
    } else if (el.name == "face") {
      if (l.face >= 0) fail(name, "two face elements in the PLY header");
      l.face = int(e);
      for (std::size_t p = 0; p < el.properties.size(); ++p)
        if (el.properties[p].name == "vertex_indices" || el.properties[p].name == "vertex_index") {
          if (!el.properties[p].count_type)
            fail(name, "face property " + el.properties[p].name + " is not a list");
          l.corners = int(p);
        }
      if (l.corners < 0) fail(name, "the face element has no vertex_indices list");
    }
  }
  if (l.vertex < 0) fail(name, "the PLY header has no vertex element");
  if (l.face < 0) fail(name, "the PLY header has no face element");
  return l;
}

// Every element's declared count against the bytes of the body: an element
// takes at least its properties' (or list counts') sizes in binary, and two
// characters (a digit and a separator) per property as text.
void check_counts(const Header& h, std::size_t body_bytes, const std::string& name) {
  // Text may end without a separator after its last number.
  const std::size_t available = body_bytes + (h.encoding == Encoding::ascii ? 1 : 0);
  std::uint64_t needed = 0;
  for (const Element& e : h.elements) {
    const std::size_t per = h.encoding == Encoding::ascii ? 2 * e.properties.size() : e.min_bytes();
    if (per == 0) continue;  // holds nothing: never walked
    const std::string what = std::string(e.name) + " elements";
    check_count(name, what.c_str(), e.count, per, available);
    needed += e.count * per;
    if (needed > available)
      fail(name, "the header declares more elements than the " + std::to_string(body_bytes) +
                     " bytes after it can hold (truncated or corrupt)");
  }
}

// Values of a body, one at a time, as text words or binary numbers.
class Values {
 public:
  Values(std::string_view body, Encoding encoding, const std::string& name, std::size_t line)
      : body_(body), words_(body), encoding_(encoding), name_(name), line_(line) {}

  double next(Type t) {
    if (encoding_ == Encoding::ascii) {
      const std::string_view word = words_.next();
      double v = 0;
      if (word.empty()) fail(name_, "the file ends before the data the header declares");
      if (!parse_double(word, v)) fail_at(name_, line_of(word), quoted(word) + " is not a number");
      return v;
    }
    const std::size_t n = size_of(t);
    if (body_.size() - at_ < n) fail(name_, "the binary data ends early (truncated file)");
    unsigned char b[8];
    for (std::size_t k = 0; k < n; ++k)
      b[k] = static_cast<unsigned char>(
          body_[at_ + (encoding_ == Encoding::little_endian ? k : n - 1 - k)]);
    at_ += n;
    auto load = [&](auto zero) {
      decltype(zero) v;
      std::memcpy(&v, b, sizeof v);
      return double(v);
    };
    switch (t) {
      case Type::int8:
        return load(std::int8_t());
      case Type::uint8:
        return load(std::uint8_t());
      case Type::int16:
        return load(std::int16_t());
      case Type::uint16:
        return load(std::uint16_t());
      case Type::int32:
        return load(std::int32_t());
      case Type::uint32:
        return load(std::uint32_t());
      case Type::float32:
        return load(float());
      case Type::float64:
        return load(double());
    }
    return 0;
  }

  // A list's length or an index: a whole number in [0, limit].
  std::uint64_t whole(Type t, std::uint64_t limit, const char* what) {
    const double v = next(t);
    if (!(v >= 0 && v <= double(limit) && v == std::floor(v)))
      fail(name_, std::string(what) + " " + number_text(v) + " out of range");
    return std::uint64_t(v);
  }

  // Bytes (binary) or characters (text) not yet read.
  std::size_t left() {
    if (encoding_ != Encoding::ascii) return body_.size() - at_;
    return words_.rest().size();
  }

  // Skips binary data.
  void skip_bytes(std::uint64_t bytes) {
    if (bytes > body_.size() - at_) fail(name_, "the binary data ends early (truncated file)");
    at_ += std::size_t(bytes);
  }

 private:
  std::size_t line_of(std::string_view word) const {
    const std::size_t offset = std::size_t(word.data() - body_.data());
    std::size_t line = line_;
    for (std::size_t i = 0; i < offset; ++i) line += body_[i] == '\n';
    return line + 1;
  }

  std::string_view body_;
  Words words_;
  Encoding encoding_;
  const std::string& name_;
  std::size_t line_;
  std::size_t at_ = 0;
};

}  // namespace

PolygonSoup parse_ply(std::string_view bytes, const std::string& name) {
  const std::string_view text = strip_byte_order_mark(bytes, name);
  const Header h = read_header(text, name);
  const Layout l = layout_of(h, name);
  const std::string_view body = text.substr(h.body);
  check_counts(h, body.size(), name);

  PolygonSoup soup;
  soup.positions.reserve(std::size_t(h.elements[l.vertex].count));
  soup.faces.reserve(std::size_t(h.elements[l.face].count));
  Values in(body, h.encoding, name, h.lines);
  const bool coloured = l.red >= 0 && l.green >= 0 && l.blue >= 0;
  // Colours as fractions: integer channels over their type's largest value.
  std::array<double, 3> colour_scale{1, 1, 1};
  if (coloured) {
    const auto& props = h.elements[l.vertex].properties;
    const int channel[3] = {l.red, l.green, l.blue};
    for (int c = 0; c < 3; ++c) {
      const Type t = props[std::size_t(channel[c])].type;
      colour_scale[std::size_t(c)] = t == Type::uint8 || t == Type::int8     ? 1.0 / 255
                                     : t == Type::uint16 || t == Type::int16 ? 1.0 / 65535
                                     : t == Type::float32 || t == Type::float64
                                         ? 1.0
                                         : 1.0 / 4294967295.0;
    }
    soup.colors.reserve(std::size_t(h.elements[l.vertex].count));
  }
  for (std::size_t e = 0; e < h.elements.size(); ++e) {
    const Element& el = h.elements[e];
    const bool vertex = int(e) == l.vertex, face = int(e) == l.face;
    const bool fixed_size = std::none_of(el.properties.begin(), el.properties.end(),
                                         [](const Property& p) { return bool(p.count_type); });
    if (el.properties.empty()) continue;
    if (!vertex && !face && fixed_size && h.encoding != Encoding::ascii) {
      in.skip_bytes(el.count * el.min_bytes());  // no overflow: checked against the body above
      continue;
    }
    for (std::uint64_t i = 0; i < el.count; ++i) {
      Vec3 p = Vec3::Zero(), rgb = Vec3::Zero();
      for (std::size_t k = 0; k < el.properties.size(); ++k) {
        const Property& prop = el.properties[k];
        if (prop.count_type) {
          // Each item takes at least a byte (binary) or two characters (text).
          const std::uint64_t n = in.whole(*prop.count_type, in.left(), "list length");
          std::vector<int>* corners = nullptr;
          if (face && int(k) == l.corners) {
            corners = &soup.faces.emplace_back();
            corners->reserve(std::size_t(n));
          }
          for (std::uint64_t j = 0; j < n; ++j) {
            if (corners)
              corners->push_back(int(in.whole(prop.type, INT_MAX, "vertex index")));
            else
              in.next(prop.type);
          }
        } else {
          const double v = in.next(prop.type);
          if (vertex) {
            if (int(k) == l.x) p.x() = v;
            if (int(k) == l.y) p.y() = v;
            if (int(k) == l.z) p.z() = v;
            if (int(k) == l.red) rgb[0] = v * colour_scale[0];
            if (int(k) == l.green) rgb[1] = v * colour_scale[1];
            if (int(k) == l.blue) rgb[2] = v * colour_scale[2];
          }
        }
      }
      if (vertex) {
        soup.positions.push_back(p);
        if (coloured) soup.colors.push_back(rgb);
      }
    }
  }
  return soup;
}

MeshFileSize peek_ply(std::string_view head, std::uint64_t file_bytes, const std::string& name) {
  const Header h = read_header(strip_byte_order_mark(head, name), name);
  const Layout l = layout_of(h, name);
  // Three coordinates take at least three bytes; a face at least one.
  const std::uint64_t nv = h.elements[l.vertex].count, nf = h.elements[l.face].count;
  return {file_bytes, std::min(nv, file_bytes / 3), std::min(nf, file_bytes),
          nv > file_bytes / 3 || nf > file_bytes};
}

}  // namespace ism::io::detail
