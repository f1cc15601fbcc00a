// gim-remesh MESH -o IMAGE.exr: octahedral geometry image of a closed genus-0
// surface. The input checks are in place; the map itself needs the map core
// (issues 3-5), so for a valid input the tool says so and writes nothing.
#include "tool/cli.hpp"
#include "tool/failure.hpp"

int main(int argc, char** argv) {
  CLI::App app{"gim-remesh: octahedral geometry image of a closed genus-0 surface"};
  ism::tool::CommonOptions common;
  std::string input, output;
  app.add_option("mesh", input, "Closed genus-0 surface (.obj, .ply, .off, .stl)")->required();
  app.add_option("-o,--output", output, "Geometry image (.exr)");
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);

  return ism::tool::run_main("gim-remesh", [&] {
    ism::tool::Run run("gim-remesh", common);
    run.load_surface(input, {.tool = "gim-remesh", .closed = true, .genus = 0});
    throw ism::tool::Failure("gim-remesh: the octahedral map is not implemented yet");
    return 0;
  });
}
