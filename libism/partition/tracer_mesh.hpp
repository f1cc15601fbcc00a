#pragma once
// Internal to partition: the mesh kernel on which path networks grow (paths
// mark vertices and edges; Steiner vertices come by edge splits, which keep
// every handle valid), shared by the one-surface and the two-surface tracer.
#include "partition/patches.hpp"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

namespace ism::partition_detail {

struct TracerTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::None);
  FaceAttributes(OpenMesh::Attributes::None);
  EdgeAttributes(OpenMesh::Attributes::None);
  HalfedgeAttributes(OpenMesh::Attributes::PrevHalfedge);
};
using TracerMesh = OpenMesh::TriMesh_ArrayKernelT<TracerTraits>;

}  // namespace ism::partition_detail
