#pragma once
// Internal types of InterSurfaceMap shared by its source files.
#include "map/chart_cell.hpp"
#include "map/inter_surface_map.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace ism {

/// Undo log of one transaction.
struct InterSurfaceMap::Edit {
  struct OldList {
    int side, edge;
    std::vector<MetaCrossing> list;
  };
  struct OldLocation {
    int side, vertex;
    MetaLocation location;
  };
  std::vector<OldList> lists;
  std::vector<OldLocation> locations;
};

/// What a local operation would write: new locations (index 0: vertices of
/// the side being edited, located on the other; index 1: vertices of the
/// other side, located in the edited side's faces) and new break lists of
/// edges of the edited side (`lists`) and of the other side.
struct InterSurfaceMap::Proposal {
  std::array<std::vector<std::pair<int, MetaLocation>>, 2> locations;
  std::vector<std::pair<int, std::vector<MetaCrossing>>> lists, other_lists;
  /// Empty, keeping the outer lists' storage.
  void clear() {
    locations[0].clear(), locations[1].clear();
    lists.clear(), other_lists.clear();
  }
};

/// A one-ring of side s around v laid out in a chart of the other side t.
struct InterSurfaceMap::Chart {
  int s = 0, t = 1, v = -1;
  std::vector<int> faces, corner, ring;  // face i = (v, ring[i], ring[i+1]); corner of v in it
  std::vector<int> spoke, boundary;      // edges (v, ring[i]) and (ring[i], ring[i+1])
  std::vector<Vec2> w;                   // chart position of ring[i]
  /// With an exact development (developed_ring): the chart positions of the
  /// break points of boundary[i] in order from ring[i], and whether every
  /// ring edge is straight there (break points where their parameters put
  /// them on the chord).
  std::vector<std::vector<Vec2>> boundary_breaks;
  bool straight_boundary = true;
  /// Likewise for the spokes (false: drawing them straight is a change).
  bool straight_spokes = true;
  Vec2 centre = Vec2::Zero();  // chart position of v
  enum Kind { fast, developed, general } kind = general;
  int single_face = -1;  // fast: the face of t holding the whole ring (the chart is its layout)
  /// Meta-vertices of t's content fixed in the chart: the ring's vertices
  /// (ring_anchor[i]), the break points of the boundary edges, and t's
  /// vertices inside (interior; a vertex of t under v sits at `centre`).
  struct Anchor {
    MetaNode node;
    Vec2 pos;
    bool operator==(const Anchor&) const = default;
  };
  std::vector<Anchor> anchors;
  std::vector<int> ring_anchor, boundary_loop, interior;
  std::vector<std::size_t> loop_start;  // where ring[i]'s anchor is in boundary_loop
  int centre_anchor = -1;               // the vertex of t that v sits on, if any
  /// A half-disc (build_half_disc): ring has faces + 1 vertices, spoke[0]
  /// and spoke.back() are v's boundary edges, and v is the anchor `slider`
  /// on the chart's straight side.
  bool half_disc = false;
  int slider = -1;
  /// A piece of an edge of t inside the ring, redrawn straight between two
  /// anchors; its break points first..last-1 (crossings with the ring's
  /// inner edges, kinks) are replaced.
  struct Chord {
    int a, b, edge;
    double ta, tb;  // parameters along the edge at a and b
    int first, last;
    Vec2 lo{0, 0}, hi{0, 0};  // box of its ends in the chart (set with the fragments)
    bool operator==(const Chord&) const = default;
  };
  std::vector<Chord> chords;
  /// The cells of t's content in the chart (for locating moved vertices
  /// and bending edges across them), each in t's face `face`.
  struct Fragment : ChartCell {
    int face;
    std::vector<int> nodes;  // its anchors, counter-clockwise
    Vec2 inside;             // a point inside it
    /// A triangle of t's content inside the ring, off its edges: its
    /// stretch sums with others in the same face of s (StretchMoments).
    bool summable = false;
    StretchMoments moments;
    bool operator==(const Fragment&) const = default;
  };
  std::vector<Fragment> fragments;
  /// A chart with at least this many fragments is large (a cone's ring
  /// holds a large part of the other side): evaluate sums its uncut
  /// fragments per face of s, and optimize_vertex stops its line searches
  /// after a round that does not get below the map's energy.
  static constexpr std::size_t kLarge = 24;
  bool large() const { return fragments.size() >= kLarge; }
  /// Per chord: the fragments on its two sides (-1 where none).
  std::vector<std::array<int, 2>> chord_fragments;
  /// Chord of a pair of anchors (undirected_edge_key).
  std::unordered_map<std::uint64_t, int> chord_of;
  /// The fragments whose map is not affine (where edges may bend), in order.
  std::vector<int> curved;
  /// Every member equal (floating point values exactly): a chart built
  /// again from the map gives the same optimisation (commit_plan).
  bool operator==(const Chart&) const = default;
  /// Back to a default chart, keeping the lists' storage (a chart reused
  /// for vertex after vertex allocates little) unless they held a large
  /// chart (whose storage, tens of MB on a 70K-face surface, is released).
  void clear() {
    if (fragments.capacity() > 4 * kLarge) {
      *this = Chart{};  // a large chart's storage is let go, not kept
      return;
    }
    s = 0, t = 1, v = -1;
    faces.clear(), corner.clear(), ring.clear(), spoke.clear(), boundary.clear(), w.clear();
    boundary_breaks.clear();
    straight_boundary = straight_spokes = true;
    centre = Vec2::Zero();
    kind = general;
    single_face = -1;
    anchors.clear(), ring_anchor.clear(), boundary_loop.clear(), interior.clear();
    loop_start.clear();
    centre_anchor = -1;
    half_disc = false, slider = -1;
    chords.clear(), fragments.clear(), chord_fragments.clear(), curved.clear();
    // (clear() walks every bucket: a large table is let go.)
    if (chord_of.bucket_count() > 256)
      decltype(chord_of)().swap(chord_of);
    else
      chord_of.clear();
  }
};

/// A placement of the region's inner vertices of s in a chart: the vertices
/// (a moved vertex may sit on an anchor, e.g. on the vertex of t it sat on),
/// the faces of s over ring positions and inner vertices, and the inner
/// edges.
struct InterSurfaceMap::Layout {
  struct Inner {
    int vertex;
    Vec2 pos;
    int on_anchor = -1;
  };
  std::vector<Inner> inner;
  /// Chart point reference: r >= 0 is ring position r, r < 0 inner vertex -1 - r.
  struct Tri {
    int face;
    std::array<int, 3> ref;     // in the order of the face's corners
    std::array<Vec2, 3> shape;  // the face's own layout (meta_face_layout of its lengths)
  };
  std::vector<Tri> tris;
  struct Spoke {
    int a, b, edge;
  };
  std::vector<Spoke> spokes;
  /// How close (relative) a new crossing may come to an end of its edges
  /// and a moved vertex to an edge of the other side: optional moves keep
  /// clear of near-degenerate pieces; a split must place its vertex.
  double clearance = 1e-6;
};

/// What optimize_vertex's search found in a chart.
struct InterSurfaceMap::Move {
  Vec2 p = Vec2::Zero();
  double energy = HUGE_VAL;     // the chart's energy there (line searches only)
  bool smooth = false;          // found by Newton steps (smooth_ring)
  std::size_t evaluations = 0;  // of the chart's energy by the line searches
  /// Whether it is a move that lowers the ring's energy `before`.
  bool gains(const Chart& chart, double before) const;
};

/// What plan_vertex found, for commit_plan.
struct InterSurfaceMap::VertexPlan::State {
  bool planned = false;  // plan_vertex ran (else commit_plan optimises anew)
  bool charted = false;  // the chart was built
  Chart chart;
  double before = HUGE_VAL;       // the ring's energy (HUGE_VAL: not cut)
  std::vector<StretchSums> sums;  // of the ring's faces, in chart.faces' order
  std::uint64_t clock = 0;        // the map's edit clock when planned
  Move move;
  /// The move's proposal and its predicted energy, where the move gains.
  bool proposed = false;
  Proposal proposal;
  double predicted = HUGE_VAL;
};

}  // namespace ism
