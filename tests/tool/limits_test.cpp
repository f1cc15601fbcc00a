// Up-front resource checks: memory sizes parsed and printed, the default
// limit, refusals that name the option, the figure and what fits, and
// output extensions.
#include "tool/limits.hpp"
#include "test_support.hpp"
#include "tool/failure.hpp"
#include "tool/tool.hpp"

#include <sys/resource.h>

#include <gtest/gtest.h>

namespace ism::tool {
namespace {

// The message of the Failure `f` throws, or "" when it does not.
template <class F>
std::string failure_of(F&& f) {
  try {
    f();
  } catch (const Failure& e) {
    return e.what();
  }
  return "";
}

tool::Run run_with_limit(const std::string& tool, std::size_t bytes) {
  return tool::Run(tool, CommonOptions{.quiet = true, .max_memory = bytes});
}

constexpr std::size_t kGB = std::size_t(1) << 30;

TEST(Limits, MemorySizesParse) {
  EXPECT_EQ(parse_memory_size("8G"), 8 * kGB);
  EXPECT_EQ(parse_memory_size("8gb"), 8 * kGB);
  EXPECT_EQ(parse_memory_size("512M"), std::size_t(512) << 20);
  EXPECT_EQ(parse_memory_size("1.5G"), 3 * kGB / 2);
  EXPECT_EQ(parse_memory_size("64K"), std::size_t(64) << 10);
  EXPECT_EQ(parse_memory_size("1000000"), std::size_t(1000000));
  EXPECT_EQ(parse_memory_size(" 2 T "), std::size_t(2) << 40);
  for (const char* bad : {"", "G", "-1G", "0", "12x", "1e30G", "nanG", "8Q"})
    EXPECT_FALSE(parse_memory_size(bad)) << bad;
}

TEST(Limits, BytesPrintShort) {
  EXPECT_EQ(format_bytes(6.4 * double(kGB)), "6.4 GB");
  EXPECT_EQ(format_bytes(850.0 * (1 << 20)), "850 MB");
  EXPECT_EQ(format_bytes(12 * 1024), "12 KB");
  EXPECT_EQ(format_bytes(300), "300 bytes");
}

TEST(Limits, DefaultIsHalfTheMachine) {
  EXPECT_GT(machine_memory_bytes(), std::size_t(256) << 20);
  EXPECT_EQ(default_memory_limit(), machine_memory_bytes() / 2);
  const tool::Run run("gim-remesh", CommonOptions{.quiet = true});
  EXPECT_EQ(run.memory_limit(), default_memory_limit());
}

TEST(Limits, GeometryImageRefusalNamesTheFigureAndWhatFits) {
  const tool::Run run = run_with_limit("gim-remesh", 8 * kGB);
  EXPECT_EQ(failure_of([&] { check_geometry_image(run, 2049); }), "");
  const std::string message = failure_of([&] { check_geometry_image(run, 16385); });
  EXPECT_EQ(message.rfind("gim-remesh: --size 16385 (the image, its normals, the remesh and its "
                          "measures) needs ~",
                          0),
            0u)
      << message;
  EXPECT_NE(message.find("(limit 8.0 GB); use --size 2049 or less, or raise --max-memory"),
            std::string::npos)
      << message;
  EXPECT_NE(failure_of([&] { check_geometry_image(run, 65537); }).find("2^k+1 between 3 and 32769"),
            std::string::npos);
  EXPECT_NE(failure_of([&] { check_geometry_image(run, 100); }).find("got 100"), std::string::npos);
}

TEST(Limits, EstimatesGrowWithTheRequest) {
  // A limit between two sizes separates them: the estimate is monotone and
  // compared with the limit given.
  const tool::Run small = run_with_limit("gim-remesh", kGB);
  EXPECT_EQ(failure_of([&] { check_geometry_image(small, 513); }), "");
  EXPECT_NE(failure_of([&] { check_geometry_image(small, 2049); }), "");
  EXPECT_EQ(failure_of([&] { check_semiregular(small, 200, 4, "the base"); }), "");
  const std::string levels = failure_of([&] { check_semiregular(small, 200, 8, "the base"); });
  EXPECT_NE(levels.find("the base at --levels 8 (1.31e+07 remesh faces) needs ~"),
            std::string::npos)
      << levels;
  EXPECT_NE(levels.find("use --levels 6 or less"), std::string::npos) << levels;
  EXPECT_EQ(failure_of([&] { check_torus_grid(small, 128, 128); }), "");
  EXPECT_NE(failure_of([&] { check_torus_grid(small, 4096, 4096); }), "");
  EXPECT_EQ(failure_of([&] { check_generated_mesh(small, 100000); }), "");
  EXPECT_NE(failure_of([&] { check_generated_mesh(small, 50000000); }), "");
}

TEST(Limits, BaseSizeMustBeBelowTheSurface) {
  const tool::Run run = run_with_limit("semireg", kGB);
  EXPECT_EQ(failure_of([&] { check_base_size(run, 100, 2562, "sphere.obj"); }), "");
  EXPECT_EQ(failure_of([&] { check_base_size(run, 100000, 2562, "sphere.obj"); }),
            "semireg: --base-size 100000 is not below sphere.obj's 2562 vertices; a base "
            "decimates the surface (use --base-size 2561 or less)");
}

TEST(Limits, SurfaceFileIsSizedFromItsHeader) {
  // The octahedron of the hostile set (8 faces) fits in 210 MB, not in 10 MB.
  const auto file = test::hostile_dir() / "off_fused_modelnet.off";
  EXPECT_EQ(failure_of([&] { check_surface_file(run_with_limit("ism-info", 210 << 20), file); }),
            "");
  const std::string message =
      failure_of([&] { check_surface_file(run_with_limit("ism-info", 10 << 20), file); });
  EXPECT_NE(message.find(file.string() + " (8 faces, 112 bytes) needs ~"), std::string::npos)
      << message;
}

TEST(Limits, OutputExtensionsAreChecked) {
  const tool::Run run = run_with_limit("gim-remesh", kGB);
  EXPECT_EQ(failure_of([&] { require_extension(run, "-o", "out.exr", {".exr"}, "OpenEXR"); }), "");
  EXPECT_EQ(failure_of([&] { require_extension(run, "-o", "", {".exr"}, "OpenEXR"); }), "");
  EXPECT_EQ(failure_of([&] { require_extension(run, "-o", "out.txt", {".exr"}, "OpenEXR"); }),
            "gim-remesh: out.txt: -o writes OpenEXR; use .exr (not .txt)");
  EXPECT_EQ(failure_of([&] { require_mesh_extension(run, "--mesh", "m"); }),
            "gim-remesh: m: --mesh writes a mesh; use .obj, .ply, .off, .stl, .drc, .glb");
}

TEST(Limits, TheAddressSpaceIsCappedAboveTheLimit) {
#if !defined(__SANITIZE_ADDRESS__)
  const tool::Run run = run_with_limit("ism-info", kGB);
  rlimit limit{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &limit), 0);
  EXPECT_NE(limit.rlim_cur, RLIM_INFINITY);
  EXPECT_GE(limit.rlim_cur, rlim_t(kGB));
  EXPECT_LE(limit.rlim_cur, rlim_t(4 * kGB));
#endif
}

}  // namespace
}  // namespace ism::tool
