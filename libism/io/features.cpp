#include "io/features.hpp"

#include "io/io.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ism::io {

std::vector<FeatureEntry> read_feature_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw FileError(path.string() + ": cannot open the feature file");
  std::vector<FeatureEntry> entries;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<double> values;
    std::string word;
    while (words >> word) {
      char* end = nullptr;
      const double v = std::strtod(word.c_str(), &end);
      if (end == word.c_str() || *end != '\0')
        throw FileError(path.string() + ":" + std::to_string(number) + ": '" + word +
                        "' is not a number");
      values.push_back(v);
    }
    auto integral = [&](double v) {
      if (v != std::floor(v))
        throw FileError(path.string() + ":" + std::to_string(number) + ": " + std::to_string(v) +
                        " is not a vertex index");
      return long(v);
    };
    FeatureEntry entry;
    if (values.empty()) continue;
    if (values.size() == 1) {
      entry.vertex = integral(values[0]);
    } else if (values.size() == 3) {
      entry.point = Vec3(values[0], values[1], values[2]);
    } else if (values.size() == 6) {
      entry.grid = std::pair<int, int>(int(integral(values[0])), int(integral(values[1])));
      entry.vertex = integral(values[2]);
    } else {
      throw FileError(path.string() + ":" + std::to_string(number) +
                      ": expected INDEX, X Y Z or ROW COL INDEX X Y Z");
    }
    entries.push_back(entry);
  }
  return entries;
}

std::vector<int> resolve_features(const std::vector<FeatureEntry>& entries,
                                  const TriangleMesh& surface, int columns,
                                  const std::string& file_name) {
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
      double best = HUGE_VAL;
      for (std::size_t v = 0; v < surface.n_vertices(); ++v) {
        const double d = (surface.positions[v] - *e.point).squaredNorm();
        if (d < best) best = d, vertex = int(v);
      }
    }
    std::size_t slot = k;
    if (gridded) {
      const auto [row, col] = *e.grid;
      const int rows = int(entries.size()) / columns;
      if (row < 0 || row >= rows || col < 0 || col >= columns)
        throw FileError(file_name + ": grid position (" + std::to_string(row) + ", " +
                        std::to_string(col) + ") outside the " + std::to_string(rows) + "x" +
                        std::to_string(columns) + " grid");
      slot = std::size_t(row * columns + col);
      if (features[slot] >= 0)
        throw FileError(file_name + ": grid position (" + std::to_string(row) + ", " +
                        std::to_string(col) + ") given twice");
    }
    features[slot] = vertex;
  }
  return features;
}

}  // namespace ism::io
