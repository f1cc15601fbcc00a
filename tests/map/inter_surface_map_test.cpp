// The symmetric map core: two surfaces, both refined, validated from both
// sides after every operation.
#include "map/inter_surface_map.hpp"
#include "domain/domain.hpp"
#include "io/io.hpp"
#include "mesh/mesh_check.hpp"
#include "partition/compatible_networks.hpp"
#include "partition/partition.hpp"
#include "partition/torus_features.hpp"
#include "pm/pm.hpp"
#include "shapes/shapes.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>

namespace ism {

// The split's undo, reached from tests only.
struct InterSurfaceMapTestAccess {
  static int split_and_undo(InterSurfaceMap& map, int side) { return map.try_split(side, false); }
  static const MetaIndex& index(const InterSurfaceMap& map) { return map.index_; }
};

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

/// Refines both sides in turn (the side less refined first), optimising
/// every new vertex, its neighbours and the other side's vertices in its
/// ring; validates after every operation and
/// checks that each kept move lowers the energy by its reported gain.
void refine_both_checked(InterSurfaceMap& map, std::size_t validate_every, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::size_t operations = 0;
  auto check = [&](const char* what, int side, int v) {
    if (++operations % validate_every) return;
    const auto problem = map.validate();
    ASSERT_FALSE(problem) << what << " side " << side << " vertex " << v << ": " << *problem;
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
    for (const auto [s, v] : todo) {
      if (!map.is_active(s, v)) continue;
      const double before = map.energy();
      const double gain = map.optimize_vertex(s, v);
      const double after = map.energy();
      ASSERT_GE(gain, 0.0);
      ASSERT_NEAR(before - after, gain, 1e-9 * before) << "side " << s << " vertex " << v;
      if (gain > 0) check("optimising", s, v);
      if (::testing::Test::HasFatalFailure()) return;
    }
  }
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

// A map of the two-sided core with kinks goes through the meta-mesh file
// (version 2, k records) and comes back the same map, bit for bit.
TEST(InterSurfaceMap, MapWithKinksReadsBackFromItsFile) {
  const TriangleMesh a = shapes::sphere(100), b = shapes::blob(120, 5);
  const ProgressiveMesh pa = octahedral_pm(a), pb = octahedral_pm(b);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  refine_both_checked(map, 10, 7);
  if (HasFatalFailure()) return;
  const MetaMesh& meta = map.meta();
  const MetaMeshSize size = meta_mesh_size(meta);
  std::printf("kinks %zu, crossings %zu\n", size.kinks, size.crossings);
  ASSERT_GT(size.kinks, 0u) << "the pair no longer has kinks: pick one that does";
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
      "moves %zu, fast %zu, developed %zu, general %zu, rejected %zu\n",
      a.n_faces(), b.n_faces(), m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency,
      st.optimizations, st.moves, st.fast_path, st.developed, st.general, st.rejected);
  EXPECT_GT(m.symmetric_efficiency, 0.3);
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
      "optimisations %zu, fast %zu, general %zu\n",
      surface.n_faces(), m.symmetric_efficiency, m.forward_efficiency, m.backward_efficiency,
      st.optimizations, st.fast_path, st.general);
  // One-rings inside one face of the coarse domain take the fast path (29 %
  // of the optimisations here; 67 % on sphere.obj's 5K faces).
  EXPECT_GT(st.fast_path, st.optimizations / 5);
  EXPECT_GT(m.symmetric_efficiency, 0.9);  // measured 0.945
}

// Two different shared models, features added by the two-surface
// partition, both sides refined from their common base, validated after
// every operation.
TEST(InterSurfaceMap, BothSidesRefineSpotAndBunny) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh a = decimated_model("spot.obj", 120),
                     b = decimated_model("bunny_small.obj", 120);
  const CompatibleNetworks networks = trace_compatible_networks(a, b, {});
  const auto pms = simplify_compatible(networks);
  InterSurfaceMap map(side_from_pm(pms[0]), side_from_pm(pms[1]));
  refine_both_checked(map, 1, 4);
  if (HasFatalFailure()) return;
  EXPECT_FALSE(map.validate());
  EXPECT_EQ(map.n_faces(0), replay(pms[0]).n_faces());
  EXPECT_EQ(map.n_faces(1), replay(pms[1]).n_faces());
  const MapMeasures m = map.measures();
  std::printf("spot %zu / bunny_small %zu faces: symmetric efficiency %.4f (%.4f, %.4f)\n",
              map.n_faces(0), map.n_faces(1), m.symmetric_efficiency, m.forward_efficiency,
              m.backward_efficiency);
  EXPECT_GT(m.symmetric_efficiency, 0.33);  // measured 0.374
}

// Known limitation (the next step of the map core), run with
// --gtest_also_run_disabled_tests: the genus-2 pair stops at M² split 68
// (no valid placement after the retries, 300 s); the genus-1 pair was still
// running after 15 minutes of CPU (validation every 5 operations and the
// energy twice per move, on a twisted base map). Neither fits in CI yet.
// The example's runs of these genera: docs/results-two-surfaces.md.
TEST(InterSurfaceMap, DISABLED_BothSidesRefineGenusOneTorusAndCup) {
  ISM_REQUIRE_SHARED_MODELS();
  const TriangleMesh a = shapes::torus(300), b = decimated_model("cup.obj", 150);
  const TriangleMesh grid = domain::torus_3x3();
  const ProgressiveMesh pa = simplify_constrained(trace_torus_network(a), grid);
  const ProgressiveMesh pb = simplify_constrained(trace_torus_network(b), grid);
  InterSurfaceMap map(side_from_pm(pa), side_from_pm(pb));
  refine_both_checked(map, 5, 2);
  if (HasFatalFailure()) return;
  const MapMeasures m = map.measures();
  std::printf("torus %zu / cup %zu faces: symmetric efficiency %.4f\n", map.n_faces(0),
              map.n_faces(1), m.symmetric_efficiency);
  EXPECT_FALSE(map.validate());
  EXPECT_GT(m.symmetric_efficiency, 0.2);
}

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
