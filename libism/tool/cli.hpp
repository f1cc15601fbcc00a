#pragma once
// The command-line side of the tool conventions. CLI11 is costly to compile:
// include this header only in a tool's main.cpp.
#include "tool/tool.hpp"

#include <CLI/CLI.hpp>

namespace ism::tool {

/// --version, -q/--quiet and --report FILE, the same in every tool.
inline void add_common_options(CLI::App& app, CommonOptions& options) {
  app.set_version_flag("--version", std::string(ISM_VERSION));
  app.add_flag("-q,--quiet", options.quiet, "No progress or notes on stderr");
  app.add_option("--report", options.report_path, "Write a JSON report (sizes, timings, measures)");
}

}  // namespace ism::tool
