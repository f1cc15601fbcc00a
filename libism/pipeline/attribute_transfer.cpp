#include "pipeline/attribute_transfer.hpp"

#include "mesh/face_adjacency.hpp"
#include "mesh/union_find.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace ism::pipeline {

io::VertexField transfer_field(const io::VertexField& field, const std::vector<Triangle>& faces,
                               const std::vector<SurfacePoint>& images) {
  io::VertexField out;
  out.columns = field.columns;
  out.values.assign(images.size() * field.columns, 0.0);
  for (std::size_t i = 0; i < images.size(); ++i) {
    const Triangle& t = faces[std::size_t(images[i].face)];
    for (int k = 0; k < 3; ++k)
      for (std::size_t c = 0; c < field.columns; ++c)
        out.values[i * field.columns + c] +=
            images[i].bary[k] * field.values[std::size_t(t[std::size_t(k)]) * field.columns + c];
  }
  return out;
}

std::vector<std::array<Texcoord, 3>> corner_texcoords(const PolygonSoup& soup,
                                                      const PreparedMesh& prepared) {
  if (soup.face_texcoords.empty()) throw std::invalid_argument("no texture coordinates (vt)");
  const std::vector<Triangle>& triangles = prepared.mesh.triangles;
  std::vector<std::array<Texcoord, 3>> out(triangles.size());
  std::size_t missing = 0;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const std::size_t origin = std::size_t(prepared.face_origin[f]);
    const std::vector<int>& corners = soup.faces[origin];
    const std::vector<int>& uv = soup.face_texcoords[origin];
    bool complete = true;
    for (int k = 0; k < 3; ++k) {
      // The corner of the soup's face that became this vertex.
      int t = -1;
      for (std::size_t c = 0; c < corners.size() && t < 0; ++c)
        if (prepared.position_vertex[std::size_t(corners[c])] == triangles[f][std::size_t(k)])
          t = uv[c];
      if (t < 0) {
        complete = false;
        break;
      }
      out[f][std::size_t(k)] = soup.texcoords[std::size_t(t)];
    }
    missing += !complete;
  }
  if (missing)
    throw std::invalid_argument(std::to_string(missing) + " of " +
                                std::to_string(triangles.size()) +
                                " triangles have a corner without a texture coordinate");
  return out;
}

TexcoordTransfer transfer_texcoords(const std::vector<Triangle>& source_faces,
                                    const std::vector<std::array<Texcoord, 3>>& corners,
                                    const std::vector<SurfacePoint>& images,
                                    const std::vector<Triangle>& target_faces) {
  // The source's charts: faces joined across an edge whose ends have the
  // same coordinates in both faces.
  UnionFind charts(source_faces.size());
  const auto across = faces_across(source_faces);
  for (std::size_t f = 0; f < source_faces.size(); ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const auto [g, j] = across[f][k];  // g's corner j is f's corner k + 1, j + 1 is k
      if (g >= 0 && corners[f][k] == corners[std::size_t(g)][std::size_t((j + 1) % 3)] &&
          corners[f][(k + 1) % 3] == corners[std::size_t(g)][std::size_t(j)])
        charts.unite(f, std::size_t(g));
    }
  TexcoordTransfer out;
  out.texcoords.resize(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const auto& uv = corners[std::size_t(images[i].face)];
    Texcoord t{0, 0};
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 2; ++c)
        t[std::size_t(c)] += images[i].bary[k] * uv[std::size_t(k)][std::size_t(c)];
    out.texcoords[i] = t;
  }
  for (const Triangle& t : target_faces) {
    const std::size_t c0 = charts.find(std::size_t(images[std::size_t(t[0])].face));
    out.seam_triangles += charts.find(std::size_t(images[std::size_t(t[1])].face)) != c0 ||
                          charts.find(std::size_t(images[std::size_t(t[2])].face)) != c0;
  }
  return out;
}

io::VertexField vertex_colors(const PolygonSoup& soup, const PreparedMesh& prepared) {
  if (soup.colors.empty())
    throw std::invalid_argument("no vertex colours (PLY red green blue, or OBJ 'v x y z r g b')");
  io::VertexField out;
  out.columns = 3;
  out.values.assign(3 * prepared.mesh.n_vertices(), 0.0);
  std::vector<char> set(prepared.mesh.n_vertices(), 0);
  for (std::size_t p = 0; p < soup.positions.size(); ++p) {
    const int v = prepared.position_vertex[p];
    if (v < 0 || set[std::size_t(v)]) continue;
    set[std::size_t(v)] = 1;
    for (int c = 0; c < 3; ++c) out.values[3 * std::size_t(v) + std::size_t(c)] = soup.colors[p][c];
  }
  return out;
}

std::vector<io::Rgb> to_rgb(const io::VertexField& colours) {
  std::vector<io::Rgb> out(colours.rows());
  for (std::size_t v = 0; v < out.size(); ++v)
    for (std::size_t c = 0; c < 3; ++c) {
      const double x = std::clamp(colours.values[3 * v + c], 0.0, 1.0);
      out[v][c] = static_cast<unsigned char>(std::lround(255 * x));
    }
  return out;
}

}  // namespace ism::pipeline
