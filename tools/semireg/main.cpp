// semireg MESH --base BASE: semi-regular remesh over a base domain (any genus).
// The input checks are in place; the map itself needs the map core
// (issues 3-5), so for a valid input the tool says so and writes nothing.
#include "tool/cli.hpp"
#include "tool/failure.hpp"

int main(int argc, char** argv) {
  CLI::App app{"semireg: semi-regular remesh over a coarse base mesh"};
  ism::tool::CommonOptions common;
  std::string input, output;
  app.add_option("mesh", input, "Closed surface (.obj, .ply, .off, .stl)")->required();
  app.add_option("-o,--output", output, "Remeshed surface (.obj, .ply, .drc)");
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);

  return ism::tool::run_main("semireg", [&] {
    ism::tool::Run run("semireg", common);
    run.load_surface(input, {.tool = "semireg"});
    throw ism::tool::Failure("semireg: the simplicial map is not implemented yet");
    return 0;
  });
}
