// Meta-mesh files: the text format of the README's "Meta-mesh files".
#include "io/io.hpp"
#include "map/meta_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>

namespace ism {

bool write_meta_mesh(const MetaMesh& meta, const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) return false;
  char line[256];
  // Version 2 only when kinks need its k records: a map without kinks is
  // written exactly as before, for readers of version 1.
  // Version 3 only when an open map needs its b records.
  bool kinks = false, open = false;
  for (const MetaSide& side : meta.side) {
    for (const auto& list : side.crossings)
      for (const MetaCrossing& c : list) kinks = kinks || c.is_kink();
    for (const MetaLocation& loc : side.location) open = open || loc.on_edge();
  }
  out << (open ? "ism-meta-mesh 3\n" : kinks ? "ism-meta-mesh 2\n" : "ism-meta-mesh 1\n");
  for (int m = 0; m < 2; ++m) {
    const MetaSide& side = meta.side[m];
    out << "mesh " << m << ' ' << side.n_vertices() << ' ' << side.faces.size() << '\n';
    for (std::size_t f = 0; f < side.faces.size(); ++f) {
      const auto& t = side.faces[f];
      const auto& l = side.lengths[f];
      std::snprintf(line, sizeof line, "f %d %d %d %.17g %.17g %.17g\n", t[0], t[1], t[2], l[0],
                    l[1], l[2]);
      out << line;
    }
  }
  for (int m = 0; m < 2; ++m)
    for (std::size_t v = 0; v < meta.side[m].n_vertices(); ++v) {
      const MetaLocation& loc = meta.side[m].location[v];
      if (loc.vertex >= 0) {
        if (m == 0) out << "on " << v << ' ' << loc.vertex << '\n';
      } else if (loc.on_edge()) {
        const auto& e = meta.side[1 - m].edges[loc.edge];
        std::snprintf(line, sizeof line, "b %d %zu %d %d %.17g\n", m, v, e[0], e[1], loc.t);
        out << line;
      } else if (loc.face >= 0) {
        std::snprintf(line, sizeof line, "in %d %zu %d %.17g %.17g %.17g\n", m, v, loc.face,
                      loc.bary[0], loc.bary[1], loc.bary[2]);
        out << line;
      }
    }
  const MetaSide& d = meta.side[0];
  const MetaSide& s = meta.side[1];
  for (std::size_t e = 0; e < d.edges.size(); ++e)
    for (const MetaCrossing& c : d.crossings[e]) {
      if (c.is_kink()) continue;  // k records below
      std::snprintf(line, sizeof line, "x %d %d %d %d %.17g %.17g\n", d.edges[e][0], d.edges[e][1],
                    s.edges[c.edge][0], s.edges[c.edge][1], c.here, c.there);
      out << line;
    }
  for (int m = 0; m < 2; ++m) {
    const MetaSide& side = meta.side[m];
    for (std::size_t e = 0; e < side.edges.size(); ++e)
      for (const MetaCrossing& c : side.crossings[e]) {
        if (!c.is_kink()) continue;
        std::snprintf(line, sizeof line, "k %d %d %d %.17g %d %.17g %.17g %.17g\n", m,
                      side.edges[e][0], side.edges[e][1], c.here, c.face, c.bary[0], c.bary[1],
                      c.bary[2]);
        out << line;
      }
  }
  out.flush();
  return bool(out);
}

MetaMesh read_meta_mesh(const std::filesystem::path& path) {
  std::error_code ec;
  const std::uintmax_t file_bytes =
      std::filesystem::is_regular_file(path, ec) ? std::filesystem::file_size(path, ec) : 0;
  std::ifstream in(path);
  if (!in || ec || !std::filesystem::is_regular_file(path, ec))
    throw io::FileError(path.string() + ": cannot be read");
  int line_number = 0;
  auto fail = [&](const std::string& why) {
    throw io::FileError(path.string() + ":" + std::to_string(line_number) + ": " + why);
  };
  // Counts are checked against the file's size before anything is sized by
  // them: a face line takes at least 14 characters ("f 0 1 2 1 1 1" and a
  // newline) and names three vertices, so the vertices faces use number at
  // most one per 4 bytes of the file. A coarse map declares its surface's
  // vertices not yet used without a line: up to 2^22 of them (200 MB of
  // locations) need no bytes.
  const std::uintmax_t max_vertices = std::max<std::uintmax_t>(file_bytes / 4, 1u << 22),
                       max_faces = file_bytes / 14;
  // A record is only what it says: nothing may follow its numbers.
  auto complete = [](std::istringstream& words) {
    if (!words.eof()) words >> std::ws;
    return words.eof();
  };
  auto fully = [&](std::istringstream& words) { return !words.fail() && complete(words); };
  std::string line;
  ++line_number;
  if (!std::getline(in, line) ||
      (line != "ism-meta-mesh 1" && line != "ism-meta-mesh 2" && line != "ism-meta-mesh 3"))
    fail("not an ism meta-mesh file");
  const int version = line.back() - '0';
  MetaMesh meta;
  int current = -1;
  std::size_t faces_expected[2] = {0, 0};
  bool mesh_seen[2] = {false, false};
  std::vector<std::array<int, 4>> crossing_edges;  // a0 b0 a1 b1 per x line
  std::vector<std::array<double, 2>> crossing_at;
  struct Kink {
    int side, a, b;
    MetaCrossing at;
    int line;
  };
  std::vector<Kink> kinks;
  struct OnEdge {  // a b record: vertex v of side m on edge a-b of the other
    int side, v, a, b;
    double t;
    int line;
  };
  std::vector<OnEdge> on_edges;
  while (std::getline(in, line)) {
    ++line_number;
    std::istringstream words(line);
    std::string kind;
    if (!(words >> kind)) continue;
    if (kind == "mesh") {
      long long side = -1, vertices = -1, faces = -1;
      words >> side >> vertices >> faces;
      if (!fully(words) || (side != 0 && side != 1) || mesh_seen[side] || vertices < 0 ||
          faces <= 0)
        fail("bad mesh line");
      if (std::uintmax_t(vertices) > max_vertices || std::uintmax_t(faces) > max_faces)
        fail("mesh " + std::to_string(side) + " declares " + std::to_string(vertices) +
             " vertices and " + std::to_string(faces) + " faces, more than the file's " +
             std::to_string(file_bytes) + " bytes can hold");
      current = int(side);
      mesh_seen[current] = true;
      meta.side[current].location.assign(std::size_t(vertices), {});
      faces_expected[current] = std::size_t(faces);
    } else if (kind == "f") {
      Triangle t;
      FaceLengths l;
      words >> t[0] >> t[1] >> t[2] >> l[0] >> l[1] >> l[2];
      if (current < 0 || !fully(words)) fail("bad face");
      for (int v : t)
        if (v < 0 || std::size_t(v) >= meta.side[current].n_vertices()) fail("no such vertex");
      for (double x : l)
        if (!(x >= 0 && std::isfinite(x))) fail("face lengths must be finite and not negative");
      if (meta.side[current].faces.size() == faces_expected[current])
        fail("more faces than the mesh line declares");
      meta.side[current].faces.push_back(t);
      meta.side[current].lengths.push_back(l);
    } else if (kind == "on") {
      int v0 = -1, v1 = -1;
      words >> v0 >> v1;
      if (!fully(words) || v0 < 0 || v1 < 0 || std::size_t(v0) >= meta.side[0].n_vertices() ||
          std::size_t(v1) >= meta.side[1].n_vertices())
        fail("bad vertex pair");
      meta.side[0].location[v0].vertex = v1;
      meta.side[1].location[v1].vertex = v0;
    } else if (kind == "in") {
      int m = -1, v = -1;
      MetaLocation loc;
      words >> m >> v >> loc.face >> loc.bary[0] >> loc.bary[1] >> loc.bary[2];
      if (!fully(words) || (m != 0 && m != 1) || v < 0 ||
          std::size_t(v) >= meta.side[m].n_vertices() || loc.face < 0 ||
          std::size_t(loc.face) >= faces_expected[1 - m] || !loc.bary.allFinite())
        fail("bad location");
      meta.side[m].location[v] = loc;
    } else if (kind == "b") {
      if (version < 3)
        fail("boundary-edge location in a version " + std::to_string(version) +
             " file (they need 'ism-meta-mesh 3')");
      OnEdge b{-1, -1, -1, -1, 0.0, line_number};
      words >> b.side >> b.v >> b.a >> b.b >> b.t;
      if (!fully(words) || (b.side != 0 && b.side != 1) || b.v < 0 ||
          std::size_t(b.v) >= meta.side[b.side].n_vertices())
        fail("bad boundary-edge location");
      if (!(b.t > 0 && b.t < 1)) fail("a boundary-edge location's parameter must lie in (0, 1)");
      on_edges.push_back(b);
    } else if (kind == "x") {
      std::array<int, 4> e;
      std::array<double, 2> s;
      words >> e[0] >> e[1] >> e[2] >> e[3] >> s[0] >> s[1];
      if (!fully(words)) fail("bad crossing");
      if (!(s[0] >= 0 && s[0] <= 1 && s[1] >= 0 && s[1] <= 1))
        fail("crossing parameters must lie in [0, 1]");
      crossing_edges.push_back(e);
      crossing_at.push_back(s);
    } else if (kind == "k") {
      if (version < 2) fail("kink record in a version 1 file (kinks need 'ism-meta-mesh 2')");
      Kink k{-1, -1, -1, {-1, 0.0, 0.0}, line_number};
      words >> k.side >> k.a >> k.b >> k.at.here >> k.at.face >> k.at.bary[0] >> k.at.bary[1] >>
          k.at.bary[2];
      if (!fully(words) || (k.side != 0 && k.side != 1)) fail("bad kink");
      if (!(k.at.here > 0 && k.at.here < 1)) fail("a kink's parameter must lie in (0, 1)");
      if (k.at.face < 0 || std::size_t(k.at.face) >= faces_expected[1 - k.side])
        fail("a kink in no face of mesh " + std::to_string(1 - k.side));
      if (!k.at.bary.allFinite() || k.at.bary.minCoeff() < -1e-9 ||
          std::abs(k.at.bary.sum() - 1) > 1e-9)
        fail("a kink's barycentric coordinates must be finite, not negative and sum to 1");
      kinks.push_back(k);
    } else {
      fail("unknown record '" + kind.substr(0, 40) + "'");
    }
  }
  line_number = 0;
  for (int m = 0; m < 2; ++m) {
    MetaSide& side = meta.side[m];
    if (!mesh_seen[m]) fail("no mesh " + std::to_string(m));
    if (side.faces.size() != faces_expected[m]) fail("face count differs from its mesh line");
    if (!build_edges(side, version >= 3))
      fail("mesh " + std::to_string(m) +
           (version >= 3 ? " is not a manifold" : " is not a closed manifold"));
    side.crossings.assign(side.edges.size(), {});
  }
  std::array<std::unordered_map<std::uint64_t, int>, 2> edge_id;
  for (int m = 0; m < 2; ++m)
    for (std::size_t e = 0; e < meta.side[m].edges.size(); ++e)
      edge_id[m][undirected_edge_key(meta.side[m].edges[e][0], meta.side[m].edges[e][1])] = int(e);
  for (std::size_t i = 0; i < crossing_edges.size(); ++i) {
    const auto& e = crossing_edges[i];
    const auto a = edge_id[0].find(undirected_edge_key(e[0], e[1]));
    const auto b = edge_id[1].find(undirected_edge_key(e[2], e[3]));
    if (a == edge_id[0].end() || b == edge_id[1].end()) fail("a crossing of no edge");
    // Parameters are stored from the first vertex named.
    const double s0 = e[0] < e[1] ? crossing_at[i][0] : 1 - crossing_at[i][0];
    const double s1 = e[2] < e[3] ? crossing_at[i][1] : 1 - crossing_at[i][1];
    meta.side[0].crossings[a->second].push_back({b->second, s0, s1});
    meta.side[1].crossings[b->second].push_back({a->second, s1, s0});
  }
  std::array<std::vector<int>, 2> edge_face;  // a face of each edge
  if (!on_edges.empty())
    for (int m = 0; m < 2; ++m) {
      edge_face[m].assign(meta.side[m].edges.size(), -1);
      for (std::size_t f = 0; f < meta.side[m].faces.size(); ++f)
        for (int e : meta.side[m].face_edges[f]) edge_face[m][e] = int(f);
    }
  for (const OnEdge& b : on_edges) {
    line_number = b.line;
    const int o = 1 - b.side;
    const auto e = edge_id[o].find(undirected_edge_key(b.a, b.b));
    if (e == edge_id[o].end()) fail("a location on no edge of mesh " + std::to_string(o));
    // Stored from the first vertex named.
    set_edge_location(meta.side[b.side].location[b.v], meta.side[o], edge_face[o][e->second],
                      e->second, b.a < b.b ? b.t : 1 - b.t);
  }
  for (const Kink& k : kinks) {
    line_number = k.line;
    const auto e = edge_id[k.side].find(undirected_edge_key(k.a, k.b));
    if (e == edge_id[k.side].end()) fail("a kink of no edge of mesh " + std::to_string(k.side));
    MetaCrossing c = k.at;
    if (k.a > k.b) c.here = 1 - c.here;  // stored from the first vertex named
    meta.side[k.side].crossings[e->second].push_back(c);
  }
  line_number = 0;
  for (MetaSide& side : meta.side)
    for (auto& list : side.crossings)
      std::sort(list.begin(), list.end(),
                [](const MetaCrossing& a, const MetaCrossing& b) { return a.here < b.here; });
  return meta;
}

}  // namespace ism
