#include "mesh/mesh_check.hpp"

#include "mesh/boundary.hpp"

#include "mesh/edge_key.hpp"
#include "mesh/union_find.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <span>
#include <sstream>
#include <unordered_map>

namespace ism {
namespace {

// Bit pattern of a position with -0.0 folded into 0.0, so that welding merges
// exactly coincident points and nothing else.
struct PositionKey {
  std::array<std::uint64_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};
struct PositionKeyHash {
  std::size_t operator()(const PositionKey& k) const {
    std::size_t h = 0;
    for (std::uint64_t b : k.bits) h = (h ^ b) * 0x100000001b3ull + (h >> 29);
    return h;
  }
};
PositionKey key_of(const Vec3& p) {
  PositionKey key;
  for (int i = 0; i < 3; ++i) {
    double v = p[i] == 0.0 ? 0.0 : p[i];
    std::memcpy(&key.bits[i], &v, sizeof v);
  }
  return key;
}

// One use of an undirected edge by a face: the face and whether the face
// traverses it from the smaller to the larger vertex index.
struct EdgeUse {
  std::size_t face;
  int corner;  // the edge runs from corner to corner+1
  bool forward;
};

// For each input position, the input index of the vertex it is welded to.
// Exactly coincident positions are merged everywhere. Positions that differ
// by rounding only (1e-10 of the bounding-box diagonal) are merged when both
// lie on the boundary: that closes the seams of meshes exported unwelded
// (a UV sphere's seam at sin(2*pi) != 0) without touching interior detail.
std::vector<int> weld_targets(const PolygonSoup& soup, std::size_t& welded_count) {
  const std::size_t n = soup.positions.size();
  UnionFind sets(n);
  std::unordered_map<PositionKey, int, PositionKeyHash> seen;
  seen.reserve(n);
  Vec3 lo = Vec3::Constant(HUGE_VAL), hi = -lo;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = soup.positions[i];
    if (!p.allFinite()) continue;  // never merged: each stays a reported vertex
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    auto [it, inserted] = seen.try_emplace(key_of(p), int(i));
    if (!inserted) sets.unite(std::size_t(it->second), i);
  }

  // Boundary vertices after the exact weld: ends of edges used once (the
  // edges' keys sorted, each run of one key its uses).
  std::vector<std::uint64_t> edge_uses;
  for (const auto& face : soup.faces)
    for (std::size_t k = 0; k < face.size(); ++k) {
      int a = int(sets.find(face[k])), b = int(sets.find(face[(k + 1) % face.size()]));
      if (a != b) edge_uses.push_back(undirected_edge_key(a, b));
    }
  std::sort(edge_uses.begin(), edge_uses.end());
  std::vector<int> boundary;
  for (std::size_t i = 0; i < edge_uses.size();) {
    std::size_t j = i;
    while (j < edge_uses.size() && edge_uses[j] == edge_uses[i]) ++j;
    if (j - i == 1) {
      boundary.push_back(int(edge_uses[i] >> 32));
      boundary.push_back(int(edge_uses[i] & 0xffffffffu));
    }
    i = j;
  }
  std::sort(boundary.begin(), boundary.end());
  boundary.erase(std::unique(boundary.begin(), boundary.end()), boundary.end());
  // Pairs within the tolerance meet in a grid of cells of that size: each
  // point is compared with the earlier points of its cell and the 26 around
  // it, at most kMaxNearCandidates of them (a cluster of countless distinct
  // points within the tolerance is joined through the first ones; without
  // the cap a hostile file of 240,000 boundary points in one plane took
  // minutes).
  const double tolerance = 1e-10 * (hi - lo).norm();
  if (tolerance > 0 && std::isfinite(tolerance)) {
    constexpr int kMaxNearCandidates = 64;
    using Cell = std::array<std::int64_t, 3>;
    struct CellHash {
      std::size_t operator()(const Cell& c) const {
        std::uint64_t h = 0;
        for (std::int64_t x : c) h = (h ^ std::uint64_t(x)) * 0x9E3779B97F4A7C15ull + (h >> 31);
        return std::size_t(h);
      }
    };
    std::unordered_map<Cell, std::vector<int>, CellHash> cells;
    for (int v : boundary) {
      const Vec3& p = soup.positions[v];
      if (!p.allFinite()) continue;
      // Within the bounding box, so at most 1e10 cells along an axis.
      Cell cell;
      for (int k = 0; k < 3; ++k) cell[k] = std::int64_t(std::floor((p[k] - lo[k]) / tolerance));
      int compared = 0;
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            const auto it = cells.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
            if (it == cells.end()) continue;
            for (int w : it->second) {
              if (compared >= kMaxNearCandidates) break;
              ++compared;
              if ((soup.positions[w] - p).norm() <= tolerance) sets.unite(std::size_t(v), w);
            }
          }
      cells[cell].push_back(v);
    }
  }

  // The representative of a set is its smallest input index.
  std::vector<int> smallest(n, INT32_MAX);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t root = sets.find(i);
    smallest[root] = std::min(smallest[root], int(i));
  }
  std::vector<int> target(n);
  std::vector<char> used(n, 0);
  for (const auto& face : soup.faces)
    for (int v : face) used[v] = 1;
  welded_count = 0;
  for (std::size_t i = 0; i < n; ++i) {
    target[i] = smallest[sets.find(i)];
    if (used[i] && target[i] != int(i)) ++welded_count;
  }
  return target;
}

std::string plural(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

PreparedMesh prepare_mesh(const PolygonSoup& soup) {
  PreparedMesh out;
  MeshCheck& c = out.check;

  // Weld; remember one input index per vertex so that messages name
  // vertices the user can find in the file.
  const std::vector<int> target = weld_targets(soup, c.welded_vertices);
  c.input_faces = soup.faces.size();
  {
    std::vector<char> used(soup.positions.size(), 0);
    for (const auto& face : soup.faces)
      for (int v : face)
        if (!used[target[v]]) used[target[v]] = 1, ++c.distinct_positions;
  }
  std::vector<int> welded(soup.positions.size(), -1);
  std::vector<Vec3> positions;
  std::vector<int> input_index;
  for (std::size_t i = 0; i < soup.positions.size(); ++i) {
    if (target[i] != int(i)) continue;
    welded[i] = int(positions.size());
    positions.push_back(soup.positions[i]);
    input_index.push_back(int(i));
  }
  for (std::size_t i = 0; i < soup.positions.size(); ++i) welded[i] = welded[target[i]];

  // Triangulate polygons (fans) and drop faces that lost a corner to welding.
  std::vector<Triangle> triangles;
  triangles.reserve(soup.faces.size());
  std::vector<int> polygon, distinct;  // (reused: one face at a time)
  for (std::size_t f = 0; f < soup.faces.size(); ++f) {
    const auto& face = soup.faces[f];
    polygon.clear();
    for (int v : face) {
      int w = welded[v];
      if (polygon.empty() || polygon.back() != w) polygon.push_back(w);
    }
    while (polygon.size() > 1 && polygon.front() == polygon.back()) polygon.pop_back();
    distinct.assign(polygon.begin(), polygon.end());
    std::sort(distinct.begin(), distinct.end());
    if (polygon.size() < 3 ||
        std::adjacent_find(distinct.begin(), distinct.end()) != distinct.end()) {
      ++c.dropped_faces;
      continue;
    }
    if (polygon.size() > 3) ++c.triangulated_polygons;
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) {
      triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
      out.face_origin.push_back(int(f));
    }
  }

  // Drop vertices no face uses.
  std::vector<int> compact(positions.size(), -1);
  for (const Triangle& t : triangles)
    for (int v : t) compact[v] = 0;
  TriangleMesh& mesh = out.mesh;
  std::vector<int> vertex_input_index;
  for (std::size_t v = 0; v < positions.size(); ++v) {
    if (compact[v] < 0) continue;
    compact[v] = int(mesh.positions.size());
    mesh.positions.push_back(positions[v]);
    vertex_input_index.push_back(input_index[v]);
  }
  for (Triangle& t : triangles)
    for (int& v : t) v = compact[v];
  out.position_vertex.resize(soup.positions.size());
  for (std::size_t i = 0; i < soup.positions.size(); ++i)
    out.position_vertex[i] = compact[std::size_t(welded[i])];
  mesh.triangles = std::move(triangles);
  c.unreferenced_vertices = positions.size() - mesh.positions.size();
  for (const Vec3& p : mesh.positions)
    if (!p.allFinite()) ++c.nonfinite_coordinates;

  const std::size_t nv = mesh.n_vertices(), nf = mesh.n_faces();
  c.vertices = nv;
  c.faces = nf;
  if (nf == 0) return out;

  // Undirected edges and the faces that use them: every use sorted by key,
  // then face and corner, so that each edge's uses are one run (in face
  // order) and the edges come in key order. Each face's three edges by
  // their run, in key order.
  struct KeyedUse {
    std::uint64_t key;
    EdgeUse use;
  };
  std::vector<KeyedUse> uses_by_key;
  uses_by_key.reserve(3 * nf);
  std::vector<std::uint64_t> face_keys;
  face_keys.reserve(nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const Triangle& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      int a = t[k], b = t[(k + 1) % 3];
      uses_by_key.push_back({undirected_edge_key(a, b), {f, k, a < b}});
    }
    std::array<int, 3> sorted = t;
    std::sort(sorted.begin(), sorted.end());
    std::uint64_t h = (std::uint64_t(sorted[0]) * 0x9E3779B97F4A7C15ull) ^
                      (std::uint64_t(sorted[1]) << 21) ^ (std::uint64_t(sorted[2]) << 42);
    face_keys.push_back(h ^ std::uint64_t(sorted[2]));
  }
  std::sort(face_keys.begin(), face_keys.end());
  for (std::size_t i = 1; i < face_keys.size(); ++i)
    c.duplicate_faces += face_keys[i] == face_keys[i - 1];
  std::sort(uses_by_key.begin(), uses_by_key.end(), [](const KeyedUse& x, const KeyedUse& y) {
    if (x.key != y.key) return x.key < y.key;
    if (x.use.face != y.use.face) return x.use.face < y.use.face;
    return x.use.corner < y.use.corner;
  });
  // Runs: edge e's uses are uses_by_key[run[e] .. run[e + 1]).
  std::vector<std::size_t> run;
  for (std::size_t i = 0; i < uses_by_key.size(); ++i)
    if (i == 0 || uses_by_key[i].key != uses_by_key[i - 1].key) run.push_back(i);
  const std::size_t n_edges = run.size();
  run.push_back(uses_by_key.size());
  c.edges = n_edges;
  auto edge_uses = [&](std::size_t e) {
    return std::span<const KeyedUse>(uses_by_key.data() + run[e], run[e + 1] - run[e]);
  };

  // Corners around a vertex are joined across manifold edges; a vertex whose
  // corners fall into more than one fan is a non-manifold vertex.
  UnionFind corners(3 * nf);
  UnionFind boundary_vertices(nv);
  std::vector<char> on_boundary(nv, 0);
  for (std::size_t e = 0; e < n_edges; ++e) {  // (in key order: deterministic examples)
    const auto uses = edge_uses(e);
    const std::uint64_t key = uses[0].key;
    if (uses.size() > 2) {
      if (!c.example_nonmanifold_edge) {
        int a = int(key >> 32), b = int(key & 0xffffffffu);
        c.example_nonmanifold_edge = {vertex_input_index[a], vertex_input_index[b]};
      }
      ++c.nonmanifold_edges;
    } else if (uses.size() == 2) {
      for (int end = 0; end < 2; ++end) {
        const EdgeUse& u = uses[0].use;
        const EdgeUse& w = uses[1].use;
        int vu = mesh.triangles[u.face][(u.corner + end) % 3];
        int cu = int(3 * u.face) + (u.corner + end) % 3;
        // The same vertex sits at corner or corner+1 of the other face.
        int cw = mesh.triangles[w.face][w.corner] == vu ? int(3 * w.face) + w.corner
                                                        : int(3 * w.face) + (w.corner + 1) % 3;
        corners.unite(cu, cw);
      }
    } else {
      int a = int(key >> 32), b = int(key & 0xffffffffu);
      boundary_vertices.unite(a, b);
      on_boundary[a] = on_boundary[b] = 1;
    }
  }
  {
    std::vector<std::size_t> fan_of(nv, SIZE_MAX);
    std::vector<char> counted(nv, 0);
    for (std::size_t corner = 0; corner < 3 * nf; ++corner) {
      int v = mesh.triangles[corner / 3][corner % 3];
      std::size_t fan = corners.find(corner);
      if (fan_of[v] == SIZE_MAX) {
        fan_of[v] = fan;
      } else if (fan_of[v] != fan && !counted[v]) {
        counted[v] = 1;
        ++c.nonmanifold_vertices;
        if (!c.example_nonmanifold_vertex || vertex_input_index[v] < *c.example_nonmanifold_vertex)
          c.example_nonmanifold_vertex = vertex_input_index[v];
      }
    }
  }
  for (std::size_t v = 0; v < nv; ++v)
    if (on_boundary[v] && boundary_vertices.find(v) == v) ++c.boundary_loops;

  // Components (through shared vertices) and a consistent orientation per
  // component, propagated across manifold edges.
  UnionFind components(nv);
  for (const Triangle& t : mesh.triangles) {
    components.unite(t[0], t[1]);
    components.unite(t[1], t[2]);
  }
  for (std::size_t v = 0; v < nv; ++v)
    if (components.find(v) == v) ++c.components;

  std::vector<signed char> flip(nf, 0);  // 0 unvisited, +1 keep, -1 flip
  std::vector<std::size_t> stack;
  std::vector<std::array<std::size_t, 3>> face_edges(nf);
  {
    std::vector<int> filled(nf, 0);
    for (std::size_t e = 0; e < n_edges; ++e)
      for (const KeyedUse& u : edge_uses(e))
        face_edges[u.use.face][std::size_t(filled[u.use.face]++)] = e;
  }
  std::size_t flipped_in_components = 0;
  for (std::size_t seed = 0; seed < nf; ++seed) {
    if (flip[seed]) continue;
    std::vector<std::size_t> members{seed};
    flip[seed] = 1;
    stack.push_back(seed);
    while (!stack.empty()) {
      std::size_t f = stack.back();
      stack.pop_back();
      for (std::size_t e : face_edges[f]) {
        const auto uses = edge_uses(e);
        if (uses.size() != 2) continue;
        const EdgeUse& mine = uses[0].use.face == f ? uses[0].use : uses[1].use;
        const EdgeUse& other = uses[0].use.face == f ? uses[1].use : uses[0].use;
        // Neighbours agree when they traverse the shared edge in opposite directions.
        signed char wanted =
            mine.forward != other.forward ? flip[f] : static_cast<signed char>(-flip[f]);
        if (!flip[other.face]) {
          flip[other.face] = wanted;
          members.push_back(other.face);
          stack.push_back(other.face);
        } else if (flip[other.face] != wanted) {
          c.orientable = false;
        }
      }
    }
    // Keep the orientation most faces of the component already have.
    std::size_t flips =
        std::count_if(members.begin(), members.end(), [&](std::size_t f) { return flip[f] < 0; });
    if (2 * flips > members.size()) {
      for (std::size_t f : members) flip[f] = static_cast<signed char>(-flip[f]);
      flips = members.size() - flips;
    }
    flipped_in_components += flips;
  }

  c.euler_characteristic = long(nv) - long(c.edges) + long(nf);
  c.bounding_box_diagonal = bounding_box_diagonal(mesh);
  c.area = surface_area(mesh);
  const double tiny_area = 1e-14 * c.bounding_box_diagonal * c.bounding_box_diagonal;
  for (std::size_t f = 0; f < nf; ++f)
    if (!(face_area(mesh, f) > tiny_area)) ++c.degenerate_faces;
  if (c.degenerate_faces == nf && c.nonfinite_coordinates == 0) {
    c.zero_area = true;
    // Collinear: every vertex on the line from vertex 0 to the vertex
    // farthest from it (to rounding, 1e-12 of the diagonal).
    const Vec3& a = mesh.positions[0];
    Vec3 b = a;
    for (const Vec3& p : mesh.positions)
      if ((p - a).squaredNorm() > (b - a).squaredNorm()) b = p;
    const Vec3 axis = (b - a).normalized();
    const double tolerance = 1e-12 * c.bounding_box_diagonal;
    c.collinear = std::all_of(mesh.positions.begin(), mesh.positions.end(), [&](const Vec3& p) {
      return ((p - a) - (p - a).dot(axis) * axis).norm() <= tolerance;
    });
  }

  if (c.manifold() && c.orientable && c.nonfinite_coordinates == 0) {
    for (std::size_t f = 0; f < nf; ++f)
      if (flip[f] < 0) std::swap(mesh.triangles[f][1], mesh.triangles[f][2]);
    c.reoriented_faces = flipped_in_components;
    try {
      for (const auto& loop : boundary_loops(mesh))
        c.loops.push_back({loop.size(), loop_length(mesh, loop)});
    } catch (const std::invalid_argument&) {
      c.loops.clear();  // not simple loops: counted above, not listed
    }
    if (c.components == 1) {
      long twice_genus = 2 - c.euler_characteristic - long(c.boundary_loops);
      if (twice_genus >= 0 && twice_genus % 2 == 0) c.genus = int(twice_genus / 2);
      if (c.closed() && signed_volume(mesh) < 0) {
        for (Triangle& t : mesh.triangles) std::swap(t[1], t[2]);
        c.flipped_inward = true;
      }
    }
  }
  return out;
}

std::vector<std::string> MeshCheck::repairs() const {
  std::vector<std::string> r;
  if (welded_vertices)
    r.push_back("welded " + plural(welded_vertices, "coincident vertex", "coincident vertices"));
  if (triangulated_polygons)
    r.push_back("triangulated " + plural(triangulated_polygons, "polygon", "polygons"));
  if (dropped_faces)
    r.push_back("dropped " + plural(dropped_faces, "face", "faces") + " with repeated corners");
  if (unreferenced_vertices)
    r.push_back("removed " +
                plural(unreferenced_vertices, "unreferenced vertex", "unreferenced vertices"));
  if (reoriented_faces)
    r.push_back("reoriented " + plural(reoriented_faces, "face", "faces") +
                " to agree with their neighbours");
  if (flipped_inward) r.push_back("flipped all faces: the closed surface was oriented inward");
  return r;
}

std::vector<std::string> MeshCheck::defects() const {
  std::vector<std::string> d;
  if (faces == 0 && input_faces > 0 && distinct_positions <= 1)
    d.push_back("no faces: all " + plural(input_faces, "face", "faces") +
                " collapse, every vertex is at one point");
  else if (faces == 0 && input_faces > 0)
    d.push_back("no faces: all " + plural(input_faces, "face", "faces") +
                " collapse, their corners take only " + std::to_string(distinct_positions) +
                " distinct positions");
  else if (faces == 0)
    d.push_back("no faces");
  if (nonfinite_coordinates)
    d.push_back(plural(nonfinite_coordinates, "vertex", "vertices") +
                " with non-finite coordinates");
  if (collinear)
    d.push_back("all " + plural(vertices, "vertex", "vertices") +
                " lie on one line: every face has zero area");
  else if (zero_area)
    d.push_back("every face has zero area (" + plural(faces, "face", "faces") + ")");
  if (nonmanifold_edges) {
    std::string s = plural(nonmanifold_edges, "non-manifold edge", "non-manifold edges");
    if (example_nonmanifold_edge)
      s += " (e.g. vertices " + std::to_string(example_nonmanifold_edge->first) + "-" +
           std::to_string(example_nonmanifold_edge->second) + ")";
    d.push_back(s);
  }
  if (nonmanifold_vertices) {
    std::string s = plural(nonmanifold_vertices, "non-manifold vertex", "non-manifold vertices");
    if (example_nonmanifold_vertex)
      s += " (e.g. vertex " + std::to_string(*example_nonmanifold_vertex) + ")";
    d.push_back(s);
  }
  if (!orientable) d.push_back("non-orientable surface");
  if (components > 1)
    d.push_back(plural(components, "connected component", "connected components"));
  return d;
}

std::vector<std::string> MeshCheck::warnings() const {
  std::vector<std::string> w;
  if (degenerate_faces) w.push_back(plural(degenerate_faces, "zero-area face", "zero-area faces"));
  if (duplicate_faces) w.push_back(plural(duplicate_faces, "duplicate face", "duplicate faces"));
  return w;
}

std::optional<std::string> unmet_requirement(const MeshCheck& check,
                                             const MeshRequirements& needs) {
  auto defects = check.defects();
  // Geometry comes first among the defects only when it is the whole story.
  const bool geometry = check.faces > 0 && check.nonfinite_coordinates == 0 && check.zero_area;
  if (!defects.empty())
    return defects.front() + ", " + needs.tool +
           (geometry ? " needs a surface of positive area"
                     : " needs one connected, orientable 2-manifold");
  if (needs.closed && !check.closed())
    return plural(check.boundary_loops, "boundary loop", "boundary loops") + ", " + needs.tool +
           " needs a closed surface" +
           (needs.closed_advice.empty() ? "" : "; " + needs.closed_advice);
  if (needs.genus && check.genus != needs.genus)
    return "genus " + std::to_string(check.genus.value_or(-1)) + ", " + needs.tool +
           " needs genus " + std::to_string(*needs.genus);
  if (check.vertices < needs.min_vertices)
    return plural(check.vertices, "vertex", "vertices") + ", " + needs.tool + " needs at least " +
           std::to_string(needs.min_vertices) +
           (needs.min_vertices_reason.empty() ? "" : " (" + needs.min_vertices_reason + ")");
  return std::nullopt;
}

}  // namespace ism
