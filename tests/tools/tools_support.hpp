#pragma once
// Running the built command-line tools from tests.
#include "mesh/triangle_mesh.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace ism::test {

struct ToolResult {
  int status;
  std::string out, err;
};

inline std::filesystem::path scratch_dir(const std::string& name) {
  std::filesystem::path dir = binary_dir() / "test-scratch" / name;
  std::filesystem::create_directories(dir);
  return dir;
}

/// A path in single quotes, for a tool's command line.
inline std::string quoted(const std::filesystem::path& p) {
  std::string q = "'";  // appended piecewise: GCC 12 warns (-Wrestrict) on "'" + ...
  q += p.string();
  q += "'";
  return q;
}

/// Writes `text` to dir/name and returns the path.
inline std::filesystem::path write_text(const std::filesystem::path& dir, const std::string& name,
                                        const std::string& text) {
  const std::filesystem::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}

inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Runs build/bin/TOOL ARGS; stdout and stderr go to files named after the
/// current test, since ctest runs tests in parallel ('/' of parameterised
/// test names replaced).
inline ToolResult run_tool(const std::string& tool, const std::string& args) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test = std::string(info->test_suite_name()) + "." + info->name();
  std::replace(test.begin(), test.end(), '/', '_');
  const auto dir = scratch_dir("tools");
  const auto out = dir / (test + ".stdout"), err = dir / (test + ".stderr");
  const std::string cmd = (binary_dir() / "bin" / tool).string() + " " + args + " >" +
                          out.string() + " 2>" + err.string();
  const int raw = std::system(cmd.c_str());
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, slurp(out), slurp(err)};
}

/// The number after "key": in a report: the first occurrence after the
/// section "section": if one is named (e.g. "map", not a variant's figure in
/// "map_variants"). A test failure and NaN when either is missing.
inline double report_number(const std::string& json, const std::string& key,
                            const std::string& section = "") {
  std::size_t from = 0;
  if (!section.empty()) {
    from = json.find("\"" + section + "\": ");
    if (from == std::string::npos) {
      ADD_FAILURE() << "no section " << section << " in the report";
      return NAN;
    }
  }
  const std::string quoted = "\"" + key + "\": ";
  const std::size_t at = json.find(quoted, from);
  if (at == std::string::npos) {
    ADD_FAILURE() << key << " not in the report";
    return NAN;
  }
  return std::strtod(json.c_str() + at + quoted.size(), nullptr);
}

// Distance from p to triangle abc (closest point by Voronoi regions of the
// triangle, Ericson, Real-Time Collision Detection, 5.1.5).
inline double point_triangle_distance(const ism::Vec3& p, const ism::Vec3& a, const ism::Vec3& b,
                                      const ism::Vec3& c) {
  const ism::Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const ism::Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const ism::Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1 / (va + vb + vc);
  return (p - (a + ab * vb * denom + ac * vc * denom)).norm();
}

inline double distance_to_faces(const ism::Vec3& p, const ism::TriangleMesh& mesh,
                                std::size_t first, std::size_t last) {
  double d = INFINITY;
  for (std::size_t f = first; f < last; ++f) {
    const auto& t = mesh.triangles[f];
    d = std::min(d, point_triangle_distance(p, mesh.positions[t[0]], mesh.positions[t[1]],
                                            mesh.positions[t[2]]));
  }
  return d;
}

}  // namespace ism::test
