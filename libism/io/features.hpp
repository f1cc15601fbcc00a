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
#include <string_view>
#include <utility>
#include <vector>

namespace ism::io {

struct FeatureEntry {
  std::optional<long> vertex;
  std::optional<Vec3> point;
  std::optional<std::pair<int, int>> grid;  // (row, col)
};

/// Parses a feature file; throws FileError naming the file and line (a word
/// that is not a finite number, an index that is not a whole number an int
/// holds, a line of another length).
std::vector<FeatureEntry> read_feature_file(const std::filesystem::path& path);
/// The same on text in memory; `name` prefixes the messages.
std::vector<FeatureEntry> parse_feature_text(std::string_view text, const std::string& name);

/// Surface vertices of the entries, in grid order (row * columns + col) when
/// every entry has a grid position, else in file order. Throws FileError for
/// more entries than surface vertices, an index out of range or a grid
/// position outside rows × columns (or given twice).
std::vector<int> resolve_features(const std::vector<FeatureEntry>& entries,
                                  const TriangleMesh& surface, int columns,
                                  const std::string& file_name);

}  // namespace ism::io
