#pragma once
// ism-info's pipeline: what a mesh is (sizes, topology, defects) and what
// reading it repaired. The command-line tool and the Python module both run it.
#include "mesh/mesh_check.hpp"
#include "report/json.hpp"
#include "tool/tool.hpp"

namespace ism::pipeline {

struct MeshInfo {
  MeshCheck check;
  Json info;  // to_json(check) and "file": ism-info --json
};

/// Reads (or takes) the mesh and checks it in `run` (stages "read", "check";
/// the info is appended to the report's "inputs"). A mesh that is not a valid
/// surface is described, not refused. Throws tool::Failure when the file
/// cannot be read (Kind::file when missing, Kind::input when malformed).
MeshInfo mesh_info(tool::Run& run, const tool::InputMesh& input);

}  // namespace ism::pipeline
