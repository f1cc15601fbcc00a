#pragma once
// Feature files: one feature per line, '#' starts a comment. A line is
//   INDEX               a 0-based surface vertex index, or
//   X Y Z               a point, snapped to the nearest surface vertex, or
//   ROW COL INDEX X Y Z a vertex at a grid position (as ../shared's
//                       *_features_3x3.txt); the position orders the features.
#include "mesh/triangle_mesh.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace ism::io {

struct FeatureEntry {
  std::optional<long> vertex;
  std::optional<Vec3> point;
  std::optional<std::pair<int, int>> grid;  // (row, col)
};

/// Parses a feature file; throws FileError naming the file and line.
std::vector<FeatureEntry> read_feature_file(const std::filesystem::path& path);

/// Features a pipeline takes: the feature file `path`, or, when `entries` is
/// given, those entries (then `path` only names them in messages).
struct FeatureSource {
  std::string path;
  std::optional<std::vector<FeatureEntry>> entries;
  bool empty() const { return path.empty() && !entries; }
  /// The entries given, or read_feature_file(path).
  std::vector<FeatureEntry> read() const { return entries ? *entries : read_feature_file(path); }
};

/// Surface vertices of the entries, in grid order (row * columns + col) when
/// every entry has a grid position, else in file order. Throws FileError for
/// an index out of range or a grid position outside rows × columns.
std::vector<int> resolve_features(const std::vector<FeatureEntry>& entries,
                                  const TriangleMesh& surface, int columns,
                                  const std::string& file_name);

}  // namespace ism::io
