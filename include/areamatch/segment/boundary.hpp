#pragma once
/// \file segment/boundary.hpp
/// Stage 2 of segmentation: free-space mask → obstacle boundary segments, the input of the
/// segment Voronoi diagram.
///
/// Boundaries are traced on the **pixel-corner lattice**: integer coordinates (x = column,
/// y = row, y down), one unit = one cell side = `resolution` metres; pixel (c, r) covers
/// [c, c+1] × [r, r+1]. Outside the image counts as obstacle. Free space is 4-connected: two
/// free cells touching only at a corner belong to different rings that share that corner.
///
/// Each ring is reduced to its corners (collinear unit edges merged), then simplified with
/// Douglas–Peucker within `simplify_tolerance_m`. Boost.Polygon's Voronoi builder accepts only
/// segments that meet at endpoints (no crossings, no endpoint inside another segment, no
/// overlaps, no duplicates, no zero length); a ring whose simplification breaks that contract
/// is put back unsimplified, which satisfies it by construction. `detail::find_conflicts`
/// checks the contract and is run on every result.

#include "../error.hpp"
#include "binarize.hpp"

#include <boost/polygon/segment_data.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <unordered_map>
#include <utility>
#include <vector>

namespace areamatch {

/// A point of the pixel-corner lattice.
struct LatticePoint {
  int x = 0;
  int y = 0;
  friend bool operator==(const LatticePoint& a, const LatticePoint& b) { return a.x == b.x && a.y == b.y; }
  friend bool operator!=(const LatticePoint& a, const LatticePoint& b) { return !(a == b); }
};

using LatticeSegment = boost::polygon::segment_data<int>;

/// Parameters of `trace_boundary`. Lengths in metres.
struct BoundaryParams {
  /// Douglas–Peucker tolerance: how far a simplified wall may stray from the pixel boundary.
  /// 0 keeps every corner (exact staircases); larger values give far fewer Voronoi sites.
  double simplify_tolerance_m = 0.05;

  void validate() const {
    if (!(std::isfinite(simplify_tolerance_m) && simplify_tolerance_m >= 0.0)) {
      throw parameter_error("BoundaryParams::simplify_tolerance_m must be >= 0");
    }
  }
};

/// The obstacle boundary as lattice segments, valid Boost.Polygon Voronoi input.
struct BoundarySegments {
  std::vector<LatticeSegment> segments;
  std::vector<int> ring_of_segment;  ///< which ring each segment came from
  std::size_t ring_count = 0;
  std::size_t reverted_rings = 0;    ///< rings left unsimplified to keep the input valid
};

namespace detail {

/// Closed boundary rings of the free space, as corner lists (first vertex not repeated), each
/// with a flag per vertex: true where the vertex is shared with another ring (a pinch).
struct TracedRings {
  std::vector<std::vector<LatticePoint>> rings;
  std::vector<std::vector<bool>> pinned;
};

inline TracedRings trace_rings(const FreeSpace& space) {
  const int W = space.width, H = space.height;
  const int VW = W + 1;
  // Directed unit edges with the free cell on their left in image coordinates
  // (a single free cell is walked top → left → bottom → right). Direction: 0 E, 1 S, 2 W, 3 N.
  static const int dx[4] = {1, 0, -1, 0}, dy[4] = {0, 1, 0, -1};
  struct Edge {
    int vertex;  // start vertex index y·VW + x
    std::uint8_t dir;
    std::size_t cell;
  };
  std::vector<Edge> edges;
  // Up to two outgoing edges per vertex (two at a pinch); −1 = none.
  std::vector<std::int32_t> out_first(static_cast<std::size_t>(VW) * (H + 1), -1), out_second;
  std::unordered_map<int, std::int32_t> second_out;  // rare: pinch vertices only
  auto add_edge = [&](int x, int y, std::uint8_t dir, std::size_t cell) {
    const int v = y * VW + x;
    const auto id = static_cast<std::int32_t>(edges.size());
    edges.push_back({v, dir, cell});
    if (out_first[v] < 0) out_first[v] = id;
    else second_out[v] = id;
  };
  for (int r = 0; r < H; ++r) {
    for (int c = 0; c < W; ++c) {
      if (!space.is_free(c, r)) continue;
      const std::size_t cell = static_cast<std::size_t>(r) * W + c;
      if (!space.is_free(c, r - 1)) add_edge(c + 1, r, 2, cell);      // top, westwards
      if (!space.is_free(c - 1, r)) add_edge(c, r, 1, cell);          // left, southwards
      if (!space.is_free(c, r + 1)) add_edge(c, r + 1, 0, cell);      // bottom, eastwards
      if (!space.is_free(c + 1, r)) add_edge(c + 1, r + 1, 3, cell);  // right, northwards
    }
  }
  TracedRings traced;
  std::vector<std::uint8_t> used(edges.size(), 0);
  for (std::size_t start = 0; start < edges.size(); ++start) {
    if (used[start]) continue;
    std::vector<LatticePoint> ring;
    std::vector<bool> pinned;
    std::size_t e = start;
    int previous_dir = -1;
    while (!used[e]) {
      used[e] = 1;
      const Edge& edge = edges[e];
      const int x = edge.vertex % VW, y = edge.vertex / VW;
      if (edge.dir != previous_dir) {
        ring.push_back({x, y});
        pinned.push_back(second_out.count(edge.vertex) != 0);
      }
      previous_dir = edge.dir;
      const int next_vertex = (y + dy[edge.dir]) * VW + (x + dx[edge.dir]);
      auto next = static_cast<std::size_t>(out_first[next_vertex]);
      const auto pinch = second_out.find(next_vertex);
      // At a pinch, stay on the boundary of the same free cell: it keeps diagonal neighbours apart.
      if (pinch != second_out.end() && edges[next].cell != edge.cell) next = static_cast<std::size_t>(pinch->second);
      e = next;
    }
    // The start vertex is a corner only if the direction changes there.
    if (ring.size() > 1 && edges[start].dir == previous_dir) {
      ring.erase(ring.begin());
      pinned.erase(pinned.begin());
    }
    traced.rings.push_back(std::move(ring));
    traced.pinned.push_back(std::move(pinned));
  }
  return traced;
}

inline double distance_to_line(const LatticePoint& p, const LatticePoint& a, const LatticePoint& b) {
  const double ux = b.x - a.x, uy = b.y - a.y;
  const double length = std::hypot(ux, uy);
  if (length == 0.0) return std::hypot(p.x - a.x, p.y - a.y);
  return std::abs(ux * (p.y - a.y) - uy * (p.x - a.x)) / length;
}

/// Douglas–Peucker on a closed ring; pinned vertices are always kept. Returns the ring unchanged
/// when simplification would leave fewer than 3 vertices.
inline std::vector<LatticePoint> simplify_ring(const std::vector<LatticePoint>& ring, const std::vector<bool>& pinned,
                                               double tolerance) {
  const std::size_t n = ring.size();
  if (tolerance <= 0.0 || n <= 4) return ring;
  std::vector<bool> keep(pinned.begin(), pinned.end());
  // Anchors: the smallest vertex (deterministic) and the one farthest from it, plus pins.
  std::size_t first = 0;
  for (std::size_t i = 1; i < n; ++i)
    if (ring[i].x < ring[first].x || (ring[i].x == ring[first].x && ring[i].y < ring[first].y)) first = i;
  std::size_t far = first;
  double best = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double d = std::hypot(ring[i].x - ring[first].x, ring[i].y - ring[first].y);
    if (d > best) best = d, far = i;
  }
  keep[first] = keep[far] = true;
  std::vector<std::size_t> anchors;
  for (std::size_t k = 0; k < n; ++k)
    if (keep[(first + k) % n]) anchors.push_back((first + k) % n);
  std::vector<std::pair<std::size_t, std::size_t>> stack;  // spans (from, steps) along the ring
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    const std::size_t from = anchors[a], to = anchors[(a + 1) % anchors.size()];
    const std::size_t steps = (to + n - from) % n == 0 ? n : (to + n - from) % n;
    stack.push_back({from, steps});
  }
  while (!stack.empty()) {
    const auto [from, steps] = stack.back();
    stack.pop_back();
    if (steps < 2) continue;
    const std::size_t to = (from + steps) % n;
    double worst = -1.0;
    std::size_t worst_step = 0;
    for (std::size_t s = 1; s < steps; ++s) {
      const double d = distance_to_line(ring[(from + s) % n], ring[from], ring[to]);
      if (d > worst) worst = d, worst_step = s;
    }
    if (worst > tolerance) {
      keep[(from + worst_step) % n] = true;
      stack.push_back({from, worst_step});
      stack.push_back({(from + worst_step) % n, steps - worst_step});
    }
  }
  std::vector<LatticePoint> out;
  for (std::size_t i = 0; i < n; ++i)
    if (keep[i]) out.push_back(ring[i]);
  return out.size() >= 3 ? out : ring;
}

inline long long orientation(const LatticePoint& a, const LatticePoint& b, const LatticePoint& c) {
  const long long v = static_cast<long long>(b.x - a.x) * (c.y - a.y) - static_cast<long long>(b.y - a.y) * (c.x - a.x);
  return (v > 0) - (v < 0);
}

inline bool within_box(const LatticePoint& a, const LatticePoint& b, const LatticePoint& p) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y && p.y <= std::max(a.y, b.y);
}

/// True when two segments meet anywhere except at one endpoint shared by both — exactly what
/// Boost.Polygon's Voronoi builder forbids (crossings, touching interiors, overlaps, duplicates).
inline bool segments_conflict(const LatticePoint& a, const LatticePoint& b, const LatticePoint& c, const LatticePoint& d) {
  if (std::max(a.x, b.x) < std::min(c.x, d.x) || std::max(c.x, d.x) < std::min(a.x, b.x) ||
      std::max(a.y, b.y) < std::min(c.y, d.y) || std::max(c.y, d.y) < std::min(a.y, b.y)) {
    return false;
  }
  const long long o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  const long long o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o1 == 0 && o2 == 0) {  // collinear: conflict when they share more than a point
    const bool use_x = a.x != b.x;
    auto key = [use_x](const LatticePoint& p) { return use_x ? p.x : p.y; };
    const int lo = std::max(std::min(key(a), key(b)), std::min(key(c), key(d)));
    const int hi = std::min(std::max(key(a), key(b)), std::max(key(c), key(d)));
    return hi > lo;
  }
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  if (o1 == 0 && within_box(a, b, c)) return c != a && c != b;
  if (o2 == 0 && within_box(a, b, d)) return d != a && d != b;
  if (o3 == 0 && within_box(c, d, a)) return a != c && a != d;
  if (o4 == 0 && within_box(c, d, b)) return b != c && b != d;
  return false;
}

/// Indices of segments that break Boost.Polygon's input contract with some other segment
/// (spatial hashing, so near-linear in the number of segments). Zero-length segments count too.
inline std::vector<std::size_t> find_conflicts(const std::vector<LatticeSegment>& segments) {
  constexpr int bucket = 32;
  std::unordered_map<long long, std::vector<std::size_t>> buckets;
  auto key = [](long long bx, long long by) { return (bx << 32) ^ (by & 0xffffffffLL); };
  std::set<std::size_t> bad;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto& s = segments[i];
    if (s.low() == s.high()) bad.insert(i);
    const int x0 = std::min(s.low().x(), s.high().x()), x1 = std::max(s.low().x(), s.high().x());
    const int y0 = std::min(s.low().y(), s.high().y()), y1 = std::max(s.low().y(), s.high().y());
    for (long long bx = (x0 >= 0 ? x0 / bucket : -1); bx <= x1 / bucket; ++bx)
      for (long long by = (y0 >= 0 ? y0 / bucket : -1); by <= y1 / bucket; ++by) buckets[key(bx, by)].push_back(i);
  }
  auto point = [](const boost::polygon::point_data<int>& p) { return LatticePoint{p.x(), p.y()}; };
  std::vector<std::pair<long long, const std::vector<std::size_t>*>> ordered;
  for (const auto& [k, list] : buckets) ordered.push_back({k, &list});
  std::sort(ordered.begin(), ordered.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [k, list_ptr] : ordered) {
    const auto& list = *list_ptr;
    for (std::size_t i = 0; i < list.size(); ++i)
      for (std::size_t j = i + 1; j < list.size(); ++j) {
        const auto& s = segments[list[i]];
        const auto& t = segments[list[j]];
        if (segments_conflict(point(s.low()), point(s.high()), point(t.low()), point(t.high()))) {
          bad.insert(list[i]);
          bad.insert(list[j]);
        }
      }
  }
  return {bad.begin(), bad.end()};
}

}  // namespace detail

/// Traces, simplifies and validates the obstacle boundary of `space` (see the file comment).
inline BoundarySegments trace_boundary(const FreeSpace& space, double resolution, const BoundaryParams& params = {}) {
  params.validate();
  const detail::TracedRings traced = detail::trace_rings(space);
  const double tolerance = params.simplify_tolerance_m / resolution;
  const std::size_t ring_count = traced.rings.size();
  std::vector<std::vector<LatticePoint>> rings(ring_count);
  for (std::size_t i = 0; i < ring_count; ++i) rings[i] = detail::simplify_ring(traced.rings[i], traced.pinned[i], tolerance);

  BoundarySegments out;
  out.ring_count = ring_count;
  std::vector<bool> reverted(ring_count, false);
  while (true) {
    out.segments.clear();
    out.ring_of_segment.clear();
    for (std::size_t i = 0; i < ring_count; ++i) {
      const auto& ring = reverted[i] ? traced.rings[i] : rings[i];
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const LatticePoint& a = ring[k];
        const LatticePoint& b = ring[(k + 1) % ring.size()];
        out.segments.emplace_back(boost::polygon::point_data<int>(a.x, a.y), boost::polygon::point_data<int>(b.x, b.y));
        out.ring_of_segment.push_back(static_cast<int>(i));
      }
    }
    const auto conflicts = detail::find_conflicts(out.segments);
    if (conflicts.empty()) break;
    bool changed = false;
    for (std::size_t s : conflicts) {
      const auto ring = static_cast<std::size_t>(out.ring_of_segment[s]);
      if (!reverted[ring]) reverted[ring] = changed = true;
    }
    if (!changed) {
      // Unsimplified rings satisfy the contract by construction; getting here is a bug.
      throw error("trace_boundary: boundary segments violate the Voronoi input contract");
    }
  }
  out.reverted_rings = static_cast<std::size_t>(std::count(reverted.begin(), reverted.end(), true));
  return out;
}

}  // namespace areamatch
