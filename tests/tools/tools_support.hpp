#pragma once
// Running the built command-line tools from tests.
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

}  // namespace ism::test
