// The symmetric map core: two surfaces, both refined, validated from both
// sides after every operation.
#include "map/inter_surface_map.hpp"
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "map/inter_surface_map_access.hpp"
#include "map/inter_surface_map_impl.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/compatible_networks.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "refine/refine_surfaces.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

namespace ism {

namespace {

/// A progressive mesh of a genus-0 surface down to the octahedron.
ProgressiveMesh octahedral_pm(const TriangleMesh& surface) {
  return simplify_constrained(trace_octahedral_network(surface), domain::octahedron());
}

/// A shared model decimated to about `vertices` vertices (positions kept).
TriangleMesh decimated_model(const char* name, std::size_t vertices) {
  const TriangleMesh full =
      prepare_mesh(io::read_polygon_soup(test::shared_models_dir() / name)).mesh;
  return base_mesh(simplify_to(full, vertices));
}

/// Progressive meshes of two surfaces of the same genus to one base: the
/// base of the first decimated to `base_vertices`, its vertices' nearest
/// points (bounding boxes matched) as the features of the second.
std::array<ProgressiveMesh, 2> common_base_pms(const TriangleMesh& a, const TriangleMesh& b,
                                               std::size_t base_vertices) {
  const ProgressiveMesh coarse = simplify_to(a, base_vertices);
  const TriangleMesh domain = base_mesh(coarse);
  auto box = [](const TriangleMesh& m) {
    Vec3 lo = m.positions[0], hi = lo;
    for (const Vec3& p : m.positions) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    return std::pair{lo, hi};
  };
  const auto [alo, ahi] = box(a);
  const auto [blo, bhi] = box(b);
  std::vector<int> fb;
  std::vector<char> taken(b.positions.size(), 0);
  for (int v : coarse.base_vertices) {
    const Vec3 u = (a.positions[v] - alo).cwiseQuotient(ahi - alo);
    int best = 0;
    double d = HUGE_VAL;
    for (std::size_t w = 0; w < b.positions.size(); ++w) {
      const double e = ((b.positions[w] - blo).cwiseQuotient(bhi - blo) - u).squaredNorm();
      if (e < d && !taken[w]) d = e, best = int(w);
    }
    taken[best] = 1;
    fb.push_back(best);
  }
  return {simplify_constrained(trace_path_network(a, domain, coarse.base_vertices), domain),
          simplify_constrained(trace_path_network(b, domain, fb), domain)};
}

/// Every InterSurfaceMap of this test binary cuts each face it takes from
/// its energy cache again and throws if the two differ.
const bool kCheckEnergyCache = [] { return setenv("ISM_CHECK_ENERGY_CACHE", "1", 1) == 0; }();

/// Refines both sides in turn (the side less refined first), optimising
/// every new vertex, its neighbours and the other side's vertices in its
/// ring (in random order), and relaxing from them after a hard split;
/// validates after every operation (every `validate_every`-th) and checks
/// that each kept move lowers the energy by its reported gain.
void refine_both_checked(InterSurfaceMap& map, std::size_t validate_every, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::size_t operations = 0;
  auto check = [&](const char* what, int side, int v) {
    if (++operations % validate_every) return;
    const auto problem = map.validate();
    ASSERT_FALSE(problem) << what << " side " << side << " vertex " << v << ": " << *problem;
  };
  // A hard split (a nearly degenerate piece the ring's one pass may not
  // undo; later splits there compound it) is relaxed from the same
  // vertices, as refine_surfaces does, each kept move checked the same way
  // (on_step); 10 moves per vertex (refine_surfaces: 50) keep the
  // validation's cost down.
  SurfaceRefineOptions options;
  options.hard_split_relaxation = 10;
  double last = 0;  // the energy before the relaxation's next move
  options.on_step = [&](const SurfaceStep& step) {
    const double now = map.energy();
    EXPECT_NEAR(last - now, step.gain, 1e-9 * last)
        << "side " << step.side << " vertex " << step.vertex;
    last = now;
    check("relaxing", step.side, step.vertex);
  };
  for (;;) {
    const double f0 = map.splits_total(0) ? double(map.splits_applied(0)) / map.splits_total(0) : 1;
    const double f1 = map.splits_total(1) ? double(map.splits_applied(1)) / map.splits_total(1) : 1;
    if (f0 >= 1 && f1 >= 1) break;
    const int side = f0 <= f1 ? 0 : 1;
    const int vs = map.split_next(side);
    ASSERT_GE(vs, 0);
    check("split", side, vs);
    if (::testing::Test::HasFatalFailure()) return;
    // The new ring on the split side, then the other side's vertices in it.
    std::vector<std::pair<int, int>> todo;
    for (int v : map.neighbours(side, vs)) todo.push_back({side, v});
    todo.push_back({side, vs});
    std::shuffle(todo.begin(), todo.end(), random);
    for (int x : map.others_in_ring(side, vs)) todo.push_back({1 - side, x});
    for (const auto& [s, v] : todo) {
      if (!map.is_active(s, v)) continue;
      const double before = map.energy();
      const double gain = map.optimize_vertex(s, v);
      const double after = map.energy();
      ASSERT_GE(gain, 0.0);
      ASSERT_NEAR(before - after, gain, 1e-9 * before) << "side " << s << " vertex " << v;
      if (gain > 0) check("optimising", s, v);
      if (::testing::Test::HasFatalFailure()) return;
    }
    if (!(map.last_split_growth() > options.hard_split_growth)) continue;
    last = map.energy();
    surfaces_relax_from(map, options, todo, options.hard_split_relaxation * todo.size());
    if (::testing::Test::HasFailure()) return;
  }
}

/// Two shared models decimated to `vertices` each, their progressive meshes
/// to one base from the two-surface partition (features added by it).
std::array<ProgressiveMesh, 2> compatible_pms(const char* a, const char* b, std::size_t vertices,
                                              int genus) {
  const CompatibleNetworks networks =
      trace_compatible_networks(decimated_model(a, vertices), decimated_model(b, vertices), {});
  EXPECT_EQ(networks.genus, genus);
  return simplify_compatible(networks);
}

/// Both sides of the map between two progressive meshes refined by
/// refine_both_checked (validated after every operation), then the whole
/// map checked from both sides and each side's faces counted against its
/// replayed mesh; prints the measures and returns them (zeros after a
/// failure).
MapMeasures refine_pair_checked(const char* name, const std::array<ProgressiveMesh, 2>& pms,
                                std::uint64_t seed) {
  InterSurfaceMap map(side_from_pm(pms[0]), side_from_pm(pms[1]));
  refine_both_checked(map, 1, seed);
  if (::testing::Test::HasFatalFailure()) return {};
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(0), replay(pms[0]).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pms[1]).n_faces());
  const MapMeasures m = map.measures();
  const auto& st = map.stats();
  std::printf(
      "%s, %zu / %zu faces: symmetric efficiency %.4f (%.4f, %.4f); splits retried %zu, in "
      "place %zu, placed with the old vertex moved %zu; moves %zu (general charts %zu of %zu "
      "optimisations), %zu predicted more than 1 %% off, worst %.4f\n",
      name, map.n_faces(0), map.n_faces(1), m.symmetric_efficiency, m.forward_efficiency,
      m.backward_efficiency, st.split_retries, st.splits_in_place, st.splits_old_moved, st.moves,
      st.general, st.optimizations, st.mispredicted, st.worst_prediction);
  // A chart's energy at the place it chose is the energy the move leaves
  // (cells located in their faces by the places on the ring they keep):
  // within 1 % for all but a few moves, whose non-affine pieces the move
  // fans anew. (Located by geometry alone, 31 % off on spot / bunny_small
  // and 46 % on torus / cup.) The worst single move swings with the path:
  // 0.056 / 0.151 / 0.185 on spot, torus and genus 2 before Newton steps
  // replaced the line searches in fast charts, 0.056 / 0.151 / 0.304 after.
  EXPECT_LT(st.mispredicted, st.moves / 50);
  EXPECT_LT(st.worst_prediction, 0.35);
  return m;
}

TEST(InterSurfaceMap, TrivialMapOfTwoBasesIsValid) {
  const TriangleMesh a = shapes::sphere(200), b = shapes::blob(300);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  EXPECT_FALSE(map.validate());
  EXPECT_GT(map.measures().symmetric_efficiency, 0.0);
  EXPECT_EQ(map.n_vertices(0), 6u);
  EXPECT_EQ(map.n_faces(1), 8u);
}

TEST(InterSurfaceMap, SmallPairIsDeterministic) {
  const TriangleMesh a = shapes::sphere(100), b = shapes::blob(120, 5);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  std::array<double, 2> energy{};
  for (int run = 0; run < 2; ++run) {
    InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
    refine_both_checked(map, 10, 7);
    if (HasFatalFailure()) return;
    energy[run] = map.energy();
  }
  EXPECT_EQ(energy[0], energy[1]);
}

/// Kinks that keep the edges' images as they are: on every edge of `side` whose first
/// break is a crossing and whose first vertex lies inside a face of the
/// other side, a kink half-way to that crossing (a bend of angle zero; the
/// pieces beside it get a corner more, so their triangulations may change).
/// Returns how many were added.
std::size_t add_straight_kinks(MetaMesh& meta, int side) {
  const MetaIndex index = build_index(meta);
  MetaSide& S = meta.side[side];
  const int t = 1 - side;
  std::size_t added = 0;
  for (std::size_t e = 0; e < S.edges.size(); ++e) {
    auto& list = S.crossings[e];
    if (list.empty() || list.front().is_kink()) continue;
    const MetaLocation& loc = S.location[S.edges[e][0]];
    if (loc.face < 0) continue;
    const auto first = break_node(meta, side, int(e), 0);
    if (!first) continue;
    const int f = loc.face;
    const auto a = place_in_face(meta, t, f, vertex_node(meta, side, S.edges[e][0]).place[t]);
    const auto b = place_in_face(meta, t, f, first->place[t]);
    if (!a || !b) continue;
    const std::array<Vec2, 3> L = meta_face_layout(meta.side[t].lengths[f]);
    const Eigen::Vector3d bary = barycentric(0.5 * (*a + *b), L[0], L[1], L[2]);
    if (!(bary.minCoeff() > 0)) continue;
    list.insert(list.begin(), MetaCrossing{-1, 0.5 * list.front().here, 0, f, bary / bary.sum()});
    ++added;
  }
  return added;
}

// A map of the two-sided core with kinks goes through the meta-mesh file
// (version 2, k records) and comes back the same map, bit for bit. Kinks
// are rare (paper §5.1): the map gets straight ones added (same images).
TEST(InterSurfaceMap, MapWithKinksReadsBackFromItsFile) {
  const TriangleMesh a = shapes::sphere(100), b = shapes::blob(120, 5);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  refine_both_checked(map, 10, 7);
  if (HasFatalFailure()) return;
  MetaMesh meta = map.meta();
  const MetaMeshSize before = meta_mesh_size(meta);
  for (int side = 0; side < 2; ++side) EXPECT_GT(add_straight_kinks(meta, side), 0u);
  ASSERT_EQ(validate(meta), std::nullopt);
  const MetaMeshSize size = meta_mesh_size(meta);
  std::printf("kinks %zu (%zu made by the map), crossings %zu\n", size.kinks, before.kinks,
              size.crossings);
  ASSERT_GT(size.kinks, before.kinks);
  EXPECT_EQ(size.crossings, before.crossings);
  EXPECT_NEAR(measures(meta)->symmetric_efficiency, map.measures().symmetric_efficiency, 1e-3);
  const auto path = std::filesystem::temp_directory_path() / "ism_meta_mesh_kinks.meta";
  ASSERT_TRUE(write_meta_mesh(meta, path));
  std::string header;
  {
    std::ifstream in(path);
    std::getline(in, header);
  }
  EXPECT_EQ(header, "ism-meta-mesh 2");
  const MetaMesh back = read_meta_mesh(path);
  EXPECT_EQ(validate(back), std::nullopt);
  // The reader numbers edges its own way: compare edge by edge through
  // their vertices.
  for (int m = 0; m < 2; ++m) {
    const MetaSide &x = meta.side[m], &y = back.side[m];
    const MetaSide &xo = meta.side[1 - m], &yo = back.side[1 - m];
    ASSERT_EQ(x.faces, y.faces);
    ASSERT_EQ(x.edges.size(), y.edges.size());
    std::map<std::array<int, 2>, std::size_t> in_y;
    for (std::size_t e = 0; e < y.edges.size(); ++e) in_y[y.edges[e]] = e;
    for (std::size_t e = 0; e < x.edges.size(); ++e) {
      ASSERT_TRUE(in_y.count(x.edges[e]));
      const auto& a = x.crossings[e];
      const auto& b = y.crossings[in_y[x.edges[e]]];
      ASSERT_EQ(a.size(), b.size()) << "side " << m << " edge " << e;
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a[i].is_kink(), b[i].is_kink());
        EXPECT_EQ(a[i].here, b[i].here);
        if (a[i].is_kink()) {
          EXPECT_EQ(a[i].face, b[i].face);
          EXPECT_EQ(a[i].bary, b[i].bary);
        } else {
          EXPECT_EQ(xo.edges[a[i].edge], yo.edges[b[i].edge]);
          EXPECT_EQ(a[i].there, b[i].there);
        }
      }
    }
  }
  const MetaMeshSize back_size = meta_mesh_size(back);
  EXPECT_EQ(back_size.kinks, size.kinks);
  EXPECT_EQ(back_size.crossings, size.crossings);
  // Same pieces; summed in the reader's edge order, so equal to rounding.
  EXPECT_NEAR(measures(back)->symmetric_efficiency, measures(meta)->symmetric_efficiency, 1e-13);
  EXPECT_EQ(back_size.pieces, size.pieces);

  // Damaged kink records: one line each, naming the line.
  std::vector<std::string> lines;
  for (std::ifstream in(path); std::getline(in, header);) lines.push_back(header);
  std::size_t k = 0;
  while (k < lines.size() && lines[k].rfind("k ", 0) != 0) ++k;
  ASSERT_LT(k, lines.size());
  auto refused = [&](std::vector<std::string> file) {
    {
      std::ofstream out(path);
      for (const auto& l : file) out << l << '\n';
    }
    try {
      read_meta_mesh(path);
    } catch (const io::FileError& e) {
      return std::string(e.what());
    }
    return std::string("read");
  };
  auto with_kink = [&](const std::string& record) {
    auto file = lines;
    file[k] = record;
    return file;
  };
  const std::string line_no = ":" + std::to_string(k + 1) + ": ";
  auto v1 = lines;
  v1[0] = "ism-meta-mesh 1";
  EXPECT_NE(refused(v1).find(line_no + "kink record in a version 1 file"), std::string::npos);
  EXPECT_NE(refused(with_kink("k 0 0 1 0.5 99999 0.2 0.3 0.5")).find(line_no + "a kink in no face"),
            std::string::npos);
  EXPECT_NE(refused(with_kink("k 1 0 1 0.5 0 0.2 0.3 0.6")).find(line_no + "a kink's barycentric"),
            std::string::npos);
  EXPECT_NE(refused(with_kink("k 1 0 1 1.5 0 0.2 0.3 0.5")).find(line_no + "a kink's parameter"),
            std::string::npos);
  EXPECT_NE(refused(with_kink("k 2 0 1 0.5 0 0.2 0.3 0.5")).find(line_no + "bad kink"),
            std::string::npos);
  EXPECT_NE(refused(with_kink("k 0 0 0 0.5 0 0.2 0.3 0.5")).find(line_no + "a kink of no edge"),
            std::string::npos);
  std::filesystem::remove(path);
}

/// An independent check of the meta-mesh: the edges of `side`, drawn
/// straight between their break points inside the faces of the other side,
/// never cross each other there (two segments crossing at a point that is
/// not an end of both). Returns how many pairs cross.
std::size_t crossing_segments(const MetaMesh& meta, int side) {
  const MetaIndex index = build_index(meta);
  const int t = 1 - side;
  const MetaSide& S = meta.side[side];
  std::vector<std::vector<std::array<Vec2, 2>>> in_face(meta.side[t].faces.size());
  std::vector<int> fa, fb;
  for (std::size_t e = 0; e < S.edges.size(); ++e) {
    if (S.edges[e][0] < 0) continue;
    std::vector<MetaNode> nodes{vertex_node(meta, side, S.edges[e][0])};
    for (std::size_t i = 0; i < S.crossings[e].size(); ++i)
      if (const auto node = break_node(meta, side, int(e), int(i))) nodes.push_back(*node);
    nodes.push_back(vertex_node(meta, side, S.edges[e][1]));
    for (std::size_t j = 0; j + 1 < nodes.size(); ++j) {
      place_faces(meta, index, t, nodes[j].place[t], fa);
      place_faces(meta, index, t, nodes[j + 1].place[t], fb);
      for (int f : fa) {
        if (std::find(fb.begin(), fb.end(), f) == fb.end()) continue;
        const auto a = place_in_face(meta, t, f, nodes[j].place[t]);
        const auto b = place_in_face(meta, t, f, nodes[j + 1].place[t]);
        if (a && b) in_face[f].push_back({*a, *b});
      }
    }
  }
  std::size_t crossings = 0;
  for (const auto& list : in_face)
    for (std::size_t i = 0; i < list.size(); ++i)
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const auto &p = list[i], &q = list[j];
        const double scale = std::max((p[1] - p[0]).squaredNorm(), (q[1] - q[0]).squaredNorm());
        const double tol = 1e-12 * scale;
        const double o1 = orient(p[0], p[1], q[0]), o2 = orient(p[0], p[1], q[1]);
        const double o3 = orient(q[0], q[1], p[0]), o4 = orient(q[0], q[1], p[1]);
        if (((o1 > tol && o2 < -tol) || (o1 < -tol && o2 > tol)) &&
            ((o3 > tol && o4 < -tol) || (o3 < -tol && o4 > tol)))
          ++crossings;
      }
  return crossings;
}

// Kinks (paper §5.1): by the paper's rule an edge bends inside a face of
// the other side only where the straight segment there would leave its
// cell; following the cells' maps, wherever its cell is not affine. Right
// after every move, each run of kinks the moved vertex's edges got is taken
// out again (the edge straight across that face): by the paper's rule the
// map must then be invalid. Both rules give maps valid from both sides, also
// by an independent check (no two edges of a side cross inside a face of the
// other); pieces not convex on a side are counted with those the overlay
// had to triangulate.
void refine_checking_kinks(KinkRule rule) {
  const TriangleMesh a = shapes::sphere(100), b = shapes::blob(120, 5);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceOptions options;
  options.kinks = rule;
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb), options);
  std::mt19937_64 random(7);
  std::size_t runs = 0, needed = 0;
  // The runs of kinks on the edges of vertex v of side s.
  auto check_kinks = [&](int s, int v) {
    const MetaMesh& meta = map.meta();
    const MetaSide& S = meta.side[s];
    for (std::size_t e = 0; e < S.edges.size(); ++e) {
      if (S.edges[e][0] != v && S.edges[e][1] != v) continue;
      const auto& list = S.crossings[e];
      for (std::size_t i = 0; i < list.size();) {
        if (!list[i].is_kink()) {
          ++i;
          continue;
        }
        std::size_t j = i;
        while (j < list.size() && list[j].is_kink()) ++j;
        ++runs;
        if (rule == KinkRule::where_needed) {
          MetaMesh straight = meta;
          auto& cut = straight.side[s].crossings[e];
          cut.erase(cut.begin() + std::ptrdiff_t(i), cut.begin() + std::ptrdiff_t(j));
          if (validate(straight)) ++needed;
        }
        i = j;
      }
    }
  };
  while (map.splits_applied(0) < map.splits_total(0) ||
         map.splits_applied(1) < map.splits_total(1)) {
    const int side = map.splits_applied(0) * map.splits_total(1) <=
                                 map.splits_applied(1) * map.splits_total(0) &&
                             map.splits_applied(0) < map.splits_total(0)
                         ? 0
                         : 1;
    const int vs = map.split_next(side);
    ASSERT_GE(vs, 0);
    std::vector<std::pair<int, int>> todo;
    for (int v : map.neighbours(side, vs)) todo.push_back({side, v});
    todo.push_back({side, vs});
    std::shuffle(todo.begin(), todo.end(), random);
    for (int x : map.others_in_ring(side, vs)) todo.push_back({1 - side, x});
    for (const auto& [s, v] : todo)
      if (map.is_active(s, v) && map.optimize_vertex(s, v) > 0) check_kinks(s, v);
  }
  ASSERT_FALSE(map.validate());
  EXPECT_EQ(crossing_segments(map.meta(), 0), 0u);
  EXPECT_EQ(crossing_segments(map.meta(), 1), 0u);
  const MetaMeshSize size = meta_mesh_size(map.meta());
  std::size_t non_convex = 0;
  const auto pieces = meta_pieces(map.meta());
  ASSERT_TRUE(pieces);
  for (const MetaPiece& piece : *pieces)
    for (int s = 0; s < 2; ++s) {
      const auto& c = piece.corner[s];
      bool convex = true;
      for (std::size_t k = 0; k < c.size(); ++k)
        convex &=
            orient(c[k], c[(k + 1) % c.size()], c[(k + 2) % c.size()]) >= -1e-9 * piece.area[s];
      if (!convex) {
        ++non_convex;
        break;
      }
    }
  std::printf(
      "kinks %s: runs made %zu (needed %zu); at the end %zu kinks, %zu pieces, %zu not convex, "
      "%zu triangulated\n",
      rule == KinkRule::where_needed ? "where needed" : "following the cells", runs, needed,
      size.kinks, size.pieces, non_convex, size.triangulated_pieces);
  if (rule == KinkRule::where_needed) {
    EXPECT_EQ(needed, runs);
  } else {
    EXPECT_GT(runs, 0u);
    EXPECT_GT(size.triangulated_pieces, 0u);
  }
}

TEST(InterSurfaceMap, KinksOnlyWhereNeededAreNeeded) {
  refine_checking_kinks(KinkRule::where_needed);
}

TEST(InterSurfaceMap, KinksFollowingTheCellsKeepTheMapValid) {
  refine_checking_kinks(KinkRule::follow_cells);
}

bool same_side(const MetaSide& a, const MetaSide& b) {
  auto same_location = [](const MetaLocation& x, const MetaLocation& y) {
    return x.vertex == y.vertex && x.face == y.face && x.bary == y.bary;
  };
  auto same_crossing = [](const MetaCrossing& x, const MetaCrossing& y) {
    return x.edge == y.edge && x.here == y.here && x.there == y.there && x.face == y.face &&
           x.bary == y.bary;
  };
  return a.faces == b.faces && a.lengths == b.lengths && a.edges == b.edges &&
         a.face_edges == b.face_edges && a.positions == b.positions &&
         std::equal(a.location.begin(), a.location.end(), b.location.begin(), b.location.end(),
                    same_location) &&
         std::equal(a.crossings.begin(), a.crossings.end(), b.crossings.begin(), b.crossings.end(),
                    [&](const auto& p, const auto& q) {
                      return std::equal(p.begin(), p.end(), q.begin(), q.end(), same_crossing);
                    });
}

bool same_index(const MetaSideIndex& a, const MetaSideIndex& b) {
  return a.edge_faces == b.edge_faces && a.vertex_edges == b.vertex_edges &&
         a.vertex_faces == b.vertex_faces && a.residents == b.residents && a.edge_of == b.edge_of;
}

TEST(InterSurfaceMap, AnUndoneSplitLeavesTheMapExactlyAsItWas) {
  // Before every split of both sides' refinement: the split's connectivity
  // change made and undone (what split_next does when the new vertex finds
  // no place) gives back the same meta-mesh, index, counts and energy.
  const TriangleMesh a = shapes::sphere(300), b = shapes::blob(400, 3);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  std::size_t undone = 0;
  for (int step = 0;; ++step) {
    const int side = step % 2 == 0 && map.splits_applied(0) < map.splits_total(0) ? 0 : 1;
    if (map.splits_applied(side) >= map.splits_total(side)) break;
    const MetaMesh meta = map.meta();
    const MetaIndex index = InterSurfaceMapTestAccess::index(map);
    const std::size_t applied = map.splits_applied(side), active = map.n_vertices(side);
    const double area = map.area(side), energy = map.energy();
    ASSERT_EQ(InterSurfaceMapTestAccess::split_and_undo(map, side), -1);
    ++undone;
    for (int s = 0; s < 2; ++s) {
      ASSERT_TRUE(same_side(map.meta().side[s], meta.side[s])) << "step " << step << " side " << s;
      ASSERT_TRUE(same_index(InterSurfaceMapTestAccess::index(map)[s], index[s]))
          << "step " << step << " side " << s;
    }
    ASSERT_EQ(map.splits_applied(side), applied);
    ASSERT_EQ(map.n_vertices(side), active);
    ASSERT_EQ(map.area(side), area);
    ASSERT_EQ(map.energy(), energy);
    const int vs = map.split_next(side);
    ASSERT_GE(vs, 0);
    for (int v : map.neighbours(side, vs)) map.optimize_vertex(side, v);
    map.optimize_vertex(side, vs);
  }
  EXPECT_EQ(undone, map.splits_total(0) + map.splits_total(1));
  EXPECT_GT(undone, 100u);
  EXPECT_FALSE(map.validate());
}

TEST(InterSurfaceMap, SplitsPlacedInTheSecondRoundOrRefusedKeepTheMapValid) {
  // The retries no generated pair needs (the bench's teapot rows do): a
  // split whose first round of attempts all fail is placed in the second
  // round, after its neighbourhood was moved; one failing every attempt of
  // both rounds throws, the map still valid at the split before and no
  // higher in energy; refinement then goes on to full resolution.
  const TriangleMesh a = shapes::sphere(300), b = shapes::blob(400, 3);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  constexpr int kRound = InterSurfaceMap::kSplitRetries + 1;
  std::size_t later = 0, refused = 0;
  for (int step = 0;; ++step) {
    const int side = step % 2 == 0 && map.splits_applied(0) < map.splits_total(0) ? 0 : 1;
    if (map.splits_applied(side) >= map.splits_total(side)) break;
    const std::size_t applied = map.splits_applied(side), retries = map.stats().split_retries;
    if (step % 100 == 50) {  // fails every attempt: throws, nothing applied
      const double energy = map.energy();
      InterSurfaceMapTestAccess::refuse_split_attempts(map, InterSurfaceMap::kSplitRounds * kRound);
      try {
        map.split_next(side);
        ADD_FAILURE() << "step " << step << ": a split refused every attempt was placed";
        return;
      } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no valid placement"), std::string::npos) << e.what();
      }
      ++refused;
      ASSERT_EQ(map.splits_applied(side), applied) << "step " << step;
      ASSERT_EQ(map.stats().split_retries, retries + InterSurfaceMap::kSplitRounds * kRound - 1);
      ASSERT_LE(map.energy(), energy * (1 + 1e-12)) << "step " << step;
      ASSERT_EQ(map.validate(), std::nullopt) << "step " << step << ": " << *map.validate();
    }
    const bool second_round = step % 12 == 0;
    const std::size_t later_before = map.stats().splits_later_round;
    if (second_round) InterSurfaceMapTestAccess::refuse_split_attempts(map, kRound);
    const int vs = map.split_next(side);
    ASSERT_GE(vs, 0) << "step " << step;
    ASSERT_EQ(map.splits_applied(side), applied + 1);
    if (second_round) {
      ++later;
      ASSERT_EQ(map.stats().splits_later_round, later_before + 1) << "step " << step;
      ASSERT_GE(map.stats().split_retries, retries + kRound);
      ASSERT_EQ(map.validate(), std::nullopt) << "step " << step << ": " << *map.validate();
    }
    for (int v : map.neighbours(side, vs)) map.optimize_vertex(side, v);
    map.optimize_vertex(side, vs);
  }
  std::printf("%zu splits placed in the second round, %zu refused; %zu retries\n", later, refused,
              map.stats().split_retries);
  EXPECT_GT(later, 20u);
  EXPECT_GE(refused, 3u);
  EXPECT_EQ(map.n_faces(0), replay(pa).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pb).n_faces());
  EXPECT_EQ(map.validate(), std::nullopt);
  EXPECT_GT(map.measures().symmetric_efficiency, 0.3);
}

TEST(InterSurfaceMap, BothSidesRefineSphereAndBlob) {
  const TriangleMesh a = shapes::sphere(300), b = shapes::blob(400, 3);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  refine_both_checked(map, 1, 1);
  if (HasFatalFailure()) return;
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(0), replay(pa).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pb).n_faces());
  const MapMeasures m = map.measures();
  const auto& st = map.stats();
  std::printf(
      "sphere %zu / blob %zu faces: symmetric efficiency %.4f (%.4f, %.4f); optimisations %zu, "
      "moves %zu, fast %zu, developed %zu, general %zu, rejected %zu; %zu predicted more than 1 "
      "%% off, worst %.4f\n",
      a.n_faces(), b.n_faces(), m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency,
      st.optimizations, st.moves, st.fast_path, st.developed, st.general, st.rejected,
      st.mispredicted, st.worst_prediction);
  EXPECT_GT(m.symmetric_efficiency, 0.3);
  EXPECT_LT(st.mispredicted, st.moves / 50);  // as in refine_pair_checked
  EXPECT_LT(st.worst_prediction, 0.25);
}

// The remeshers' case on the symmetric core: side 0 an abstract domain (the
// equilateral octahedron) that never refines, side 1 a surface refined to
// full resolution; the domain's vertices released (they move inside the
// surface's faces), validated after every operation.
TEST(InterSurfaceMap, SurfaceOverTheOctahedronRefinesOneSide) {
  const TriangleMesh surface = shapes::blob(800, 2);
  const ProgressiveMesh pm = octahedral_pm(surface);
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry domain(octahedron, equilateral_lengths(octahedron));
  InterSurfaceMap map(side_from_domain(domain, pm), side_from_pm(pm));
  refine_both_checked(map, 1, 3);
  if (HasFatalFailure()) return;
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(0), 8u);
  EXPECT_EQ(map.n_faces(1), replay(pm).n_faces());
  const MapMeasures m = map.measures();
  const auto& st = map.stats();
  std::printf(
      "blob %zu faces over the octahedron: symmetric efficiency %.4f (%.4f, %.4f); "
      "optimisations %zu, fast %zu, developed %zu, general %zu\n",
      surface.n_faces(), m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency,
      st.optimizations, st.fast_path, st.developed, st.general);
  // One-rings inside one face of the coarse domain take the fast path (32 %
  // of the optimisations here; 65 % on sphere.obj's 5K faces).
  EXPECT_GT(st.fast_path, st.optimizations / 5);
  // Rings across the domain's edges are charted by their exact development
  // (the domain is flat there), so most are isometric and take the
  // triangles' energy: 30 % of the optimisations here, general 38 % (with
  // the law of cosines alone none was developed and 67 % general: the edges
  // a cone's move bends were never straightened).
  EXPECT_GT(st.developed, st.optimizations / 5);
  EXPECT_GT(m.symmetric_efficiency, 0.9);  // measured 0.958
}

// The anisotropy penalty (torus-remesh's fallback variants) is in every
// energy the core lowers: the refinement's exact gains hold with it (the
// domain's vertices charted large, where the pieces' stretch is summed per
// face and the penalty per part), and the map's energy is the plain one
// plus each piece's penalty computed here from its triangles' Jacobians.
TEST(InterSurfaceMap, TheAnisotropyPenaltyIsInEveryEnergy) {
  const TriangleMesh surface = shapes::blob(400, 2);
  const ProgressiveMesh pm = octahedral_pm(surface);
  const TriangleMesh octahedron = domain::octahedron();
  const DomainGeometry domain(octahedron, equilateral_lengths(octahedron));
  const double weight = 1, threshold = 1.2;  // bites on much of the map
  InterSurfaceOptions options;
  options.anisotropy_weight = weight;
  options.anisotropy_threshold = threshold;
  // The penalty of a map from its pieces' triangles' Jacobians; how many
  // pieces it bites on.
  auto penalty_of = [&](const MetaMesh& meta, double total_area1, std::size_t& biting) {
    const auto pieces = meta_pieces(meta);
    EXPECT_TRUE(pieces);
    double penalty = 0, area1 = 0;
    biting = 0;
    for (const MetaPiece& piece : pieces ? *pieces : std::vector<MetaPiece>{}) {
      const PieceTriangulation tri = triangulate_piece(piece);
      EXPECT_FALSE(tri.triangles.empty());
      const auto& [p, q] = tri.points;
      bool bites = false;
      for (const auto& t : tri.triangles) {
        const std::array<Vec2, 3> a{p[t[0]], p[t[1]], p[t[2]]}, b{q[t[0]], q[t[1]], q[t[2]]};
        const Eigen::Matrix2d J = affine_linear_part(a, b);
        const double area = 0.5 * orient(b[0], b[1], b[2]);
        const double excess =
            std::max(0.0, J.squaredNorm() / J.determinant() - (threshold + 1 / threshold));
        penalty += weight * area * excess * excess;
        area1 += area;
        bites |= excess > 0;
      }
      biting += bites;
    }
    EXPECT_NEAR(area1, total_area1, 1e-9 * area1);
    return penalty / total_area1;
  };
  InterSurfaceMap map(side_from_domain(domain, pm), side_from_pm(pm), options);
  refine_both_checked(map, 1, 3);
  if (HasFatalFailure()) return;
  ASSERT_FALSE(map.validate());
  EXPECT_GT(map.stats().general, 0u);
  const InterSurfaceMap plain(map.meta(), side_from_domain(domain, pm), side_from_pm(pm),
                              {0, map.splits_applied(1)});
  std::size_t biting = 0;
  const double penalty = penalty_of(map.meta(), map.area(1), biting);
  EXPECT_GT(biting, map.n_faces(1) / 10);
  EXPECT_GT(penalty, 1e-3 * plain.energy());
  EXPECT_NEAR(map.energy(), plain.energy() + penalty, 1e-9 * map.energy());
  // A domain vertex's chart is large: its ring's energy summed per face of
  // the surface is the cells' (the penalty added part by part).
  std::size_t compared = 0;
  for (int v = 0; v < 6; ++v)
    for (const Vec2& offset : {Vec2(0.01, 0), Vec2(-0.005, 0.008), Vec2(0, -0.01)}) {
      const auto [summed, cells] =
          InterSurfaceMapTestAccess::large_chart_energies(map, 0, v, offset);
      if (!(cells < HUGE_VAL)) continue;
      EXPECT_NEAR(summed, cells, 1e-9 * cells) << "vertex " << v;
      ++compared;
    }
  EXPECT_GE(compared, 6u);
  // And the refinement lowered it: the map refined without it has more.
  InterSurfaceMap unpenalised(side_from_domain(domain, pm), side_from_pm(pm));
  refine_both_checked(unpenalised, 1 << 30, 3);
  if (HasFatalFailure()) return;
  std::size_t biting_unpenalised = 0;
  const double penalty_unpenalised =
      penalty_of(unpenalised.meta(), unpenalised.area(1), biting_unpenalised);
  std::printf(
      "energy %.6f = stretch %.6f + penalty %.6f (%zu pieces past the onset); refined without "
      "it: stretch %.6f, penalty %.6f (%zu pieces)\n",
      map.energy(), plain.energy(), penalty, biting, unpenalised.energy(), penalty_unpenalised,
      biting_unpenalised);
  // (Measured 0.00519 against 0.00598; the totals are within 0.05 % either
  // way, as vertex-at-a-time descents of nearby energies are.)
  EXPECT_LT(penalty, penalty_unpenalised);
}

// Two different shared models, features added by the two-surface
// partition, both sides refined from their common base, validated after
// every operation.
TEST(InterSurfaceMap, BothSidesRefineSpotAndBunny) {
  ISM_REQUIRE_SHARED_MODELS();
  const MapMeasures m = refine_pair_checked(
      "spot / bunny_small", compatible_pms("spot.obj", "bunny_small.obj", 120, 0), 4);
  EXPECT_GT(m.symmetric_efficiency, 0.33);  // measured 0.552 (0.499 without hard-split relaxation)
}

// Genus 1: a generated torus and cup.obj, both from the 3x3 torus grid,
// validated from both sides after every operation.
TEST(InterSurfaceMap, BothSidesRefineGenusOneTorusAndCup) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh grid = domain::torus_3x3();
  const MapMeasures m = refine_pair_checked(
      "torus / cup",
      {simplify_constrained(trace_torus_network(shapes::torus(300)), grid),
       simplify_constrained(trace_torus_network(decimated_model("cup.obj", 150)), grid)},
      2);
  // Measured 0.296 (0.274 with line searches in developed charts, 0.239 also without hard-split
  // relaxation; 0.225-0.281 over the last changes of the
  // line searches, 0.247-0.305 with golden sections, 0.189 with every split allowed to move the old
  // vertex): the path swings with rounding. A winding base map ends near 0.1
  // (docs/results-two-surfaces.md).
  EXPECT_GT(m.symmetric_efficiency, 0.2);
}

// Genus 2: double_torus.obj and eight_loop2.obj, features added by the
// two-surface partition, both sides refined from their common base (paths
// and Steiner vertices take each side to 1-2K faces), validated from both
// sides after every operation, every move's gain checked against the
// energy's drop (~5 min). This driver moves only the new ring and the other
// side's vertices in it, relaxing from them after a hard split (no sweeps):
// 0.64 here; the example with sweeps reaches 0.79
// (docs/results-two-surfaces.md).
TEST(InterSurfaceMap, BothSidesRefineGenusTwoDoubleTorusAndEightLoop) {
  ISM_REQUIRE_SHARED_MODELS();
  const MapMeasures m =
      refine_pair_checked("double_torus / eight_loop2",
                          compatible_pms("double_torus.obj", "eight_loop2.obj", 70, 2), 5);
  EXPECT_GT(m.symmetric_efficiency,
            0.3);  // measured 0.642 (0.592 with line searches in developed charts; 0.041 with
                   // Newton steps there but no hard-split relaxation)
}

// Known limitation, run with --gtest_also_run_disabled_tests: this harder
// genus-2 pair (a generated double torus and double_torus.obj, features
// from nearest points) stopped at M² split 1496 with the golden line
// searches (no valid placement of the new vertex after 3 retries: every
// candidate needs a crossing too close to a break point, and the split in
// place folds a piece; ~30 min). Its history and the example's runs of
// this genus: docs/results-two-surfaces.md.
TEST(InterSurfaceMap, DISABLED_BothSidesRefineGenusTwo) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh a = shapes::double_torus(300), b = decimated_model("double_torus.obj", 150);
  const auto pms = common_base_pms(a, b, 20);
  InterSurfaceMap map(side_from_pm(pms[0]), side_from_pm(pms[1]));
  refine_both_checked(map, 5, 3);
  if (HasFatalFailure()) return;
  const MapMeasures m = map.measures();
  std::printf("double torus %zu / eight %zu faces: symmetric efficiency %.4f\n", map.n_faces(0),
              map.n_faces(1), m.symmetric_efficiency);
  EXPECT_FALSE(map.validate());
  EXPECT_GT(m.symmetric_efficiency, 0.1);
}

}  // namespace
}  // namespace ism
