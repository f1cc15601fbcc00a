// The pieces of ism-batch: shards, lists, the shared results file under
// concurrent writers, and child processes that time out or fail to start.
#include "tool/batch.hpp"

#include "test_support.hpp"
#include "tool/child_process.hpp"
#include "tool/failure.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <sstream>
#include <thread>

namespace ism::tool {
namespace {

namespace fs = std::filesystem;

fs::path scratch_dir(const std::string& name) {
  fs::path dir = test::binary_dir() / "test-scratch" / "batch" / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> lines_of(const fs::path& p) {
  std::vector<std::string> lines;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) lines.push_back(line);
  return lines;
}

std::string failure_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const Failure& e) {
    return e.what();
  }
  return "";
}

TEST(BatchShard, ParsesAndRefuses) {
  const Shard s = parse_shard("2/5");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 5);
  EXPECT_EQ(s.str(), "2/5");
  EXPECT_NE(failure_of([] { parse_shard("2/2"); }).find("0..1 (Slurm: --array=0-1)"),
            std::string::npos);
  for (const char* bad : {"1", "a/2", "1/b", "-1/2", "0/0", "1/2x", ""})
    EXPECT_NE(failure_of([&] { parse_shard(bad); }), "") << bad;
}

TEST(BatchShard, ShardsPartitionTheList) {
  for (int count : {1, 2, 3, 7}) {
    std::vector<int> taken(20, 0);
    for (int i = 0; i < count; ++i)
      for (std::size_t k = 0; k < taken.size(); ++k) taken[k] += Shard{i, count}.takes(k);
    for (int t : taken) EXPECT_EQ(t, 1) << count << " shards";
  }
}

TEST(BatchList, NamesCommentsAndRefusals) {
  const fs::path dir = scratch_dir("list");
  const fs::path list = dir / "list.txt";
  std::ofstream(list) << "# meshes\n\n/data/a/model.obj\n  /data/b/other.ply  \n"
                      << "/data/c/model.obj\tc_model\r\n";
  const auto entries = read_batch_list(list);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].name, "model");
  EXPECT_EQ(entries[0].path, fs::path("/data/a/model.obj"));
  EXPECT_EQ(entries[1].name, "other");
  EXPECT_EQ(entries[1].path, fs::path("/data/b/other.ply"));
  EXPECT_EQ(entries[2].name, "c_model");
  std::ofstream(dir / "relative.txt") << "sub/mesh.obj\n";
  EXPECT_EQ(read_batch_list(dir / "relative.txt")[0].path, fs::current_path() / "sub/mesh.obj");

  std::ofstream(dir / "twice.txt") << "/a/model.obj\n# x\n/b/model.obj\n";
  EXPECT_EQ(failure_of([&] { read_batch_list(dir / "twice.txt"); }),
            (dir / "twice.txt").string() +
                ":3: the name 'model' is also on line 1; give distinct names as PATH<TAB>NAME");
  std::ofstream(dir / "hidden.txt") << "/a/.obj\n";
  EXPECT_NE(failure_of([&] { read_batch_list(dir / "hidden.txt"); }).find(":1: '.obj'"),
            std::string::npos);
  std::ofstream(dir / "empty.txt") << "# nothing\n";
  EXPECT_NE(failure_of([&] { read_batch_list(dir / "empty.txt"); }).find("no meshes"),
            std::string::npos);
  EXPECT_NE(failure_of([&] { read_batch_list(dir / "absent.txt"); }).find("cannot read"),
            std::string::npos);
}

TEST(BatchResults, AppendsAndReplacesOneLinePerName) {
  const ResultsFile results(scratch_dir("results") / "out");
  results.put("a", R"({"name":"a","v":1})", false);
  results.put("b", R"({"name":"b","v":1})", false);
  EXPECT_EQ(results.names(), (std::set<std::string>{"a", "b"}));
  results.put("a", R"({"name":"a","v":2})", true);
  EXPECT_EQ(lines_of(results.path()),
            (std::vector<std::string>{R"({"name":"b","v":1})", R"({"name":"a","v":2})"}));
}

// Processes that append and replace at the same time: every line whole,
// every name once.
TEST(BatchResults, ConcurrentWritersKeepEveryLineWhole) {
  const fs::path dir = scratch_dir("concurrent") / "out";
  const int writers = 4, per_writer = 50;
  std::vector<pid_t> children;
  for (int w = 0; w < writers; ++w) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const ResultsFile results(dir);
      // Long lines, so that interleaved writes would show.
      const std::string padding = R"(","p":")" + std::string(2000, 'x') + R"("})";
      for (int i = 0; i < per_writer; ++i) {
        std::string name = "w", line = R"({"name":")";
        name.append(std::to_string(w)).append("_").append(std::to_string(i));
        results.put(name, line + name + padding, false);
        // Writer 0 also replaces its own earlier lines while the others append.
        if (w == 0 && i % 5 == 4) results.put(name, line + name + R"(","replaced":true})", true);
      }
      ::_exit(0);
    }
    children.push_back(pid);
  }
  for (pid_t pid : children) {
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  std::map<std::string, int> seen;
  int replaced = 0;
  for (const std::string& line : lines_of(dir / "results.jsonl")) {
    ASSERT_EQ(line.front(), '{');
    ASSERT_EQ(line.back(), '}');
    const std::size_t start = line.find("\"name\":\"") + 8;
    ++seen[line.substr(start, line.find('"', start) - start)];
    replaced += line.find("\"replaced\":true") != std::string::npos;
  }
  EXPECT_EQ(seen.size(), std::size_t(writers * per_writer));
  for (const auto& [name, count] : seen) EXPECT_EQ(count, 1) << name;
  EXPECT_EQ(replaced, per_writer / 5);
}

TEST(BatchChild, ExitCodeOutputsAndWorkingFolder) {
  const fs::path dir = scratch_dir("child");
  const ChildResult r = run_child(
      {"/bin/sh", "-c", "pwd; echo oops >&2; exit 3"},
      {.working_dir = dir, .stdout_file = dir / "out.txt", .stderr_file = dir / "err.txt"});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_FALSE(r.timed_out);
  EXPECT_EQ(slurp(dir / "out.txt"), fs::canonical(dir).string() + "\n");
  EXPECT_EQ(slurp(dir / "err.txt"), "oops\n");

  const ChildResult missing =
      run_child({(dir / "no-such-program").string()}, {.stderr_file = dir / "err2.txt"});
  EXPECT_EQ(missing.exit_code, 127);
  EXPECT_NE(slurp(dir / "err2.txt").find("cannot run the program"), std::string::npos);
}

// A timeout ends the whole process group: the child and what it started.
TEST(BatchChild, TimeoutKillsTheProcessGroup) {
  const fs::path dir = scratch_dir("timeout");
  const fs::path pid_file = dir / "grandchild.pid";
  const ChildResult r =
      run_child({"/bin/sh", "-c", "sleep 60 & echo $! > " + pid_file.string() + "; wait"},
                {.timeout_seconds = 0.5, .grace_seconds = 1});
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.exit_code, -1);
  EXPECT_EQ(r.term_signal, SIGTERM);
  EXPECT_LT(r.seconds, 5.0);
  const pid_t grandchild = std::stoi(slurp(pid_file));
  // Gone, or a zombie waiting for init to reap it.
  bool alive = false;
  for (int i = 0; i < 50; ++i) {
    const std::string stat = slurp("/proc/" + std::to_string(grandchild) + "/stat");
    alive = !stat.empty() && stat.find(") Z") == std::string::npos;
    if (!alive) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_FALSE(alive) << "sleep " << grandchild << " survived the timeout";
}

TEST(BatchChild, IgnoredTermGetsKilledAfterTheGrace) {
  const ChildResult r = run_child({"/bin/sh", "-c", "trap '' TERM; sleep 60"},
                                  {.timeout_seconds = 0.3, .grace_seconds = 0.3});
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.term_signal, SIGKILL);
  EXPECT_LT(r.seconds, 5.0);
}

TEST(BatchFigures, SectionsWithoutTimes) {
  const std::string report = R"({"tool": "gim-remesh",
    "inputs": [{"file": "a.obj", "check": {"vertices": 10, "faces": 16, "genus": 0,
                "boundary_loops": 0, "area": 3.5}}],
    "map_variants": [{"score": 0.5, "seconds": 2}],
    "map": {"valid": true, "symmetric_efficiency": 0.75, "seconds": 4, "nested": {"x": 1}},
    "distance": {"psnr_db": 61.5},
    "seconds": {"total": 9}, "peak_memory_mb": 100})";
  EXPECT_EQ(tool_figures(report),
            R"({"input":{"vertices":10,"faces":16,"genus":0,"boundary_loops":0},)"
            R"("map":{"valid":true,"symmetric_efficiency":0.75},"distance":{"psnr_db":61.5}})");
  EXPECT_EQ(tool_figures("not json"), "{}");
  EXPECT_EQ(tool_figures(""), "{}");
}

TEST(BatchTools, KnownToolsOnly) {
  EXPECT_EQ(batch_tool("gim-remesh").output_extension, ".exr");
  EXPECT_EQ(batch_tool("ism-info").output_extension, "");
  EXPECT_EQ(failure_of([] { batch_tool("rm"); }),
            "ism-batch: unknown tool 'rm' (known: ism-info, gim-remesh, semireg, torus-remesh)");
}

}  // namespace
}  // namespace ism::tool
