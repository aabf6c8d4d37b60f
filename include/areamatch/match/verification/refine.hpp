#pragma once
/// \file match/verification/refine.hpp
/// Trimmed ICP on the boundaries of the two maps' area-covered free space: turns a coarse
/// per-area transform into an accurate global one (docs/algorithm.md). The
/// matching gate shrinks from `gates_m.front()` to `gates_m.back()`; at each step only the
/// `keep_fraction` closest correspondences count, so laser streaks, furniture and rooms one map
/// lacks do not pull the result. Each step minimises the distances to the destination's walls
/// along their normals (point-to-line), so the walls across a corridor pin a map sliding along
/// it; point-to-point steps, which pull every point towards its nearest boundary point, stop
/// short there. With `RefineParams::same_side_only` (merging's refinement) a point is paired
/// with the nearest wall that faces free space the same way: the two faces of a wall between a
/// room one map entered and one only the other did look opposite ways, a wall's thickness apart,
/// and would pull the map across it.

#include "../../error.hpp"
#include "../../transform.hpp"
#include "boundary_lookup.hpp"
#include "edges.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

namespace areamatch {

struct RefineParams {
  std::vector<double> gates_m{2.0, 1.2, 0.7, 0.4};  ///< correspondence gates, one stage each
  int iterations_per_gate = 4;
  double keep_fraction = 0.8;       ///< share of the gated correspondences kept (closest first)
  double point_spacing_m = 0.1;     ///< source boundary points are thinned to about this spacing
  int max_points = 2000;            ///< and to at most this many
  double lookup_cell_m = 0.1;       ///< cell of the destination's nearest-boundary-point lookup
  /// Also fit the scale (a similarity instead of a rigid motion); each iteration may change it by
  /// at most `max_scale_step` (factor), so a bad early match cannot collapse the map. The scale is
  /// fitted by point-to-point steps (point-to-line ones fitting it too lost lab_b_rot123 in
  /// `areamatch eval --estimate-scale`: docs/matching.md).
  bool estimate_scale = false;
  double max_scale_step = 1.1;
  /// Minimise distances along the destination's wall normals (point-to-line) rather than to the
  /// nearest boundary points; needs a lookup built with normals (`BoundaryLookup`'s
  /// `normal_radius_m`), else point-to-point.
  bool point_to_line = true;
  /// The destination's wall normals come from its boundary points within this radius (the
  /// matcher builds its destination lookup with `MatcherParams::refinement`'s).
  double normal_radius_m = 0.2;
  /// Pair a source edge point with the nearest destination edge point that faces the same way
  /// (`BoundaryLookup::nearest_facing`, when both maps' free sides are known: `free_sides`),
  /// not merely the nearest. Across a wall the two faces look opposite ways; without this, the
  /// face of a room only one map entered is pulled onto the other face of its wall, a wall's
  /// thickness away (0.11–0.13 m off on partial robot maps). Off in the matcher (measured there,
  /// not adopted: docs/matching.md); merging refines its accepted matches with it (`MergeParams`).
  bool same_side_only = false;
  /// An edge point's free side: the direction to the free cells within this radius, less the
  /// direction to the others (at least the point's 8 neighbours).
  double free_side_radius_m = 0.1;
  /// A gate's iterations stop early once a step turns by less than `converged_rad` and moves by
  /// less than `converged_m` (and, fitting the scale, changes it by a factor within
  /// `converged_scale` of 1): far below what the evidence can tell apart, so more steps change
  /// nothing a user could see.
  double converged_rad = 1e-5;
  double converged_m = 1e-4;
  double converged_scale = 1e-6;

  void validate() const {
    if (gates_m.empty()) throw parameter_error("RefineParams::gates_m must not be empty");
    for (double g : gates_m) detail::require_positive(g, "RefineParams::gates_m");
    if (iterations_per_gate < 1) throw parameter_error("RefineParams::iterations_per_gate must be >= 1");
    if (!(keep_fraction > 0.0 && keep_fraction <= 1.0)) throw parameter_error("RefineParams::keep_fraction must be in (0, 1]");
    detail::require_positive(point_spacing_m, "RefineParams::point_spacing_m");
    if (max_points < 3) throw parameter_error("RefineParams::max_points must be >= 3");
    detail::require_positive(lookup_cell_m, "RefineParams::lookup_cell_m");
    detail::require_positive(normal_radius_m, "RefineParams::normal_radius_m");
    detail::require_positive(free_side_radius_m, "RefineParams::free_side_radius_m");
    detail::require_non_negative(converged_rad, "RefineParams::converged_rad");
    detail::require_non_negative(converged_m, "RefineParams::converged_m");
    detail::require_non_negative(converged_scale, "RefineParams::converged_scale");
    if (!(max_scale_step >= 1.0 && std::isfinite(max_scale_step))) {
      throw parameter_error("RefineParams::max_scale_step must be a finite factor >= 1");
    }
  }
};

namespace detail {

/// One correspondence of ICP. Small, because trimming moves every match: the destination point
/// by address (its normal, for point-to-line, looked up from it when summing).
struct IcpMatch {
  double distance2;
  Eigen::Vector2d from;  ///< F·scale·x, the source point before rotation
  const Eigen::Vector2d* to;
};

/// One point-to-line step on `T` (rotation matrix `rotation`): linearised about the matched
/// points' centre c, a small turn a about c and a shift t move y to y + a·perp(y − c) + t;
/// minimises Σ ((that − to)·normal)² (3×3 normal equations). Returns whether it converged.
inline bool point_to_line_step(const std::vector<IcpMatch>& matches, const Eigen::Matrix2d& rotation, const BoundaryLookup& dest,
                               const RefineParams& params, Similarity2& T) {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& m : matches) c += rotation * m.from;
  c = c / static_cast<double>(matches.size()) + T.translation;
  // The sums in scalars, the symmetric A's six entries once each: accumulating a 3×3
  // temporary per match stalled on its stack round trip (a fifth of ICP's time). Same sums.
  double a00 = 0.0, a01 = 0.0, a02 = 0.0, a11 = 0.0, a12 = 0.0, a22 = 0.0, b0 = 0.0, b1 = 0.0, b2 = 0.0;
  for (const auto& m : matches) {
    const Eigen::Vector2d y = rotation * m.from + T.translation, q = y - c;
    const Eigen::Vector2d& normal = dest.normal_at(m.to);
    const double j0 = q.x() * normal.y() - q.y() * normal.x(), j1 = normal.x(), j2 = normal.y();
    const double residual = (y - *m.to).dot(normal);
    a00 += j0 * j0;
    a01 += j0 * j1;
    a02 += j0 * j2;
    a11 += j1 * j1;
    a12 += j1 * j2;
    a22 += j2 * j2;
    b0 -= j0 * residual;
    b1 -= j1 * residual;
    b2 -= j2 * residual;
  }
  Eigen::Matrix3d A;
  A << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  const Eigen::Vector3d b(b0, b1, b2);
  // A tiny ridge keeps a direction no wall constrains (a straight corridor's length) where it is.
  const Eigen::Vector3d step = (A + (1e-9 * A.trace() + 1e-12) * Eigen::Matrix3d::Identity()).ldlt().solve(b);
  const Eigen::Rotation2Dd turn(step(0));
  T.rotation = wrap_angle(T.rotation + step(0));
  T.translation = turn * (T.translation - c) + c + step.tail<2>();
  return std::abs(step(0)) < params.converged_rad && step.tail<2>().norm() < params.converged_m;
}

/// One point-to-point step: the 2D Procrustes rotation that best turns the centred source points
/// onto the targets, and with `params.estimate_scale` the scale too (into `shape.scale`). Returns
/// whether it converged.
inline bool procrustes_step(const std::vector<IcpMatch>& matches, const RefineParams& params, Similarity2& shape,
                            Similarity2& T) {
  Eigen::Vector2d mean_from = Eigen::Vector2d::Zero(), mean_to = Eigen::Vector2d::Zero();
  for (const auto& m : matches) {
    mean_from += m.from;
    mean_to += *m.to;
  }
  mean_from /= static_cast<double>(matches.size());
  mean_to /= static_cast<double>(matches.size());
  double dot = 0.0, cross = 0.0;
  for (const auto& m : matches) {
    const Eigen::Vector2d a = m.from - mean_from, b = *m.to - mean_to;
    dot += a.dot(b);
    cross += a.x() * b.y() - a.y() * b.x();
  }
  const double angle = std::atan2(cross, dot);
  const Eigen::Rotation2Dd turn(angle);
  // With scale: the factor k minimising Σ |b − k·R·a|² is Σ b·(R·a) / Σ |a|².
  double k = 1.0;
  if (params.estimate_scale) {
    double along = 0.0, norm2 = 0.0;
    for (const auto& m : matches) {
      const Eigen::Vector2d a = m.from - mean_from;
      along += (*m.to - mean_to).dot(turn * a);
      norm2 += a.squaredNorm();
    }
    if (norm2 > 0.0 && along > 0.0) k = std::clamp(along / norm2, 1.0 / params.max_scale_step, params.max_scale_step);
    shape.scale *= k;
  }
  const Similarity2 previous = T;
  T.rotation = wrap_angle(angle);
  T.scale = shape.scale;
  T.translation = mean_to - turn * (k * mean_from);
  return std::abs(wrap_angle(T.rotation - previous.rotation)) < params.converged_rad &&
         (T.translation - previous.translation).norm() < params.converged_m && std::abs(k - 1.0) < params.converged_scale;
}

/// The least-squares rigid motion taking `from[i]` onto `to[i]` (2D Procrustes), keeping `shape`'s
/// scale and reflection (its rotation and translation are ignored). `shape` itself (with zero
/// rotation and translation) for fewer than three pairs.
inline Similarity2 least_squares_rigid(const std::vector<Eigen::Vector2d>& from, const std::vector<Eigen::Vector2d>& to,
                                       const Similarity2& shape) {
  Similarity2 kept{0.0, Eigen::Vector2d::Zero(), shape.scale, shape.reflected};
  Similarity2 T = kept;
  if (from.size() < 3 || to.size() != from.size()) return T;
  std::vector<IcpMatch> matches;
  matches.reserve(from.size());
  for (std::size_t i = 0; i < from.size(); ++i) matches.push_back({0.0, kept * from[i], &to[i]});
  RefineParams rigid;
  rigid.estimate_scale = false;
  procrustes_step(matches, rigid, kept, T);
  return T;
}

}  // namespace detail

/// Trimmed ICP from `initial`: the rigid transform (reflection and scale kept; the scale fitted
/// too with `params.estimate_scale`) that best lays `source_points` onto the destination
/// boundary. Point-to-line steps with `params.point_to_line` and a lookup with normals (rigid
/// only), else point-to-point. With `source_sides` (the points' free sides, `free_sides`; empty:
/// none) and a lookup with sides, `params.same_side_only` pairs each point with the nearest wall
/// facing the same way. Returns `initial` when too few points match.
inline Similarity2 refine_icp(const std::vector<Eigen::Vector2d>& source_points, const BoundaryLookup& dest,
                              const Similarity2& initial, const RefineParams& params,
                              const std::vector<Eigen::Vector2d>* source_sides = nullptr) {
  Similarity2 T = initial;
  if (dest.empty() || source_points.size() < 3) return T;
  const bool same_side = params.same_side_only && source_sides && !source_sides->empty() && dest.has_sides();
  if (same_side && source_sides->size() != source_points.size()) {
    throw parameter_error("refine_icp: one free side per source point");
  }
  const bool point_to_line = params.point_to_line && dest.has_normals() && !params.estimate_scale;
  std::vector<detail::IcpMatch> matches;
  matches.reserve(source_points.size());
  Similarity2 shape{0.0, Eigen::Vector2d::Zero(), initial.scale, initial.reflected};
  for (double gate : params.gates_m) {
    for (int iteration = 0; iteration < params.iterations_per_gate; ++iteration) {
      matches.clear();
      const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(T.rotation).toRotationMatrix();
      const Eigen::Matrix2d side_turn = rotation * shape.linear();  // scale does not change a side's direction
      for (std::size_t i = 0; i < source_points.size(); ++i) {
        const Eigen::Vector2d from = shape * source_points[i];
        const Eigen::Vector2d y = rotation * from + T.translation;
        const Eigen::Vector2d* d = same_side ? dest.nearest_facing(y, side_turn * (*source_sides)[i]) : dest.nearest(y);
        if (!d) continue;
        const double d2 = (*d - y).squaredNorm();
        if (d2 <= gate * gate) matches.push_back({d2, from, d});
      }
      if (matches.size() < 3) return T;
      const std::size_t keep = std::max<std::size_t>(3, static_cast<std::size_t>(params.keep_fraction * matches.size()));
      if (keep < matches.size()) {
        std::nth_element(matches.begin(), matches.begin() + static_cast<std::ptrdiff_t>(keep), matches.end(),
                         [](const detail::IcpMatch& a, const detail::IcpMatch& b) { return a.distance2 < b.distance2; });
        matches.resize(keep);
      }
      const bool converged = point_to_line ? detail::point_to_line_step(matches, rotation, dest, params, T)
                                           : detail::procrustes_step(matches, params, shape, T);
      if (converged) break;
    }
  }
  return T;
}

}  // namespace areamatch
