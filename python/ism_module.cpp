// The Python module `ism`: one snake_case function per tool, numpy arrays in
// and out, the tools' options with their defaults, the tools' one-line
// messages as Python exceptions. Each function runs the same pipeline as its
// command-line tool (libism/pipeline), so the results are the same bit for bit.
#include "io/features.hpp"
#include "io/io.hpp"
#include "pipeline/gim_remesh.hpp"
#include "pipeline/map_surfaces.hpp"
#include "pipeline/mesh_info.hpp"
#include "pipeline/semireg.hpp"
#include "pipeline/torus_remesh.hpp"
#include "sample/geometry_image_file.hpp"
#include "tool/failure.hpp"
#include "tool/output_file.hpp"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>

namespace py = pybind11;
using namespace py::literals;

namespace ism::python {
namespace {

// ---- arrays in ---------------------------------------------------------

std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) s += (k ? ", " : "") + std::to_string(a.shape(k));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

std::string dtype_of(const py::array& a) {
  return py::str(a.dtype()).cast<std::string>();
}

// An (n, columns) array of any real floating type (float64 as is; float32 and
// float16 widened exactly), any strides. Other dtypes are a TypeError, other
// shapes a ValueError.
py::array_t<double, py::array::c_style> float_rows(const py::handle& object, const char* name,
                                                   py::ssize_t columns) {
  const py::array a = py::array::ensure(object);
  if (!a)
    throw py::type_error(std::string(name) + " must be a numpy array (or convertible to one)");
  if (a.dtype().kind() != 'f')
    throw py::type_error(std::string(name) + " must be a float array (float64 or float32), got " +
                         dtype_of(a));
  if (a.ndim() != 2 || a.shape(1) != columns)
    throw py::value_error(std::string(name) + " must have shape (n, " + std::to_string(columns) +
                          "), got " + shape_of(a));
  return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(a);
}

// An integer array of the given rank (int32, int64 or any other integer type,
// any strides) as int64.
py::array_t<std::int64_t, py::array::c_style> int_array(const py::handle& object,
                                                        const char* name) {
  const py::array a = py::array::ensure(object);
  if (!a)
    throw py::type_error(std::string(name) + " must be a numpy array (or convertible to one)");
  if (a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw py::type_error(std::string(name) + " must be an integer array (int32 or int64), got " +
                         dtype_of(a));
  return py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
}

// V (n, 3) and F (m, 3) as the polygon soup a file would give: indices
// checked against n.
PolygonSoup soup_of(const py::handle& v_object, const py::handle& f_object) {
  const auto v = float_rows(v_object, "V", 3);
  const auto f = int_array(f_object, "F");
  if (f.ndim() != 2 || f.shape(1) != 3)
    throw py::value_error("F must have shape (m, 3), got " + shape_of(f));
  PolygonSoup soup;
  const auto vr = v.unchecked<2>();
  soup.positions.resize(std::size_t(v.shape(0)));
  for (py::ssize_t i = 0; i < v.shape(0); ++i)
    soup.positions[std::size_t(i)] = Vec3(vr(i, 0), vr(i, 1), vr(i, 2));
  const auto fr = f.unchecked<2>();
  soup.faces.resize(std::size_t(f.shape(0)));
  for (py::ssize_t i = 0; i < f.shape(0); ++i)
    for (int k = 0; k < 3; ++k) {
      const std::int64_t index = fr(i, k);
      if (index < 0 || index >= v.shape(0))
        throw py::value_error("F[" + std::to_string(i) + ", " + std::to_string(k) +
                              "] = " + std::to_string(index) + " is out of range for " +
                              std::to_string(v.shape(0)) + " vertices");
      soup.faces[std::size_t(i)].push_back(int(index));
    }
  return soup;
}

bool is_path(const py::handle& object) {
  return py::isinstance<py::str>(object) ||
         py::isinstance(object, py::module_::import("os").attr("PathLike"));
}

std::string path_of(const py::handle& object) {
  return py::str(py::module_::import("os").attr("fspath")(object)).cast<std::string>();
}

// The surface argument: a mesh file's path (faces None), or V and F.
tool::InputMesh input_mesh(const py::object& surface, const py::object& faces, const char* name) {
  if (faces.is_none()) {
    if (!is_path(surface))
      throw py::type_error(std::string("give a mesh file's path, or V (n, 3) and F (m, 3) as ") +
                           name + "(V, F, ...)");
    return {path_of(surface), std::nullopt};
  }
  return {"(V, F)", soup_of(surface, faces)};
}

// Features: None, a feature file's path, vertex indices (k,) or points (k, 3).
io::FeatureSource feature_source(const py::object& object, const char* name) {
  if (object.is_none()) return {};
  if (is_path(object)) return {path_of(object), std::nullopt};
  const py::array a = py::array::ensure(object);
  std::vector<io::FeatureEntry> entries;
  if (a && (a.dtype().kind() == 'i' || a.dtype().kind() == 'u') && a.ndim() == 1) {
    const auto indices = int_array(a, name);
    for (py::ssize_t i = 0; i < indices.shape(0); ++i)
      entries.push_back({.vertex = long(indices.at(i))});
  } else if (a && a.dtype().kind() == 'f' && a.ndim() == 2) {
    const auto points = float_rows(a, name, 3);
    const auto p = points.unchecked<2>();
    for (py::ssize_t i = 0; i < points.shape(0); ++i)
      entries.push_back({.point = Vec3(p(i, 0), p(i, 1), p(i, 2))});
  } else {
    throw py::type_error(std::string(name) +
                         " must be a file path, vertex indices (k,) of an integer type or "
                         "points (k, 3) of a float type");
  }
  return {name, std::move(entries)};
}

std::string optional_path(const py::object& object) {
  return object.is_none() ? std::string() : path_of(object);
}

// ---- arrays out --------------------------------------------------------

py::array_t<double> positions_array(const std::vector<Vec3>& points,
                                    std::vector<py::ssize_t> shape) {
  shape.push_back(3);
  py::array_t<double> out(shape);
  double* data = out.mutable_data();
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) data[3 * i + k] = points[i][k];
  return out;
}

// An octahedral image's channel A as an (n, n) float32 array, None when the
// image has none (a closed surface's).
py::object alpha_array(const GeometryImage& image) {
  if (image.alpha.empty()) return py::none();
  py::array_t<float> a({py::ssize_t(image.n), py::ssize_t(image.n)});
  std::copy(image.alpha.begin(), image.alpha.end(), a.mutable_data());
  return a;
}

template <std::size_t Corners>
py::array_t<std::int64_t> faces_array(const std::vector<std::array<int, Corners>>& faces) {
  py::array_t<std::int64_t> out({py::ssize_t(faces.size()), py::ssize_t(Corners)});
  std::int64_t* data = out.mutable_data();
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (std::size_t k = 0; k < Corners; ++k) data[Corners * f + k] = faces[f][k];
  return out;
}

py::object to_python(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null:
      return py::none();
    case Json::value_t::boolean:
      return py::bool_(j.get<bool>());
    case Json::value_t::number_integer:
      return py::int_(j.get<std::int64_t>());
    case Json::value_t::number_unsigned:
      return py::int_(j.get<std::uint64_t>());
    case Json::value_t::number_float:
      return py::float_(j.get<double>());
    case Json::value_t::string:
      return py::str(j.get_ref<const std::string&>());
    case Json::value_t::array: {
      py::list out;
      for (const Json& item : j) out.append(to_python(item));
      return out;
    }
    case Json::value_t::object: {
      py::dict out;
      for (const auto& [key, value] : j.items()) out[py::str(key)] = to_python(value);
      return out;
    }
    default:
      return py::none();
  }
}

// ---- options -----------------------------------------------------------

// The map options every remeshing tool takes (tool/cli.hpp: add_map_options).
struct MapArguments {
  bool hold_features;
  int final_sweeps;
  std::size_t contenders;  // 0: the tool's default
  double drop_behind;
  std::optional<double> inverse_weight, curvature_weight, anisotropy_weight, anisotropy_threshold;
  py::object meta_mesh;

  void apply(tool::MapSettings& settings) const {
    settings.hold_features = hold_features;
    settings.final_sweeps = final_sweeps;
    if (contenders > 12)
      throw py::value_error("contenders must be in 0..12 (0: the tool's default)");
    settings.contenders = contenders;
    if (!(drop_behind >= -1 && drop_behind <= 1))
      throw py::value_error("drop_behind must be in [-1, 1] (negative: every map refined whole)");
    settings.drop_behind = drop_behind;
    if (inverse_weight) settings.set_inverse_weight(*inverse_weight);
    if (curvature_weight) settings.curvature_weight = *curvature_weight;
    if (anisotropy_weight) settings.set_anisotropy_weight(*anisotropy_weight);
    if (anisotropy_threshold) settings.set_anisotropy_threshold(*anisotropy_threshold);
    settings.meta_mesh_path = optional_path(meta_mesh);
  }
};

// core= of the tools that offer the symmetric core (tool/cli.hpp: add_core_option).
tool::MapCore map_core(const std::string& core) {
  if (core == "symmetric") return tool::MapCore::symmetric;
  if (core != "surface-map")
    throw py::value_error("core must be 'surface-map' or 'symmetric', got '" + core + "'");
  return tool::MapCore::surface_map;
}

tool::CommonOptions common_options(const py::object& report, bool quiet) {
  return {.quiet = quiet, .report_path = optional_path(report), .cap_address_space = false};
}

// Runs a pipeline without the GIL (its threads never touch Python) and
// finishes the run; returns the pipeline's result and the report.
template <class Result, class Options>
std::pair<Result, py::object> run_pipeline(const char* tool_name,
                                           Result (*pipeline)(tool::Run&, const Options&),
                                           const Options& options,
                                           const tool::CommonOptions& common) {
  std::optional<Result> result;
  Json report;
  {
    py::gil_scoped_release release;
    tool::Run run(tool_name, common);
    result.emplace(pipeline(run, options));
    run.finish();
    report = run.report();
  }
  return {std::move(*result), to_python(report)};
}

// One surface of two: a mesh file's path, or a tuple (V, F).
tool::InputMesh one_surface(const py::object& surface, const char* name) {
  if (py::isinstance<py::tuple>(surface) && py::len(surface) == 2) {
    const py::tuple t = surface.cast<py::tuple>();
    return {"(V, F)", soup_of(t[0], t[1])};
  }
  if (!is_path(surface))
    throw py::type_error(std::string(name) + " must be a mesh file's path or a tuple (V, F)");
  return {path_of(surface), std::nullopt};
}

// Where each vertex of one surface maps on the other: its face (n,) and
// barycentric coordinates there (n, 3).
py::tuple correspondence_arrays(const std::vector<SurfacePoint>& images) {
  py::array_t<std::int64_t> face(py::ssize_t(images.size()));
  py::array_t<double> bary({py::ssize_t(images.size()), py::ssize_t(3)});
  std::int64_t* f = face.mutable_data();
  double* b = bary.mutable_data();
  for (std::size_t i = 0; i < images.size(); ++i) {
    f[i] = images[i].face;
    for (int k = 0; k < 3; ++k) b[3 * i + std::size_t(k)] = images[i].bary[k];
  }
  return py::make_tuple(face, bary);
}

py::object named_tuple(const char* name, std::initializer_list<const char*> fields,
                       const char* doc) {
  py::list names;
  for (const char* f : fields) names.append(f);
  py::object type = py::module_::import("collections").attr("namedtuple")(name, names);
  type.attr("__doc__") = doc;
  type.attr("__module__") = "ism";
  return type;
}

// ---- the module --------------------------------------------------------

void raise_failure(const tool::Failure& e) {
  switch (e.kind()) {
    case tool::Failure::Kind::input:
      PyErr_SetString(PyExc_ValueError, e.what());
      break;
    case tool::Failure::Kind::file:
      PyErr_SetString(PyExc_OSError, e.what());
      break;
    case tool::Failure::Kind::internal:
      PyErr_SetString(PyExc_RuntimeError, e.what());
      break;
  }
}

}  // namespace
}  // namespace ism::python

PYBIND11_MODULE(ism, m) {
  using namespace ism;
  using namespace ism::python;
  m.doc() =
      "ism: inter-surface mapping and remeshing (Schreiner et al., SIGGRAPH 2004).\n\n"
      "One function per command-line tool, with the tool's options and defaults, running the\n"
      "same pipeline (the results are the tool's bit for bit). Meshes go in as V (n, 3)\n"
      "float64 or float32 and F (m, 3) int32 or int64 arrays, or as a file path; arrays and a\n"
      "report dict (the tool's --report) come out. A tool's one-line message is raised as\n"
      "ValueError (unsuitable mesh, features or option), OSError (a file cannot be read or\n"
      "written) or RuntimeError (the optimisation failed).";
  m.attr("__version__") = ISM_VERSION;
  // Every function returns numpy arrays: say so at import, not after a long run.
  try {
    py::module_::import("numpy");
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) throw;
    throw py::import_error(
        "ism needs numpy, which this Python (" +
        py::module_::import("sys").attr("executable").cast<std::string>() +
        ") does not have; use the interpreter the module was built for (Debian's /usr/bin/python3 "
        "with python3-numpy) or install numpy");
  }

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const tool::Failure& e) {
      raise_failure(e);
    } catch (const io::FileError& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    }
  });

  const py::object gim_result =
      named_tuple("GimRemeshResult", {"image", "normals", "vertices", "faces", "report", "alpha"},
                  "gim_remesh's result: image (n, n, 3) float64 surface positions (README, "
                  "'Geometry image layout'; the .exr holds them as float32), normals (n, n, 3) "
                  "unit normals, vertices (V, 3) and faces (F, 3) of the image as a mesh (open "
                  "where the input is), report (dict, as --report), alpha (n, n) float32: 1 on "
                  "the input surface, 0 on a cap that closed a hole (None for a closed input).");
  const py::object semireg_result =
      named_tuple("SemiregResult", {"vertices", "faces", "base_vertices", "base_faces", "report"},
                  "semireg's result: the semi-regular remesh (base vertices first), the base used "
                  "(its vertices where the map puts them), report (dict, as --report).");
  const py::object torus_result =
      named_tuple("TorusRemeshResult", {"grid", "vertices", "quads", "triangles", "report"},
                  "torus_remesh's result: grid (V rows, U columns, 3) periodic geometry image, "
                  "vertices (U*V, 3) = grid row-major, quads (U*V, 4) and triangles (2*U*V, 3) on "
                  "them (README, 'Torus grids'), report (dict, as --report).");
  const py::object map_result = named_tuple(
      "MapResult", {"faces", "on_a", "on_b", "a_to_b", "b_to_a", "report"},
      "map_surfaces' result: the overlay pair (faces (T, 3) and the positions of its vertices "
      "on A and on B, (W, 3) each: the same triangles on both surfaces, the map affine on each), "
      "a_to_b = (face (nA,), bary (nA, 3)): where each vertex of A lands on B (a face of B as "
      "read and barycentric coordinates there; the rows of PREFIX_A_to_B.txt), b_to_a the same "
      "from B, report (dict, as --report).");
  m.attr("MapResult") = map_result;
  m.attr("GimRemeshResult") = gim_result;
  m.attr("SemiregResult") = semireg_result;
  m.attr("TorusRemeshResult") = torus_result;

  m.def(
      "read_mesh",
      [](const py::object& path) {
        const std::string file = path_of(path);
        PolygonSoup soup;
        try {
          soup = io::read_polygon_soup(file);
        } catch (const io::FileError& e) {
          throw tool::reading_failure(file, e);
        }
        const PreparedMesh prepared = prepare_mesh(soup);
        return py::make_tuple(
            positions_array(prepared.mesh.positions, {py::ssize_t(prepared.mesh.n_vertices())}),
            faces_array(prepared.mesh.triangles));
      },
      "path"_a,
      "read_mesh(path) -> (V, F)\n\n"
      "Reads OBJ, PLY, OFF or STL as every tool does: coincident vertices welded, polygons\n"
      "triangulated, orientation made consistent (and outward for a closed surface). V is\n"
      "(n, 3) float64, F (m, 3) int64. Use check() for what was repaired or is wrong.");

  m.def(
      "write_mesh",
      [](const py::object& path, const py::object& v_object, const py::object& f_object,
         int draco_bits, bool glb_draco) {
        const std::string file = path_of(path);
        const std::string ext = std::filesystem::path(file).extension().string();
        if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl" && ext != ".drc" &&
            ext != ".glb")
          throw py::value_error(file +
                                ": unsupported output format (use .obj, .ply, .off, .stl, .drc "
                                "or .glb)");
        tool::check_settings("write_mesh", tool::MapSettings{},
                             {.draco_bits = draco_bits, .glb_draco = glb_draco});
        const PolygonSoup soup = soup_of(v_object, f_object);
        TriangleMesh mesh{soup.positions, {}};
        for (const auto& f : soup.faces) mesh.triangles.push_back({f[0], f[1], f[2]});
        py::gil_scoped_release release;
        tool::OutputFile out(file, {});
        try {
          io::write_mesh_file(mesh, out.temp_path(),
                              {.draco_bits = draco_bits, .glb_draco = glb_draco});
        } catch (const io::FileError&) {
          throw tool::Failure(file + ": cannot write the file", tool::Failure::Kind::file);
        } catch (const std::invalid_argument& e) {
          throw tool::Failure(file + ": " + e.what());
        }
        out.commit();
      },
      "path"_a, "V"_a, "F"_a, py::kw_only(), "draco_bits"_a = 14, "glb_draco"_a = false,
      "write_mesh(path, V, F, *, draco_bits=14, glb_draco=False)\n\n"
      "Writes a triangle mesh as the tools do, by extension: OBJ (17 digits), PLY (binary), OFF,\n"
      "STL, Draco (.drc, positions quantized to draco_bits) or glTF 2.0 binary (.glb, plain, or\n"
      "Draco-compressed with glb_draco). The file appears only when complete.");

  m.def(
      "check",
      [](const py::object& surface, const py::object& faces) {
        const tool::InputMesh input = input_mesh(surface, faces, "check");
        Json info;
        {
          py::gil_scoped_release release;
          tool::Run run("ism-info", {.quiet = true});
          info = pipeline::mesh_info(run, input).info;
        }
        return to_python(info);
      },
      "surface"_a, "faces"_a = py::none(),
      "check(path) or check(V, F) -> dict\n\n"
      "ism-info --json: sizes, components, boundary loops, Euler characteristic, genus,\n"
      "manifoldness, orientability, area, defects, repairs. A mesh that is not a valid surface\n"
      "is described ('valid_surface': False, 'defects'), not refused.");

  m.def(
      "gim_remesh",
      [gim_result](const py::object& surface, const py::object& faces, int size,
                   const std::string& metric, bool grid_points, const std::string& core,
                   const py::object& features, bool hold_features, int final_sweeps,
                   std::size_t contenders, double drop_behind, std::optional<double> inverse_weight,
                   std::optional<double> curvature_weight, std::optional<double> anisotropy_weight,
                   std::optional<double> anisotropy_threshold, const py::object& output,
                   const py::object& normals, const py::object& mesh, int draco_bits,
                   bool glb_draco, const py::object& preview, const py::object& mask,
                   const py::object& dump_patches, const py::object& meta_mesh,
                   const py::object& report, bool quiet) {
        pipeline::GimRemeshOptions o;
        o.input = input_mesh(surface, faces, "gim_remesh");
        o.features = feature_source(features, "features");
        o.size = size;
        o.metric = metric;
        o.unfold = !grid_points;
        o.output = optional_path(output);
        o.normals = optional_path(normals);
        o.mesh = optional_path(mesh);
        o.preview = optional_path(preview);
        o.mask = optional_path(mask);
        o.dump_patches = optional_path(dump_patches);
        o.mesh_file = {.draco_bits = draco_bits, .glb_draco = glb_draco};
        MapArguments{hold_features,     final_sweeps,         contenders,
                     drop_behind,       inverse_weight,       curvature_weight,
                     anisotropy_weight, anisotropy_threshold, meta_mesh}
            .apply(o.map);
        o.map.core = map_core(core);
        auto [r, rep] =
            run_pipeline("gim-remesh", &pipeline::gim_remesh, o, common_options(report, quiet));
        const py::ssize_t n = r.image.n;
        return gim_result(positions_array(r.image.pixels, {n, n}),
                          positions_array(r.normals.pixels, {n, n}),
                          positions_array(r.remesh.positions, {py::ssize_t(r.remesh.n_vertices())}),
                          faces_array(r.remesh.triangles), rep, alpha_array(r.image));
      },
      "surface"_a, "faces"_a = py::none(), py::kw_only(), "size"_a = 257,
      "metric"_a = "right-isosceles", "grid_points"_a = false, "core"_a = "surface-map",
      "features"_a = py::none(), "hold_features"_a = false, "final_sweeps"_a = 8,
      "contenders"_a = 0, "drop_behind"_a = 0.01, "inverse_weight"_a = py::none(),
      "curvature_weight"_a = py::none(), "anisotropy_weight"_a = py::none(),
      "anisotropy_threshold"_a = py::none(), "output"_a = py::none(), "normals"_a = py::none(),
      "mesh"_a = py::none(), "draco_bits"_a = 14, "glb_draco"_a = false, "preview"_a = py::none(),
      "mask"_a = py::none(), "dump_patches"_a = py::none(), "meta_mesh"_a = py::none(),
      "report"_a = py::none(), "quiet"_a = false,
      "gim_remesh(path or V, F, *, size=257, ...) -> GimRemeshResult(image, normals, vertices, "
      "faces, report)\n\n"
      "Octahedral geometry image of a genus-0 surface (holes capped; the output .exr then has\n"
      "an alpha channel, mask (.png) marks the surface, vertices/faces drop the caps), as the\n"
      "gim-remesh tool (same\n"
      "options, same defaults; grid_points is --grid-points; curvature_weight None means the "
      "tool's 0.5, inverse_weight None\n"
      "its two map variants; core 'symmetric' the one map both sides refine, holes capped\n"
      "alike). features: a file path, 6 vertex indices or 6 points for\n"
      "+x -x +y -y +z -z (default automatic). output/normals (.exr), mesh (.obj .ply .off .stl\n"
      ".drc .glb), preview (.png), dump_patches (.ply), meta_mesh, report (.json) are written\n"
      "when given.");

  m.def(
      "semireg",
      [semireg_result](const py::object& surface, const py::object& faces, const py::object& base,
                       const py::object& base_vertices, std::size_t base_size, int levels,
                       bool grid_points, const std::string& core, bool hold_features,
                       int final_sweeps, std::size_t contenders, double drop_behind,
                       std::optional<double> inverse_weight, std::optional<double> curvature_weight,
                       std::optional<double> anisotropy_weight,
                       std::optional<double> anisotropy_threshold, const py::object& output,
                       const py::object& write_base, int draco_bits, bool glb_draco,
                       const py::object& dump_patches, const py::object& meta_mesh,
                       const py::object& report, bool quiet) {
        pipeline::SemiregOptions o;
        o.input = input_mesh(surface, faces, "semireg");
        if (!base.is_none()) {
          if (is_path(base)) {
            o.base = {path_of(base), std::nullopt};
          } else {
            const py::tuple vf = py::tuple(base);
            if (vf.size() != 2)
              throw py::type_error("base must be a mesh file's path or a tuple (V, F)");
            o.base = {"base", soup_of(vf[0], vf[1])};
          }
        }
        o.base_vertices = feature_source(base_vertices, "base_vertices");
        o.base_size = base_size;
        o.levels = levels;
        o.unfold = !grid_points;
        o.output = optional_path(output);
        o.write_base = optional_path(write_base);
        o.dump_patches = optional_path(dump_patches);
        o.mesh_file = {.draco_bits = draco_bits, .glb_draco = glb_draco};
        MapArguments{hold_features,     final_sweeps,         contenders,
                     drop_behind,       inverse_weight,       curvature_weight,
                     anisotropy_weight, anisotropy_threshold, meta_mesh}
            .apply(o.map);
        o.map.core = map_core(core);
        auto [r, rep] =
            run_pipeline("semireg", &pipeline::semireg, o, common_options(report, quiet));
        return semireg_result(
            positions_array(r.remesh.positions, {py::ssize_t(r.remesh.n_vertices())}),
            faces_array(r.remesh.triangles),
            positions_array(r.base.positions, {py::ssize_t(r.base.n_vertices())}),
            faces_array(r.base.triangles), rep);
      },
      "surface"_a, "faces"_a = py::none(), py::kw_only(), "base"_a = py::none(),
      "base_vertices"_a = py::none(), "base_size"_a = 0, "levels"_a = 4, "grid_points"_a = false,
      "core"_a = "surface-map", "hold_features"_a = false, "final_sweeps"_a = 8, "contenders"_a = 0,
      "drop_behind"_a = 0.01, "inverse_weight"_a = py::none(), "curvature_weight"_a = py::none(),
      "anisotropy_weight"_a = py::none(), "anisotropy_threshold"_a = py::none(),
      "output"_a = py::none(), "write_base"_a = py::none(), "draco_bits"_a = 14,
      "glb_draco"_a = false, "dump_patches"_a = py::none(), "meta_mesh"_a = py::none(),
      "report"_a = py::none(), "quiet"_a = false,
      "semireg(path or V, F, *, base=... | base_vertices=... | base_size=N, levels=4, ...) -> "
      "SemiregResult(vertices, faces, base_vertices, base_faces, report)\n\n"
      "Semi-regular remesh of a surface of any genus, closed or open, as the semireg tool (same\n"
      "options and defaults; grid_points is --grid-points). Exactly one base: base (a mesh\n"
      "path or a tuple (V, F)), base_vertices (a file path, vertex indices or points) or\n"
      "base_size (decimate to N vertices). core 'symmetric': the one map both sides refine\n"
      "(closed surfaces only). output and\n"
      "write_base (.obj .ply .off .stl .drc .glb), dump_patches, meta_mesh, report are written\n"
      "when given.");

  m.def(
      "torus_remesh",
      [torus_result](
          const py::object& surface, const py::object& faces, const py::object& size,
          const py::object& features, bool triangulate, bool no_global_reembedding,
          bool grid_points, const std::string& core, bool hold_features, int final_sweeps,
          std::size_t contenders, double drop_behind, std::optional<double> inverse_weight,
          std::optional<double> curvature_weight, std::optional<double> anisotropy_weight,
          std::optional<double> anisotropy_threshold, const py::object& output,
          const py::object& image, int draco_bits, bool glb_draco, const py::object& dump_patches,
          const py::object& meta_mesh, const py::object& report, bool quiet) {
        pipeline::TorusRemeshOptions o;
        o.input = input_mesh(surface, faces, "torus_remesh");
        o.features = feature_source(features, "features");
        if (py::isinstance<py::tuple>(size) || py::isinstance<py::list>(size)) {
          const py::sequence uv = size;
          if (uv.size() != 2) throw py::value_error("size must be N, (U, V) or 'UxV'");
          o.size = std::to_string(uv[0].cast<long long>()) + "x" +
                   std::to_string(uv[1].cast<long long>());
        } else {
          o.size = py::str(size).cast<std::string>();
        }
        o.triangulate = triangulate;
        o.no_global_reembedding = no_global_reembedding;
        o.unfold = !grid_points;
        o.output = optional_path(output);
        o.image = optional_path(image);
        o.dump_patches = optional_path(dump_patches);
        o.mesh_file = {.draco_bits = draco_bits, .glb_draco = glb_draco};
        MapArguments{hold_features,     final_sweeps,         contenders,
                     drop_behind,       inverse_weight,       curvature_weight,
                     anisotropy_weight, anisotropy_threshold, meta_mesh}
            .apply(o.map);
        o.map.core = map_core(core);
        auto [r, rep] =
            run_pipeline("torus-remesh", &pipeline::torus_remesh, o, common_options(report, quiet));
        return torus_result(
            positions_array(r.grid.points, {py::ssize_t(r.grid.rows), py::ssize_t(r.grid.columns)}),
            positions_array(r.quads.positions, {py::ssize_t(r.quads.n_vertices())}),
            faces_array(r.quads.quads), faces_array(r.triangles.triangles), rep);
      },
      "surface"_a, "faces"_a = py::none(), py::kw_only(), "size"_a = 128, "features"_a = py::none(),
      "triangulate"_a = false, "no_global_reembedding"_a = false, "grid_points"_a = false,
      "core"_a = "surface-map", "hold_features"_a = false, "final_sweeps"_a = 8, "contenders"_a = 0,
      "drop_behind"_a = 0.01, "inverse_weight"_a = py::none(), "curvature_weight"_a = py::none(),
      "anisotropy_weight"_a = py::none(), "anisotropy_threshold"_a = py::none(),
      "output"_a = py::none(), "image"_a = py::none(), "draco_bits"_a = 14, "glb_draco"_a = false,
      "dump_patches"_a = py::none(), "meta_mesh"_a = py::none(), "report"_a = py::none(),
      "quiet"_a = false,
      "torus_remesh(path or V, F, *, size=128, ...) -> TorusRemeshResult(grid, vertices, quads, "
      "triangles, report)\n\n"
      "Valence-4 grid remesh of a closed genus-1 surface, as the torus-remesh tool (same\n"
      "options and defaults; grid_points is --grid-points). size: N, (U, V) or 'UxV'. features: a "
      "file path, 9 vertex\n"
      "indices or 9 points, row-major in the 3x3 grid (default automatic). core 'symmetric':\n"
      "the one map both sides refine (re-embedded on the flat torus before its final\n"
      "sweeps). output (quads as\n"
      ".obj .ply .off; triangles with triangulate=True or as .stl .drc; .glb triangles), image\n"
      "(.exr), dump_patches, meta_mesh, report are written when given.");

  m.def(
      "map_surfaces",
      [map_result](const py::object& a, const py::object& b, const py::object& features,
                   bool hold_features, double release_features_at, const py::object& output,
                   const py::object& meta_mesh, const std::vector<double>& morph, int morph_frames,
                   bool morph_glb, std::optional<int> level_sweeps,
                   const std::vector<int>& race_level_sweeps, std::optional<double> relaxation_gain,
                   const std::string& schedule, int threads, const py::object& report, bool quiet) {
        pipeline::MapSurfacesOptions o;
        o.a = one_surface(a, "a");
        o.b = one_surface(b, "b");
        if (!features.is_none()) {
          if (!is_path(features))
            throw py::type_error(
                "features must be a pairs file's path (lines 'IA IB' or "
                "'XA YA ZA XB YB ZB')");
          o.features = path_of(features);
        }
        o.hold_features = hold_features;
        o.release_features_at = release_features_at;
        o.output_prefix = optional_path(output);
        o.meta_mesh = optional_path(meta_mesh);
        o.morph = morph;
        o.morph_frames = morph_frames;
        o.morph_glb = morph_glb;
        o.level_sweeps = level_sweeps;
        o.race_level_sweeps = race_level_sweeps;
        o.relaxation_gain = relaxation_gain;
        const auto kind = pipeline::schedule_kind(schedule);
        if (!kind)
          throw py::value_error("schedule must be one of " + pipeline::schedule_names(", ") +
                                " (got '" + schedule + "')");
        o.schedule = *kind;
        o.threads = threads;
        auto [r, rep] =
            run_pipeline("ism-map", &pipeline::map_surfaces, o, common_options(report, quiet));
        const auto n = py::ssize_t(r.overlay.positions[0].size());
        return map_result(faces_array(r.overlay.triangles),
                          positions_array(r.overlay.positions[0], {n}),
                          positions_array(r.overlay.positions[1], {n}),
                          correspondence_arrays(r.correspondence[0]),
                          correspondence_arrays(r.correspondence[1]), rep);
      },
      "a"_a, "b"_a, py::kw_only(), "features"_a = py::none(), "hold_features"_a = false,
      "release_features_at"_a = 0.5, "output"_a = py::none(), "meta_mesh"_a = py::none(),
      "morph"_a = std::vector<double>{}, "morph_frames"_a = 0, "morph_glb"_a = false,
      "level_sweeps"_a = py::none(), "race_level_sweeps"_a = std::vector<int>{2, 3},
      "relaxation_gain"_a = py::none(), "schedule"_a = "auto", "threads"_a = 0,
      "report"_a = py::none(), "quiet"_a = false,
      "map_surfaces(a, b, *, features=None, ...) -> MapResult(faces, on_a, on_b, a_to_b, "
      "b_to_a, report)\n\n"
      "A continuous bijective piecewise-linear map between two closed surfaces of the same\n"
      "genus, as the ism-map tool (same options, same defaults, the same map): a and b are mesh\n"
      "file paths or tuples (V, F); features a pairs file (default automatic). The features are\n"
      "released at release_features_at of the refinement (0.5; 0 from the start) unless\n"
      "hold_features. schedule 'thorough', 'fast' or 'auto' (fast from 80000 faces together);\n"
      "level_sweeps and relaxation_gain left None are the schedule's. output (a prefix: the\n"
      "overlay pair and correspondence files, morphs with morph / morph_frames / morph_glb),\n"
      "meta_mesh and report are written when given.");

  m.def(
      "read_geometry_image",
      [](const py::object& path, bool with_alpha) -> py::object {
        const std::string file = path_of(path);
        GeometryImage image;
        try {
          image = read_geometry_image(file);
        } catch (const io::FileError& e) {
          throw tool::reading_failure(file, e);
        }
        // The file's float32 values, exactly.
        const auto n = py::ssize_t(image.n);
        py::array_t<float> out({n, n, py::ssize_t(3)});
        float* data = out.mutable_data();
        for (std::size_t i = 0; i < image.pixels.size(); ++i)
          for (int k = 0; k < 3; ++k) data[3 * i + k] = float(image.pixels[i][k]);
        if (!with_alpha) return py::object(std::move(out));
        return py::make_tuple(out, alpha_array(image));
      },
      "path"_a, "alpha"_a = false,
      "read_geometry_image(path, alpha=False) -> image (n, n, 3) float32\n"
      "read_geometry_image(path, alpha=True) -> (image, alpha)\n\n"
      "An octahedral geometry image (.exr, n = 2^k+1) as the file stores it: R, G, B = x, y, z,\n"
      "row 0 at the top (README, 'Geometry image layout'). alpha: the file's channel A as an\n"
      "(n, n) float32 array (1 on the input surface, 0 on the caps of its holes, as\n"
      "GimRemeshResult.alpha), None when the file has no A (a closed surface's image).");

  m.def(
      "geometry_image_mesh",
      [](const py::object& image_object) {
        py::array a = py::array::ensure(image_object);
        if (!a || a.ndim() != 3 || a.shape(0) != a.shape(1) || a.shape(2) != 3)
          throw py::value_error("image must have shape (n, n, 3), got " +
                                (a ? shape_of(a) : std::string("no array")));
        if (!is_geometry_image_size(int(a.shape(0))))
          throw py::value_error("image size must be 2^k+1, got " + std::to_string(a.shape(0)));
        const auto rows =
            float_rows(a.reshape(std::vector<py::ssize_t>{a.shape(0) * a.shape(1), 3}), "image", 3);
        GeometryImage image;
        image.n = int(a.shape(0));
        const auto p = rows.unchecked<2>();
        for (py::ssize_t i = 0; i < rows.shape(0); ++i)
          image.pixels.emplace_back(p(i, 0), p(i, 1), p(i, 2));
        const TriangleMesh mesh = image_to_mesh(image);
        return py::make_tuple(positions_array(mesh.positions, {py::ssize_t(mesh.n_vertices())}),
                              faces_array(mesh.triangles));
      },
      "image"_a,
      "geometry_image_mesh(image) -> (V, F)\n\n"
      "The closed genus-0 mesh an octahedral geometry image describes: (n-1)^2+2 vertices\n"
      "(mirrored border pixels shared), 2(n-1)^2 faces.");
}
