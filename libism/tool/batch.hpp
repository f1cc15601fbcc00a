#pragma once
// One tool over many meshes, one process per mesh (ism-batch). Shards split
// a list between processes or cluster jobs; all of them append to one
// results file under a lock, one JSON line per mesh. A mesh's outputs are
// written in a hidden temporary folder and appear, renamed, only when the
// tool succeeded; a failed or timed-out mesh leaves only its line.
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace ism::tool {

/// Shard `index` of `count` (0 <= index < count) takes the list's entries
/// k with k % count == index.
struct Shard {
  int index = 0, count = 1;
  bool takes(std::size_t entry) const { return int(entry % std::size_t(count)) == index; }
  std::string str() const { return std::to_string(index) + "/" + std::to_string(count); }
};

/// Parses "i/n"; throws Failure with the reason when it is not 0 <= i < n.
Shard parse_shard(const std::string& text);

/// One mesh of a list: its path (made absolute) and its name, which names its
/// output folder and its results line.
struct BatchEntry {
  std::filesystem::path path;
  std::string name;
};

/// Reads a list: one mesh per line, "PATH" or "PATH<TAB>NAME"; blank lines
/// and lines starting with '#' are skipped; relative paths are relative to
/// the current folder. The name defaults to the file name without its
/// extension. Throws Failure ("LIST:LINE: ...") for a missing list, an empty
/// one, a name that is not a plain file name, or a name given twice (with
/// the other line).
std::vector<BatchEntry> read_batch_list(const std::filesystem::path& list);

/// The batch's results file, DIR/results.jsonl, shared by concurrent
/// processes through the lock file DIR/.results.lock (fcntl record lock, so
/// also between hosts on a file system that supports it, e.g. NFS v4).
class ResultsFile {
 public:
  /// Creates DIR if needed. Throws Failure when it cannot.
  explicit ResultsFile(std::filesystem::path dir);
  const std::filesystem::path& path() const { return path_; }

  /// The names that have a line (read under the lock).
  std::set<std::string> names() const;
  /// Adds `line` (one JSON object, no newline) as the line of `name`. When
  /// `replace` is set, any earlier line of `name` is removed (the file is
  /// rewritten under the lock and renamed into place); otherwise the line is
  /// appended with one write.
  void put(const std::string& name, const std::string& line, bool replace) const;

 private:
  std::filesystem::path dir_, path_, lock_;
};

struct BatchOptions {
  std::string tool;                  // ism-info, gim-remesh, semireg, torus-remesh
  std::filesystem::path executable;  // the tool's program
  std::filesystem::path inputs;      // the list
  std::filesystem::path out;         // DIR
  Shard shard;
  bool skip_existing = false;  // skip meshes that already have a line
  double timeout_seconds = 0;  // per mesh; <= 0: none
  /// Passed to the tool after the mesh; "{name}" becomes the mesh's name and
  /// "{dir}" the folder of its input. Relative output paths land in the
  /// mesh's output folder (the tool runs there).
  std::vector<std::string> tool_args;
};

struct BatchSummary {
  int meshes = 0, ok = 0, failed = 0, timed_out = 0, skipped = 0;
  int interrupted_by = 0;  // a signal that stopped the batch (its mesh has no line)
};

/// The tools ism-batch knows, with the extension of the main output it
/// names after the mesh when the tool options give no -o/--output.
struct BatchTool {
  std::string name;
  std::string output_extension;  // empty: the tool writes no main output
};
const std::vector<BatchTool>& batch_tools();
/// Throws Failure naming the known tools when `name` is not one of them.
const BatchTool& batch_tool(const std::string& name);

/// Runs the shard's meshes one after the other. For each: the tool runs in
/// DIR/.NAME.partial-PID with "--report report.json" (and "-o NAME.EXT"),
/// stdout and stderr go to stdout.txt and stderr.txt there; on success the
/// folder is renamed to DIR/NAME (replacing an earlier one), otherwise it is
/// removed with any earlier DIR/NAME. Then the mesh's line is put in the results file:
///   {"name", "input", "tool", "status": "ok" | "failed" | "timeout",
///    "error": the tool's last stderr line or what ended it (null when ok),
///    "exit_code", "seconds" (wall), "outputs": "NAME" or null, "figures": the
///    report's measures (tool_figures()), "peak_memory_mb", "shard"}.
/// `progress` gets one message per mesh. Throws Failure for errors of the
/// batch itself (list, DIR, tool missing); a mesh's failure is only its line.
BatchSummary run_batch(const BatchOptions& options,
                       const std::function<void(const std::string&)>& progress);

/// The figures of a tool's report (JSON text) kept in a results line: the
/// input's vertices, faces, genus and boundary loops, and every number or
/// boolean of the report's sections map, image, grid, remesh, distance,
/// meta_mesh and base (time and memory excluded: the figures of one mesh do
/// not depend on the machine). Returns "{}" when the text is not a report.
std::string tool_figures(const std::string& report_json);

}  // namespace ism::tool
