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
/// overlaps, no duplicates, no zero length); a simplified segment that breaks that contract is
/// split where Douglas–Peucker would split it next, until no segment does (at worst down to the
/// unsimplified ring, which satisfies it by construction). `detail::find_conflicts` checks the
/// contract and is run on every result.

#include "../detail/blocks.hpp"
#include "../error.hpp"
#include "binarize.hpp"
#include "ring_tracer.hpp"

#include <boost/polygon/segment_data.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace areamatch {

using LatticeSegment = boost::polygon::segment_data<int>;

/// Parameters of `trace_boundary`. Lengths in metres.
struct BoundaryParams {
  /// Douglas–Peucker tolerance: how far a simplified wall may stray from the pixel boundary.
  /// 0 keeps every corner (exact staircases); larger values give far fewer Voronoi sites.
  double simplify_tolerance_m = 0.1;
  /// Free space no wider than this is left out of the Voronoi input (traced from the free
  /// space's morphological opening by a disc of this diameter): laser streaks through windows
  /// and slivers between scan rays are far too thin for the skeleton (it needs 2·min_clearance)
  /// but each adds walls to the diagram. The areas still cover the whole free space. 0 (the
  /// default) traces every free cell: 0.1 halves lab_b's Voronoi input, but tipped one of its
  /// matches (docs/performance.md).
  double min_traced_width_m = 0.0;
  /// Most Voronoi input segments accepted; beyond, segmenting throws `limit_error` instead of
  /// running for minutes. The Voronoi builder costs about 16 000 instructions per segment
  /// (callgrind, lab_b; 59 000 with Boost's own circle events) and its diagram ~700 bytes, so
  /// roughly 6 s and 0.7 GB at the limit on the CI machine. The shared maps need at most 4994, a
  /// 100 m synthetic robot map with noise (`areamatch generate --width 100 --height 100 --seed 3`)
  /// 25 604, the 400 × 300 m one turned by 37° (`--width 400 --height 300 --seed 7`) 331 748: the
  /// limit follows `max_grid_cells`, which allows floors of that size.
  std::size_t max_segments = 1'000'000;

  void validate() const {
    detail::require_non_negative(simplify_tolerance_m, "BoundaryParams::simplify_tolerance_m");
    detail::require_non_negative(min_traced_width_m, "BoundaryParams::min_traced_width_m");
  }
};

/// The obstacle boundary as lattice segments, valid Boost.Polygon Voronoi input.
struct BoundarySegments {
  std::vector<LatticeSegment> segments;
  std::vector<int> ring_of_segment;  ///< which ring each segment came from
  std::size_t ring_count = 0;
  std::size_t refined_rings = 0;     ///< rings whose simplification was refined to keep the input valid
};

namespace detail {

/// Douglas–Peucker on the stretch of a closed ring from corner `from`, `steps` corners long (its
/// ends already kept): keeps the corner farthest from the chord and recurses on both halves
/// while that corner is farther than `tolerance`. With `force_split` the first split is made
/// whatever the distance (a segment that must not stay whole).
inline void refine_span(const std::vector<LatticePoint>& ring, std::size_t from, std::size_t steps, double tolerance,
                        std::vector<bool>& keep, bool force_split = false) {
  const std::size_t n = ring.size();
  std::vector<std::pair<std::size_t, std::size_t>> stack{{from, steps}};  // spans (from, steps)
  while (!stack.empty()) {
    const auto [start, length] = stack.back();
    stack.pop_back();
    if (length < 2) continue;
    const std::size_t end = (start + length) % n;
    // The farthest corner from the chord a→b: by |cross(b − a, p − a)| (exact integers), divided
    // by the chord's length once; a closed chord (a = b) measures the distance to a.
    const LatticePoint& a = ring[start];
    const double ux = ring[end].x - a.x, uy = ring[end].y - a.y;
    const double chord = std::hypot(ux, uy);
    double worst_measure = -1.0;
    std::size_t worst_step = 0;
    for (std::size_t s = 1; s < length; ++s) {
      const LatticePoint& p = ring[(start + s) % n];
      const double measure = chord == 0.0 ? std::hypot(p.x - a.x, p.y - a.y) : std::abs(ux * (p.y - a.y) - uy * (p.x - a.x));
      if (measure > worst_measure) worst_measure = measure, worst_step = s;
    }
    const double worst = chord == 0.0 ? worst_measure : worst_measure / chord;
    if (worst > tolerance || force_split) {
      force_split = false;
      keep[(start + worst_step) % n] = true;
      stack.push_back({start, worst_step});
      stack.push_back({(start + worst_step) % n, length - worst_step});
    }
  }
}

/// Douglas–Peucker on a closed ring: which vertices to keep. Pinned vertices are always kept;
/// all are kept when simplification would leave fewer than 3.
inline std::vector<bool> simplify_ring(const std::vector<LatticePoint>& ring, const std::vector<bool>& pinned,
                                       double tolerance) {
  const std::size_t n = ring.size();
  if (tolerance <= 0.0 || n <= 4) return std::vector<bool>(n, true);
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
  for (std::size_t a = 0; a < anchors.size(); ++a) {
    const std::size_t from = anchors[a], to = anchors[(a + 1) % anchors.size()];
    const std::size_t steps = (to + n - from) % n == 0 ? n : (to + n - from) % n;
    refine_span(ring, from, steps, tolerance, keep);
  }
  if (std::count(keep.begin(), keep.end(), true) < 3) keep.assign(n, true);
  return keep;
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
/// (16-cell grid buckets, so near-linear in the number of segments). Zero-length segments count too.
/// With `fresh`, only pairs with at least one fresh segment are tested (the others are known
/// to be compatible).
inline std::vector<std::size_t> find_conflicts(const std::vector<LatticeSegment>& segments,
                                               const std::vector<bool>* fresh = nullptr) {
  constexpr int bucket = 16;
  // (bucket, segment) for every bucket a segment's box touches, sorted: each bucket's segments
  // are then one contiguous group (a sort instead of a hash map of vectors: no allocation per
  // bucket). Two segments that touch share the bucket of the point where they do.
  std::vector<std::pair<long long, std::uint32_t>> entries;
  entries.reserve(2 * segments.size());
  std::vector<std::uint8_t> bad(segments.size(), 0);
  auto key = [](long long bx, long long by) { return (bx << 32) ^ (by & 0xffffffffLL); };
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const auto& s = segments[i];
    if (s.low() == s.high()) bad[i] = 1;
    const int x0 = std::min(s.low().x(), s.high().x()), x1 = std::max(s.low().x(), s.high().x());
    const int y0 = std::min(s.low().y(), s.high().y()), y1 = std::max(s.low().y(), s.high().y());
    for (long long bx = (x0 >= 0 ? x0 / bucket : -1); bx <= x1 / bucket; ++bx)
      for (long long by = (y0 >= 0 ? y0 / bucket : -1); by <= y1 / bucket; ++by)
        entries.emplace_back(key(bx, by), static_cast<std::uint32_t>(i));
  }
  std::sort(entries.begin(), entries.end());
  auto point = [](const boost::polygon::point_data<int>& p) { return LatticePoint{p.x(), p.y()}; };
  for (std::size_t group = 0; group < entries.size();) {
    std::size_t end = group;
    while (end < entries.size() && entries[end].first == entries[group].first) ++end;
    for (std::size_t i = group; i < end; ++i)
      for (std::size_t j = i + 1; j < end; ++j) {
        const std::uint32_t a = entries[i].second, b = entries[j].second;
        if (fresh && !(*fresh)[a] && !(*fresh)[b]) continue;
        const auto& s = segments[a];
        const auto& t = segments[b];
        if (segments_conflict(point(s.low()), point(s.high()), point(t.low()), point(t.high()))) bad[a] = bad[b] = 1;
      }
    group = end;
  }
  std::vector<std::size_t> conflicting;
  for (std::size_t i = 0; i < segments.size(); ++i)
    if (bad[i]) conflicting.push_back(i);
  return conflicting;
}

}  // namespace detail

/// Traces, simplifies and validates the obstacle boundary of `space` (see the file comment).
/// Where a simplified segment breaks the Voronoi input contract it is split at the skipped corner
/// farthest from it (and its halves refined within the tolerance), until no conflict is left.
/// On lab_b Douglas–Peucker gives 3097 segments, a third of them in conflict (laser streaks one
/// cell wide); this repair ends at 4994, putting back every corner a conflict skipped at 5720.
inline BoundarySegments trace_boundary(const FreeSpace& space, double resolution, const BoundaryParams& params = {}) {
  params.validate();
  const detail::TracedRings traced = detail::trace_rings(space);
  const double tolerance = params.simplify_tolerance_m / resolution;
  const std::size_t ring_count = traced.rings.size();
  std::vector<std::vector<bool>> keep(ring_count);
  for (std::size_t i = 0; i < ring_count; ++i) keep[i] = detail::simplify_ring(traced.rings[i], traced.pinned[i], tolerance);

  BoundarySegments out;
  out.ring_count = ring_count;
  std::vector<std::pair<std::size_t, std::size_t>> span_of_segment;  // (ring, first corner index)
  std::vector<bool> refined(ring_count, false);
  // Splitting can create new conflicts (lab_b: 1042, then 891, 117, 16, 3, none). Should any
  // be left after split_rounds, they get every skipped corner back, which ends it in a round or two.
  constexpr int split_rounds = 8;
  // Corners kept since the last check: segments ending at one are new, and only pairs with a
  // new segment can conflict (the others were checked already).
  std::vector<std::vector<bool>> added(ring_count);
  std::vector<bool> fresh;
  for (int round = 0;; ++round) {
    out.segments.clear();
    out.ring_of_segment.clear();
    span_of_segment.clear();
    fresh.clear();
    for (std::size_t i = 0; i < ring_count; ++i) {
      const auto& ring = traced.rings[i];
      std::vector<std::size_t> kept;
      for (std::size_t k = 0; k < ring.size(); ++k)
        if (keep[i][k]) kept.push_back(k);
      for (std::size_t k = 0; k < kept.size(); ++k) {
        const std::size_t from = kept[k], to = kept[(k + 1) % kept.size()];
        out.segments.emplace_back(boost::polygon::point_data<int>(ring[from].x, ring[from].y),
                                  boost::polygon::point_data<int>(ring[to].x, ring[to].y));
        out.ring_of_segment.push_back(static_cast<int>(i));
        span_of_segment.push_back({i, from});
        fresh.push_back(round == 0 || added[i][from] || added[i][to]);
      }
    }
    const auto conflicts = detail::find_conflicts(out.segments, &fresh);
    if (conflicts.empty()) break;
    for (std::size_t i = 0; i < ring_count; ++i) added[i] = keep[i];
    bool changed = false;
    for (std::size_t s : conflicts) {
      const auto [ring, first] = span_of_segment[s];
      auto& flags = keep[ring];
      const std::size_t n = flags.size();
      std::size_t steps = 1;
      while (!flags[(first + steps) % n]) ++steps;
      if (steps < 2) continue;  // an unsimplified edge: the other segment of the conflict gives way
      if (round < split_rounds) {
        // Split where Douglas–Peucker would next, and keep both halves within the tolerance.
        detail::refine_span(traced.rings[ring], first, steps, tolerance, flags, true);
      } else {
        for (std::size_t k = 1; k < steps; ++k) flags[(first + k) % n] = true;
      }
      changed = refined[ring] = true;
    }
    for (std::size_t i = 0; i < ring_count; ++i)
      for (std::size_t k = 0; k < added[i].size(); ++k) added[i][k] = keep[i][k] && !added[i][k];
    if (!changed) {
      // Unsimplified rings satisfy the contract by construction; getting here is a bug.
      throw error("trace_boundary: boundary segments violate the Voronoi input contract");
    }
  }
  out.refined_rings = static_cast<std::size_t>(std::count(refined.begin(), refined.end(), true));
  return out;
}

}  // namespace areamatch
