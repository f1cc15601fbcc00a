#include "tool/output_file.hpp"
#include "io/io.hpp"
#include "test_support.hpp"
#include "tool/failure.hpp"
#include "tool/tool.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace ism::tool {
namespace {

namespace fs = std::filesystem;

fs::path scratch_dir() {
  fs::path dir = test::binary_dir() / "test-scratch" / "tool";
  fs::create_directories(dir);
  return dir;
}

TEST(OutputFile, AppearsOnlyOnCommit) {
  const fs::path target = scratch_dir() / "out.txt";
  fs::remove(target);
  {
    OutputFile out(target, {});
    EXPECT_EQ(out.temp_path().extension(), ".txt");
    EXPECT_EQ(out.temp_path().parent_path(), target.parent_path());
    std::ofstream(out.temp_path()) << "done";
    EXPECT_FALSE(fs::exists(target));
    out.commit();
  }
  EXPECT_TRUE(fs::exists(target));
}

TEST(OutputFile, UncommittedOutputLeavesNothing) {
  const fs::path target = scratch_dir() / "abandoned.txt";
  fs::remove(target);
  fs::path temp;
  {
    OutputFile out(target, {});
    temp = out.temp_path();
    std::ofstream(temp) << "partial";
  }
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(target));
}

TEST(OutputFile, RefusesToOverwriteAnInput) {
  const fs::path input = scratch_dir() / "input.obj";
  std::ofstream(input) << "v 0 0 0\n";
  // The same file through another spelling of its path.
  const fs::path other = scratch_dir() / "." / "input.obj";
  EXPECT_THROW(OutputFile(other, {input}), Failure);
  EXPECT_THROW(OutputFile(scratch_dir() / "no-such-folder" / "x.obj", {}), Failure);
}

TEST(OutputFile, AWritersFailureNamesTheUsersPathAndLeavesNothing) {
  // The writer sees the temporary file and names it in its error; the
  // failure a user reads names the path they gave, with the writer's reason.
  const fs::path target = scratch_dir() / "failed.png";
  fs::remove(target);
  tool::Run run("test", {.quiet = true});
  fs::path temp;
  try {
    write_output(run, target.string(), [&](const fs::path& p) {
      temp = p;
      std::ofstream(p) << "partial";
      throw io::FileError(p.string() + ": cannot write PNG: no writer here");
    });
    FAIL() << "no failure";
  } catch (const Failure& f) {
    EXPECT_EQ(std::string(f.what()), target.string() + ": cannot write PNG: no writer here");
    EXPECT_EQ(f.kind(), Failure::Kind::file);
  }
  EXPECT_FALSE(temp.empty());
  EXPECT_FALSE(fs::exists(temp));
  EXPECT_FALSE(fs::exists(target));
}

TEST(Run, PeakMemoryIsReported) {
  EXPECT_GT(peak_memory_bytes(), 1u << 20);
}

}  // namespace
}  // namespace ism::tool
