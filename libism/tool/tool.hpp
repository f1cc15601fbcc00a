#pragma once
// Conventions shared by every command-line front end: one-line failures,
// progress on stderr, stage timings and peak memory in a JSON report, outputs
// that appear only when complete and never over an input.
#include "mesh/mesh_check.hpp"
#include "report/json.hpp"
#include "tool/failure.hpp"
#include "tool/output_file.hpp"
#include "tool/progress.hpp"

#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace ism::tool {

/// A mesh a pipeline reads: the file `path`, or, when `soup` is given, that
/// polygon soup as a file would hold it (then `path` only names it in
/// messages and the report, and is neither read nor protected from writes).
struct InputMesh {
  std::string path;
  std::optional<PolygonSoup> soup;
  bool empty() const { return path.empty() && !soup; }
};

/// A reading error as a Failure with the reader's message: Kind::file when
/// `path` is not a readable file, Kind::input when its content is at fault.
Failure reading_failure(const std::filesystem::path& path, const std::exception& error);

/// Options every tool takes (see tool/cli.hpp for the command-line side).
struct CommonOptions {
  bool quiet = false;
  std::string report_path;     // empty: no report
  std::size_t max_memory = 0;  // bytes; 0: default_memory_limit() (tool/limits.hpp)
  /// The command-line tools also cap the process's address space at the
  /// limit (plus slack), so that an allocation beyond it fails cleanly; a
  /// process that embeds the library (the Python module) is left alone.
  bool cap_address_space = true;
};

/// Peak resident memory of this process so far, in bytes.
std::size_t peak_memory_bytes();

/// One invocation of a tool: its inputs, stages, messages and report.
class Run {
 public:
  Run(std::string tool_name, CommonOptions options);

  const std::string& tool_name() const { return tool_; }
  bool quiet() const { return options_.quiet; }
  /// Memory this run may take (--max-memory or the default); the process's
  /// address space is capped a little above it (tool/limits.hpp).
  std::size_t memory_limit() const { return memory_limit_; }
  Json& report() { return report_; }

  /// Reads and checks a surface; throws Failure naming the file and the
  /// first unmet requirement, or, before reading, the memory its declared
  /// size would need beyond the limit. Repairs are announced on stderr and the
  /// check goes into the report under "input" (and into *check when given).
  TriangleMesh load_surface(const std::filesystem::path& path, const MeshRequirements& needs,
                            MeshCheck* check = nullptr);
  /// The same for a file or a soup given in memory (InputMesh).
  TriangleMesh load_surface(const InputMesh& input, const MeshRequirements& needs,
                            MeshCheck* check = nullptr);
  /// The same, keeping the soup as read (its texture coordinates and
  /// colours) and where each triangle and vertex came from in it.
  PreparedMesh load_prepared(const InputMesh& input, const MeshRequirements& needs,
                             PolygonSoup* soup = nullptr);
  /// Files that outputs must never overwrite.
  void add_input(const std::filesystem::path& path);
  /// Throws Failure now if `path` could not be written later (an input, a
  /// missing folder), so that no work is wasted.
  void check_output(const std::filesystem::path& path) const;
  const std::vector<std::filesystem::path>& inputs() const { return inputs_; }

  /// Starts a named stage (ends the previous one). The report gives its
  /// wall time ("seconds") and the process's peak resident memory when it
  /// ended ("peak_memory_mb_by_stage": the peak so far, so it never falls;
  /// the stage at which it rises is the one that raised it).
  Progress& stage(const std::string& name);
  /// A note on stderr unless quiet.
  void note(const std::string& message) const;

  /// Ends the last stage and writes the report (if asked for).
  void finish();

 private:
  void end_stage();

  std::string tool_;
  CommonOptions options_;
  std::size_t memory_limit_ = 0;
  Json report_ = Json::object();
  std::vector<std::filesystem::path> inputs_;
  std::chrono::steady_clock::time_point start_;
  std::string stage_name_;
  std::chrono::steady_clock::time_point stage_start_;
  Json stages_ = Json::object();
  Json stage_peaks_ = Json::object();  // MB at each stage's end
  Progress progress_;
};

/// Writes one output through a temporary file in the target's folder and
/// renames it when complete; nothing when `path` is empty. A writer's
/// io::FileError becomes a one-line Failure naming the file.
void write_output(const Run& run, const std::string& path,
                  const std::function<void(const std::filesystem::path&)>& write);

/// Runs a tool's body: a Failure prints its message as one line and exits 1,
/// running out of memory prints "tool: out of memory ..." with the peak and
/// the limit, any other exception prints "tool: message"; all exit 1.
int run_main(const std::string& tool_name, const std::function<int()>& body);

}  // namespace ism::tool
