#include "io/features.hpp"

#include "io/io.hpp"
#include "io/mesh_parse.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <unordered_map>

namespace ism::io {

std::vector<FeatureEntry> parse_feature_text(std::string_view text, const std::string& name) {
  text = detail::strip_byte_order_mark(text, name);
  std::vector<FeatureEntry> entries;
  detail::Lines lines(text);
  std::string_view line;
  while (lines.next(line)) {
    const std::size_t number = lines.number();
    if (auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    detail::Words words(line);
    double values[6];
    std::size_t n = 0;
    while (!words.done()) {
      const std::string_view word = words.next();
      if (n == 6) detail::fail_at(name, number, "expected INDEX, X Y Z or ROW COL INDEX X Y Z");
      if (!detail::parse_double(word, values[n]))
        detail::fail_at(name, number, detail::quoted(word) + " is not a number");
      if (!std::isfinite(values[n]))
        detail::fail_at(name, number, detail::quoted(word) + " is not a finite number");
      ++n;
    }
    // Indices and grid positions: whole numbers an int holds.
    auto integral = [&](double v) {
      if (v != std::floor(v) || std::abs(v) > INT_MAX)
        detail::fail_at(name, number, detail::number_text(v) + " is not a vertex index");
      return long(v);
    };
    FeatureEntry entry;
    if (n == 0) continue;
    if (n == 1) {
      entry.vertex = integral(values[0]);
    } else if (n == 3) {
      entry.point = Vec3(values[0], values[1], values[2]);
    } else if (n == 6) {
      entry.grid = std::pair<int, int>(int(integral(values[0])), int(integral(values[1])));
      entry.vertex = integral(values[2]);
    } else {
      detail::fail_at(name, number, "expected INDEX, X Y Z or ROW COL INDEX X Y Z");
    }
    entries.push_back(entry);
  }
  return entries;
}

std::vector<FeatureEntry> read_feature_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw FileError(path.string() + ": cannot open the feature file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FileError(path.string() + ": cannot open the feature file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_feature_text(text.str(), path.string());
}

std::vector<int> resolve_features(const std::vector<FeatureEntry>& entries,
                                  const TriangleMesh& surface, int columns,
                                  const std::string& file_name) {
  // Each feature is its own vertex: more than the surface has cannot be
  // resolved (and would cost entries x vertices to snap).
  if (entries.size() > surface.n_vertices())
    throw FileError(file_name + ": " + std::to_string(entries.size()) +
                    " features, more than the surface's " + std::to_string(surface.n_vertices()) +
                    " vertices");
  std::vector<int> features(entries.size(), -1);
  const bool gridded =
      columns > 0 && !entries.empty() &&
      std::all_of(entries.begin(), entries.end(), [](auto& e) { return bool(e.grid); });
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const FeatureEntry& e = entries[k];
    int vertex = -1;
    if (e.vertex) {
      if (*e.vertex < 0 || std::size_t(*e.vertex) >= surface.n_vertices())
        throw FileError(file_name + ": feature " + std::to_string(k) + ": vertex index " +
                        std::to_string(*e.vertex) + " out of range (the surface has " +
                        std::to_string(surface.n_vertices()) + " vertices)");
      vertex = int(*e.vertex);
    } else {
      // The first vertex even when every distance overflows to infinity.
      double best = HUGE_VAL;
      for (std::size_t v = 0; v < surface.n_vertices(); ++v) {
        const double d = (surface.positions[v] - *e.point).squaredNorm();
        if (vertex < 0 || d < best) best = d, vertex = int(v);
      }
    }
    std::size_t slot = k;
    if (gridded) {
      const auto [row, col] = *e.grid;
      const long rows = long(entries.size()) / columns;
      if (row < 0 || row >= rows || col < 0 || col >= columns)
        throw FileError(file_name + ": grid position (" + std::to_string(row) + ", " +
                        std::to_string(col) + ") outside the " + std::to_string(rows) + "x" +
                        std::to_string(columns) + " grid");
      slot = std::size_t(row) * std::size_t(columns) + std::size_t(col);
      if (features[slot] >= 0)
        throw FileError(file_name + ": grid position (" + std::to_string(row) + ", " +
                        std::to_string(col) + ") given twice");
    }
    features[slot] = vertex;
  }
  return features;
}

}  // namespace ism::io

// ---- Feature pairs and landmark lists ------------------------------------
//
// Hostile input: lines are read with a length cap, numbers must be finite,
// indices are checked against the surface before use, and nothing is sized
// from the file's own figures (the pair count is bounded by the surfaces:
// a vertex may be paired once only).

namespace ism::io {
namespace {

constexpr std::size_t kMaxLine = 4096;

class LineReader {
 public:
  explicit LineReader(const std::filesystem::path& path) : path_(path), in_(path) {
    if (!in_) throw FileError(path.string() + ": cannot open the file");
  }
  /// The next line without its comment, split into numbers; false at the end.
  bool next(std::vector<double>& values) {
    std::string line;
    char c;
    bool any = false;
    while (in_.get(c)) {
      any = true;
      if (c == '\n') break;
      if (line.size() >= kMaxLine)
        throw FileError(path_.string() + ":" + std::to_string(number_ + 1) + ": line longer than " +
                        std::to_string(kMaxLine) + " characters");
      line.push_back(c);
    }
    if (!any) {
      if (in_.bad()) throw FileError(path_.string() + ": read error");
      return false;
    }
    ++number_;
    if (auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    values.clear();
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0' || !std::isfinite(v))
        throw FileError(where() + ": '" + word + "' is not a finite number");
      values.push_back(v);
    }
    return true;
  }
  std::string where() const { return path_.string() + ":" + std::to_string(number_); }
  int line() const { return number_; }

 private:
  std::filesystem::path path_;
  std::ifstream in_;
  int number_ = 0;
};

// A number as the file wrote it, near enough: integers in full, others %g.
std::string number_text(double v) {
  char text[64];
  if (std::abs(v) < 1e15 && v == std::floor(v))
    std::snprintf(text, sizeof text, "%.0f", v);
  else
    std::snprintf(text, sizeof text, "%g", v);
  return text;
}

int vertex_index(const LineReader& reader, double v, const TriangleMesh& mesh,
                 const std::string& side) {
  if (v != std::floor(v))
    throw FileError(reader.where() + ": " + number_text(v) + " is not a vertex index");
  if (v < 0 || v >= double(mesh.n_vertices()))
    throw FileError(reader.where() + ": vertex index " + number_text(v) + " of " + side +
                    " out of range (" + side + " has " + std::to_string(mesh.n_vertices()) +
                    " vertices)");
  return int(v);
}

// Nearest vertex to a point through a uniform grid of buckets, built on the
// first query, so that a file of many points costs no more than the mesh
// size times a small factor (not points x vertices).
class NearestVertex {
 public:
  explicit NearestVertex(const TriangleMesh& mesh) : mesh_(mesh) {}

  int operator()(const Vec3& p) {
    if (cells_.empty()) build();
    Eigen::Vector3i c = cell_of(p);
    int best = -1;
    double best_d = HUGE_VAL;
    const int most = n_.maxCoeff();
    for (int r = 0; r <= most; ++r) {
      if (best >= 0 && std::pow(std::max(0, r - 1) * h_, 2) > best_d) break;
      // The shell of cells at Chebyshev distance r.
      for (int x = c.x() - r; x <= c.x() + r; ++x)
        for (int y = c.y() - r; y <= c.y() + r; ++y)
          for (int z = c.z() - r; z <= c.z() + r; ++z) {
            if (std::max({std::abs(x - c.x()), std::abs(y - c.y()), std::abs(z - c.z())}) != r)
              continue;
            if (x < 0 || y < 0 || z < 0 || x >= n_.x() || y >= n_.y() || z >= n_.z()) continue;
            for (int v : cells_[std::size_t((x * n_.y() + y) * n_.z() + z)]) {
              const double d = (mesh_.positions[v] - p).squaredNorm();
              if (d < best_d) best_d = d, best = v;
            }
          }
    }
    return best;
  }

 private:
  void build() {
    lo_ = Vec3::Constant(HUGE_VAL);
    Vec3 hi = Vec3::Constant(-HUGE_VAL);
    for (const Vec3& q : mesh_.positions)
      if (q.allFinite()) lo_ = lo_.cwiseMin(q), hi = hi.cwiseMax(q);
    if (!(lo_.x() <= hi.x())) lo_ = hi = Vec3::Zero();
    const double side = (hi - lo_).maxCoeff();
    const int per_axis = std::clamp(int(std::cbrt(double(mesh_.n_vertices()))), 1, 128);
    h_ = side > 0 ? side / per_axis : 1.0;
    for (int a = 0; a < 3; ++a) n_[a] = std::clamp(int((hi[a] - lo_[a]) / h_) + 1, 1, per_axis + 1);
    cells_.assign(std::size_t(n_.x()) * n_.y() * n_.z(), {});
    for (std::size_t v = 0; v < mesh_.n_vertices(); ++v)
      if (mesh_.positions[v].allFinite()) {
        const Eigen::Vector3i c = cell_of(mesh_.positions[v]);
        cells_[std::size_t((c.x() * n_.y() + c.y()) * n_.z() + c.z())].push_back(int(v));
      }
  }
  Eigen::Vector3i cell_of(const Vec3& p) const {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a)
      c[a] = int(std::clamp(std::floor((p[a] - lo_[a]) / h_), 0.0, double(n_[a] - 1)));
    return c;
  }

  const TriangleMesh& mesh_;
  Vec3 lo_ = Vec3::Zero();
  double h_ = 1;
  Eigen::Vector3i n_ = Eigen::Vector3i::Ones();
  std::vector<std::vector<int>> cells_;
};

// Collects pairs and refuses a vertex paired twice, naming both lines.
class PairSet {
 public:
  explicit PairSet(const std::array<std::string, 2>& names) : names_(names) {}
  void add(const std::string& where, int line, int a, int b) {
    for (int side = 0; side < 2; ++side) {
      const int v = side ? b : a;
      auto [it, fresh] = line_of_[side].emplace(v, line);
      if (!fresh)
        throw FileError(where + ": vertex " + std::to_string(v) + " of " + names_[side] +
                        " is already paired on line " + std::to_string(it->second));
    }
    result.pairs.push_back({a, b});
    result.lines.push_back(line);
  }
  FeaturePairs result;

 private:
  std::array<std::string, 2> names_;
  std::array<std::unordered_map<int, int>, 2> line_of_;
};

}  // namespace

FeaturePairs read_feature_pairs(const std::filesystem::path& path, const TriangleMesh& a,
                                const TriangleMesh& b, const std::array<std::string, 2>& names) {
  LineReader reader(path);
  PairSet set(names);
  NearestVertex nearest_a(a), nearest_b(b);
  std::vector<double> v;
  while (reader.next(v)) {
    if (v.empty()) continue;
    int ia, ib;
    if (v.size() == 2) {
      ia = vertex_index(reader, v[0], a, names[0]);
      ib = vertex_index(reader, v[1], b, names[1]);
      ++set.result.by_index;
    } else if (v.size() == 6) {
      if (a.n_vertices() == 0 || b.n_vertices() == 0)
        throw FileError(reader.where() + ": a surface has no vertices");
      ia = nearest_a(Vec3(v[0], v[1], v[2]));
      ib = nearest_b(Vec3(v[3], v[4], v[5]));
    } else {
      throw FileError(reader.where() + ": expected 'IA IB' or 'XA YA ZA XB YB ZB', found " +
                      std::to_string(v.size()) + " numbers");
    }
    set.add(reader.where(), reader.line(), ia, ib);
  }
  return std::move(set.result);
}

namespace {

struct Landmark {
  int vertex;
  int line;
  std::optional<long> id;
  bool by_index = false;
};

// One landmark list; all its lines of one kind (index, point, or id + point).
std::vector<Landmark> read_landmarks(const std::filesystem::path& path, const TriangleMesh& mesh,
                                     const std::string& side) {
  NearestVertex nearest(mesh);
  LineReader reader(path);
  std::vector<Landmark> out;
  std::size_t kind = 0;
  std::map<long, int> id_line;
  std::vector<double> v;
  while (reader.next(v)) {
    if (v.empty()) continue;
    if (v.size() != 1 && v.size() != 3 && v.size() != 4)
      throw FileError(reader.where() + ": expected 'INDEX', 'X Y Z' or 'ID X Y Z', found " +
                      std::to_string(v.size()) + " numbers");
    if (kind && v.size() != kind)
      throw FileError(reader.where() + ": " + std::to_string(v.size()) +
                      " numbers where the lines before have " + std::to_string(kind));
    kind = v.size();
    if (out.size() >= mesh.n_vertices())
      throw FileError(reader.where() + ": more landmarks than " + side + " has vertices");
    Landmark l{-1, reader.line(), std::nullopt};
    if (kind == 1) {
      l.vertex = vertex_index(reader, v[0], mesh, side);
      l.by_index = true;
    } else {
      if (mesh.n_vertices() == 0) throw FileError(reader.where() + ": the surface has no vertices");
      const std::size_t first = kind == 4 ? 1 : 0;
      l.vertex = nearest(Vec3(v[first], v[first + 1], v[first + 2]));
      if (kind == 4) {
        if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 1e15)
          throw FileError(reader.where() + ": landmark id " + number_text(v[0]) +
                          " is not an integer");
        l.id = long(v[0]);
        auto [it, fresh] = id_line.emplace(*l.id, reader.line());
        if (!fresh)
          throw FileError(reader.where() + ": landmark id " + std::to_string(*l.id) +
                          " already given on line " + std::to_string(it->second));
      }
    }
    out.push_back(l);
  }
  return out;
}

}  // namespace

FeaturePairs read_landmark_pairs(const std::filesystem::path& path_a, const TriangleMesh& a,
                                 const std::filesystem::path& path_b, const TriangleMesh& b,
                                 const std::array<std::string, 2>& names) {
  const std::vector<Landmark> la = read_landmarks(path_a, a, names[0]);
  const std::vector<Landmark> lb = read_landmarks(path_b, b, names[1]);
  const bool by_id_a = !la.empty() && la.front().id, by_id_b = !lb.empty() && lb.front().id;
  if (!la.empty() && !lb.empty() && by_id_a != by_id_b)
    throw FileError(path_a.string() + ", " + path_b.string() +
                    ": one list pairs by id (ID X Y Z), the other by line order");
  PairSet set(names);
  if (by_id_a && by_id_b) {
    std::map<long, const Landmark*> of_b;
    for (const Landmark& l : lb) of_b[*l.id] = &l;
    std::size_t matched = 0;
    for (const Landmark& l : la) {
      auto it = of_b.find(*l.id);
      if (it == of_b.end()) continue;
      ++matched;
      set.add(
          path_a.string() + ":" + std::to_string(l.line) + " (id " + std::to_string(*l.id) + ")",
          l.line, l.vertex, it->second->vertex);
    }
    set.result.unmatched = la.size() + lb.size() - 2 * matched;
    return std::move(set.result);
  }
  if (la.size() != lb.size())
    throw FileError(path_a.string() + " has " + std::to_string(la.size()) + " landmarks, " +
                    path_b.string() + " has " + std::to_string(lb.size()) +
                    "; lists paired by line order need the same length");
  for (std::size_t k = 0; k < la.size(); ++k)
    set.add(path_a.string() + ":" + std::to_string(la[k].line) + " and " + path_b.string() + ":" +
                std::to_string(lb[k].line),
            la[k].line, la[k].vertex, lb[k].vertex);
  for (std::size_t k = 0; k < la.size(); ++k)
    set.result.by_index += la[k].by_index || lb[k].by_index;
  return std::move(set.result);
}

}  // namespace ism::io
