#include "sample/sample.hpp"

#include "domain/domain.hpp"
#include "mesh/mesh_check.hpp"
#include "mesh/union_find.hpp"
#include "metrics/metrics.hpp"

#include "closed_surface_checks.hpp"

#include <gtest/gtest.h>

#include <Eigen/SVD>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iostream>
#include <map>
#include <set>
#include <stdexcept>

namespace ism {
namespace {

Vec3 on_octahedron(const OctahedronPoint& p) {
  const TriangleMesh o = domain::octahedron();
  Vec3 x = Vec3::Zero();
  for (int k = 0; k < 3; ++k) x += p.bary[k] * o.positions[o.triangles[p.face][k]];
  return x;
}

Vec3 on_sphere(const OctahedronPoint& p) {
  return on_octahedron(p).normalized();
}

bool bit_equal(const Vec3& a, const Vec3& b) {
  return std::memcmp(a.data(), b.data(), 3 * sizeof(double)) == 0;
}

// The documented unfolded positions of the octahedron vertices (-z: its
// corner in the quadrant of the face asking).
Eigen::Vector2d unfolded_vertex(int vertex, int face) {
  const TriangleMesh o = domain::octahedron();
  switch (vertex) {
    case 0:
      return {1, 0};
    case 1:
      return {-1, 0};
    case 2:
      return {0, 1};
    case 3:
      return {0, -1};
    case 4:
      return {0, 0};
  }
  Eigen::Vector2d corner(1, 1);
  for (int v : o.triangles[face]) {
    if (v == 1) corner.x() = -1;
    if (v == 3) corner.y() = -1;
  }
  return corner;
}

TEST(Sample, ImageSizes) {
  for (int n : {3, 5, 9, 17, 257, 32769}) EXPECT_TRUE(is_geometry_image_size(n)) << n;
  for (int n : {-1, 0, 1, 2, 4, 6, 10, 256, 65537}) EXPECT_FALSE(is_geometry_image_size(n)) << n;
  EXPECT_THROW(sample_octahedral(4, on_octahedron), std::invalid_argument);
  EXPECT_THROW(sample_octahedral(2, on_octahedron), std::invalid_argument);
  GeometryImage bad;
  bad.n = 5;
  bad.pixels.resize(24);
  EXPECT_THROW(image_to_mesh(bad), std::invalid_argument);
}

TEST(Sample, FacesMatchTheDocumentedUnfolding) {
  const TriangleMesh o = domain::octahedron();
  for (int f = 0; f < 8; ++f) {
    std::array<Eigen::Vector2d, 3> corner;
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d bary = Eigen::Vector3d::Zero();
      bary[k] = 1.0;
      corner[k] = square_point(f, bary);
      EXPECT_EQ(corner[k], unfolded_vertex(o.triangles[f][k], f))
          << "face " << f << " corner " << k;
      EXPECT_EQ(octahedron_position({f, bary}), o.positions[o.triangles[f][k]]);
    }
    // Counter-clockwise in (u,v), as on the outward octahedron.
    const Eigen::Vector2d a = corner[1] - corner[0], b = corner[2] - corner[0];
    EXPECT_GT(a.x() * b.y() - a.y() * b.x(), 0.0) << "face " << f;
  }
}

TEST(Sample, OctahedronPointRoundTrip) {
  const int steps = 400;
  for (int i = 0; i <= steps; ++i)
    for (int j = 0; j <= steps; ++j) {
      const double u = -1.0 + 2.0 * j / steps, v = -1.0 + 2.0 * i / steps;
      const OctahedronPoint p = octahedron_point(u, v);
      ASSERT_GE(p.face, 0);
      ASSERT_LT(p.face, 8);
      EXPECT_GE(p.bary.minCoeff(), 0.0);
      EXPECT_NEAR(p.bary.sum(), 1.0, 1e-14);
      const Eigen::Vector2d back = square_point(p.face, p.bary);
      EXPECT_NEAR(back.x(), u, 1e-14);
      EXPECT_NEAR(back.y(), v, 1e-14);
      // The position on |x|+|y|+|z| = 1 agrees with the face's vertices.
      EXPECT_LT((octahedron_position(p) - on_octahedron(p)).norm(), 1e-15);
      EXPECT_NEAR(octahedron_position(p).lpNorm<1>(), 1.0, 1e-14);
    }
  // Face points back and forth: same face and bary inside, same 3D point always.
  for (int f = 0; f < 8; ++f)
    for (int a = 0; a <= 40; ++a)
      for (int b = 0; a + b <= 40; ++b) {
        const Eigen::Vector3d bary(a / 40.0, b / 40.0, (40 - a - b) / 40.0);
        const Eigen::Vector2d uv = square_point(f, bary);
        const OctahedronPoint p = octahedron_point(uv.x(), uv.y());
        EXPECT_LT((octahedron_position(p) - octahedron_position({f, bary})).norm(), 1e-14);
        if (bary.minCoeff() > 0.0) {
          EXPECT_EQ(p.face, f);
          EXPECT_LT((p.bary - bary).norm(), 1e-14);
        }
      }
}

TEST(Sample, MirroredBoundaryIsOnePoint) {
  const int steps = 256;
  for (int j = 0; j <= steps; ++j) {
    const double t = -1.0 + 2.0 * j / steps;
    auto same = [](Eigen::Vector2d a, Eigen::Vector2d b) {
      return octahedron_position(octahedron_point(a.x(), a.y())) ==
             octahedron_position(octahedron_point(b.x(), b.y()));
    };
    EXPECT_TRUE(same({t, 1}, {-t, 1})) << t;
    EXPECT_TRUE(same({t, -1}, {-t, -1})) << t;
    EXPECT_TRUE(same({1, t}, {1, -t})) << t;
    EXPECT_TRUE(same({-1, t}, {-1, -t})) << t;
  }
  const Vec3 minus_z(0, 0, -1);
  for (double u : {-1.0, 1.0})
    for (double v : {-1.0, 1.0}) EXPECT_EQ(octahedron_position(octahedron_point(u, v)), minus_z);
}

TEST(Sample, VerticesLandOnTheDocumentedPixels) {
  const TriangleMesh o = domain::octahedron();
  for (int n : {3, 5, 17, 65}) {
    const int m = (n - 1) / 2, last = n - 1;
    const std::array<std::array<int, 2>, 6> expected = {
        {{m, last}, {m, 0}, {0, m}, {last, m}, {m, m}, {0, 0}}};
    for (int v = 0; v < 6; ++v) {
      EXPECT_EQ(octahedron_vertex_pixel(n, v), expected[v]);
      const Eigen::Vector2d uv = pixel_square_point(n, expected[v][0], expected[v][1]);
      EXPECT_EQ(octahedron_position(octahedron_point(uv.x(), uv.y())), o.positions[v]);
    }
    for (int row : {0, last})
      for (int col : {0, last}) {
        const Eigen::Vector2d uv = pixel_square_point(n, row, col);
        EXPECT_EQ(octahedron_position(octahedron_point(uv.x(), uv.y())), o.positions[5]);
      }
  }
}

TEST(Sample, EvaluatesEachDistinctPointOnce) {
  std::atomic<int> calls{0};
  const GeometryImage img = sample_octahedral(17, [&](const OctahedronPoint& p) {
    ++calls;
    return on_sphere(p);
  });
  EXPECT_EQ(calls.load(), 16 * 16 + 2);
  // Deterministic whatever the thread schedule.
  const GeometryImage again = sample_octahedral(17, on_sphere);
  for (std::size_t p = 0; p < img.pixels.size(); ++p)
    EXPECT_TRUE(bit_equal(img.pixels[p], again.pixels[p]));
}

void expect_closed_outward_sphere(const GeometryImage& img) {
  const int n = img.n, last = n - 1;
  // Mirrored pixels bit-identical.
  for (int k = 0; k < n; ++k) {
    EXPECT_TRUE(bit_equal(img.at(0, k), img.at(0, last - k)));
    EXPECT_TRUE(bit_equal(img.at(last, k), img.at(last, last - k)));
    EXPECT_TRUE(bit_equal(img.at(k, 0), img.at(last - k, 0)));
    EXPECT_TRUE(bit_equal(img.at(k, last), img.at(last - k, last)));
  }
  EXPECT_TRUE(bit_equal(img.at(0, 0), img.at(0, last)));
  EXPECT_TRUE(bit_equal(img.at(0, 0), img.at(last, 0)));
  EXPECT_TRUE(bit_equal(img.at(0, 0), img.at(last, last)));

  const TriangleMesh mesh = image_to_mesh(img);
  const std::size_t cells = static_cast<std::size_t>(n - 1) * (n - 1);
  ASSERT_EQ(mesh.n_vertices(), cells + 2);
  ASSERT_EQ(mesh.n_faces(), 2 * cells);

  // Every edge in exactly two faces, once in each direction.
  std::map<std::pair<int, int>, int> directed;
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[k], t[(k + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    const auto reverse = directed.find({edge.second, edge.first});
    ASSERT_NE(reverse, directed.end());
    EXPECT_EQ(reverse->second, 1);
  }
  const long edges = static_cast<long>(directed.size() / 2);
  EXPECT_EQ(static_cast<long>(mesh.n_vertices()) - edges + static_cast<long>(mesh.n_faces()), 2);

  UnionFind components(mesh.n_vertices());
  std::size_t merges = 0;
  for (const Triangle& t : mesh.triangles)
    merges += components.unite(t[0], t[1]) + components.unite(t[1], t[2]);
  EXPECT_EQ(merges, mesh.n_vertices() - 1);

  std::set<std::array<double, 3>> distinct;
  for (const Vec3& p : mesh.positions) distinct.insert({p.x(), p.y(), p.z()});
  EXPECT_EQ(distinct.size(), mesh.n_vertices());
  EXPECT_GT(signed_volume(mesh), 0.0);

  // The shared validator agrees: nothing to weld, nothing to turn around.
  PolygonSoup soup{mesh.positions, {}};
  for (const Triangle& t : mesh.triangles) soup.faces.push_back({t[0], t[1], t[2]});
  const MeshCheck check = prepare_mesh(soup).check;
  EXPECT_TRUE(check.valid_surface());
  EXPECT_EQ(check.genus, 0);
  EXPECT_TRUE(check.repairs().empty());
}

TEST(Sample, OctahedronImageIsAClosedOutwardGenusZeroMesh) {
  for (int n : {3, 5, 17, 65}) {
    SCOPED_TRACE(n);
    const GeometryImage img = sample_octahedral(n, on_octahedron);
    expect_closed_outward_sphere(img);
    EXPECT_NEAR(signed_volume(image_to_mesh(img)), 4.0 / 3.0, 1e-12);
    if (n == 3) {
      // The coarsest image is the octahedron itself.
      const TriangleMesh mesh = image_to_mesh(img);
      const TriangleMesh o = domain::octahedron();
      std::set<std::array<int, 3>> ours, theirs;
      auto key = [](const TriangleMesh& m, const Triangle& t) {
        // Rotate so that the smallest position (lexicographic) comes first.
        std::array<std::array<double, 3>, 3> p;
        for (int k = 0; k < 3; ++k)
          p[k] = {m.positions[t[k]].x(), m.positions[t[k]].y(), m.positions[t[k]].z()};
        int first = std::min_element(p.begin(), p.end()) - p.begin();
        std::array<int, 3> code;
        for (int k = 0; k < 3; ++k) {
          const auto& q = p[(first + k) % 3];
          code[k] = static_cast<int>(std::lround(q[0] + 3 * q[1] + 9 * q[2]));
        }
        return code;
      };
      for (const Triangle& t : mesh.triangles) ours.insert(key(mesh, t));
      for (const Triangle& t : o.triangles) theirs.insert(key(o, t));
      EXPECT_EQ(ours, theirs);
    }
  }
}

TEST(Sample, SphereImageIsAClosedOutwardGenusZeroMesh) {
  for (int n : {3, 5, 17, 65}) {
    SCOPED_TRACE(n);
    expect_closed_outward_sphere(sample_octahedral(n, on_sphere));
  }
}

TEST(Sample, FirstMirrorPixelGivesTheVertex) {
  GeometryImage img = sample_octahedral(9, on_sphere);
  const Vec3 first = img.at(0, 2);
  img.at(0, 6) = Vec3(7, 7, 7);  // mirror of (0, 2), not bit-identical any more
  img.at(8, 8) = Vec3(9, 9, 9);  // a corner other than (0, 0)
  const TriangleMesh mesh = image_to_mesh(img);
  const std::vector<int> vertex = image_vertex_of_pixel(9);
  EXPECT_EQ(mesh.positions[vertex[2]], first);
  EXPECT_EQ(mesh.positions[0], img.at(0, 0));
}

TEST(Sample, VertexOfPixelWeldsMirrors) {
  const int n = 9, last = n - 1;
  const std::vector<int> vertex = image_vertex_of_pixel(n);
  auto at = [&](int r, int c) { return vertex[static_cast<std::size_t>(r) * n + c]; };
  EXPECT_EQ(at(0, 0), 0);
  EXPECT_EQ(at(last, last), 0);
  EXPECT_EQ(at(0, 2), at(0, 6));
  EXPECT_EQ(at(3, last), at(5, last));
  EXPECT_NE(at(3, last), at(3, last - 1));
  EXPECT_EQ(*std::max_element(vertex.begin(), vertex.end()), (n - 1) * (n - 1) + 1);
}

// Efficiency of one affine piece: right isosceles legs 1 -> equilateral side 1.
double right_isosceles_to_equilateral_efficiency() {
  // J sends the legs e1, e2 to two unit vectors 60 degrees apart.
  Eigen::Matrix2d j;
  j << 1.0, 0.5, 0.0, std::sqrt(3.0) / 2.0;
  const Eigen::Vector2d s = Eigen::JacobiSVD<Eigen::Matrix2d>(j).singularValues();
  const double sigma2 = 0.5 * s.squaredNorm();
  const double area_domain = 0.5, area_range = std::sqrt(3.0) / 4.0;
  return 1.0 / (sigma2 * area_domain / area_range);  // the same for every piece
}

TEST(Sample, EfficiencyOfTheOctahedron) {
  const double expected_square = right_isosceles_to_equilateral_efficiency();
  EXPECT_NEAR(expected_square, std::sqrt(3.0) / 2.0, 1e-15);
  for (int n : {3, 5, 17, 65}) {
    SCOPED_TRACE(n);
    const GeometryImage img = sample_octahedral(n, on_octahedron);
    EXPECT_NEAR(image_efficiency(img, ImageDomain::octahedron), 1.0, 1e-9);
    EXPECT_NEAR(image_efficiency(img, ImageDomain::square), expected_square, 1e-9);
    EXPECT_EQ(flipped_triangles(img), 0u);
  }
}

TEST(Sample, EfficiencyAgreesWithOneWayStretch) {
  // The octahedron image gives the domain triangles with the same numbering
  // as the sphere mesh. On every face the unfolding keeps |dx| and |dy| and
  // drops z (inside the diamond (u,v) = (x,y), outside it (±(1-|y|), ±(1-|x|))),
  // so the square-domain lengths are those of the octahedron projected to xy.
  const int n = 17;
  const TriangleMesh domain = image_to_mesh(sample_octahedral(n, on_octahedron));
  const GeometryImage img = sample_octahedral(n, on_sphere);
  const TriangleMesh range = image_to_mesh(img);
  auto lengths = [](const std::array<Vec3, 3>& p) {
    return TriangleLengths{(p[1] - p[2]).norm(), (p[2] - p[0]).norm(), (p[0] - p[1]).norm()};
  };
  std::vector<StretchPiece> on_square, on_octahedron_face;
  for (const Triangle& t : range.triangles) {
    std::array<Vec3, 3> d, flat, r;
    for (int k = 0; k < 3; ++k) {
      d[k] = domain.positions[t[k]];
      flat[k] = {d[k].x(), d[k].y(), 0.0};
      r[k] = range.positions[t[k]];
    }
    on_square.push_back({lengths(flat), lengths(r)});
    on_octahedron_face.push_back({lengths(d), lengths(r)});
  }
  EXPECT_NEAR(image_efficiency(img, ImageDomain::square), one_way_stretch(on_square).efficiency,
              1e-12);
  EXPECT_NEAR(image_efficiency(img, ImageDomain::octahedron),
              one_way_stretch(on_octahedron_face).efficiency, 1e-12);
}

TEST(Sample, EfficiencyNeedsSurfaceArea) {
  GeometryImage flat = sample_octahedral(5, [](const OctahedronPoint&) { return Vec3(1, 2, 3); });
  EXPECT_THROW(image_efficiency(flat, ImageDomain::square), std::invalid_argument);
  // Collapsing the lower half (z < 0) to a point leaves zero-weight triangles
  // that still count in the domain area: the efficiency drops below the
  // octahedron's but stays finite.
  const GeometryImage half = sample_octahedral(17, [](const OctahedronPoint& p) {
    const Vec3 x = on_octahedron(p);
    return x.z() < 0.0 ? Vec3(0, 0, 0) : x;
  });
  const double e = image_efficiency(half, ImageDomain::octahedron);
  EXPECT_GT(e, 0.0);
  EXPECT_LT(e, 1.0);
}

TEST(Sample, SphereEfficiencyAndFlips) {
  const GeometryImage img = sample_octahedral(257, on_sphere);
  const double square = image_efficiency(img, ImageDomain::square);
  const double octahedron = image_efficiency(img, ImageDomain::octahedron);
  std::cout << "sphere n=257: square efficiency " << square << ", octahedron efficiency "
            << octahedron << "\n";
  EXPECT_NEAR(square, 0.7735, 0.005);
  EXPECT_LT(octahedron, 1.0);
  EXPECT_GT(octahedron, square);
  EXPECT_EQ(flipped_triangles(img), 0u);
}

TEST(Sample, FoldedImageHasFlippedTriangles) {
  GeometryImage img = sample_octahedral(17, on_sphere);
  EXPECT_EQ(flipped_triangles(img), 0u);
  std::swap(img.at(3, 5), img.at(11, 9));
  EXPECT_GT(flipped_triangles(img), 0u);
  // Swapping two neighbours folds only locally, still seen.
  GeometryImage near = sample_octahedral(17, on_sphere);
  std::swap(near.at(5, 5), near.at(5, 6));
  EXPECT_GT(flipped_triangles(near), 0u);
}

TEST(Sample, UnfoldReSamplesFoldedPixelsNearby) {
  const int n = 17;
  const double pixel = 2.0 / (n - 1);
  const GeometryImage clean = sample_octahedral(n, on_sphere);
  // Pixel (5, 5) replaced by the sample 1.6 pixels to its right (past its
  // neighbour), and a side pixel with its mirror 1.6 pixels along the side.
  auto folded = [&] {
    GeometryImage img = clean;
    const Eigen::Vector2d a = pixel_square_point(n, 5, 5), b = pixel_square_point(n, 0, 4);
    img.at(5, 5) = on_sphere(octahedron_point(a.x() + 1.6 * pixel, a.y()));
    img.at(0, 4) = img.at(0, 12) = on_sphere(octahedron_point(b.x() + 1.6 * pixel, b.y()));
    return img;
  };
  GeometryImage img = folded();
  const std::size_t folds = flipped_triangles(img);
  ASSERT_GT(folds, 0u);
  std::vector<OctahedronPoint> moved_to;
  const UnfoldReport r = unfold_geometry_image(img, on_sphere, &moved_to);
  EXPECT_EQ(r.folds_before, folds);
  EXPECT_EQ(r.folds_after, 0u);
  EXPECT_EQ(flipped_triangles(img), 0u);
  ASSERT_EQ(moved_to.size(), img.pixels.size());
  // Mirrored pixels stay one point; a pixel that is not its grid sample holds
  // the sample of the point it was moved to, within 0.75 pixels (each way) of
  // its own point or its mirror's; the others were not moved.
  const std::vector<int> vertex = image_vertex_of_pixel(n);
  std::map<int, std::vector<std::size_t>> pixels_of;
  for (std::size_t p = 0; p < vertex.size(); ++p) pixels_of[vertex[p]].push_back(p);
  std::set<int> moved_vertices;
  for (std::size_t p = 0; p < img.pixels.size(); ++p) {
    for (std::size_t q : pixels_of[vertex[p]]) EXPECT_TRUE(bit_equal(img.pixels[p], img.pixels[q]));
    if (bit_equal(img.pixels[p], clean.pixels[p])) {
      EXPECT_EQ(moved_to[p].face, -1) << p;
      continue;
    }
    moved_vertices.insert(vertex[p]);
    ASSERT_GE(moved_to[p].face, 0) << p;
    EXPECT_TRUE(bit_equal(on_sphere(moved_to[p]), img.pixels[p])) << p;
    const Eigen::Vector2d at = square_point(moved_to[p].face, moved_to[p].bary);
    double nearest = HUGE_VAL;
    for (std::size_t q : pixels_of[vertex[p]]) {
      const Eigen::Vector2d own = pixel_square_point(n, int(q) / n, int(q) % n);
      nearest = std::min(nearest, (at - own).lpNorm<Eigen::Infinity>());
    }
    EXPECT_LE(nearest, 0.75 * pixel + 1e-12) << p;
  }
  EXPECT_EQ(r.moved_vertices, moved_vertices.size());
  EXPECT_GE(moved_to[5 * n + 5].face, 0);
  EXPECT_GE(moved_to[4].face, 0);

  // An image without folds, or one with alpha (an open surface's), is left as it is.
  GeometryImage same = clean;
  EXPECT_EQ(unfold_geometry_image(same, on_sphere).moved_vertices, 0u);
  EXPECT_EQ(
      std::memcmp(same.pixels.data(), clean.pixels.data(), clean.pixels.size() * sizeof(Vec3)), 0);
  GeometryImage open = folded();
  open.alpha.assign(open.pixels.size(), 1.0f);
  const UnfoldReport kept = unfold_geometry_image(open, on_sphere);
  EXPECT_EQ(kept.folds_after, folds);
  EXPECT_EQ(kept.moved_vertices, 0u);
}

// A sphere image with a cap: alpha 0 on the pixels whose sample lies within
// 0.5 of the north pole (the +z end of the sphere: the centre of the image).
GeometryImage sphere_with_cap(int n) {
  GeometryImage img = sample_octahedral(n, on_sphere);
  img.alpha.resize(img.pixels.size());
  for (std::size_t p = 0; p < img.pixels.size(); ++p)
    img.alpha[p] = (img.pixels[p] - Vec3(0, 0, 1)).norm() < 0.5 ? 0.0f : 1.0f;
  return img;
}

TEST(Sample, SurfaceMeshDropsTheGridTrianglesThatTouchACap) {
  const int n = 33;
  const GeometryImage img = sphere_with_cap(n);
  const TriangleMesh all = image_to_mesh(img), open = image_to_surface_mesh(img);
  // Every kept triangle is a triangle of the whole mesh whose corners are all
  // off the cap; the dropped ones touch it.
  std::set<std::array<Vec3, 3>, bool (*)(const std::array<Vec3, 3>&, const std::array<Vec3, 3>&)>
      kept([](const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
        return std::lexicographical_compare(a[0].data(), a[0].data() + 3 * 3, b[0].data(),
                                            b[0].data() + 3 * 3);
      });
  for (const Triangle& t : open.triangles)
    kept.insert({open.positions[t[0]], open.positions[t[1]], open.positions[t[2]]});
  std::size_t off_cap = 0;
  for (const Triangle& t : all.triangles) {
    bool touches = false;
    for (int v : t) touches |= (all.positions[v] - Vec3(0, 0, 1)).norm() < 0.5;
    off_cap += !touches;
    EXPECT_EQ(kept.count({all.positions[t[0]], all.positions[t[1]], all.positions[t[2]]}),
              touches ? 0u : 1u);
  }
  EXPECT_EQ(open.n_faces(), off_cap);
  EXPECT_LT(open.n_faces(), all.n_faces());
  // A disc removed from a sphere: one boundary loop, genus 0, no stray vertex.
  const MeshCheck c = test::check_of(open);
  EXPECT_TRUE(c.valid_surface());
  EXPECT_EQ(c.boundary_loops, 1u);
  EXPECT_EQ(c.genus, 0);
  EXPECT_EQ(c.unreferenced_vertices, 0u);
  // Without alpha: the closed mesh.
  const GeometryImage closed = sample_octahedral(n, on_sphere);
  EXPECT_EQ(image_to_surface_mesh(closed).triangles, image_to_mesh(closed).triangles);
  GeometryImage bad = img;
  bad.alpha.pop_back();
  EXPECT_THROW(image_to_surface_mesh(bad), std::invalid_argument);
}

TEST(Sample, EfficiencyAndFoldsOfAnImageWithAlphaCountTheSurfaceOnly) {
  GeometryImage img = sphere_with_cap(65);
  const GeometryImage closed = sample_octahedral(65, on_sphere);
  // Fold the cap: no effect on the measures of the surface.
  GeometryImage folded = img;
  for (std::size_t p = 0; p < folded.pixels.size(); ++p)
    if (folded.alpha[p] == 0.0f) folded.pixels[p].z() = 2.0 - folded.pixels[p].z();
  for (ImageDomain d : {ImageDomain::square, ImageDomain::octahedron}) {
    EXPECT_EQ(image_efficiency(folded, d), image_efficiency(img, d));
    EXPECT_NE(image_efficiency(img, d), image_efficiency(closed, d));
  }
  EXPECT_EQ(flipped_triangles(img), 0u);
  EXPECT_EQ(flipped_triangles(folded), 0u);
  folded.alpha.clear();
  EXPECT_GT(flipped_triangles(folded), 0u);
}

}  // namespace
}  // namespace ism
