#pragma once
/// \file match/proposal/hypotheses.hpp
/// Transform hypotheses: for every mutually matched area pair, a rotation from the segments its
/// features matched and a translation that puts the source segment's midpoint on the
/// destination's (paper §III-D, docs/algorithm.md), with the pair's overlap as a filter.
///
/// The paper takes one rotation per pair. On real maps that rotation is usually wrong (a
/// different pair of doors, a rectangle's ambiguous diameter; docs/algorithm.md), so the default
/// also emits the turns by 180° and ±90° and the hull diameter next to the passage pair, and adds
/// rotations from the maps' dominant wall directions anchored at each pair's centroids.

#include "../../area_graph.hpp"
#include "../../error.hpp"
#include "../../geometry.hpp"
#include "../../transform.hpp"
#include "../raster.hpp"
#include "costs.hpp"
#include "features.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <vector>

namespace areamatch {

/// Where a hypothesis came from.
enum class HypothesisOrigin : std::uint8_t {
  passage_pair,    ///< the passage-distance segments of the pair
  hull_diameter,   ///< the hull diameters of the pair
  wall_direction,  ///< the maps' dominant wall directions, anchored at the pair's centroids
  other            ///< a user feature's segments
};

inline const char* to_string(HypothesisOrigin origin) {
  switch (origin) {
    case HypothesisOrigin::passage_pair: return "passage_pair";
    case HypothesisOrigin::hull_diameter: return "hull_diameter";
    case HypothesisOrigin::wall_direction: return "wall_direction";
    default: return "other";
  }
}

/// One candidate transform and what it came from.
struct Hypothesis {
  Similarity2 T_dest_source;   ///< source world → destination world (scale 1)
  int source_area = -1;        ///< the pair that produced it
  int dest_area = -1;
  double pair_cost = 0.0;      ///< the pair's total feature cost
  double area_overlap = 0.0;   ///< OP of the pair under this transform
  HypothesisOrigin origin = HypothesisOrigin::other;
};

/// How hypotheses are made.
/// How a map's dominant wall direction is found (`dominant_wall_direction`): a length-weighted
/// histogram of its areas' hull edges across the 90° of wall directions, the bin with the most
/// length around it, and the circular mean of the edges near that bin.
struct WallDirectionParams {
  int bins = 90;                  ///< histogram bins across 90° (1° each)
  int peak_window_bins = 2;       ///< a bin's length is summed over ±this many bins: a peak split across bins is still found
  double mean_window_bins = 5.0;  ///< the mean is over the edges within ±this many bins of the peak's centre

  void validate() const {
    if (bins < 1) throw parameter_error("WallDirectionParams::bins must be >= 1");
    if (peak_window_bins < 0 || 2 * peak_window_bins + 1 > bins) {
      throw parameter_error("WallDirectionParams::peak_window_bins must be in [0, (bins - 1) / 2]");
    }
    detail::require_positive(mean_window_bins, "WallDirectionParams::mean_window_bins");
  }
};

struct HypothesisParams {
  /// Turns added to each segment rotation (radians). The paper: {0}. Default {0, π, ±π/2}:
  /// segments have no direction, and rooms overlap their own quarter turns.
  std::vector<double> extra_turns{0.0, pi, 0.5 * pi, -0.5 * pi};
  /// Every feature's segments give hypotheses (default), or only the first feature that has
  /// segments for the pair, as the paper does (passage pair if it was used, else hull diameter).
  bool all_segment_sources = true;
  /// Also add the four rotations that align the maps' dominant wall directions (mod 90°),
  /// anchored at the centroids of every pair.
  bool wall_directions = true;
  WallDirectionParams wall_direction;
  /// Keep a hypothesis only when its pair overlaps by at least this (OP, 0..1). The paper gives
  /// no value; 0.5 is our reading (docs/algorithm.md). Only a filter: rooms overlap their own turns.
  double min_area_overlap = 0.5;
  /// OP from Boost.Geometry polygon intersection (exact, the paper's) or from the rasters (fast).
  bool exact_overlap = false;

  void validate() const {
    for (double turn : extra_turns) {
      if (!std::isfinite(turn)) throw parameter_error("HypothesisParams::extra_turns must be finite");
    }
    if (extra_turns.empty()) throw parameter_error("HypothesisParams::extra_turns must not be empty");
    wall_direction.validate();
    if (!(min_area_overlap >= 0.0 && min_area_overlap <= 1.0)) {
      throw parameter_error("HypothesisParams::min_area_overlap must be in [0, 1], got " + std::to_string(min_area_overlap));
    }
  }
};

namespace detail {

/// The y-mirror F = diag(1, −1), or the identity.
inline Eigen::Vector2d mirror_if(const Eigen::Vector2d& p, bool reflected) {
  return reflected ? Eigen::Vector2d(p.x(), -p.y()) : p;
}

/// T(x) = R(α)(F x − p) + q.
inline Similarity2 anchored_transform(double alpha, const Eigen::Vector2d& p_mirrored, const Eigen::Vector2d& q,
                                      bool reflected) {
  Similarity2 T;
  T.rotation = wrap_angle(alpha);
  T.reflected = reflected;
  T.translation = q - Eigen::Rotation2Dd(T.rotation) * p_mirrored;
  return T;
}

/// Direction (radians) of the segment a→b.
inline double direction(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::atan2(b.y() - a.y(), b.x() - a.x());
}

/// A polygon under a transform, corrected (a reflection flips its orientation).
inline Polygon2 transformed(const Polygon2& polygon, const Similarity2& T) {
  Polygon2 out;
  auto map_ring = [&](const auto& ring, auto& target) {
    target.reserve(ring.size());
    for (const auto& p : ring) target.push_back(to_point(T * to_vector(p)));
  };
  map_ring(polygon.outer(), out.outer());
  for (const auto& inner : polygon.inners()) {
    out.inners().emplace_back();
    map_ring(inner, out.inners().back());
  }
  bg::correct(out);
  return out;
}

/// OP = area(T(P_i) ∩ P_j) / min(a_i, a_j) with Boost.Geometry, after an envelope check; none
/// when Boost.Geometry cannot overlay the two polygons (it throws on some degenerate inputs).
inline std::optional<double> exact_area_overlap(const Area& source, const Area& dest, const Similarity2& T) {
  const double denominator = std::min(bg::area(source.polygon), bg::area(dest.polygon));
  if (!(denominator > 0.0)) return 0.0;
  const Polygon2 moved = transformed(source.polygon, T);
  if (bg::disjoint(bg::return_envelope<Box2>(moved), bg::return_envelope<Box2>(dest.polygon))) return 0.0;
  MultiPolygon2 intersection;
  try {
    bg::intersection(moved, dest.polygon, intersection);
  } catch (const bg::exception&) {
    return std::nullopt;
  }
  return std::min(1.0, bg::area(intersection) / denominator);
}

}  // namespace detail

/// The dominant wall direction of a map, in [0, π/2): the length-weighted circular mean (mod 90°)
/// of the edges of its areas' convex hulls around the peak of their histogram. Hull edges follow
/// walls; furniture and staircase corners barely move the peak.
inline double dominant_wall_direction(const AreaGraph& graph, const WallDirectionParams& params = {}) {
  const int bins = params.bins;
  std::vector<double> histogram(static_cast<std::size_t>(bins), 0.0);
  std::vector<std::pair<double, double>> edges;  // (direction·4 mod 2π, length)
  for (const Area& area : graph.areas) {
    const auto& ring = area.convex_hull.outer();
    for (std::size_t i = 0; i + 1 < ring.size(); ++i) {
      const Eigen::Vector2d a = to_vector(ring[i]), b = to_vector(ring[i + 1]);
      const double length = (b - a).norm();
      if (length <= 0.0) continue;
      double quad = std::fmod(4.0 * detail::direction(a, b), 2.0 * pi);  // mod 90° as a full turn
      if (quad < 0.0) quad += 2.0 * pi;
      edges.emplace_back(quad, length);
      histogram[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(quad / (2.0 * pi) * bins)))] += length;
    }
  }
  if (edges.empty()) return 0.0;
  // Summed over ±peak_window_bins, so a peak split across bins is still found.
  int peak = 0;
  double peak_value = -1.0;
  for (int b = 0; b < bins; ++b) {
    double value = 0.0;
    for (int d = -params.peak_window_bins; d <= params.peak_window_bins; ++d) {
      value += histogram[static_cast<std::size_t>((b + d + bins) % bins)];
    }
    if (value > peak_value) {
      peak_value = value;
      peak = b;
    }
  }
  const double centre = (peak + 0.5) / bins * 2.0 * pi;
  double s = 0.0, c = 0.0;
  for (const auto& [quad, length] : edges) {
    if (std::abs(wrap_angle(quad - centre)) < 2.0 * pi * params.mean_window_bins / bins) {
      s += length * std::sin(quad);
      c += length * std::cos(quad);
    }
  }
  double mean = std::atan2(s, c);
  if (mean < 0.0) mean += 2.0 * pi;
  return mean / 4.0;
}

/// Everything the hypothesis stage needs about the two maps.
struct HypothesisInputs {
  const AreaGraph* source = nullptr;
  const AreaGraph* dest = nullptr;
  const AreaRaster* source_raster = nullptr;  ///< for the raster overlap
  const AreaRaster* dest_raster = nullptr;
  double source_wall_direction = 0.0;
  double dest_wall_direction = 0.0;
};

/// The pair's overlap percentage OP under T: exact (Boost.Geometry, the paper's) or counted on
/// the rasters. Where the exact overlay fails the raster overlap stands in, and
/// `*overlay_failures` (when given) counts it (`MatchStatistics::overlay_failures`).
inline double pair_overlap(const HypothesisInputs& in, const AreaPair& pair, bool exact, const Similarity2& T,
                           std::size_t* overlay_failures = nullptr) {
  const Area& source_area = in.source->areas[static_cast<std::size_t>(pair.source)];
  const Area& dest_area = in.dest->areas[static_cast<std::size_t>(pair.dest)];
  if (exact) {
    if (const std::optional<double> op = detail::exact_area_overlap(source_area, dest_area, T)) return *op;
    if (overlay_failures) ++*overlay_failures;
  }
  return raster_area_overlap(*in.source_raster, *in.dest_raster, pair.source, pair.dest, source_area.size_m2,
                             dest_area.size_m2, T);
}

/// Hypotheses of one pair on one side of the mirror, appended to `out` when their overlap
/// passes. `segments` is the pair's segment evidence in feature order.
inline void add_pair_hypotheses(const HypothesisInputs& in, const AreaPair& pair,
                                const std::vector<SegmentMatch>& segments, bool reflected,
                                const HypothesisParams& params, std::vector<Hypothesis>& out,
                                std::size_t* overlay_failures = nullptr) {
  const Area& source_area = in.source->areas[static_cast<std::size_t>(pair.source)];
  const Area& dest_area = in.dest->areas[static_cast<std::size_t>(pair.dest)];
  auto overlap = [&](const Similarity2& T) { return pair_overlap(in, pair, params.exact_overlap, T, overlay_failures); };
  auto emit = [&](const Similarity2& T, HypothesisOrigin origin) {
    Hypothesis h;
    h.T_dest_source = T;
    h.source_area = pair.source;
    h.dest_area = pair.dest;
    h.pair_cost = pair.cost;
    h.origin = origin;
    h.area_overlap = overlap(T);
    if (h.area_overlap >= params.min_area_overlap) out.push_back(h);
  };
  auto add = [&](double alpha, const Eigen::Vector2d& p_mirrored, const Eigen::Vector2d& q, HypothesisOrigin origin) {
    for (double turn : params.extra_turns) emit(detail::anchored_transform(alpha + turn, p_mirrored, q, reflected), origin);
  };
  for (const SegmentMatch& match : segments) {
    const Eigen::Vector2d u1 = detail::mirror_if(match.source.a, reflected);
    const Eigen::Vector2d u2 = detail::mirror_if(match.source.b, reflected);
    const double alpha = detail::direction(match.dest.a, match.dest.b) - detail::direction(u1, u2);
    const HypothesisOrigin origin = match.kind == SegmentSource::passage_pair    ? HypothesisOrigin::passage_pair
                                    : match.kind == SegmentSource::hull_diameter ? HypothesisOrigin::hull_diameter
                                                                                 : HypothesisOrigin::other;
    add(alpha, 0.5 * (u1 + u2), 0.5 * (match.dest.a + match.dest.b), origin);
    if (!params.all_segment_sources) break;
  }
  if (params.wall_directions) {
    // Mirroring negates the source's directions; the four quarter turns cover the rest.
    const double source_direction = reflected ? -in.source_wall_direction : in.source_wall_direction;
    const double alpha = in.dest_wall_direction - source_direction;
    for (int m = 0; m < 4; ++m) {
      emit(detail::anchored_transform(alpha + m * 0.5 * pi, detail::mirror_if(source_area.centroid, reflected),
                                      dest_area.centroid, reflected),
           HypothesisOrigin::wall_direction);
    }
  }
}

}  // namespace areamatch
