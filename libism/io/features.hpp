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
/// more entries than surface vertices, an index out of range or a grid
/// position outside rows × columns (or given twice).
std::vector<int> resolve_features(const std::vector<FeatureEntry>& entries,
                                  const TriangleMesh& surface, int columns,
                                  const std::string& file_name);

}  // namespace ism::io

namespace ism::io {

/// Corresponding vertices of two surfaces A and B: pairs[k] = {vertex of A,
/// vertex of B}, each 0-based, each in range, no vertex in two pairs.
struct FeaturePairs {
  std::vector<std::array<int, 2>> pairs;
  /// Source line of each pair (of the pairs file, or of A's landmark list).
  std::vector<int> lines;
  /// Landmarks of `ID X Y Z` lists whose ID is in one list only (skipped).
  std::size_t unmatched = 0;
  /// Pairs whose vertices were given as indices (not as points).
  std::size_t by_index = 0;
};

/// Reads a pairs file (`names`: the surfaces in messages): one pair per line, `IA IB` (0-based
/// vertex indices of A and B) or `XA YA ZA XB YB ZB` (points, each snapped to the nearest vertex of
/// its surface); '#' starts a comment. Throws FileError naming the file and line for a malformed
/// line, a non-finite number, an index out of range, a vertex paired twice, or a line longer than
/// 4096 characters. An empty file gives no pairs (callers that need pairs say so).
FeaturePairs read_feature_pairs(const std::filesystem::path& path, const TriangleMesh& a,
                                const TriangleMesh& b,
                                const std::array<std::string, 2>& names = {"A", "B"});

/// Reads two landmark lists, one per surface, and pairs them: lines are
/// `INDEX` (0-based vertex) or `X Y Z` (a point snapped to the nearest
/// vertex), paired by line order, the lists of equal length; or `ID X Y Z`
/// (SHREC/.vts style: a landmark id and its point), paired by id, ids present
/// in one list only counted in `unmatched`. Same errors as read_feature_pairs,
/// plus lists of different lengths or kinds, and an id given twice.
FeaturePairs read_landmark_pairs(const std::filesystem::path& path_a, const TriangleMesh& a,
                                 const std::filesystem::path& path_b, const TriangleMesh& b,
                                 const std::array<std::string, 2>& names = {"A", "B"});

}  // namespace ism::io
