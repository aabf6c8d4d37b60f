#pragma once
/// \file match/proposal/paper_features.hpp
/// The paper's three area features (§III-B, docs/algorithm.md): `AreaSize`, `PassageDistances`
/// and `HullDiameter`, with what they share: the relative difference they compare by and the
/// segments they match (the hypothesis stage turns a segment pair into a rotation). The feature
/// contract and `FeatureSet` are in match/proposal/features.hpp.

#include "../../area_graph.hpp"
#include "../../geometry.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace areamatch {

/// |a − b| / max(a, b) for non-negative values, guarded: 0 when both are ≈ 0, 1 when only one is
/// (docs/algorithm.md).
inline double relative_difference(double a, double b) {
  constexpr double epsilon = 1e-9;
  const double denominator = std::max(a, b);
  if (denominator < epsilon) return std::max(std::abs(a), std::abs(b)) < epsilon ? 0.0 : 1.0;
  return std::min(1.0, std::abs(a - b) / denominator);
}

/// Where a segment came from: the hypothesis stage ranks and reports by it.
enum class SegmentSource : std::uint8_t {
  passage_pair,   ///< two passages of the area (a passage distance)
  hull_diameter,  ///< the longest distance across the area's convex hull
  other           ///< a user feature
};

inline const char* to_string(SegmentSource source) {
  return source == SegmentSource::passage_pair ? "passage_pair"
         : source == SegmentSource::hull_diameter ? "hull_diameter" : "other";
}

/// A segment in one area, in its map's world frame (metres). Undirected: a and b may swap.
struct AreaSegment {
  Eigen::Vector2d a = Eigen::Vector2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  double length() const { return (b - a).norm(); }
};

/// Two segments a feature comparison matched, one per area: the evidence for a rotation.
struct SegmentMatch {
  AreaSegment source;
  AreaSegment dest;
  SegmentSource kind = SegmentSource::other;
};

// --- The paper's features ------------------------------------------------------------------------

/// Area size: c_a = |√a_i − √a_j| / √max(a_i, a_j). The square root makes it linear in length.
struct AreaSize {
  using descriptor_type = double;  ///< m²
  descriptor_type describe(const AreaGraph&, const Area& area) const { return area.size_m2; }
  double cost(double source, double dest) const { return relative_difference(bound_key(source), bound_key(dest)); }
  double bound_key(double size_m2) const { return std::sqrt(std::max(0.0, size_m2)); }
};

namespace detail {

/// The longest distance between two vertices of a convex hull, and that segment.
inline AreaSegment hull_diameter(const Polygon2& hull) {
  const FarthestVertices diameter = farthest_vertices(hull);
  return {diameter.a, diameter.b};
}

}  // namespace detail

/// Convex-hull longest distance: c_l = |ld_i − ld_j| / max(ld_i, ld_j). Its segments are the two
/// diameters.
struct HullDiameter {
  using descriptor_type = AreaSegment;
  descriptor_type describe(const AreaGraph&, const Area& area) const {
    return detail::hull_diameter(area.convex_hull);
  }
  double cost(const descriptor_type& source, const descriptor_type& dest) const {
    return relative_difference(source.length(), dest.length());
  }
  double bound_key(const descriptor_type& diameter) const { return diameter.length(); }
  std::optional<SegmentMatch> segments(const descriptor_type& source, const descriptor_type& dest) const {
    return SegmentMatch{source, dest, SegmentSource::hull_diameter};
  }
};

/// Passage distances: the distance between every pair of an area's passages (K passages give
/// K(K−1)/2 values). c_p = min over pairs |pd_n − pd_m| / max(pd_n, pd_m), and the pair that
/// reached the minimum is the segment evidence.
///
/// An area with fewer than two passages has no passage distance. Then, as the paper says ("the
/// convex hull longest distance is used for regions that cannot obtain passage distance"), the
/// cost falls back to the hull-diameter cost c_l — whenever *either* side lacks a passage
/// distance, so every pair gets a cost in [0, 1] and the weights keep summing to one — and there
/// is no passage-pair evidence for that pair (the hull diameters give it instead).
struct PassageDistances {
  /// Each passage is paired with at most this many others, its nearest (ties: the earlier
  /// passage); a pair is kept when either end chose the other. An area of up to max_partners + 1
  /// passages keeps all K(K−1)/2 pairs, as the paper does (every area of the shared maps: the
  /// most passages any has is 55); a corridor of a large floor with thousands of doors keeps
  /// about max_partners pairs per door instead of millions — which told nothing anyway: among a
  /// million lengths some length matches any other area's.
  std::size_t max_partners = 63;

  struct descriptor_type {
    std::vector<AreaSegment> pairs;   ///< one per pair of distinct passage positions
    std::vector<double> lengths;      ///< pairs[n].length(), ascending
    AreaSegment hull_diameter;        ///< the fallback
  };

  descriptor_type describe(const AreaGraph& graph, const Area& area) const {
    descriptor_type d;
    std::vector<Eigen::Vector2d> positions;
    for (int id : area.passages) {
      const Eigen::Vector2d& p = graph.passages[static_cast<std::size_t>(id)].position;
      // The same opening listed twice would give pd = 0 and a 0/0 cost (docs/algorithm.md).
      const bool seen = std::any_of(positions.begin(), positions.end(),
                                    [&](const Eigen::Vector2d& q) { return (q - p).norm() < 1e-6; });
      if (!seen) positions.push_back(p);
    }
    // Sorted by length (ties in the order of the passages) so the cost is a merge of two sorted
    // lists, not all pairs of pairs. Each length computed once: a corridor with K doors has
    // K(K−1)/2 pairs, and sorting the segments by a recomputed length was most of a large map's
    // descriptor time.
    const std::size_t k = positions.size();
    std::vector<std::pair<double, std::size_t>> order;  // (length, i · k + j), i < j
    for (const std::size_t ij : pair_indices(positions)) {
      order.emplace_back((positions[ij % k] - positions[ij / k]).norm(), ij);
    }
    std::sort(order.begin(), order.end());
    d.pairs.reserve(order.size());
    d.lengths.reserve(order.size());
    for (const auto& [length, ij] : order) {
      d.pairs.push_back({positions[ij / k], positions[ij % k]});
      d.lengths.push_back(length);
    }
    d.hull_diameter = detail::hull_diameter(area.convex_hull);
    return d;
  }

  double cost(const descriptor_type& source, const descriptor_type& dest) const {
    if (source.pairs.empty() || dest.pairs.empty()) {
      return relative_difference(source.hull_diameter.length(), dest.hull_diameter.length());
    }
    const auto [n, m] = best(source, dest);
    return relative_difference(source.lengths[n], dest.lengths[m]);
  }

  std::optional<SegmentMatch> segments(const descriptor_type& source, const descriptor_type& dest) const {
    if (source.pairs.empty() || dest.pairs.empty()) return std::nullopt;
    const auto [n, m] = best(source, dest);
    return SegmentMatch{source.pairs[n], dest.pairs[m], SegmentSource::passage_pair};
  }

 private:
  /// The pairs i < j of passage positions kept (see `max_partners`), as i · K + j, ascending.
  std::vector<std::size_t> pair_indices(const std::vector<Eigen::Vector2d>& positions) const {
    const std::size_t k = positions.size();
    std::vector<std::size_t> out;
    if (k <= max_partners + 1) {
      out.reserve(k > 1 ? k * (k - 1) / 2 : 0);
      for (std::size_t i = 0; i < k; ++i) {
        for (std::size_t j = i + 1; j < k; ++j) out.push_back(i * k + j);
      }
      return out;
    }
    out.reserve(k * max_partners);
    std::vector<std::pair<double, std::size_t>> others;  // (squared distance, j)
    for (std::size_t i = 0; i < k; ++i) {
      others.clear();
      for (std::size_t j = 0; j < k; ++j) {
        if (j != i) others.emplace_back((positions[j] - positions[i]).squaredNorm(), j);
      }
      std::nth_element(others.begin(), others.begin() + static_cast<std::ptrdiff_t>(max_partners), others.end());
      for (std::size_t n = 0; n < max_partners; ++n) {
        const std::size_t j = others[n].second;
        out.push_back(std::min(i, j) * k + std::max(i, j));
      }
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

  /// Indices of the closest pair of lengths (relative difference), first in order on ties.
  static std::pair<std::size_t, std::size_t> best(const descriptor_type& s, const descriptor_type& d) {
    std::pair<std::size_t, std::size_t> arg{0, 0};
    double best_cost = 2.0;
    // For each source length only the nearest destination lengths (either side in the sorted
    // list) can be the minimum of the relative difference.
    std::size_t m = 0;
    for (std::size_t n = 0; n < s.lengths.size(); ++n) {
      while (m + 1 < d.lengths.size() && d.lengths[m + 1] <= s.lengths[n]) ++m;
      for (std::size_t c = m; c < std::min(m + 2, d.lengths.size()); ++c) {
        const double cost = relative_difference(s.lengths[n], d.lengths[c]);
        if (cost < best_cost) {
          best_cost = cost;
          arg = {n, c};
        }
      }
    }
    return arg;
  }
};

}  // namespace areamatch
