#include "map/piece_cdt.hpp"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <deque>

namespace ism {

namespace {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<int, Kernel>;
using FaceInfo = CGAL::Triangulation_face_base_with_info_2<int, Kernel>;
using FaceBase = CGAL::Constrained_triangulation_face_base_2<Kernel, FaceInfo>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Cdt =
    CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds, CGAL::No_constraint_intersection_tag>;
}  // namespace

std::optional<std::vector<std::array<int, 3>>> polygon_cdt(
    const std::vector<Eigen::Vector2d>& polygon) {
  const int n = int(polygon.size());
  if (n < 3) return std::nullopt;
  try {
    Cdt cdt;
    std::vector<Cdt::Vertex_handle> handle(n);
    for (int i = 0; i < n; ++i) {
      handle[i] = cdt.insert(Kernel::Point_2(polygon[i].x(), polygon[i].y()));
      handle[i]->info() = i;
    }
    if (int(cdt.number_of_vertices()) != n) return std::nullopt;  // repeated points
    for (int i = 0; i < n; ++i) cdt.insert_constraint(handle[i], handle[(i + 1) % n]);
    if (int(cdt.number_of_vertices()) != n) return std::nullopt;
    // Faces reachable from the infinite ones without crossing a constraint
    // are outside (info 0); the rest inside (info 1).
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
    std::deque<Cdt::Face_handle> queue;
    for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f)
      if (cdt.is_infinite(f)) f->info() = 0, queue.push_back(f);
    while (!queue.empty()) {
      Cdt::Face_handle f = queue.front();
      queue.pop_front();
      for (int k = 0; k < 3; ++k) {
        Cdt::Face_handle g = f->neighbor(k);
        if (g->info() != -1 || cdt.is_constrained(Cdt::Edge(f, k))) continue;
        g->info() = f->info();
        queue.push_back(g);
      }
    }
    std::vector<std::array<int, 3>> out;
    for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
      if (f->info() == 0) continue;
      if (f->info() == -1) {
        // Enclosed by constraints only: inside.
        f->info() = 1;
      }
      out.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
    }
    if (int(out.size()) != n - 2) return std::nullopt;
    return out;
  } catch (...) {
    return std::nullopt;
  }
}

}  // namespace ism
