// InterSurfaceMap: set-up, the edit transaction, energy and checks. The
// local operations (charts, optimisation, splits) are in local_chart.cpp.
#include "map/inter_surface_map.hpp"

#include "map/inter_surface_map_impl.hpp"
#include "metrics/metrics.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace ism {

MapSideInput side_from_pm(const ProgressiveMesh& pm) {
  MapSideInput in;
  in.base_faces = pm.base.triangles;
  in.base_vertices = pm.base_vertices;
  in.n_vertices = pm.base.n_vertices();
  in.positions = pm.base.positions;
  in.splits = pm.splits;
  return in;
}

MapSideInput side_from_domain(const TriangleMesh& domain, std::vector<FaceLengths> lengths) {
  MapSideInput in;
  in.base_faces = domain.triangles;
  in.n_vertices = domain.n_vertices();
  for (std::size_t v = 0; v < in.n_vertices; ++v) in.base_vertices.push_back(int(v));
  in.base_lengths = std::move(lengths);
  return in;
}

MapSideInput side_from_domain(const DomainGeometry& domain, const ProgressiveMesh& pm) {
  if (pm.base_vertices.size() != domain.n_vertices())
    throw std::invalid_argument("the base mesh and the domain have different vertex counts");
  std::vector<int> domain_vertex(pm.base.n_vertices(), -1);
  for (std::size_t i = 0; i < pm.base_vertices.size(); ++i)
    domain_vertex[pm.base_vertices[i]] = int(i);
  MapSideInput in;
  in.n_vertices = domain.n_vertices();
  for (std::size_t v = 0; v < in.n_vertices; ++v) in.base_vertices.push_back(int(v));
  for (const Triangle& t : pm.base.triangles) {
    const Triangle d{domain_vertex[t[0]], domain_vertex[t[1]], domain_vertex[t[2]]};
    const auto found = domain.find_face(d);
    if (!found) throw std::invalid_argument("a base face is not a domain face");
    const auto [f, r] = *found;
    const FaceLengths& l = domain.lengths(f);
    in.base_faces.push_back(d);
    in.base_lengths.push_back({l[r], l[(r + 1) % 3], l[(r + 2) % 3]});
  }
  return in;
}

InterSurfaceMap::InterSurfaceMap(MapSideInput side0, MapSideInput side1,
                                 InterSurfaceOptions options)
    : input_{std::move(side0), std::move(side1)}, options_(options) {
  const std::size_t nb = input_[0].base_vertices.size();
  if (input_[1].base_vertices.size() != nb ||
      input_[0].base_faces.size() != input_[1].base_faces.size())
    throw std::invalid_argument("the two base meshes differ in size");
  for (int s = 0; s < 2; ++s) {
    const MapSideInput& in = input_[s];
    MetaSide& side = meta_.side[s];
    if (in.positions.empty() && in.base_lengths.size() != in.base_faces.size())
      throw std::invalid_argument("a side has neither positions nor a metric");
    side.faces = in.base_faces;
    side.positions = in.positions;
    side.location.assign(in.n_vertices, {});
    pinned_[s].assign(in.n_vertices, 0);
    for (std::size_t f = 0; f < side.faces.size(); ++f)
      side.lengths.push_back(in.positions.empty() ? in.base_lengths[f]
                                                  : face_lengths(s, side.faces[f]));
    if (!build_edges(side, true)) throw std::invalid_argument("a base mesh is not a manifold");
    side.crossings.assign(side.edges.size(), {});
  }
  // Base face f of both sides: the same base vertices in the same order.
  std::array<std::vector<int>, 2> base_of;
  for (int s = 0; s < 2; ++s) {
    base_of[s].assign(input_[s].n_vertices, -1);
    for (std::size_t i = 0; i < nb; ++i) base_of[s][input_[s].base_vertices[i]] = int(i);
  }
  for (std::size_t f = 0; f < input_[0].base_faces.size(); ++f)
    for (int k = 0; k < 3; ++k)
      if (base_of[0][input_[0].base_faces[f][k]] != base_of[1][input_[1].base_faces[f][k]])
        throw std::invalid_argument("base face " + std::to_string(f) +
                                    " differs between the sides");
  for (std::size_t i = 0; i < nb; ++i) {
    const int v0 = input_[0].base_vertices[i], v1 = input_[1].base_vertices[i];
    meta_.side[0].location[v0].vertex = v1;
    meta_.side[1].location[v1].vertex = v0;
    pinned_[0][v0] = pinned_[1][v1] = options_.hold_features;
  }
  index_and_measure();
}

void InterSurfaceMap::release_features() {
  for (int s = 0; s < 2; ++s)
    for (int v : input_[s].base_vertices) pinned_[s][v] = 0;
}

namespace {

/// Whether environment variable `name` is set to something other than "0".
bool env_flag(const char* name) {
  const char* value = std::getenv(name);
  return value && *value && std::string(value) != "0";
}

}  // namespace

void InterSurfaceMap::index_and_measure() {
  const auto& d = options_.forward_density;
  if (!d.empty() && d.size() != meta_.side[1].n_vertices())
    throw std::invalid_argument("the forward density has " + std::to_string(d.size()) +
                                " values for " + std::to_string(meta_.side[1].n_vertices()) +
                                " vertices");
  if (!(options_.anisotropy_weight >= 0) || !(options_.anisotropy_threshold >= 1))
    throw std::invalid_argument("the anisotropy penalty needs a weight >= 0 and a threshold >= 1");
  index_ = build_index(meta_);
  check_cache_ = env_flag("ISM_CHECK_ENERGY_CACHE");
  check_plans_ = env_flag("ISM_CHECK_PLANS");
  touch_all({0, 1});
  for (int s = 0; s < 2; ++s) {
    active_[s] = 0;
    for (std::size_t v = 0; v < meta_.side[s].n_vertices(); ++v) active_[s] += is_active(s, int(v));
    area_[s] = 0;
    for (std::size_t f = 0; f < meta_.side[s].faces.size(); ++f) area_[s] += face_area(s, int(f));
  }
}

InterSurfaceMap::InterSurfaceMap(MetaMesh meta, MapSideInput side0, MapSideInput side1,
                                 std::array<std::size_t, 2> applied, InterSurfaceOptions options)
    : meta_(std::move(meta)), input_{std::move(side0), std::move(side1)}, options_(options) {
  if (const auto problem = ism::validate(meta_))
    throw std::invalid_argument("the map to resume is not valid: " + *problem);
  for (int s = 0; s < 2; ++s) {
    const MapSideInput& in = input_[s];
    MetaSide& side = meta_.side[s];
    if (side.n_vertices() != in.n_vertices || applied[s] > in.splits.size())
      throw std::invalid_argument("the map to resume does not fit its sides");
    if (side.positions.empty()) side.positions = in.positions;
    pinned_[s].assign(in.n_vertices, 0);
    for (int v : in.base_vertices) pinned_[s][v] = options_.hold_features;
    next_split_[s] = applied[s];
  }
  index_and_measure();
}

FaceLengths InterSurfaceMap::face_lengths(int s, const Triangle& t) const {
  const auto& x = meta_.side[s].positions;
  FaceLengths l{(x[t[1]] - x[t[0]]).norm(), (x[t[2]] - x[t[1]]).norm(), (x[t[0]] - x[t[2]]).norm()};
  // A face of an intermediate level can be flat (a path's Steiner vertex
  // split off along the edge it lies on): its metric is made a thin
  // triangle (the longest edge 1e-4 shorter than the other two together),
  // so that it can be cut into pieces of positive area.
  const int k = int(std::max_element(l.begin(), l.end()) - l.begin());
  const double others = l[(k + 1) % 3] + l[(k + 2) % 3];
  l[k] = std::min(l[k], others * (1 - 1e-4));
  return l;
}

double InterSurfaceMap::face_area(int s, int f) const {
  const auto& l = meta_.side[s].lengths[f];
  return triangle_area({l[0], l[1], l[2]});
}

std::vector<int> InterSurfaceMap::ring_faces(int s, int v) const {
  std::vector<int> out;
  ring_faces(s, v, out);
  return out;
}

void InterSurfaceMap::ring_faces(int s, int v, std::vector<int>& out) const {
  const MetaSide& side = meta_.side[s];
  const auto& around = index_[s].vertex_faces[v];
  out.clear();
  if (around.empty()) return;
  auto corner = [&](int f) {
    const Triangle& t = side.faces[f];
    return t[0] == v ? 0 : t[1] == v ? 1 : 2;
  };
  int f = around.front();
  do {
    out.push_back(f);
    const int last = side.faces[f][(corner(f) + 2) % 3];
    int next = -1;
    for (int g : around)
      if (side.faces[g][(corner(g) + 1) % 3] == last) next = g;
    f = next;
    if (f < 0 || out.size() > around.size()) {
      out.clear();
      return;
    }
  } while (f != out.front());
  if (out.size() != around.size()) out.clear();
}

void InterSurfaceMap::fan_faces(int s, int v, std::vector<int>& out) const {
  const MetaSide& side = meta_.side[s];
  const auto& around = index_[s].vertex_faces[v];
  out.clear();
  auto corner = [&](int f) {
    const Triangle& t = side.faces[f];
    return t[0] == v ? 0 : t[1] == v ? 1 : 2;
  };
  // The first face: no face of v ends (counter-clockwise) where it begins.
  int first = -1;
  for (int f : around) {
    const int begin = side.faces[f][(corner(f) + 1) % 3];
    bool preceded = false;
    for (int g : around) preceded = preceded || side.faces[g][(corner(g) + 2) % 3] == begin;
    if (!preceded) {
      if (first >= 0) return;  // (two boundary stretches at v)
      first = f;
    }
  }
  for (int f = first; f >= 0 && out.size() <= around.size();) {
    out.push_back(f);
    const int last = side.faces[f][(corner(f) + 2) % 3];
    int next = -1;
    for (int g : around)
      if (side.faces[g][(corner(g) + 1) % 3] == last) next = g;
    f = next;
  }
  if (out.size() != around.size()) out.clear();
}

std::vector<int> InterSurfaceMap::neighbours(int s, int v) const {
  std::vector<int> out;
  for (int f : ring_faces(s, v)) {
    const Triangle& t = meta_.side[s].faces[f];
    out.push_back(t[0] == v ? t[1] : t[1] == v ? t[2] : t[0]);
  }
  return out;
}

std::vector<int> InterSurfaceMap::others_in_ring(int s, int v) const {
  std::vector<int> out;
  for (int f : index_[s].vertex_faces[v])
    for (int x : index_[s].residents[f]) out.push_back(x);
  // Those on a vertex of the ring or on v, in the other side's order.
  const std::size_t inside = out.size();
  for (int w : neighbours(s, v))
    out.insert(out.end(), index_[s].lodgers[w].begin(), index_[s].lodgers[w].end());
  out.insert(out.end(), index_[s].lodgers[v].begin(), index_[s].lodgers[v].end());
  std::sort(out.begin() + std::ptrdiff_t(inside), out.end());
  return out;
}

// ---------------------------------------------------------------- edits

void InterSurfaceMap::touch_face(int s, int f) {
  auto& stamps = face_edit_[s];
  if (std::size_t(f) >= stamps.size())
    stamps.resize(std::max(std::size_t(f) + 1, meta_.side[s].faces.size()), edit_all_);
  stamps[f] = edit_clock_;
}

void InterSurfaceMap::touch_vertex(int s, int v) {
  for (int f : index_[s].vertex_faces[v]) touch_face(s, f);
}

void InterSurfaceMap::touch_edge(int s, int e) {
  for (int f : index_[s].edge_faces[e])
    if (f >= 0) touch_face(s, f);
}

void InterSurfaceMap::touch_crossings(int s, const std::vector<MetaCrossing>& list) {
  for (const MetaCrossing& c : list)
    if (c.is_kink())
      touch_face(1 - s, c.face);
    else
      touch_edge(1 - s, c.edge);
}

void InterSurfaceMap::touch_location(int s, const MetaLocation& loc) {
  // A point of side s's map on side t: its face, and the face across an
  // edge it lies on (a point on an edge belongs to both); or the faces
  // around the vertex it sits on.
  const int t = 1 - s;
  if (loc.face >= 0) {
    touch_face(t, loc.face);
    for (int k = 0; k < 3; ++k)
      if (!(loc.bary[(k + 2) % 3] > 0))  // on edge k (from corner k to k + 1)
        touch_edge(t, meta_.side[t].face_edges[loc.face][k]);
  } else if (loc.vertex >= 0) {
    touch_vertex(t, loc.vertex);
  }
}

void InterSurfaceMap::touch_under(int s, const std::vector<int>& faces) {
  const int t = 1 - s;
  const MetaSide& S = meta_.side[s];
  const MetaSideIndex& IS = index_[s];
  ++edit_clock_;  // (sums cut until now are older than the touches)
  for (const int f : faces) {
    for (const int v : S.faces[f]) {
      touch_location(s, S.location[v]);
      for (const int x : IS.lodgers[v]) touch_vertex(t, x);
    }
    for (const int x : IS.residents[f]) touch_vertex(t, x);
    for (const int e : S.face_edges[f]) touch_crossings(s, S.crossings[e]);
  }
}

void InterSurfaceMap::touch_all(std::initializer_list<int> stale_sums) {
  edit_all_ = ++edit_clock_;
  for (int s : stale_sums) sums_all_[s] = edit_all_;
}

bool InterSurfaceMap::sums_valid(int s, int f, const CachedSums& entry) const {
  const auto& stamps = face_edit_[s];
  return entry.stamp >= sums_all_[s] &&
         (std::size_t(f) >= stamps.size() || entry.stamp >= stamps[f]);
}

bool InterSurfaceMap::untouched_since(int s, const std::vector<int>& faces,
                                      std::uint64_t since) const {
  if (edit_all_ > since) return false;
  const auto& stamps = face_edit_[s];
  for (int f : faces)
    if (std::size_t(f) >= stamps.size() || stamps[f] > since) return false;
  return true;
}

void InterSurfaceMap::set_location(int s, int v, const MetaLocation& loc, Edit* edit) {
  MetaLocation& current = meta_.side[s].location[v];
  if (edit) edit->locations.push_back({s, v, current});
  ++edit_clock_;
  touch_vertex(s, v);
  touch_location(s, current);
  touch_location(s, loc);
  if (current.on_edge())
    remove_on_edge(index_, s, v, current.edge);
  else if (current.face >= 0)
    remove_resident(index_, s, v, current.face);
  else if (current.vertex >= 0)
    remove_lodger(index_, s, v, current.vertex);
  current = loc;
  if (current.on_edge())
    add_on_edge(index_, meta_, s, v, current.edge);
  else if (current.face >= 0)
    add_resident(index_, s, v, current.face);
  else if (current.vertex >= 0)
    add_lodger(index_, s, v, current.vertex);
}

void InterSurfaceMap::set_breaks(int s, int e, std::vector<MetaCrossing> list, Edit* edit) {
  auto& current = meta_.side[s].crossings[e];
  ++edit_clock_;
  touch_edge(s, e);
  touch_crossings(s, current);
  touch_crossings(s, list);
  if (edit) edit->lists.push_back({s, e, std::move(current)});
  current = std::move(list);
}

void InterSurfaceMap::rollback(Edit& edit) {
  for (auto it = edit.lists.rbegin(); it != edit.lists.rend(); ++it)
    meta_.side[it->side].crossings[it->edge] = std::move(it->list);
  for (auto it = edit.locations.rbegin(); it != edit.locations.rend(); ++it)
    set_location(it->side, it->vertex, it->location, nullptr);
  edit = Edit{};
}

// ---------------------------------------------------------------- energy and checks

namespace {

/// `v`, grown to at least n entries (new faces appear with splits).
template <class T>
std::vector<T>& fit(std::vector<T>& v, std::size_t n) {
  if (v.size() < n) v.resize(n);
  return v;
}

/// fn(0), ..., fn(n - 1), on the caller's arena's threads when there are
/// several (each call independent; the caller combines the results in
/// index order, so the outcome does not depend on the threads).
template <class Fn>
void for_each_index(std::size_t n, Fn&& fn) {
  if (n < 2) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, n, 1),
      [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i < range.end(); ++i) fn(i);
      },
      tbb::simple_partitioner());
}

}  // namespace

double InterSurfaceMap::faces_energy(int s, const std::vector<int>& faces) const {
  // The cached sums of a face are those of the map as committed (see the
  // members' comment); a face without them is cut now and cached.
  const EnergyTerms terms = energy_terms();
  auto& cache = fit(sums_cache_[s], meta_.side[s].faces.size());
  std::vector<std::size_t> to_cut;
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (check_cache_ || !sums_valid(s, faces[i], cache[faces[i]])) to_cut.push_back(i);
  std::vector<StretchSums> fresh(to_cut.size());
  std::vector<char> cut(to_cut.size(), 0);
  for_each_index(to_cut.size(), [&](std::size_t k) {
    cut[k] = !add_face_sums(meta_, index_, s, faces[to_cut[k]], terms, fresh[k]);
  });
  double energy = 0;
  for (std::size_t i = 0, k = 0; i < faces.size(); ++i) {
    const int f = faces[i];
    CachedSums& entry = cache[f];
    if (k < to_cut.size() && to_cut[k] == i) {
      const bool valid = sums_valid(s, f, entry);
      if (valid && (!cut[k] || !(entry.sums == fresh[k])))
        throw std::logic_error("the energy cached for face " + std::to_string(f) + " of side " +
                               std::to_string(s) + " is stale");
      if (!cut[k]) return HUGE_VAL;
      entry = {edit_clock_, fresh[k]};
      ++k;
    }
    energy += entry.sums.energy(terms);
  }
  return energy;
}

double InterSurfaceMap::faces_energy_read(int s, const std::vector<int>& faces,
                                          std::vector<StretchSums>* sums) const {
  const EnergyTerms terms = energy_terms();
  const auto& cache = sums_cache_[s];
  if (sums) sums->resize(faces.size());
  double energy = 0;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const int f = faces[i];
    if (std::size_t(f) < cache.size() && sums_valid(s, f, cache[f])) {
      energy += cache[f].sums.energy(terms);
      if (sums) (*sums)[i] = cache[f].sums;
      continue;
    }
    StretchSums fresh;
    if (add_face_sums(meta_, index_, s, f, terms, fresh)) return HUGE_VAL;  // (a problem)
    energy += fresh.energy(terms);
    if (sums) (*sums)[i] = fresh;
  }
  return energy;
}

void InterSurfaceMap::keep_sums(int s, const std::vector<int>& faces,
                                const std::vector<StretchSums>& sums, std::uint64_t clock) const {
  auto& cache = fit(sums_cache_[s], meta_.side[s].faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i)
    if (!sums_valid(s, faces[i], cache[faces[i]])) cache[faces[i]] = {clock, sums[i]};
}

EnergyTerms InterSurfaceMap::energy_terms() const {
  EnergyTerms terms{area_[0], area_[1], options_.inverse_weight, options_.forward_density};
  terms.anisotropy_weight = options_.anisotropy_weight;
  terms.anisotropy_onset = anisotropy_onset(options_.anisotropy_threshold);
  return terms;
}

double InterSurfaceMap::energy() const {
  // Cut afresh (not from the cache): tests compare it with the gains.
  std::vector<int> all(meta_.side[1].faces.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = int(f);
  std::vector<StretchSums> sums;
  if (check_faces(1, all, &sums)) return HUGE_VAL;
  return sums_energy(sums);
}

double InterSurfaceMap::cached_energy() const {
  // (Side 1's faces hold the pieces energy() sums, in the same order.)
  std::vector<int> all(meta_.side[1].faces.size());
  for (std::size_t f = 0; f < all.size(); ++f) all[f] = int(f);
  return faces_energy(1, all);
}

double InterSurfaceMap::sums_energy(const std::vector<StretchSums>& sums) const {
  const EnergyTerms terms = energy_terms();
  double energy = 0;
  for (const StretchSums& face : sums) energy += face.energy(terms);
  return energy;
}

double InterSurfaceMap::replace_overlay(MetaMesh candidate) {
  for (int s = 0; s < 2; ++s) {
    const MetaSide &now = meta_.side[s], &next = candidate.side[s];
    if (next.faces != now.faces || next.lengths != now.lengths || next.edges != now.edges ||
        next.face_edges != now.face_edges || next.location.size() != now.location.size() ||
        next.crossings.size() != now.crossings.size() || next.positions != now.positions)
      return 0;
    for (std::size_t v = 0; v < now.location.size(); ++v) {
      const MetaLocation &a = now.location[v], &b = next.location[v];
      if ((a.face < 0 && a.vertex < 0) != (b.face < 0 && b.vertex < 0)) return 0;
      if (pinned_[s][v] && (a.vertex != b.vertex || a.face != b.face || a.bary != b.bary)) return 0;
    }
  }
  if (ism::validate(candidate)) return 0;
  const double before = energy();
  MetaIndex index = build_index(candidate);
  std::swap(meta_, candidate);
  std::swap(index_, index);
  const double after = energy();
  if (after < before) {
    touch_all({0, 1});  // every face may have changed
    return before - after;
  }
  std::swap(meta_, candidate);  // rolled back, the old index with it
  std::swap(index_, index);
  return 0;
}

std::optional<std::string> InterSurfaceMap::validate() const {
  return ism::validate(meta_);
}

MapMeasures InterSurfaceMap::measures() const {
  return ism::measures(meta_).value_or(MapMeasures{});
}

std::optional<std::string> InterSurfaceMap::check_faces(int s, const std::vector<int>& faces,
                                                        std::vector<StretchSums>* sums) const {
  // Cutting the changed faces of s checks that every record their pieces
  // use is kept by both edges (break_node, for the boundary's edges and for
  // the points of the other side's edges on them), that the pieces tile
  // the faces and that each is positive on both sides. The edit leaves the
  // ring's boundary and everything outside it as they were, so the pieces
  // form a continuous, orientation-preserving map of the region onto the
  // same boundary curve on the other side: of degree one inside, zero
  // outside, i.e. a bijection onto what the region covered before. So the
  // other side's faces need not be cut again (for a coarse domain each is a
  // whole face of the octahedron with all its content: O(n) per move).
  const EnergyTerms terms = energy_terms();
  if (sums) sums->assign(faces.size(), {});
  std::vector<std::optional<std::string>> problems(faces.size());
  for_each_index(faces.size(), [&](std::size_t i) {
    if (sums)
      problems[i] = add_face_sums(meta_, index_, s, faces[i], terms, (*sums)[i]);
    else
      problems[i] = cut_face(meta_, index_, s, faces[i]).error;
  });
  for (auto& problem : problems)
    if (problem) return problem;
  return std::nullopt;
}

std::optional<double> InterSurfaceMap::apply(int s, const std::vector<int>& faces,
                                             const Proposal& proposal, double energy_before,
                                             bool need_gain) {
  Edit edit;
  for (const auto& [v, loc] : proposal.locations[0]) set_location(s, v, loc, &edit);
  for (const auto& [x, loc] : proposal.locations[1]) set_location(1 - s, x, loc, &edit);
  for (const auto& [e, list] : proposal.lists) set_breaks(s, e, list, &edit);
  for (const auto& [g, list] : proposal.other_lists) set_breaks(1 - s, g, list, &edit);
  std::vector<StretchSums> sums;
  const auto problem = check_faces(s, faces, &sums);
  const double after = problem ? HUGE_VAL : sums_energy(sums);
  if (problem || !(after < HUGE_VAL) || (need_gain && !(after < energy_before * (1 - 1e-12)))) {
    last_refusal_ = problem ? *problem : !(after < HUGE_VAL) ? "infinite energy" : "no gain";
    rollback(edit);
    return std::nullopt;
  }
  // Committed: the faces of s it changed are exactly `faces`, their sums
  // just cut; those of the other side's faces it touched are stale
  // (face_edit_).
  auto& cache = fit(sums_cache_[s], meta_.side[s].faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i) cache[faces[i]] = {edit_clock_, sums[i]};
  return energy_before - after;
}

}  // namespace ism
