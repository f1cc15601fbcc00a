// ism-batch TOOL --inputs LIST --out DIR [--shard i/n] [--skip-existing]
// [--timeout S] -- TOOL-OPTIONS: one tool over many meshes, one process per
// mesh, one JSON line per mesh in DIR/results.jsonl. Shards run as separate
// processes (GNU parallel, a Slurm job array) and share the results file.
#include "tool/batch.hpp"
#include "tool/child_process.hpp"
#include "tool/cli.hpp"
#include "tool/failure.hpp"

#include <unistd.h>

#include <cstdlib>
#include <sstream>

namespace {

namespace fs = std::filesystem;

// The tool's program: beside ism-batch first (a build or install folder),
// then on PATH.
fs::path find_tool(const std::string& name) {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec && ::access((self.parent_path() / name).c_str(), X_OK) == 0)
    return self.parent_path() / name;
  if (const char* path = std::getenv("PATH")) {
    std::stringstream folders(path);
    std::string folder;
    while (std::getline(folders, folder, ':'))
      if (!folder.empty() && ::access((fs::path(folder) / name).c_str(), X_OK) == 0)
        return fs::path(folder) / name;
  }
  throw ism::tool::Failure("ism-batch: " + name + " not found beside ism-batch or on PATH");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "ism-batch TOOL --inputs LIST --out DIR [--shard i/n] [--skip-existing] [--timeout S] -- "
      "TOOL-OPTIONS\nRuns one ism tool over a list of meshes, one process per mesh: each mesh's "
      "outputs in DIR/NAME/, one JSON line per mesh in DIR/results.jsonl (README \"Batches\")"};
  ism::tool::CommonOptions common;
  ism::tool::BatchOptions o;
  std::string shard = "0/1";
  app.add_option("tool", o.tool, "ism-info, gim-remesh, semireg or torus-remesh")->required();
  app.add_option("--inputs", o.inputs,
                 "List of meshes: one path per line, or PATH<TAB>NAME; '#' comments")
      ->required();
  app.add_option("--out", o.out, "Output folder (created): DIR/NAME/ per mesh, DIR/results.jsonl")
      ->required();
  app.add_option("--shard", shard,
                 "Run the list entries k with k % n == i (Slurm: "
                 "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)")
      ->capture_default_str();
  app.add_flag("--skip-existing", o.skip_existing,
               "Skip meshes that already have a line in DIR/results.jsonl (resume)");
  app.add_option("--timeout", o.timeout_seconds,
                 "Seconds per mesh; the tool's process group is then killed")
      ->check(CLI::PositiveNumber);
  app.add_option("tool-options", o.tool_args,
                 "After --: the tool's options; {name} is the mesh's name, {dir} its input's "
                 "folder; relative outputs land in DIR/NAME/");
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);

  return ism::tool::run_main("ism-batch", [&] {
    ism::tool::Run run("ism-batch", common);
    o.shard = ism::tool::parse_shard(shard);
    ism::tool::batch_tool(o.tool);
    o.executable = find_tool(o.tool);
    run.add_input(o.inputs);
    run.stage("batch");
    const ism::tool::BatchSummary s =
        ism::tool::run_batch(o, [&](const std::string& m) { run.note("ism-batch: " + m); });
    ism::Json& r = run.report()["batch"];
    r["tool"] = o.tool;
    r["shard"] = o.shard.str();
    r["results"] = (fs::absolute(o.out) / "results.jsonl").string();
    r["meshes"] = s.meshes;
    r["ok"] = s.ok;
    r["failed"] = s.failed;
    r["timed_out"] = s.timed_out;
    r["skipped"] = s.skipped;
    if (s.interrupted_by) {
      r["interrupted_by"] = ism::tool::signal_name(s.interrupted_by);
      run.finish();
      std::fprintf(stderr, "ism-batch: stopped by %s\n",
                   ism::tool::signal_name(s.interrupted_by).c_str());
      return 128 + s.interrupted_by;
    }
    run.finish();
    run.note("ism-batch: shard " + o.shard.str() + ": " + std::to_string(s.meshes) + " meshes, " +
             std::to_string(s.ok) + " ok, " + std::to_string(s.failed) + " failed, " +
             std::to_string(s.timed_out) + " timed out, " + std::to_string(s.skipped) + " skipped");
    return 0;
  });
}
