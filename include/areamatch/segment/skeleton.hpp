#pragma once
/// \file segment/skeleton.hpp
/// Stage 3 of segmentation: boundary segments → segment Voronoi diagram (Boost.Polygon) → the
/// free-space skeleton, a graph of branches sampled with their clearance.
///
/// Coordinates are those of the pixel-corner lattice (see boundary.hpp): one unit = one cell.
/// A Voronoi edge is kept when it is primary and finite, both its vertices lie in free cells and
/// its clearance (distance to the walls that generate it) stays ≥ `min_clearance_m` along it —
/// that removes the diagram inside walls, outside the building and in gaps too narrow to pass.
/// Curved edges (a wall corner against a wall) are parabolic arcs and are sampled as such.
/// Every sample keeps its two *feet*: the nearest points on the two walls it lies between, which
/// later give each passage's line across the opening.

#include "../detail/adjacency.hpp"
#include "../detail/compact_voronoi.hpp"
#include "../detail/span.hpp"
#include "../detail/voronoi_circles.hpp"
#include "../error.hpp"
#include "binarize.hpp"
#include "boundary.hpp"

#include <boost/polygon/voronoi.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace areamatch {

/// One point of the skeleton with its distance to the nearest wall and where that wall is.
struct SkeletonSample {
  Eigen::Vector2d position = Eigen::Vector2d::Zero();  ///< lattice units
  double clearance = 0.0;                               ///< lattice units
  Eigen::Vector2d foot_a = Eigen::Vector2d::Zero();     ///< nearest point on one wall
  Eigen::Vector2d foot_b = Eigen::Vector2d::Zero();     ///< nearest point on the other wall
};

/// A junction (degree ≥ 3), dead end (degree 1) or loop anchor of the skeleton.
struct SkeletonNode {
  SkeletonSample sample;
  std::vector<int> branches;  ///< ids of the branches ending here (twice for a self-loop)
};

/// A chain of Voronoi edges between two nodes, sampled at most `sample_step` apart. Its samples
/// are `Skeleton::samples_of(branch)`: the first lies at node `from`, the last at node `to`.
struct SkeletonBranch {
  int from = -1;
  int to = -1;
  std::size_t first_sample = 0;  ///< where its samples start in `Skeleton::samples`
  std::size_t sample_count = 0;
  double length = 0.0;  ///< lattice units
  bool removed = false; ///< pruned
};

/// A branch's samples, valid while its skeleton is neither changed nor gone.
using SkeletonSamples = detail::ConstSpan<SkeletonSample>;

struct Skeleton {
  /// Lattice coordinates here are those of the cropped free-space mask; add this offset for the
  /// source grid's pixel-corner lattice.
  Eigen::Vector2d lattice_offset = Eigen::Vector2d::Zero();
  std::vector<SkeletonNode> nodes;
  std::vector<SkeletonBranch> branches;
  /// Every branch's samples, branch after branch, in one array: a large floor has millions, and
  /// an array per branch left the heap in tens of thousands of pieces once they were let go.
  std::vector<SkeletonSample> samples;
  std::size_t voronoi_edges = 0;  ///< primary finite edges examined

  SkeletonSamples samples_of(const SkeletonBranch& branch) const {
    const SkeletonSample* first = samples.data() + branch.first_sample;
    return {first, first + branch.sample_count};
  }

  int degree(int node) const {
    int d = 0;
    for (int b : nodes[node].branches) d += !branches[b].removed;
    return d;
  }
};

/// Parameters of `build_skeleton`. Lengths in metres.
struct SkeletonParams {
  /// Skeleton closer than this to a wall is dropped: gaps narrower than twice this are not
  /// passable. The reference implementation's `voronoiMinimumDistanceToObstacle`, 0.25 m.
  double min_clearance_m = 0.25;
  /// Spacing of samples along skeleton edges.
  double sample_step_m = 0.05;
  /// Dead ends shorter than this whose clearance never reaches `keep_clearance_m` are pruned
  /// (wall niches, corner spurs), repeatedly until none is left.
  double spur_length_m = 1.0;
  /// A dead end whose clearance reaches this is a room, never a spur. `VoronoiSegmenter` sets it
  /// from the door width (`detail::room_clearance_m`, the threshold `detect_rooms` uses) and
  /// refuses another value here; `build_skeleton` called directly reads it.
  double keep_clearance_m = 0.625;
  /// Compute the Voronoi diagram's corner circle events without multiprecision where that is
  /// provably as accurate (detail/voronoi_circles.hpp: about half the diagram's time); false:
  /// Boost's stock builder. The same diagram either way, up to rounding in the last bits of the
  /// vertices (the same areas; passages within 1e-9 m: tested). Without effect where the faster events
  /// are not compiled in (`AREAMATCH_FAST_VORONOI_CIRCLES`, set from the Boost version).
  bool fast_circle_events = true;

  void validate() const {
    detail::require_non_negative(min_clearance_m, "SkeletonParams::min_clearance_m");
    detail::require_positive(sample_step_m, "SkeletonParams::sample_step_m");
    detail::require_non_negative(spur_length_m, "SkeletonParams::spur_length_m");
    detail::require_non_negative(keep_clearance_m, "SkeletonParams::keep_clearance_m");
  }
};

namespace detail {

/// The site (point or segment) of a Voronoi cell.
struct VoronoiSite {
  bool is_point = false;
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();

  /// The nearest point of the site to p.
  Eigen::Vector2d foot(const Eigen::Vector2d& p) const {
    if (is_point) return a;
    const Eigen::Vector2d d = b - a;
    const double t = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return a + t * d;
  }
};

inline VoronoiSite site_of(const CompactVoronoi::Site& cell, const std::vector<LatticeSegment>& segments) {
  const LatticeSegment& s = segments[cell.source_index];
  const Eigen::Vector2d low(s.low().x(), s.low().y()), high(s.high().x(), s.high().y());
  VoronoiSite site;
  if (cell.contains_point()) {
    site.is_point = true;
    site.a = cell.category == boost::polygon::SOURCE_CATEGORY_SEGMENT_START_POINT ? low : high;
  } else {
    site.a = low;
    site.b = high;
  }
  return site;
}

/// Points along a Voronoi edge from v0 to v1 at most `step` apart (both ends included), into
/// `points` (cleared first: one buffer serves every edge). A curved edge lies on the parabola of
/// points equidistant from a point site and a segment site.
inline void edge_points(const Eigen::Vector2d& v0, const Eigen::Vector2d& v1, bool curved, const VoronoiSite& s0,
                        const VoronoiSite& s1, double step, std::vector<Eigen::Vector2d>& points) {
  points.clear();
  if (!curved) {
    const int n = std::max(1, static_cast<int>(std::ceil((v1 - v0).norm() / step)));
    for (int i = 0; i <= n; ++i) points.push_back(v0 + (v1 - v0) * (static_cast<double>(i) / n));
    return;
  }
  const VoronoiSite& point_site = s0.is_point ? s0 : s1;
  const VoronoiSite& segment_site = s0.is_point ? s1 : s0;
  const Eigen::Vector2d origin = segment_site.a;
  const Eigen::Vector2d u = (segment_site.b - segment_site.a).normalized();
  const Eigen::Vector2d n(-u.y(), u.x());
  auto local = [&](const Eigen::Vector2d& p) { return Eigen::Vector2d((p - origin).dot(u), (p - origin).dot(n)); };
  const Eigen::Vector2d p = local(point_site.a);
  const double x0 = local(v0).x(), x1 = local(v1).x();
  // y = ((x − px)² + py²) / (2 py); arc length ≤ |Δx|·√(1 + slope²) with slope (x − px)/py.
  const double slope = std::max(std::abs(x0 - p.x()), std::abs(x1 - p.x())) / std::abs(p.y());
  const int n_steps = std::max(1, static_cast<int>(std::ceil(std::abs(x1 - x0) * std::sqrt(1.0 + slope * slope) / step)));
  points.push_back(v0);
  for (int i = 1; i < n_steps; ++i) {
    const double x = x0 + (x1 - x0) * (static_cast<double>(i) / n_steps);
    const double y = ((x - p.x()) * (x - p.x()) + p.y() * p.y()) / (2.0 * p.y());
    points.push_back(origin + x * u + y * n);
  }
  points.push_back(v1);
}

/// A Voronoi edge kept for the skeleton: its end vertices (by index in the diagram, so the result
/// does not depend on memory addresses; and their positions) and the two sites it separates.
/// Its samples are not held: `edge_samples` makes them again, the same every time. Held, they
/// were about nine samples of 56 bytes an edge, 51 MB beside the diagram on a 240 × 160 m floor.
struct KeptEdge {
  std::size_t v0, v1;
  Eigen::Vector2d p0, p1;
  VoronoiSite s0, s1;
  bool curved = false;
  std::uint32_t sample_count = 0;  ///< how many samples `edge_samples` makes of it
};

/// The samples of a Voronoi edge from p0 to p1 at most `step` apart, with their clearance and
/// feet on the two sites, into `samples` (cleared first; `points` is scratch). Stops after the
/// first sample narrower than `min_clearance` and returns false then.
inline bool edge_samples(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, bool curved, const VoronoiSite& s0,
                         const VoronoiSite& s1, double step, double min_clearance, std::vector<Eigen::Vector2d>& points,
                         std::vector<SkeletonSample>& samples) {
  samples.clear();
  edge_points(p0, p1, curved, s0, s1, step, points);
  for (const Eigen::Vector2d& p : points) {
    SkeletonSample sample;
    sample.position = p;
    sample.foot_a = s0.foot(p);
    sample.foot_b = s1.foot(p);
    sample.clearance = 0.5 * ((sample.foot_a - p).norm() + (sample.foot_b - p).norm());
    if (sample.clearance < min_clearance) return false;
    samples.push_back(sample);
  }
  return true;
}

inline void edge_samples(const KeptEdge& e, double step, std::vector<Eigen::Vector2d>& points, std::vector<SkeletonSample>& samples) {
  edge_samples(e.p0, e.p1, e.curved, e.s0, e.s1, step, -std::numeric_limits<double>::infinity(), points, samples);
}

/// The diagram's finite primary edges that run through free space (`is_free(col, row)` of a
/// lattice cell) at least `min_clearance` (lattice units) from the walls all along, sampled every
/// `step`; each undirected edge once. Counts the edges looked at in `skeleton.voronoi_edges`.
template <class IsFree>
std::vector<KeptEdge> kept_edges(const CompactVoronoi& diagram, const IsFree& is_free, const BoundarySegments& boundary,
                                 double min_clearance, double step, Skeleton& skeleton) {
  auto is_free_at = [&](const CompactVoronoi::Vertex& v) {
    return is_free(static_cast<int>(std::floor(v.x)), static_cast<int>(std::floor(v.y)));
  };
  std::vector<KeptEdge> kept;
  std::vector<Eigen::Vector2d> points;
  std::vector<SkeletonSample> samples;
  for (const CompactVoronoi::Edge& edge : diagram.edges()) {  // each undirected edge once
    if (!edge.primary || !edge.is_finite()) continue;
    ++skeleton.voronoi_edges;
    const CompactVoronoi::Vertex& a = diagram.vertices()[edge.vertex[0]];
    const CompactVoronoi::Vertex& b = diagram.vertices()[edge.vertex[1]];
    if (!is_free_at(a) || !is_free_at(b)) continue;
    const VoronoiSite s0 = site_of(diagram.sites()[edge.site[0]], boundary.segments);
    const VoronoiSite s1 = site_of(diagram.sites()[edge.site[1]], boundary.segments);
    const Eigen::Vector2d p0(a.x, a.y), p1(b.x, b.y);
    if ((s0.foot(p0) - p0).norm() < min_clearance || (s0.foot(p1) - p1).norm() < min_clearance) continue;
    if (!edge_samples(p0, p1, edge.is_curved(), s0, s1, step, min_clearance, points, samples)) continue;
    kept.push_back({edge.vertex[0], edge.vertex[1], p0, p1, s0, s1, edge.is_curved(), static_cast<std::uint32_t>(samples.size())});
  }
  kept.shrink_to_fit();
  return kept;
}

/// The graph over the kept edges into `skeleton`: nodes are vertices of degree ≠ 2 (plus one
/// anchor per pure loop), branches the chains of edges between them, with each edge's samples
/// (`edge_samples`, sampled every `step`).
inline void link_kept_edges(const std::vector<KeptEdge>& kept, std::size_t vertex_count, double step, Skeleton& skeleton) {
  // Per diagram vertex (by index, ascending): its kept edges in the order they were kept.
  const auto incident = build_adjacency<std::size_t>(vertex_count, kept.size(), [&](std::size_t i) {
    return LinkEnds<std::size_t>{kept[i].v0, i, kept[i].v1, i};
  });
  auto degree_of = [&](std::size_t vertex) { return incident.degree(vertex); };
  auto first_edge = [&](std::size_t vertex) { return *incident.begin(vertex); };
  std::vector<int> node_of_vertex(vertex_count, -1);
  auto make_node = [&](std::size_t vertex, const SkeletonSample& sample) {
    if (node_of_vertex[vertex] >= 0) return node_of_vertex[vertex];
    const int id = static_cast<int>(skeleton.nodes.size());
    skeleton.nodes.push_back({sample, {}});
    node_of_vertex[vertex] = id;
    return id;
  };
  // Every kept edge goes into one branch, sharing its first sample with the edge before it:
  // the edges' own counts bound the skeleton's samples, so the array is never moved.
  std::size_t sample_bound = 0;
  for (const KeptEdge& e : kept) sample_bound += e.sample_count;
  skeleton.samples.reserve(sample_bound);
  std::vector<Eigen::Vector2d> points;
  std::vector<SkeletonSample> samples;
  auto sample_at = [&](std::size_t edge, std::size_t vertex) {
    edge_samples(kept[edge], step, points, samples);
    return kept[edge].v0 == vertex ? samples.front() : samples.back();
  };
  for (std::size_t vertex = 0; vertex < vertex_count; ++vertex)
    if (degree_of(vertex) != 0 && degree_of(vertex) != 2) make_node(vertex, sample_at(first_edge(vertex), vertex));

  std::vector<bool> used(kept.size(), false);
  auto walk = [&](std::size_t start_vertex, std::size_t start_edge) {
    SkeletonBranch branch;
    branch.from = node_of_vertex[start_vertex];
    branch.first_sample = skeleton.samples.size();
    std::vector<SkeletonSample>& all = skeleton.samples;
    std::size_t vertex = start_vertex, e = start_edge;
    while (true) {
      used[e] = true;
      // The edge's samples in walking order; the first is shared with the previous edge.
      edge_samples(kept[e], step, points, samples);
      const bool forward = kept[e].v0 == vertex;
      const std::size_t skip = all.size() == branch.first_sample ? 0 : 1;
      if (forward) all.insert(all.end(), samples.begin() + static_cast<std::ptrdiff_t>(skip), samples.end());
      else all.insert(all.end(), samples.rbegin() + static_cast<std::ptrdiff_t>(skip), samples.rend());
      vertex = forward ? kept[e].v1 : kept[e].v0;
      if (node_of_vertex[vertex] >= 0) break;
      const std::size_t* next = incident.begin(vertex);  // degree 2: this edge and the next
      e = next[0] == e ? next[1] : next[0];
    }
    branch.to = node_of_vertex[vertex];
    branch.sample_count = all.size() - branch.first_sample;
    for (std::size_t i = branch.first_sample + 1; i < all.size(); ++i) branch.length += (all[i].position - all[i - 1].position).norm();
    const int id = static_cast<int>(skeleton.branches.size());
    skeleton.nodes[branch.from].branches.push_back(id);
    skeleton.nodes[branch.to].branches.push_back(id);
    skeleton.branches.push_back(std::move(branch));
  };
  for (std::size_t vertex = 0; vertex < vertex_count; ++vertex) {
    if (node_of_vertex[vertex] < 0) continue;
    for (const std::size_t* e = incident.begin(vertex); e != incident.end(vertex); ++e)
      if (!used[*e]) walk(vertex, *e);
  }
  // Loops made only of degree-2 vertices get an anchor node at their smallest vertex.
  for (std::size_t vertex = 0; vertex < vertex_count; ++vertex) {
    if (degree_of(vertex) == 0 || used[first_edge(vertex)]) continue;
    make_node(vertex, sample_at(first_edge(vertex), vertex));
    walk(vertex, first_edge(vertex));
  }
}

/// Prunes short (< `spur_length`), narrow (never `keep_clearance` wide) dead ends until none is
/// left; lattice units.
inline void prune_spurs(Skeleton& skeleton, double spur_length, double keep_clearance) {
  bool pruned = true;
  while (pruned) {
    pruned = false;
    for (auto& branch : skeleton.branches) {
      if (branch.removed || branch.from == branch.to) continue;
      const bool from_leaf = skeleton.degree(branch.from) == 1, to_leaf = skeleton.degree(branch.to) == 1;
      if (from_leaf == to_leaf) continue;  // not a dead end (or an isolated piece)
      if (branch.length >= spur_length) continue;
      double widest = 0.0;
      const SkeletonSamples samples = skeleton.samples_of(branch);
      for (std::size_t i = 0; i + 1 < samples.size(); ++i) {
        const auto& s = from_leaf ? samples[i] : samples[samples.size() - 1 - i];
        widest = std::max(widest, s.clearance);
      }
      if (widest >= keep_clearance) continue;
      branch.removed = true;
      pruned = true;
    }
  }
}

/// `build_skeleton` of the free space whose cells `is_free(col, row)` tells (lattice coordinates;
/// `lattice_offset` places them in the grid): the segmenter's, which holds the free space as runs
/// by then.
template <class IsFree>
Skeleton skeleton_of(const IsFree& is_free, const Eigen::Vector2d& lattice_offset, const BoundarySegments& boundary,
                     double resolution, const SkeletonParams& params) {
  params.validate();
  Skeleton skeleton;
  skeleton.lattice_offset = lattice_offset;
  if (boundary.segments.empty()) return skeleton;

  std::vector<KeptEdge> kept;
  std::size_t vertex_count = 0;
  {  // the diagram is let go before the skeleton is linked: on a large floor it is the largest piece
    CompactVoronoi diagram;  // Boost's diagram at a fifth of its memory
    // Boost.Polygon's builder, with corner circle events computed without multiprecision when
    // that is provably as accurate (detail/voronoi_circles.hpp; about half the diagram's time).
    construct_segment_voronoi(boundary.segments.begin(), boundary.segments.end(), &diagram, params.fast_circle_events);
    kept = kept_edges(diagram, is_free, boundary, params.min_clearance_m / resolution, params.sample_step_m / resolution,
                      skeleton);
    vertex_count = diagram.vertices().size();
  }
  link_kept_edges(kept, vertex_count, params.sample_step_m / resolution, skeleton);
  prune_spurs(skeleton, params.spur_length_m / resolution, params.keep_clearance_m / resolution);
  return skeleton;
}

}  // namespace detail

/// Builds the pruned skeleton of `space` from its boundary (see the file comment).
inline Skeleton build_skeleton(const FreeSpace& space, const BoundarySegments& boundary, double resolution,
                               const SkeletonParams& params = {}) {
  return detail::skeleton_of([&space](int col, int row) { return space.is_free(col, row); },
                             Eigen::Vector2d(space.offset_col, space.offset_row), boundary, resolution, params);
}

}  // namespace areamatch
