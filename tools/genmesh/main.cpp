// ism-genmesh SHAPE -o FILE: closed manifold test surfaces of a requested size
// (sphere, ellipsoid, blob, torus, double-torus), written as OBJ/PLY/OFF/STL.
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "shapes/shapes.hpp"
#include "tool/cli.hpp"
#include "tool/failure.hpp"
#include "tool/limits.hpp"

#include <map>

int main(int argc, char** argv) {
  CLI::App app{"ism-genmesh: write a generated closed triangle mesh"};
  ism::tool::CommonOptions common;
  std::string shape, output;
  int faces = 5000;
  double radius = 1.0, major = 2.0, minor = 1.0, bumpiness = 0.35;
  std::vector<double> axes{1.0, 0.75, 0.5};
  std::uint64_t seed = 1;
  app.add_option("shape", shape, "sphere | ellipsoid | blob | torus | double-torus")
      ->required()
      ->check(CLI::IsMember({"sphere", "ellipsoid", "blob", "torus", "double-torus"}));
  app.add_option("-o,--output", output, "Output mesh (.obj, .ply, .off, .stl)")->required();
  app.add_option("--faces", faces, "Approximate number of faces")
      ->check(CLI::Range(20, 50'000'000));
  app.add_option("--radius", radius, "Sphere radius")->check(CLI::PositiveNumber);
  app.add_option("--axes", axes, "Ellipsoid semi-axes a b c")
      ->expected(3)
      ->check(CLI::PositiveNumber);
  app.add_option("--R", major, "Torus major radius")->check(CLI::PositiveNumber);
  app.add_option("--r", minor, "Torus minor radius (< R)")->check(CLI::PositiveNumber);
  app.add_option("--seed", seed, "Blob seed");
  app.add_option("--bumpiness", bumpiness, "Blob bump amplitude")->check(CLI::Range(0.0, 0.6));
  ism::tool::add_common_options(app, common);
  CLI11_PARSE(app, argc, argv);

  return ism::tool::run_main("ism-genmesh", [&] {
    ism::tool::Run run("ism-genmesh", common);
    ism::tool::require_extension(run, "-o", output, {".obj", ".ply", ".off", ".stl"}, "a mesh");
    ism::tool::check_generated_mesh(run, std::size_t(faces));
    ism::tool::OutputFile out(output, run.inputs());
    if (shape == "torus" && minor >= major)
      throw ism::tool::Failure("ism-genmesh: --r must be smaller than --R");
    run.stage("generate");
    ism::TriangleMesh mesh;
    if (shape == "sphere") mesh = ism::shapes::sphere(faces, radius);
    if (shape == "ellipsoid") mesh = ism::shapes::ellipsoid(faces, {axes[0], axes[1], axes[2]});
    if (shape == "blob") mesh = ism::shapes::blob(faces, seed, bumpiness);
    if (shape == "torus") mesh = ism::shapes::torus(faces, major, minor);
    if (shape == "double-torus") mesh = ism::shapes::double_torus(faces);
    run.stage("write");
    try {
      ism::io::write_mesh(mesh, out.temp_path());
    } catch (const ism::io::FileError&) {
      throw ism::tool::Failure(output + ": cannot write the file (use .obj, .ply, .off or .stl)");
    }
    out.commit();
    run.report()["output"] = output;
    run.report()["vertices"] = mesh.n_vertices();
    run.report()["faces"] = mesh.n_faces();
    run.note(output + ": " + std::to_string(mesh.n_vertices()) + " vertices, " +
             std::to_string(mesh.n_faces()) + " faces");
    run.finish();
    return 0;
  });
}
