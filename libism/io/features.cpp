#include "io/features.hpp"

#include "io/io.hpp"
#include "io/mesh_parse.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <fstream>
#include <sstream>

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
