#include "pipeline/mesh_info.hpp"

#include "io/io.hpp"
#include "report/report.hpp"
#include "tool/limits.hpp"

namespace ism::pipeline {

MeshInfo mesh_info(tool::Run& run, const tool::InputMesh& input) {
  PolygonSoup soup;
  if (input.soup) {
    soup = *input.soup;
  } else {
    run.add_input(input.path);
    run.stage("read");
    try {
      tool::check_surface_file(run, input.path);
      soup = io::read_polygon_soup(input.path);
    } catch (const io::FileError& e) {
      throw tool::reading_failure(input.path, e);
    }
  }
  run.stage("check");
  MeshInfo result{prepare_mesh(soup).check, Json()};
  result.info = to_json(result.check);
  result.info["file"] = input.path;
  run.report()["inputs"].push_back(result.info);
  return result;
}

}  // namespace ism::pipeline
